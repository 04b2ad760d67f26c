// The adversarial accuracy suite: generated volumes and transfer functions on
// which an error estimate from samples can be blind (layers thinner than a
// voxel, jumps, huge extinction, high-frequency fields), random rays through
// them, and the tally of each method's error against the exact piecewise
// reference, unshaded or lit (SharpLighting), with or without a gradient
// opacity whose knots the case's gradients cross (CrossedGradientOpacity).
// Shared by the numerical core's tests (few rays) and avos-bench-accuracy
// (100,000 rays per case).
#ifndef avos_numerics_AdversarialCases_h
#define avos_numerics_AdversarialCases_h

#include "avos/numerics/GradientOpacity.h"
#include "avos/numerics/PiecewiseGradientOpacity.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/PiecewiseShading.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/TransferFunction.h"
#include "avos/numerics/Volume.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace adversarial
{
namespace an = avos::numerics;

// Scalars in [0, 255] on an N^3 grid; steps in grid (voxel) units.
struct Case
{
  std::string Name;
  int Dimensions[3] = { 0, 0, 0 };
  std::vector<double> Data;
  an::TransferFunction<double> TF;
};

constexpr int N = 40;

inline Case MakeVolume(
  const std::string& name, double (*field)(double, double, double, unsigned), unsigned seed)
{
  Case c;
  c.Name = name;
  c.Dimensions[0] = c.Dimensions[1] = c.Dimensions[2] = N;
  c.Data.resize(static_cast<std::size_t>(N) * N * N);
  for (int k = 0; k < N; ++k)
  {
    for (int j = 0; j < N; ++j)
    {
      for (int i = 0; i < N; ++i)
      {
        const double x = 2.0 * i / (N - 1) - 1.0, y = 2.0 * j / (N - 1) - 1.0,
                     z = 2.0 * k / (N - 1) - 1.0;
        c.Data[i + N * (j + static_cast<std::size_t>(N) * k)] = field(x, y, z, seed);
      }
    }
  }
  return c;
}

// Segmented data: 255 inside a union of balls, 0 outside.
inline double Binary(double x, double y, double z, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.7, 0.7);
  for (int b = 0; b < 6; ++b)
  {
    const double cx = u(rng), cy = u(rng), cz = u(rng), r = 0.2 + 0.25 * (u(rng) + 0.7);
    if ((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz) < r * r)
    {
      return 255.0;
    }
  }
  return 0.0;
}

// Two materials (60 and 190) with a little noise on each.
inline double TwoMaterial(double x, double y, double z, unsigned seed)
{
  const double noise = 4.0 * std::sin(37.0 * x + 11.0 * y) * std::cos(29.0 * z + seed);
  return (Binary(x, y, z, seed) > 0.0 ? 190.0 : 60.0) + noise;
}

// Marschner and Lobb's test signal (f_M = 6, alpha = 0.25), scaled to [0, 255].
inline double MarschnerLobb(double x, double y, double z, unsigned)
{
  const double pi = 3.14159265358979323846;
  const double rho = std::cos(2.0 * pi * 6.0 * std::cos(pi * std::sqrt(x * x + y * y) / 2.0));
  return 255.0 * (1.0 - std::sin(pi * z / 2.0) + 0.25 * (1.0 + rho)) / (2.0 * 1.25);
}

// A smooth random field: a sum of sinusoids in [0, 255].
inline double Smooth(double x, double y, double z, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double v = 0.0;
  for (int i = 0; i < 4; ++i)
  {
    const double fx = 6.0 * u(rng), fy = 6.0 * u(rng), fz = 6.0 * u(rng), p = 6.28 * u(rng);
    v += std::sin(fx * x + fy * y + fz * z + p);
  }
  return 127.5 + 127.5 * v / 4.0;
}

// A spike of extinction `peak`, `width` scalar units wide, centred on
// `centre`, coloured against a blue background.
inline an::TransferFunction<double> Spike(double centre, double width, double peak)
{
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(centre - width / 2, 0.0);
  tf.AddOpacityKnot(centre, peak);
  tf.AddOpacityKnot(centre + width / 2, 0.0);
  tf.AddOpacityKnot(255.0, 0.0);
  tf.AddColorKnot(0.0, 0.0, 0.2, 1.0);
  tf.AddColorKnot(centre - width / 2, 0.1, 0.3, 0.9);
  tf.AddColorKnot(centre, 1.0, 0.6, 0.1);
  tf.AddColorKnot(centre + width / 2, 0.9, 0.9, 0.2);
  tf.AddColorKnot(255.0, 1.0, 1.0, 1.0);
  tf.Finalize();
  return tf;
}

// Jumps only: transparent below 128, a step of extinction and colour there,
// another at 200.
inline an::TransferFunction<double> Steps()
{
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(128.0, 0.0);
  tf.AddOpacityKnot(128.0, 0.8);
  tf.AddOpacityKnot(200.0, 0.8);
  tf.AddOpacityKnot(200.0, 4.0);
  tf.AddOpacityKnot(255.0, 4.0);
  tf.AddColorKnot(0.0, 0.0, 0.0, 1.0);
  tf.AddColorKnot(128.0, 0.0, 0.0, 1.0);
  tf.AddColorKnot(128.0, 1.0, 0.2, 0.2);
  tf.AddColorKnot(200.0, 1.0, 0.2, 0.2);
  tf.AddColorKnot(200.0, 0.2, 1.0, 0.2);
  tf.AddColorKnot(255.0, 0.9, 1.0, 0.9);
  tf.Finalize();
  return tf;
}

// Up to `knots` random knots over [bottom, top] (some repeated: jumps),
// extinction up to `peak`, random colours; `integral`: knots on whole scalar
// values.
inline an::TransferFunction<double> Random(unsigned seed, int knots, double peak,
  double top = 255.0, bool integral = false, double bottom = 0.0)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> values(static_cast<std::size_t>(knots));
  for (double& v : values)
  {
    const double x = bottom + (top - bottom) * u(rng);
    v = integral ? std::round(x) : x;
  }
  std::sort(values.begin(), values.end());
  an::TransferFunction<double> tf;
  for (double v : values)
  {
    const int repeat = u(rng) < 0.2 ? 2 : 1;
    for (int r = 0; r < repeat; ++r)
    {
      const double a = u(rng);
      tf.AddOpacityKnot(v, a * a * a * peak);
      tf.AddColorKnot(v, u(rng), u(rng), u(rng));
    }
  }
  tf.Finalize();
  return tf;
}

// The suite: binary volumes with spikes 1, 5 and 20 units wide at the
// material boundary, two materials with a spike at their interface, steps,
// extinction up to 50 per voxel, Marschner-Lobb, random 64-knot functions.
inline std::vector<Case> MakeSuite()
{
  std::vector<Case> cases;
  for (double width : { 1.0, 5.0, 20.0 })
  {
    Case c = MakeVolume("binary, spike " + std::to_string(static_cast<int>(width)), Binary, 7);
    c.TF = Spike(127.5, width, 20.0);
    cases.push_back(std::move(c));
  }
  {
    Case c = MakeVolume("two materials, spike 5", TwoMaterial, 11);
    c.TF = Spike(125.0, 5.0, 10.0);
    cases.push_back(std::move(c));
  }
  {
    Case c = MakeVolume("Marschner-Lobb, steps", MarschnerLobb, 0);
    c.TF = Steps();
    cases.push_back(std::move(c));
  }
  {
    Case c = MakeVolume("smooth, extinction 50", Smooth, 3);
    c.TF = Spike(170.0, 30.0, 50.0);
    cases.push_back(std::move(c));
  }
  {
    Case c = MakeVolume("Marschner-Lobb, random 16 knots", MarschnerLobb, 0);
    c.TF = Random(5, 16, 2.0);
    cases.push_back(std::move(c));
  }
  {
    Case c = MakeVolume("smooth, random 64 knots", Smooth, 9);
    c.TF = Random(13, 64, 3.0);
    cases.push_back(std::move(c));
  }
  return cases;
}

struct Ray
{
  glm::dvec3 Origin;
  glm::dvec3 Direction; // unit: t in voxel units
  double Length;
};

// A ray through two uniform random points of the box of `dimensions` at
// least `span` apart, clipped to the box.
inline Ray RandomRay(const int dimensions[3], std::mt19937& rng, double span)
{
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (;;)
  {
    glm::dvec3 a, b;
    for (int k = 0; k < 3; ++k)
    {
      a[k] = u(rng) * (dimensions[k] - 1);
      b[k] = u(rng) * (dimensions[k] - 1);
    }
    if (glm::length(b - a) < span)
    {
      continue;
    }
    const glm::dvec3 d = glm::normalize(b - a);
    double t0 = -1e9, t1 = 1e9;
    if (an::ClipToGrid(a, d, dimensions, t0, t1))
    {
      return { a + t0 * d, d, t1 - t0 };
    }
  }
}

// Ray i of a case.
inline Ray MakeRay(const Case& c, unsigned i)
{
  std::mt19937 rng(i * 2654435761u + 99u);
  return RandomRay(c.Dimensions, rng, 1.0);
}

// The shaded rows' lighting: a sharp highlight (specular power 128), one-sided
// lighting (n.l's kink), two coloured directional lights.
inline an::ShadingModel<double> SharpLighting()
{
  an::ShadingModel<double> m;
  m.Ambient = 0.05;
  m.Diffuse = 0.6;
  m.Specular = 0.7;
  m.SpecularPower = 128.0;
  m.TwoSided = false;
  m.Lights.push_back({ glm::normalize(glm::dvec3(0.3, -0.5, 0.8)), glm::dvec3(0.9, 0.7, 0.5),
    glm::dvec3(1.0, 0.9, 0.8) });
  m.Lights.push_back(
    { glm::normalize(glm::dvec3(-0.6, 0.2, 0.3)), glm::dvec3(0.2, 0.3, 0.6), glm::dvec3(0.5) });
  return m;
}

// A gradient opacity G whose knots a case's gradients cross: 0.05 at 0, 1 at
// a quarter of the largest gradient at a cell centre, 0.35 at 0.6 of it.
inline an::TransferFunction<double> CrossedGradientOpacity(const Case& c)
{
  const an::TrilinearVolume<double, double> volume(c.Data.data(), c.Dimensions);
  double largest = 0.0;
  for (int k = 1; k + 1 < c.Dimensions[2]; ++k)
  {
    for (int j = 1; j + 1 < c.Dimensions[1]; ++j)
    {
      for (int i = 1; i + 1 < c.Dimensions[0]; ++i)
      {
        largest =
          std::max(largest, glm::length(volume.Gradient(glm::dvec3(i + 0.5, j + 0.5, k + 0.5))));
      }
    }
  }
  an::TransferFunction<double> g;
  g.AddColorKnot(0.0, 1.0, 1.0, 1.0);
  g.AddOpacityKnot(0.0, 0.05);
  g.AddOpacityKnot(0.25 * largest, 1.0);
  g.AddOpacityKnot(0.6 * largest, 0.35);
  g.Finalize();
  return g;
}

enum class Method
{
  Piecewise,
  Coupled,
  Decoupled,
  Reference
};

inline const char* MethodName(Method m)
{
  switch (m)
  {
    case Method::Piecewise:
      return "piecewise";
    case Method::Coupled:
      return "coupled";
    case Method::Decoupled:
      return "decoupled";
    default:
      return "reference";
  }
}

// Integrates one ray with a method at a tolerance, lit by `lighting` and
// scaled by the gradient opacity `opacity` where given (grid = world, seen
// along the ray); `tf` is the case's function prepared for that tolerance
// (piecewise methods).
inline an::RayResult<double> Integrate(const Case& c,
  const an::PiecewiseTransferFunction<double>& tf, const Ray& ray, Method method, double eps,
  const an::ShadingModel<double>* lighting = nullptr,
  const an::GradientOpacity<double>* opacity = nullptr)
{
  const an::TrilinearVolume<double, double> volume(c.Data.data(), c.Dimensions);
  const an::RayShading<double> shading{ lighting, glm::dmat3(1.0), -ray.Direction, ray.Origin,
    ray.Direction };
  const bool piecewise = method == Method::Piecewise || method == Method::Reference;
  if (piecewise && opacity)
  {
    const an::Interval<double> whole{ 0.0, ray.Length };
    return an::IntegratePiecewiseGradientOpacity(volume, ray.Origin, ray.Direction, &whole, 1, tf,
      eps, *opacity, lighting ? &shading : nullptr);
  }
  if (piecewise && lighting)
  {
    const an::Interval<double> whole{ 0.0, ray.Length };
    return an::IntegratePiecewiseShaded(
      volume, ray.Origin, ray.Direction, &whole, 1, tf, eps, shading);
  }
  if (method == Method::Piecewise || method == Method::Reference)
  {
    return an::IntegratePiecewise(volume, ray.Origin, ray.Direction, ray.Length, tf, eps);
  }
  an::AdaptiveSettings<double> settings;
  settings.Tolerance = eps;
  settings.Coupling = method == Method::Coupled ? an::Strategy::Coupled : an::Strategy::Decoupled;
  settings.FieldMinimum = 0.0;
  settings.FieldMaximum = 255.0;
  auto adaptive = [&](const auto& field)
  {
    using Field = std::decay_t<decltype(field)>;
    return opacity
      ? an::IntegrateAdaptive(
          an::GradientOpacityField<double, Field>{ field, opacity }, c.TF, ray.Length, settings)
      : an::IntegrateAdaptive(field, c.TF, ray.Length, settings);
  };
  if (lighting)
  {
    return adaptive(an::ShadedRayField<double, an::TrilinearVolume<double, double>>{
      volume, ray.Origin, ray.Direction, shading });
  }
  return adaptive(
    an::RayField<double, an::TrilinearVolume<double, double>>{ volume, ray.Origin, ray.Direction });
}

struct Tally
{
  long Rays = 0;
  long Within[4] = { 0, 0, 0, 0 }; // rays within eps, per channel
  double Maximum[4] = { 0, 0, 0, 0 };
  double Samples = 0; // per ray
  double Pieces = 0;  // per ray (piecewise)
  double Cells = 0;   // per ray (piecewise)
  long Failures = 0;  // rays that returned an error

  double Percent(int channel) const
  {
    return 100.0 * this->Within[channel] / std::max(1L, this->Rays);
  }
  double WorstPercent() const
  {
    return std::min({ this->Percent(0), this->Percent(1), this->Percent(2), this->Percent(3) });
  }
  double WorstMaximum() const
  {
    return std::max({ this->Maximum[0], this->Maximum[1], this->Maximum[2], this->Maximum[3] });
  }
  // Another thread's tally added (its per-ray figures still sums).
  void Add(const Tally& t)
  {
    this->Rays += t.Rays;
    this->Failures += t.Failures;
    this->Samples += t.Samples;
    this->Pieces += t.Pieces;
    this->Cells += t.Cells;
    for (int ch = 0; ch < 4; ++ch)
    {
      this->Within[ch] += t.Within[ch];
      this->Maximum[ch] = std::max(this->Maximum[ch], t.Maximum[ch]);
    }
  }
};

// The case's gradient opacity (CrossedGradientOpacity) where `graded`.
struct CaseGradient
{
  an::TransferFunction<double> Function;
  an::GradientOpacity<double> Opacity;
  bool Graded;

  CaseGradient(const Case& c, bool graded)
    : Graded(graded)
  {
    if (graded)
    {
      this->Function = CrossedGradientOpacity(c);
      this->Opacity.Function = &this->Function;
    }
  }
  CaseGradient(const CaseGradient&) = delete;
  CaseGradient& operator=(const CaseGradient&) = delete;
  const an::GradientOpacity<double>* Get() const { return this->Graded ? &this->Opacity : nullptr; }
};

// The exact reference of rays [0, count) of a case (lit by `lighting`
// where given, with its gradient opacity where `graded`).
inline std::vector<glm::dvec4> References(const Case& c, unsigned count, int threads = 1,
  const an::ShadingModel<double>* lighting = nullptr, bool graded = false)
{
  const CaseGradient gradient(c, graded);
  an::PiecewiseTransferFunction<double> tf;
  tf.Build(c.TF, 1e-7);
  std::vector<glm::dvec4> rgba(count);
  auto work = [&](unsigned begin, unsigned end)
  {
    for (unsigned i = begin; i < end; ++i)
    {
      rgba[i] = Integrate(c, tf, MakeRay(c, i), Method::Reference,
        an::PiecewiseReferenceTolerance<double>(), lighting, gradient.Get())
                  .RGBA;
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
  {
    pool.emplace_back(work, count * t / threads, count * (t + 1) / threads);
  }
  for (auto& t : pool)
  {
    t.join();
  }
  return rgba;
}

// A method's errors on rays [0, reference.size()) of a case (lit by
// `lighting` where given, with its gradient opacity where `graded`).
inline Tally Measure(const Case& c, const std::vector<glm::dvec4>& reference, Method method,
  double eps, int threads = 1, const an::ShadingModel<double>* lighting = nullptr,
  bool graded = false)
{
  const CaseGradient gradient(c, graded);
  an::PiecewiseTransferFunction<double> tf;
  tf.Build(c.TF, an::PiecewiseRelativeError(eps));
  const unsigned count = static_cast<unsigned>(reference.size());
  std::vector<Tally> partial(static_cast<std::size_t>(threads));
  auto work = [&](int t)
  {
    Tally& tally = partial[static_cast<std::size_t>(t)];
    for (unsigned i = count * t / threads; i < count * (t + 1) / threads; ++i)
    {
      const an::RayResult<double> r =
        Integrate(c, tf, MakeRay(c, i), method, eps, lighting, gradient.Get());
      ++tally.Rays;
      tally.Failures += r.Error.empty() ? 0 : 1;
      tally.Samples += static_cast<double>(r.Statistics.Samples);
      tally.Pieces += static_cast<double>(r.Statistics.Pieces);
      tally.Cells += static_cast<double>(r.Statistics.Cells);
      for (int ch = 0; ch < 4; ++ch)
      {
        const double e = std::abs(r.RGBA[ch] - reference[i][ch]);
        tally.Within[ch] += e <= eps ? 1 : 0;
        tally.Maximum[ch] = std::max(tally.Maximum[ch], std::isfinite(e) ? e : 1e300);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
  {
    pool.emplace_back(work, t);
  }
  for (auto& t : pool)
  {
    t.join();
  }
  Tally total;
  for (const Tally& t : partial)
  {
    total.Add(t);
  }
  const double n = static_cast<double>(std::max(1L, total.Rays));
  total.Samples /= n;
  total.Pieces /= n;
  total.Cells /= n;
  return total;
}

} // namespace adversarial

#endif
