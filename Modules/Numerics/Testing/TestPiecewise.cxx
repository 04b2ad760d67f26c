// Piecewise adaptive integration (PiecewiseIntegrator.h, Pieces.h): the
// reference proven exact against closed forms and against the adaptive
// reference, the tolerance held on the adversarial suite, termination and
// bad input.
#include "AdversarialCases.h"
#include "Oracles.h"
#include "RandomRays.h"

#include "avos/numerics/Accumulation.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Volume.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

namespace an = avos::numerics;

namespace
{
using Volume = an::TrilinearVolume<double, double>;

// A volume of dims^3 points whose scalar is f(i, j, k).
template <typename F>
std::vector<double> Grid(const int dims[3], F f)
{
  std::vector<double> data;
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        data.push_back(f(i, j, k));
      }
    }
  }
  return data;
}

an::PiecewiseTransferFunction<double> Prepare(const an::TransferFunction<double>& tf, double eps)
{
  an::PiecewiseTransferFunction<double> p;
  const std::string error = p.Build(tf, an::PiecewiseRelativeError(eps));
  EXPECT_EQ(error, "");
  return p;
}

// VTK's alpha model (unit distance 2) with a ramp up to opaque.
an::TransferFunction<double> RampToOpaque()
{
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(80.0, 0.05);
  tf.AddOpacityKnot(150.0, 0.9);
  tf.AddOpacityKnot(200.0, 1.0);
  tf.AddOpacityKnot(255.0, 0.3);
  tf.AddColorKnot(0.0, 1.0, 0.0, 0.0);
  tf.AddColorKnot(255.0, 0.0, 1.0, 1.0);
  tf.SetOpacityModel(an::OpacityModel::Alpha, 2.0);
  tf.Finalize();
  return tf;
}

// A random ray through the box of `dims`: origin, unit direction, length.
adversarial::Ray RandomRay(const int dims[3], std::mt19937& rng)
{
  return adversarial::RandomRay(dims, rng, 0.5);
}

constexpr double ReferenceTolerance = an::PiecewiseReferenceTolerance<double>();

// No error, and every channel in [0, 1] (no NaN).
bool Usable(const an::RayResult<double>& r)
{
  bool ok = r.Error.empty();
  for (int c = 0; c < 4; ++c)
  {
    ok = ok && r.RGBA[c] >= 0.0 && r.RGBA[c] <= 1.0;
  }
  return ok;
}
} // namespace

// Constant scalar and transfer function: alpha = 1 - e^{-tau D}, I = c alpha.
TEST(Piecewise, ReferenceIsExactOnConstants)
{
  const int dims[3] = { 5, 4, 6 };
  const std::vector<double> data = Grid(dims, [](int, int, int) { return 0.3; });
  const Volume volume(data.data(), dims);
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.7);
  tf.AddOpacityKnot(1.0, 0.7);
  tf.AddColorKnot(0.0, 0.2, 0.5, 0.9);
  tf.Finalize();
  const auto ptf = Prepare(tf, ReferenceTolerance);
  std::mt19937 rng(1);
  for (int i = 0; i < 200; ++i)
  {
    const adversarial::Ray ray = RandomRay(dims, rng);
    const auto r = an::IntegratePiecewise(
      volume, ray.Origin, ray.Direction, ray.Length, ptf, ReferenceTolerance, false);
    ASSERT_EQ(r.Error, "");
    const double alpha = -std::expm1(-0.7 * ray.Length);
    EXPECT_NEAR(r.RGBA.a, alpha, 1e-12);
    EXPECT_NEAR(r.RGBA.r, 0.2 * alpha, 1e-12);
    EXPECT_NEAR(r.RGBA.b, 0.9 * alpha, 1e-12);
    // Constant colour: the integral by parts needs no sample inside.
    EXPECT_EQ(r.Statistics.Samples, r.Statistics.Pieces);
  }
}

// A linear field (trilinear interpolation reproduces it exactly) through
// smooth, jumping and step transfer functions: the closed form of
// Williams and Max (Oracles.h) to 1e-9.
TEST(Piecewise, ReferenceIsExactOnLinearFields)
{
  const int dims[3] = { 9, 7, 8 };
  std::mt19937 rng(2);
  for (unsigned seed = 0; seed < 60; ++seed)
  {
    randomrays::Ray<double> family = randomrays::Make<double>(seed);
    // The field's gradient: s spans the transfer function's [0, 1] and more.
    const glm::dvec3 g(0.11 + 0.01 * (seed % 5), -0.07, 0.05);
    const double s0 = -0.1 + 0.01 * (seed % 7);
    const std::vector<double> data =
      Grid(dims, [&](int i, int j, int k) { return s0 + g.x * i + g.y * (j - 6) + g.z * k; });
    const Volume volume(data.data(), dims);
    const auto ptf = Prepare(family.TF, ReferenceTolerance);
    for (int i = 0; i < 20; ++i)
    {
      const adversarial::Ray ray = RandomRay(dims, rng);
      const double start = s0 + g.x * ray.Origin.x + g.y * (ray.Origin.y - 6) + g.z * ray.Origin.z;
      const double slope = glm::dot(g, ray.Direction);
      if (slope != 0.0 && std::abs(slope) < 1e-3)
      {
        continue; // the oracle's own accuracy needs |dtau/dt| = 0 or >= 1e-3
      }
      const glm::dvec4 exact = oracles::LinearField(family.TF, start, slope, ray.Length);
      const auto r = an::IntegratePiecewise(
        volume, ray.Origin, ray.Direction, ray.Length, ptf, ReferenceTolerance, false);
      ASSERT_EQ(r.Error, "");
      for (int c = 0; c < 4; ++c)
      {
        EXPECT_NEAR(r.RGBA[c], exact[c], 1e-9)
          << "seed " << seed << " ray " << i << " channel " << c;
      }
    }
  }
}

// Trilinear (cubic along the ray) fields against the adaptive reference of
// RayIntegrators.h, whose error is below 1e-6.
TEST(Piecewise, ReferenceAgreesWithAdaptiveReference)
{
  const int dims[3] = { 6, 6, 6 };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  for (unsigned seed = 0; seed < 40; ++seed)
  {
    const std::vector<double> data = Grid(dims, [&](int, int, int) { return u(rng); });
    const Volume volume(data.data(), dims);
    const randomrays::Ray<double> family = randomrays::Make<double>(seed);
    const auto ptf = Prepare(family.TF, ReferenceTolerance);
    for (int i = 0; i < 10; ++i)
    {
      const adversarial::Ray ray = RandomRay(dims, rng);
      const an::RayField<double, Volume> field{ volume, ray.Origin, ray.Direction };
      const auto expected = an::IntegrateReference(field, family.TF, ray.Length);
      const auto r = an::IntegratePiecewise(
        volume, ray.Origin, ray.Direction, ray.Length, ptf, ReferenceTolerance);
      ASSERT_EQ(r.Error, "");
      for (int c = 0; c < 4; ++c)
      {
        worst = std::max(worst, std::abs(r.RGBA[c] - expected.RGBA[c]));
      }
    }
  }
  EXPECT_LT(worst, 2e-6);
}

// VTK's alpha model: extinction -ln(1 - alpha) approximated within eps / 8
// (relative); the whole ray within eps of the adaptive reference.
TEST(Piecewise, AlphaModelHoldsTolerance)
{
  const int dims[3] = { 8, 8, 8 };
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::vector<double> data = Grid(dims, [&](int, int, int) { return 255.0 * u(rng); });
  const Volume volume(data.data(), dims);
  const an::TransferFunction<double> tf = RampToOpaque();
  for (double eps : { 1e-2, 1e-3, 1e-4 })
  {
    const auto ptf = Prepare(tf, eps);
    double worst = 0.0;
    for (int i = 0; i < 200; ++i)
    {
      const adversarial::Ray ray = RandomRay(dims, rng);
      const an::RayField<double, Volume> field{ volume, ray.Origin, ray.Direction };
      const auto expected = an::IntegrateReference(field, tf, ray.Length);
      const auto r =
        an::IntegratePiecewise(volume, ray.Origin, ray.Direction, ray.Length, ptf, eps);
      for (int c = 0; c < 4; ++c)
      {
        worst = std::max(worst, std::abs(r.RGBA[c] - expected.RGBA[c]));
      }
    }
    EXPECT_LT(worst, eps) << "eps " << eps;
  }
}

// The reference in VTK's alpha model against its closed form: a ramp
// s = 20 t along x through alpha rising linearly in s from 0 at 0 to 0.9 at
// 255 (unit distance 1.5), a constant colour. With u = 1 - alpha(s(t)) =
// 1 - b t, tau = -ln(u) / 1.5 and, as d/dt (u ln u - u) = -b ln u, the depth
// over [0, D] is (u ln u - u + 1) / (1.5 b) at u = u(D); the colour is
// c (1 - e^{-depth}). Within 1e-9 (the reference's 1e-10), where the
// adaptive Simpson reference (1e-6) is no proof.
TEST(Piecewise, AlphaModelReferenceIsExact)
{
  const int dims[3] = { 13, 3, 3 };
  const std::vector<double> data = Grid(dims, [](int i, int, int) { return 20.0 * i; });
  const Volume volume(data.data(), dims);
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(255.0, 0.9);
  tf.AddColorKnot(0.0, 0.3, 0.6, 0.9);
  tf.SetOpacityModel(an::OpacityModel::Alpha, 1.5);
  tf.Finalize();
  const double eps = ReferenceTolerance;
  const auto ptf = Prepare(tf, eps);
  for (const double D : { 2.5, 7.0, 12.0 })
  {
    const double b = 0.9 * 20.0 / 255.0, u = 1.0 - b * D;
    const double depth = (u * std::log(u) - u + 1.0) / (1.5 * b);
    const double alpha = -std::expm1(-depth);
    const auto r = an::IntegratePiecewise(volume, glm::dvec3(0.0, 1.0, 1.0),
      glm::dvec3(1.0, 0.0, 0.0), D, ptf, eps, false);
    ASSERT_EQ(r.Error, "");
    EXPECT_NEAR(r.RGBA.a, alpha, 1e-9) << "D " << D;
    EXPECT_NEAR(r.RGBA.r, 0.3 * alpha, 1e-9) << "D " << D;
    EXPECT_NEAR(r.RGBA.b, 0.9 * alpha, 1e-9) << "D " << D;
  }
}

// The alpha model's extinction, cubic between the extra knots, is
// within the relative error r of -ln(1 - alpha) / d below the flat depth
// (Pieces.h), sampled densely on every piece, for several r.
TEST(Piecewise, AlphaExtinctionWithinRelativeError)
{
  const an::TransferFunction<double> tf = RampToOpaque();
  const double flat = an::PiecewiseTransferFunction<double>::FlatDepth / 2.0;
  for (double r : { 1.25e-3, 1.25e-4, 1.25e-5 })
  {
    an::PiecewiseTransferFunction<double> ptf;
    ASSERT_EQ(ptf.Build(tf, r), "");
    const std::vector<double>& knots = ptf.GetKnots();
    double worst = 0.0;
    long samples = 0;
    for (std::size_t i = 1; i < knots.size(); ++i)
    {
      const auto& piece = ptf[i];
      for (int k = 0; k <= 64; ++k)
      {
        const double s = knots[i - 1] + (knots[i] - knots[i - 1]) * k / 64.0;
        double alpha = 0.0;
        for (const auto& p : tf.GetPieces())
        {
          if (s >= p.Start && (s <= p.Start + p.Length || p.Length == 0.0))
          {
            alpha = p.Opacity + p.OpacitySlope * (s - p.Start);
          }
        }
        const double exact = tf.ToExtinction(alpha);
        // Skipped: opaque, the chord up to it, transparent (exact), and
        // alpha within 1e-9 of 1, where the knots are as close as double
        // resolves s (alpha there is known only to |alpha'| ulp(s)).
        if (!(alpha < 1.0 - 1e-9) || exact >= flat || exact == 0.0)
        {
          continue;
        }
        const double d = s - piece.Start;
        const double tau =
          piece.Tau + d * (piece.TauSlope + d * (piece.TauCurvature + d * piece.TauCubic));
        worst = std::max(worst, std::abs(tau - exact) / exact);
        ++samples;
      }
    }
    EXPECT_GT(samples, 1000);
    EXPECT_LE(worst, r * (1.0 + 1e-9)) << "r " << r;
    // Nor needlessly short: each cut is the longest the bound allows, and
    // the bound is within a factor of 4 of the error it bounds (0.29 to
    // 0.64 of r here).
    EXPECT_GT(worst, r / 4.0) << "r " << r;
  }
}

// Opacities above 1 in VTK's alpha model are opaque: a ramp from 0 to 20 is
// opaque (tau = 40 per unit) from alpha = 1 on, and so are its pieces. (The
// last cut once ran from alpha = 1 - e^-36 to 20 as one chord, 10 % below
// the opaque value over most of the ramp: rays through it off by 1e-3 to
// 2e-3 at every tolerance.)
TEST(Piecewise, AlphaOpacitiesAboveOneAreOpaque)
{
  an::TransferFunction<double> tf;
  tf.SetOpacityModel(an::OpacityModel::Alpha, 1.0);
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(1.0, 20.0);
  tf.AddColorKnot(0.0, 1.0, 1.0, 1.0);
  tf.Finalize();
  an::PiecewiseTransferFunction<double> ptf;
  ASSERT_EQ(ptf.Build(tf, 1e-4), "");
  const double opaque = tf.ToExtinction(1.0);
  double worst = 0.0;
  for (int k = 0; k <= 1000; ++k)
  {
    const double s = 0.05 + 0.95 * k / 1000.0; // alpha = 20 s >= 1
    const auto& piece = ptf[ptf.Locate(s)];
    const double d = s - piece.Start;
    const double tau =
      piece.Tau + d * (piece.TauSlope + d * (piece.TauCurvature + d * piece.TauCubic));
    worst = std::max(worst, std::abs(tau - opaque) / opaque);
  }
  EXPECT_LE(worst, 1e-12);
}

// The series of the colour integral J on a piece whose depth is one term of
// degree 10: q(v) = v^3, tau = 10 q^3, theta(v) = v^10 on [0, 1] (A = 1, so
// the sub-interval is not halved for A). Its series has terms only at every
// tenth power: 40 terms leave a tail of about 1 / 5!, far above the share,
// and such a sub-interval must be halved, not accepted after 40 terms (as it
// was: J off by 4e-4).
TEST(Piecewise, SeriesSettlesHighDegreeDepths)
{
  const an::Cubic<double> q{ { 0.0, 0.0, 0.0, 1.0 } };
  const an::detail::PieceDepth<double> depth(q, 0.0, 0.0, 0.0, 10.0);
  ASSERT_EQ(depth.Degree, 10);
  an::RayStatistics<double> stats;
  const double J = an::detail::SeriesIntegral(
    depth, q, 1.0, std::exp(-1.0), [](double, double, double) { return 1e-14; }, stats);
  // int_0^1 3 v^2 e^{-v^10} dv = int_0^1 e^{-u^(10/3)} du (u = v^3), by
  // 8-point Gauss-Legendre on 400 panels (smooth: exact to rounding).
  using G = an::detail::GaussLegendre<double>;
  double exact = 0.0;
  for (int i = 0; i < 400; ++i)
  {
    exact += an::detail::Quadrature(G::N8, G::W8, i / 400.0, (i + 1) / 400.0,
      [](double v) { return 3.0 * v * v * std::exp(-std::pow(v, 10.0)); });
  }
  EXPECT_NEAR(J, exact, 1e-12);
  EXPECT_GT(stats.Rejected, 0); // it was halved
}

// Knots inside transparent ranges bound nothing that is integrated:
// PieceWalk seeks no crossing between two transparent pieces, and must still
// find the one where a transparent piece meets a visible one. A transfer
// function with a comb of such knots gives the same pieces and the same rays
// as the one without them (rounding apart).
TEST(Piecewise, TransparentKnotsChangeNothing)
{
  const int dims[3] = { 8, 8, 8 };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::vector<double> data = Grid(dims, [&](int, int, int) { return 255.0 * u(rng); });
  const Volume volume(data.data(), dims);
  auto make = [](bool comb)
  {
    // Knots are added in order: the comb's where the opacity is zero.
    std::map<double, double> opacity{ { 0.0, 0.0 }, { 100.0, 0.0 }, { 140.0, 0.8 }, { 180.0, 0.2 },
      { 200.0, 0.0 }, { 255.0, 0.0 } };
    std::map<double, double> red{ { 0.0, 1.0 }, { 100.0, 0.6 }, { 200.0, 0.2 }, { 255.0, 0.0 } };
    for (double s = 5.0; comb && s < 250.0; s += 5.0)
    {
      if (s < 95.0 || s > 200.0)
      {
        opacity[s] = 0.0;
        red[s + 2.5] = std::fmod(0.37 * s, 1.0); // a colour under zero opacity
      }
    }
    an::TransferFunction<double> tf;
    for (const auto& k : opacity)
    {
      tf.AddOpacityKnot(k.first, k.second);
    }
    for (const auto& k : red)
    {
      tf.AddColorKnot(k.first, k.second, 0.5, 0.5);
    }
    tf.Finalize();
    return tf;
  };
  const an::TransferFunction<double> combed = make(true);
  const auto plain = Prepare(make(false), ReferenceTolerance);
  const auto comb = Prepare(combed, ReferenceTolerance);
  ASSERT_GT(comb.GetKnots().size(), plain.GetKnots().size() + 50);
  double worst = 0.0, worstReference = 0.0;
  for (int i = 0; i < 400; ++i)
  {
    const adversarial::Ray ray = RandomRay(dims, rng);
    const an::RayField<double, Volume> field{ volume, ray.Origin, ray.Direction };
    const auto expected = an::IntegrateReference(field, combed, ray.Length);
    const auto a = an::IntegratePiecewise(
      volume, ray.Origin, ray.Direction, ray.Length, plain, ReferenceTolerance);
    const auto b = an::IntegratePiecewise(
      volume, ray.Origin, ray.Direction, ray.Length, comb, ReferenceTolerance);
    ASSERT_EQ(a.Error, "");
    ASSERT_EQ(b.Error, "");
    EXPECT_EQ(a.Statistics.Pieces, b.Statistics.Pieces) << "ray " << i;
    for (int c = 0; c < 4; ++c)
    {
      worst = std::max(worst, std::abs(a.RGBA[c] - b.RGBA[c]));
      worstReference = std::max(worstReference, std::abs(b.RGBA[c] - expected.RGBA[c]));
    }
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worstReference, 2e-6); // as in ReferenceAgreesWithAdaptiveReference
}

// A knot crossing (detail::Crossing) equals the root bisection finds on the
// sign of s - value, on the monotone stretches of random cells of 8-bit
// data, and stays within the bracket near a triple root (s' = 0 there, where
// Newton's step fails and bisection takes over).
TEST(Piecewise, CrossingEqualsBisection)
{
  auto bisect = [](const an::Cubic<double>& s, double value, double lo, double hi)
  {
    const double sign = s(hi) >= s(lo) ? 1.0 : -1.0;
    for (int i = 0; i < 200 && lo < hi; ++i)
    {
      const double m = 0.5 * (lo + hi);
      if (m == lo || m == hi)
      {
        break;
      }
      (sign * (s(m) - value) < 0.0 ? lo : hi) = m;
    }
    return 0.5 * (lo + hi);
  };
  std::mt19937 rng(6);
  std::uniform_int_distribution<int> corner(0, 255);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  long crossings = 0;
  double worst = 0.0;
  for (int n = 0; n < 2000; ++n)
  {
    double c[8];
    for (double& v : c)
    {
      v = corner(rng);
    }
    const glm::dvec3 d = glm::normalize(glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
    const an::Cubic<double> s = an::CellCubic(c, glm::dvec3(u(rng), u(rng), u(rng)), d);
    double roots[2];
    const int r = an::detail::QuadraticRoots(3.0 * s.K[3], 2.0 * s.K[2], s.K[1], 1.0, roots);
    std::vector<double> bounds{ 0.0 };
    bounds.insert(bounds.end(), roots, roots + r);
    bounds.push_back(1.0);
    for (std::size_t b = 0; b + 1 < bounds.size(); ++b)
    {
      const double lo = bounds[b], hi = bounds[b + 1];
      const double a = s(lo), z = s(hi);
      for (double value = std::floor(std::min(a, z)) + 1.0; value < std::max(a, z); value += 1.0)
      {
        const double x = an::detail::Crossing(s, value, lo, hi);
        ASSERT_GE(x, lo);
        ASSERT_LE(x, hi);
        worst = std::max(worst, std::abs(x - bisect(s, value, lo, hi)));
        ++crossings;
      }
    }
  }
  EXPECT_GT(crossings, 10000);
  EXPECT_LT(worst, 1e-13);
  // (u - 0.3)^3: a triple root, conditioned to about the cube root of the
  // rounding of its coefficients.
  const an::Cubic<double> triple{ { -0.027, 0.27, -0.9, 1.0 } };
  const double x = an::detail::Crossing(triple, 0.0, 0.0, 1.0);
  EXPECT_NEAR(x, 0.3, 1e-5);
}

// detail::Extrema's shortcut (no roots sought where |K1| dominates the
// rest of s') only where s' keeps its sign: checked in long double at 2,001
// points of [0, l] on cell cubics of random corners, directions and lengths
// (scaled from 1e-6 to 1e6); there QuadraticRoots finds no root either, so
// the cut is the same.
TEST(Piecewise, ExtremaShortcutOnlyWhereMonotone)
{
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> corner(0, 255);
  long shortcuts = 0, searched = 0;
  for (int n = 0; n < 20000; ++n)
  {
    double c[8];
    const double scale = std::pow(10.0, 12.0 * u(rng) - 6.0);
    for (double& v : c)
    {
      v = scale * corner(rng);
    }
    const glm::dvec3 d = glm::normalize(glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
    const an::Cubic<double> s = an::CellCubic(c, glm::dvec3(u(rng), u(rng), u(rng)), d);
    const double length = 1.7 * u(rng);
    double extrema[2], roots[2];
    const int r = an::detail::Extrema(s, length, extrema);
    const int q = an::detail::QuadraticRoots(3.0 * s.K[3], 2.0 * s.K[2], s.K[1], length, roots);
    const double rest = 2.0 * std::abs(s.K[2]) * length + 3.0 * std::abs(s.K[3]) * length * length;
    if (std::abs(s.K[1]) <= 2.0 * rest)
    {
      ++searched;
      ASSERT_EQ(r, q);
      for (int i = 0; i < r; ++i)
      {
        ASSERT_EQ(extrema[i], roots[i]);
      }
      continue;
    }
    ++shortcuts;
    ASSERT_EQ(r, 0);
    ASSERT_EQ(q, 0) << "QuadraticRoots finds a root the shortcut skips";
    for (int i = 0; i <= 2000; ++i)
    {
      const long double x = static_cast<long double>(length) * i / 2000;
      const long double ds =
        static_cast<long double>(s.K[1]) + x * (2.0L * s.K[2] + x * 3.0L * s.K[3]);
      ASSERT_GT(ds * s.K[1], 0.0L) << "s' changes sign at u = " << static_cast<double>(x);
    }
  }
  // Both paths are exercised (4,561 shortcuts of 20,000 here: random
  // corners make rougher cells than data do).
  EXPECT_GT(shortcuts, 2000);
  EXPECT_GT(searched, 2000);
}

// The suite of AdversarialCases.h on 2,000 rays per case: the piecewise
// method keeps >= 99.9 % of rays within eps in every channel and its largest
// error within 2 eps, at every eps; the paper's coupled rule does not (the
// suite is adversarial: a thin layer hides between its samples).
TEST(Piecewise, AdversarialSuite)
{
  bool coupledFailed = false;
  for (const adversarial::Case& c : adversarial::MakeSuite())
  {
    const std::vector<glm::dvec4> reference = adversarial::References(c, 2000);
    for (double eps : { 1e-2, 1e-3, 1e-4 })
    {
      const adversarial::Tally t =
        adversarial::Measure(c, reference, adversarial::Method::Piecewise, eps);
      EXPECT_EQ(t.Failures, 0);
      EXPECT_GE(t.WorstPercent(), 99.9) << c.Name << ", eps " << eps;
      EXPECT_LE(t.WorstMaximum(), 2.0 * eps) << c.Name << ", eps " << eps;
    }
    const adversarial::Tally coupled =
      adversarial::Measure(c, reference, adversarial::Method::Coupled, 1e-3);
    coupledFailed = coupledFailed || coupled.WorstMaximum() > 10.0 * 1e-3;
  }
  EXPECT_TRUE(coupledFailed);
}

// Termination on adversarial input: a checkerboard (the cubic oscillates in
// every cell), 4,096 knots, extinction 50; every result finite, in [0, 1],
// and within the stated bound on pieces (3 (m + 1) per cell crossed).
TEST(Piecewise, TerminatesOnAdversarialInput)
{
  const int dims[3] = { 24, 24, 24 };
  const std::vector<double> data =
    Grid(dims, [](int i, int j, int k) { return ((i + j + k) % 2) ? 255.0 : 0.0; });
  const Volume volume(data.data(), dims);
  const an::TransferFunction<double> tf = adversarial::Random(17, 4096, 50.0);
  const auto ptf = Prepare(tf, 1e-3);
  const double m = static_cast<double>(ptf.GetKnots().size());
  std::mt19937 rng(5);
  for (int i = 0; i < 300; ++i)
  {
    const adversarial::Ray ray = RandomRay(dims, rng);
    const auto r = an::IntegratePiecewise(volume, ray.Origin, ray.Direction, ray.Length, ptf, 1e-3);
    ASSERT_TRUE(Usable(r));
    EXPECT_LE(r.Statistics.Cells, 3 * 23 + 3);
    EXPECT_LE(static_cast<double>(r.Statistics.Pieces), 3.0 * (m + 1.0) * r.Statistics.Cells);
  }
}

// NaN and infinite scalars: cells with a non-finite corner are transparent;
// the rest of the ray is integrated; no NaN leaves the integrator.
TEST(Piecewise, NonFiniteScalars)
{
  const int dims[3] = { 6, 6, 6 };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> data = Grid(dims,
    [&](int i, int j, int k)
    {
      const int n = (i * 7 + j * 3 + k) % 27;
      return n == 0 ? nan : (n == 1 ? inf : (n == 2 ? -inf : 0.03 * n));
    });
  const Volume volume(data.data(), dims);
  const auto ptf = Prepare(randomrays::Make<double>(1).TF, 1e-3);
  std::mt19937 rng(6);
  double opacity = 0.0;
  for (int i = 0; i < 200; ++i)
  {
    const adversarial::Ray ray = RandomRay(dims, rng);
    const auto r = an::IntegratePiecewise(volume, ray.Origin, ray.Direction, ray.Length, ptf, 1e-3);
    ASSERT_TRUE(Usable(r));
    opacity = std::max(opacity, r.RGBA.a);
  }
  EXPECT_GT(opacity, 0.0) << "the finite cells are integrated";
}

TEST(Piecewise, BadInput)
{
  const int dims[3] = { 3, 3, 3 };
  const std::vector<double> data(27, 0.5);
  const Volume volume(data.data(), dims);
  const auto ptf = Prepare(randomrays::Make<double>(0).TF, 1e-3);
  const glm::dvec3 o(0.0, 1.0, 1.0), d(1.0, 0.0, 0.0);
  for (double eps : { 0.0, -1.0, 2.0, 1e-13, std::numeric_limits<double>::quiet_NaN() })
  {
    EXPECT_NE(an::IntegratePiecewise(volume, o, d, 2.0, ptf, eps).Error, "") << eps;
  }
  EXPECT_NE(
    an::IntegratePiecewise(volume, o, d, std::numeric_limits<double>::infinity(), ptf, 1e-3).Error,
    "");
  EXPECT_NE(an::IntegratePiecewise(volume, glm::dvec3(std::nan("")), d, 2.0, ptf, 1e-3).Error, "");
  const an::PiecewiseTransferFunction<double> unbuilt;
  EXPECT_NE(an::IntegratePiecewise(volume, o, d, 2.0, unbuilt, 1e-3).Error, "");
  const int flat[3] = { 3, 1, 3 };
  const Volume degenerate(data.data(), flat);
  EXPECT_NE(an::IntegratePiecewise(degenerate, o, d, 2.0, ptf, 1e-3).Error, "");

  an::PiecewiseTransferFunction<double> p;
  an::TransferFunction<double> empty;
  EXPECT_NE(p.Build(empty, 1e-3), "");
  an::TransferFunction<double> alpha = randomrays::Make<double>(0).TF;
  alpha.SetOpacityModel(an::OpacityModel::Alpha, 1.0);
  alpha.Finalize();
  EXPECT_NE(p.Build(alpha, 1e-13), ""); // below the alpha model's floor
  EXPECT_EQ(p.Build(alpha, 1e-4), "");
}

// ClassifyRange answers what its definition says, through its integer
// tables (integral knots, integral and other range ends, zero opacity pieces,
// jumps, the alpha model's extra knots) and without them (a span over 2^16
// units, knots beyond 2^52): the piece of lo, a knot strictly inside (lo, hi),
// a visible piece between those of lo and hi.
TEST(Piecewise, ClassifyRangeEqualsItsDefinition)
{
  std::vector<an::TransferFunction<double>> tfs;
  for (unsigned seed = 0; seed < 12; ++seed)
  {
    tfs.push_back(adversarial::Random(seed, 3 + 20 * (seed % 3), 2.0, 255.0, seed % 2 == 0));
    if (seed % 4 == 1)
    {
      tfs.back().SetOpacityModel(an::OpacityModel::Alpha, 1.0);
      tfs.back().Finalize();
    }
  }
  tfs.push_back(adversarial::Random(3, 10, 2.0, 1e6, true));
  an::TransferFunction<double> far;
  far.AddOpacityKnot(1e17, 0.0);
  far.AddOpacityKnot(1e17 + 64.0, 1.0);
  far.AddColorKnot(1e17, 1.0, 1.0, 1.0);
  far.Finalize();
  tfs.push_back(far);
  for (const auto& tf : tfs)
  {
    an::PiecewiseTransferFunction<double> p;
    ASSERT_EQ(p.Build(tf, 1e-3), "");
    const std::vector<double>& knots = p.GetKnots();
    std::vector<double> ends{ knots.front() - 1.0, knots.back() + 1.0 };
    for (double k : knots)
    {
      ends.insert(
        ends.end(), { k, std::floor(k), std::ceil(k), k + 0.5, std::nextafter(k, 1e300) });
    }
    for (std::size_t i = 0; i < ends.size(); ++i)
    {
      for (std::size_t j = i; j < ends.size(); j += 1 + ends.size() / 97)
      {
        const double lo = std::min(ends[i], ends[j]), hi = std::max(ends[i], ends[j]);
        const auto c = p.ClassifyRange(lo, hi);
        const std::size_t first = p.Locate(lo), last = p.Locate(hi);
        bool visible = false;
        for (std::size_t k = first; k <= last; ++k)
        {
          visible = visible || p.IsVisible(k);
        }
        ASSERT_EQ(c.First, first) << lo << " " << hi;
        ASSERT_EQ(c.Crossings, p.CountBelow(hi) > first) << lo << " " << hi;
        ASSERT_EQ(c.Visible, visible) << lo << " " << hi;
      }
    }
  }
}

// NextVisible and PreviousVisibleEnd (PieceWalk passes transparent runs
// with them) answer what IsVisible says, at every piece, on functions whose
// knots are transparent with probability 0.6 (runs of them, some at the
// ends), in both opacity models.
TEST(Piecewise, VisibleNeighboursEqualTheirDefinition)
{
  for (unsigned seed = 0; seed < 16; ++seed)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    an::TransferFunction<double> tf;
    for (int k = 0; k < 40; ++k)
    {
      const double s = 6.0 * k + 3.0 * u(rng);
      tf.AddOpacityKnot(s, u(rng) < 0.6 ? 0.0 : u(rng));
      tf.AddColorKnot(s, u(rng), u(rng), u(rng));
    }
    if (seed % 2 == 1)
    {
      tf.SetOpacityModel(an::OpacityModel::Alpha, 1.0);
    }
    tf.Finalize();
    an::PiecewiseTransferFunction<double> p;
    ASSERT_EQ(p.Build(tf, 1e-3), "");
    const std::size_t n = p.GetNumberOfPieces();
    std::size_t transparent = 0;
    for (std::size_t i = 0; i <= n; ++i)
    {
      std::size_t next = i;
      while (next < n && !p.IsVisible(next))
      {
        ++next;
      }
      ASSERT_EQ(p.NextVisible(i), next) << "seed " << seed << " piece " << i;
      if (i < n)
      {
        std::size_t end = i + 1;
        while (end > 0 && !p.IsVisible(end - 1))
        {
          --end;
        }
        ASSERT_EQ(p.PreviousVisibleEnd(i), end) << "seed " << seed << " piece " << i;
        transparent += p.IsVisible(i) ? 0 : 1;
      }
    }
    EXPECT_GE(transparent, 5u) << "seed " << seed;
  }
}

// Locate's bucket grid answers exactly what std::upper_bound does, and
// CountBelow what std::lower_bound does, on knots with clusters and jumps,
// at the knots themselves and next to them.
TEST(Piecewise, LocateEqualsBinarySearch)
{
  for (unsigned seed = 0; seed < 20; ++seed)
  {
    const an::TransferFunction<double> tf = adversarial::Random(seed, 4 + 50 * (seed % 4), 2.0);
    an::PiecewiseTransferFunction<double> p;
    ASSERT_EQ(p.Build(tf, 1e-3), "");
    const std::vector<double>& knots = p.GetKnots();
    std::vector<double> probes{ -1.0, 300.0 };
    for (double k : knots)
    {
      probes.insert(
        probes.end(), { k, std::nextafter(k, -1e9), std::nextafter(k, 1e9), k + 1e-3, k - 1e-3 });
    }
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-5.0, 260.0);
    for (int i = 0; i < 1000; ++i)
    {
      probes.push_back(u(rng));
    }
    for (double s : probes)
    {
      ASSERT_EQ(p.Locate(s),
        static_cast<std::size_t>(std::upper_bound(knots.begin(), knots.end(), s) - knots.begin()))
        << s;
      ASSERT_EQ(p.CountBelow(s),
        static_cast<std::size_t>(std::lower_bound(knots.begin(), knots.end(), s) - knots.begin()))
        << s;
      // LocateNear: the same answer from any guess, right or wrong.
      for (std::size_t guess : { std::size_t(0), p.Locate(s), p.Locate(s) + 1, knots.size(),
             knots.size() + 1, knots.size() / 2 })
      {
        ASSERT_EQ(p.LocateNear(s, guess), p.Locate(s)) << s << " " << guess;
      }
    }
    for (std::size_t guess = 0; guess <= knots.size() + 1; ++guess)
    {
      ASSERT_EQ(p.LocateNear(std::nan(""), guess), p.Locate(std::nan(""))) << guess;
    }
  }
}

// CellWalker::Fill (branch-free steps, in batches that resume) visits Next's
// cells with Next's bounds, to the bit: rays from inside and outside the
// box, with zero direction components, through grid points and edges (ties
// between axes), and batch limits from 1 to the batch's capacity.
TEST(Piecewise, CellWalkerFillEqualsNext)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> position(-1.0, 12.0), component(-1.0, 1.0),
    span(0.0, 40.0);
  std::uniform_int_distribution<int> limits(1, an::CellBatch<double>::Capacity), pick(0, 5);
  long cells = 0;
  for (int r = 0; r < 20000; ++r)
  {
    const int dims[3] = { 2 + r % 31, 2 + (r / 31) % 5, 2 + (r / 155) % 17 };
    glm::dvec3 origin(position(rng), position(rng), position(rng));
    glm::dvec3 direction(component(rng), component(rng), component(rng));
    switch (pick(rng))
    {
      case 0: // through grid points: ties between all three axes
        origin = glm::floor(origin);
        direction = glm::dvec3(1.0, -1.0, 1.0) * std::abs(direction.x);
        break;
      case 1: // along an edge: ties between two axes, one component zero
        origin = glm::dvec3(std::floor(origin.x), std::floor(origin.y), origin.z);
        direction = glm::dvec3(direction.x, direction.x, 0.0);
        break;
      case 2: // along an axis
        direction = glm::dvec3(0.0, 0.0, direction.z);
        break;
      default:
        break;
    }
    const double tBegin = -0.5 * span(rng), tEnd = span(rng);
    an::CellWalker<double> next(dims, origin, direction, tBegin, tEnd);
    an::CellWalker<double> fill = next;
    std::vector<std::array<double, 5>> expected, found;
    int cell[3] = { 0, 0, 0 };
    double t0 = 0.0, t1 = 0.0;
    while (next.Next(cell, t0, t1))
    {
      expected.push_back({ double(cell[0]), double(cell[1]), double(cell[2]), t0, t1 });
    }
    an::CellBatch<double> batch;
    for (;;)
    {
      batch.Count = 0;
      if (fill.Fill(batch, limits(rng)) == 0)
      {
        break;
      }
      for (int c = 0; c < batch.Count; ++c)
      {
        found.push_back({ double(batch.Index[0][c]), double(batch.Index[1][c]),
          double(batch.Index[2][c]), batch.Begin[c], batch.End[c] });
      }
    }
    ASSERT_EQ(found, expected) << "ray " << r;
    cells += static_cast<long>(found.size());
  }
  EXPECT_GT(cells, 4 * 20000); // the rays do cross the boxes
}
