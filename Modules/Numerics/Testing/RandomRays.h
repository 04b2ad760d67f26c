// Seeded random rays for the accuracy tests and the benchmarks: smooth and
// discontinuous transfer functions, linear and non-linear fields.
#ifndef avos_numerics_RandomRays_h
#define avos_numerics_RandomRays_h

#include "avos/numerics/TransferFunction.h"

#include <cmath>
#include <random>
#include <vector>

namespace randomrays
{

template <typename Real>
struct Ray
{
  avos::numerics::TransferFunction<Real> TF;
  // s(t) = Offset + Slope t + sum Amplitude_i sin(Frequency_i t + Phase_i)
  Real Offset = 0, Slope = 0;
  Real Amplitude[3] = { 0, 0, 0 }, Frequency[3] = { 0, 0, 0 }, Phase[3] = { 0, 0, 0 };
  Real Length = 1;

  Real operator()(Real t) const
  {
    Real s = this->Offset + this->Slope * t;
    for (int i = 0; i < 3; ++i)
    {
      s += this->Amplitude[i] * std::sin(this->Frequency[i] * t + this->Phase[i]);
    }
    return s;
  }
};

// Ray i of a fixed family: even rays have smooth transfer functions (64 knots
// of a sum of sinusoids), odd rays discontinuous ones (jumps in tau and
// colour); every other pair has a linear field, the rest a non-linear one.
template <typename Real>
Ray<Real> Make(unsigned seed)
{
  std::mt19937 rng(seed * 2654435761u + 12345u);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Ray<Real> ray;
  const double tauMax = 0.05 + 1.5 * u(rng);
  if (seed % 2 == 0)
  {
    double a[3], f[3], p[3];
    for (int i = 0; i < 3; ++i)
    {
      a[i] = u(rng);
      f[i] = 1.0 + 8.0 * u(rng);
      p[i] = 6.283 * u(rng);
    }
    for (int k = 0; k < 64; ++k)
    {
      const double s = k / 63.0;
      double v = 0;
      for (int i = 0; i < 3; ++i)
      {
        v += a[i] * (0.5 + 0.5 * std::sin(f[i] * s + p[i]));
      }
      v /= (a[0] + a[1] + a[2]);
      ray.TF.AddOpacityKnot(Real(s), Real(tauMax * v * v));
      ray.TF.AddColorKnot(Real(s), Real(0.5 + 0.5 * std::sin(7 * s + p[0])),
        Real(0.5 + 0.5 * std::sin(5 * s + p[1])), Real(v));
    }
  }
  else
  {
    const int knots = 4 + static_cast<int>(6 * u(rng));
    double s = 0;
    for (int k = 0; k < knots; ++k)
    {
      const double tau = tauMax * u(rng) * u(rng);
      ray.TF.AddOpacityKnot(Real(s), Real(tau));
      ray.TF.AddColorKnot(Real(s), Real(u(rng)), Real(u(rng)), Real(u(rng)));
      if (u(rng) < 0.5) // a jump at s
      {
        ray.TF.AddOpacityKnot(Real(s), Real(tauMax * u(rng)));
        ray.TF.AddColorKnot(Real(s), Real(u(rng)), Real(u(rng)), Real(u(rng)));
      }
      s += 1.0 / (knots - 1);
    }
  }
  ray.Length = Real(5.0 + 45.0 * u(rng));
  ray.Offset = Real(u(rng));
  ray.Slope = Real((u(rng) - 0.5) * 2.0 / double(ray.Length));
  if ((seed / 2) % 2 == 1)
  {
    for (int i = 0; i < 3; ++i)
    {
      ray.Amplitude[i] = Real(0.2 * u(rng));
      ray.Frequency[i] = Real(0.05 + 1.5 * u(rng));
      ray.Phase[i] = Real(6.283 * u(rng));
    }
  }
  ray.TF.Finalize();
  return ray;
}

} // namespace randomrays

#endif
