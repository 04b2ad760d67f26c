// Closed-form solutions of the volume rendering integral, for the tests.
//
// 1. Constant colour c and extinction tau over a length L:
//      alpha = 1 - e^{-tau L},  I = c alpha.
// 2. A linear field s(t) = s0 + k t through a piecewise-linear transfer
//    function (Williams and Max, "A volume density optical model", 1992, and
//    VTK's vtkUnstructuredGridLinearRayIntegrator solve the same piecewise
//    problem). Between the parameters where s crosses a knot, tau and C are
//    linear in t: tau = a + b t, C = p + q t (t from the piece's start, length
//    h). With u(t) = a t + b t^2 / 2 (so u' = tau) and integrating t u' e^{-u}
//    by parts:
//      int_0^h (p + q t) u' e^{-u} dt = p (1 - e^{-u(h)}) + q (E(h) - h e^{-u(h)}),
//      E(h) = int_0^h e^{-u(t)} dt, which is
//        b = 0: (1 - e^{-a h}) / a   (h if a = 0),
//        b > 0: sqrt(pi / (2b)) [erfcx(x(0)) - e^{-u(h)} erfcx(x(h))], x = (a + b t) / sqrt(2b),
//        b < 0: sqrt(2 / |b|) [e^{-u(h)} F(y(h)) - F(y(0))],          y = (|b| t - a) / sqrt(2|b|),
//    erfcx(x) = e^{x^2} erfc(x) and F Dawson's integral e^{-y^2} int_0^y e^{v^2} dv
//    (completing the square in u; Abramowitz and Stegun 7.1.1, 7.1.17).
//    The pieces are composited front to back: I += T I_piece, T *= e^{-u(h)}.
//    For accuracy the tests keep |b| = 0 or |b| >= 1e-3 (the two terms of E
//    cancel as b -> 0).
// 3. tau(s) = s with constant colours and s(t) = A + B sin(w t) (non-polynomial):
//      theta(D) = A D + (B / w)(1 - cos w D), alpha = 1 - e^{-theta(D)}, I = c alpha.
// 4. tau(s) = s, colour C = g s / lambda and s(t) = lambda / (1 + t):
//      theta(t) = lambda ln(1 + t), e^{-theta} = (1 + t)^{-lambda},
//      I = int g s^2 / lambda (1 + t)^{-lambda} dt = g lambda / (lambda + 1) (1 - (1 + D)^{-lambda
//      - 1}), alpha = 1 - (1 + D)^{-lambda}.
#ifndef avos_numerics_Oracles_h
#define avos_numerics_Oracles_h

#include "avos/numerics/TransferFunction.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace oracles
{

// e^{x^2} erfc(x) for x >= 0: direct below 26 (no overflow, erfc accurate),
// asymptotic series above (relative error < 1e-12).
inline double Erfcx(double x)
{
  if (x < 26.0)
  {
    return std::exp(x * x) * std::erfc(x);
  }
  const double x2 = 1.0 / (2.0 * x * x);
  double term = 1.0, sum = 1.0;
  for (int n = 1; n < 8; ++n)
  {
    term *= -(2 * n - 1) * x2;
    sum += term;
  }
  return sum / (x * std::sqrt(M_PI));
}

// Dawson's integral: positive-term series e^{-y^2} sum y^{2n+1} / (n! (2n+1))
// below 6, asymptotic sum (2n-1)!! / (2^{n+1} y^{2n+1}) above.
inline double Dawson(double y)
{
  const double a = std::abs(y);
  double result = 0.0;
  if (a < 6.0)
  {
    double power = a; // a^{2n+1} / n!
    for (int n = 0; n < 400; ++n)
    {
      const double term = power / (2 * n + 1);
      result += term;
      if (term < 1e-17 * result)
      {
        break;
      }
      power *= a * a / (n + 1);
    }
    result *= std::exp(-a * a);
  }
  else
  {
    const double inv = 1.0 / (2.0 * a * a);
    double term = 1.0, sum = 1.0;
    for (int n = 1; n < 30; ++n)
    {
      term *= (2 * n - 1) * inv;
      sum += term;
    }
    result = sum / (2.0 * a);
  }
  return y < 0 ? -result : result;
}

// int_0^h e^{-(a t + b t^2 / 2)} dt.
inline double ExpQuadraticIntegral(double a, double b, double h)
{
  const double uh = a * h + 0.5 * b * h * h;
  if (b == 0.0)
  {
    return a == 0.0 ? h : -std::expm1(-a * h) / a;
  }
  if (b > 0.0)
  {
    const double r = std::sqrt(2.0 * b);
    return std::sqrt(M_PI / (2.0 * b)) * (Erfcx(a / r) - std::exp(-uh) * Erfcx((a + b * h) / r));
  }
  const double beta = -b;
  const double r = std::sqrt(2.0 * beta);
  return std::sqrt(2.0 / beta) * (std::exp(-uh) * Dawson((beta * h - a) / r) - Dawson(-a / r));
}

// Exact RGBA of s(t) = s0 + k t, t in [0, D], through tf (extinction model).
inline glm::dvec4 LinearField(
  const avos::numerics::TransferFunction<double>& tf, double s0, double k, double D)
{
  // Piece boundaries: where s crosses a knot value.
  std::vector<double> cuts{ 0.0, D };
  if (k != 0.0)
  {
    for (double v : tf.GetKnotValues())
    {
      const double t = (v - s0) / k;
      if (t > 0.0 && t < D)
      {
        cuts.push_back(t);
      }
    }
  }
  std::sort(cuts.begin(), cuts.end());
  glm::dvec3 color(0.0);
  double T = 1.0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
  {
    const double h = cuts[i + 1] - cuts[i];
    if (h <= 0.0)
    {
      continue;
    }
    // Evaluate inside the piece: both ends may sit on a knot (a jump).
    const double sA = s0 + k * (cuts[i] + 1e-3 * h), sB = s0 + k * (cuts[i + 1] - 1e-3 * h);
    const double w = 1.0 / (1.0 - 2e-3);
    const double tauA = tf.GetExtinction(sA), tauB = tf.GetExtinction(sB);
    const glm::dvec3 cA = tf.GetColor(sA), cB = tf.GetColor(sB);
    const double b = (tauB - tauA) * w / h;
    const double a = tauA - b * 1e-3 * h;
    const glm::dvec3 q = (cB - cA) * w / h;
    const glm::dvec3 p = cA - q * (1e-3 * h);
    const double uh = a * h + 0.5 * b * h * h;
    const double E = ExpQuadraticIntegral(a, b, h);
    const double Th = std::exp(-uh);
    color += T * (p * (1.0 - Th) + q * (E - h * Th));
    T *= Th;
  }
  return glm::dvec4(color, 1.0 - T);
}

} // namespace oracles

#endif
