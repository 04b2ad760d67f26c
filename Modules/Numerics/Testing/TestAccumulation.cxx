// The additive and average projections (Accumulation.h) against a brute-force
// oracle: composite Simpson with 2e-4-voxel steps on the exact integrand
// (the trilinear field and the transfer function evaluated at every sample),
// whose error at the kinks (cell faces, knot crossings) is below 1e-7 here.
// Additive must match it to 1e-7 in the extinction model (the method is exact)
// and within the pieces' relative error in VTK's alpha model; the average
// within its tolerance, and its length in the range exactly.
#include "avos/numerics/Accumulation.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace avos::numerics;

namespace
{
constexpr int N[3] = { 7, 6, 5 };

struct Scene
{
  std::vector<double> Data;
  TransferFunction<double> TF;
  double Min = 0.0, Max = 0.0;

  explicit Scene(unsigned seed, bool alpha)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 100.0);
    this->Data.resize(N[0] * N[1] * N[2]);
    for (double& v : this->Data)
    {
      v = u(rng);
    }
    this->Min = *std::min_element(this->Data.begin(), this->Data.end());
    this->Max = *std::max_element(this->Data.begin(), this->Data.end());
    const double knots[][5] = { { 10, 0.2, 0.3, 0.9, 0.0 }, { 30, 0.9, 0.6, 0.1, 0.3 },
      { 55, 0.1, 0.9, 0.3, 0.05 }, { 70, 1.0, 0.2, 0.2, 0.6 }, { 90, 0.9, 0.9, 0.9, 0.1 } };
    for (const auto& k : knots)
    {
      this->TF.AddColorKnot(k[0], k[1], k[2], k[3]);
      this->TF.AddOpacityKnot(k[0], alpha ? std::min(k[4], 0.9) : k[4]);
    }
    if (alpha)
    {
      this->TF.SetOpacityModel(OpacityModel::Alpha, 0.8);
    }
    this->TF.Finalize();
  }
};

// Composite Simpson of f over [0, D].
template <typename F>
double Simpson(double D, F&& f)
{
  const int n = 2 * static_cast<int>(std::ceil(D / 4e-4));
  const double h = D / n;
  double sum = f(0.0) + f(D);
  for (int i = 1; i < n; ++i)
  {
    sum += (i % 2 ? 4.0 : 2.0) * f(i * h);
  }
  return sum * h / 3.0;
}

struct Ray
{
  glm::dvec3 Origin, Direction;
  double D;
};

Ray RandomRay(std::mt19937& rng)
{
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (;;)
  {
    glm::dvec3 a, b;
    for (int c = 0; c < 3; ++c)
    {
      a[c] = u(rng) * (N[c] - 1);
      b[c] = u(rng) * (N[c] - 1);
    }
    if (glm::length(b - a) > 2.0)
    {
      return { a, glm::normalize(b - a), glm::length(b - a) };
    }
  }
}
} // namespace

// Every Gauss-Legendre rule integrates the monomials up to its degree
// 2 N - 1 exactly on [0, 1] (a wrong digit in a weight or node fails: the
// 8-point rule had one, 5e-8 off, found by Piecewise.SeriesSettlesHighDegreeDepths).
TEST(Accumulation, GaussLegendreRulesAreExact)
{
  using G = detail::GaussLegendre<double>;
  for (int k = 0; k <= 15; ++k)
  {
    auto monomial = [k](double v) { return std::pow(v, k); };
    const double exact = 1.0 / (k + 1);
    if (k <= 7)
    {
      EXPECT_NEAR(detail::Quadrature(G::N4, G::W4, 0.0, 1.0, monomial), exact, 1e-15) << k;
    }
    if (k <= 13)
    {
      EXPECT_NEAR(detail::Quadrature(G::N7, G::W7, 0.0, 1.0, monomial), exact, 1e-15) << k;
    }
    EXPECT_NEAR(detail::Quadrature(G::N8, G::W8, 0.0, 1.0, monomial), exact, 1e-15) << k;
  }
}

TEST(Accumulation, AdditiveIsExactOnEveryPiece)
{
  for (bool alpha : { false, true })
  {
    const Scene scene(11, alpha);
    const TrilinearVolume<double, double> volume(scene.Data.data(), N);
    PiecewiseTransferFunction<double> pieces;
    const double r = 1e-6;
    ASSERT_EQ(pieces.Build(scene.TF, r), "");
    std::mt19937 rng(5);
    double worst = 0.0;
    for (int i = 0; i < 40; ++i)
    {
      const Ray ray = RandomRay(rng);
      const Interval<double> all{ 0.0, ray.D };
      const auto a =
        AdditiveAlongRay(volume, ray.Origin, ray.Direction, &all, 1, pieces, scene.Min, scene.Max);
      ASSERT_EQ(a.Error, "");
      const double oracle = Simpson(ray.D,
        [&](double t)
        {
          const double s = volume(ray.Origin + t * ray.Direction);
          double tau;
          glm::dvec3 color;
          scene.TF.Classify(s, tau, color);
          return tau * (s - scene.Min) / (scene.Max - scene.Min);
        });
      worst = std::max(worst, std::abs(a.Value - oracle) / std::max(1.0, oracle));
    }
    // Exact in the extinction model; within r A (plus the oracle's 1e-7) in VTK's.
    EXPECT_LT(worst, (alpha ? r : 0.0) + 1e-7) << (alpha ? "alpha" : "extinction");
  }
}

// One cell, one transfer-function segment: the integrand is a polynomial of
// degree 9 along the ray, smooth, so the oracle is accurate to 1e-13 and the
// five-point rule must match it (four points would not: the test can fail).
TEST(Accumulation, AdditiveIsExactOnAPolynomial)
{
  const int one[3] = { 2, 2, 2 };
  const double corners[8] = { 10, 90, 80, 5, 95, 20, 15, 85 };
  const TrilinearVolume<double, double> volume(corners, one);
  TransferFunction<double> tf;
  tf.AddColorKnot(0.0, 1.0, 1.0, 1.0);
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(100.0, 3.0);
  tf.Finalize();
  PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(tf, 1e-3), "");
  const glm::dvec3 o(0.0, 0.1, 0.05), d = glm::normalize(glm::dvec3(1.0, 0.9, 0.95));
  double t0 = 0.0, t1 = 10.0;
  ASSERT_TRUE(ClipToGrid(o, d, one, t0, t1));
  const Interval<double> all{ t0, t1 };
  const auto a = AdditiveAlongRay(volume, o, d, &all, 1, pieces, 5.0, 95.0);
  ASSERT_EQ(a.Error, "");
  const double oracle = Simpson(t1 - t0,
    [&](double t)
    {
      const double s = volume(o + (t0 + t) * d);
      return 0.03 * s * (s - 5.0) / 90.0;
    });
  EXPECT_NEAR(a.Value, oracle, 1e-12 * oracle);
}

TEST(Accumulation, AverageWithinItsTolerance)
{
  const Scene scene(12, true);
  const TrilinearVolume<double, double> volume(scene.Data.data(), N);
  const double r0 = 25.0, r1 = 75.0, h = 0.5;
  AverageRange<double> range;
  ASSERT_EQ(range.Build(scene.TF, r0, r1), "");
  std::mt19937 rng(6);
  int met = 0;
  for (int i = 0; i < 40; ++i)
  {
    const Ray ray = RandomRay(rng);
    const Interval<double> all{ 0.0, ray.D };
    auto inRange = [&](double t)
    {
      const double s = volume(ray.Origin + t * ray.Direction);
      return s >= r0 && s <= r1;
    };
    const double length = Simpson(ray.D, [&](double t) { return inRange(t) ? 1.0 : 0.0; });
    const double integral = Simpson(ray.D,
      [&](double t)
      {
        const double s = volume(ray.Origin + t * ray.Direction);
        if (!(s >= r0 && s <= r1))
        {
          return 0.0;
        }
        double tau;
        glm::dvec3 color;
        scene.TF.Classify(s, tau, color);
        return -std::expm1(-tau * h) * (s - scene.Min) / (scene.Max - scene.Min);
      });
    for (double tolerance : { 1e-3, 1e-6 })
    {
      const auto m = AverageAlongRay(volume, ray.Origin, ray.Direction, &all, 1, range, scene.TF, h,
        scene.Min, scene.Max, tolerance);
      ASSERT_EQ(m.Error, "");
      // The indicator's Simpson sum errs by a step at each crossing.
      EXPECT_NEAR(m.Length, length, 2e-3);
      if (length > 0.05)
      {
        EXPECT_NEAR(m.Value, integral / length, tolerance + 2e-3 / length);
      }
    }
    met += length > 0.05;
  }
  EXPECT_GT(met, 20) << "most rays meet the range";
}

TEST(Accumulation, BadInput)
{
  const Scene scene(13, false);
  const TrilinearVolume<double, double> volume(scene.Data.data(), N);
  PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(scene.TF, 1e-3), "");
  const Interval<double> all{ 0.0, 2.0 };
  const glm::dvec3 o(1, 1, 1), d(1, 0, 0);
  EXPECT_NE(AdditiveAlongRay(volume, o, d, &all, 1, pieces, 5.0, 5.0).Error, "");
  AverageRange<double> range;
  ASSERT_EQ(range.Build(scene.TF, 20.0, 80.0), "");
  EXPECT_NE(AverageAlongRay(volume, o, d, &all, 1, range, scene.TF, 0.0, 0.0, 1.0, 1e-3).Error, "");
  EXPECT_NE(AverageAlongRay(volume, o, d, &all, 1, range, scene.TF, 0.5, 0.0, 1.0, 0.0).Error, "");
  EXPECT_NE(range.Build(scene.TF, 5.0, 1.0), "");
  EXPECT_NE(range.Build(scene.TF, std::nan(""), 1.0), "");
  // A range of zero width: built, holds no ray.
  ASSERT_EQ(range.Build(scene.TF, 50.0, 50.0), "");
  const auto none = AverageAlongRay(volume, o, d, &all, 1, range, scene.TF, 0.5, 0.0, 100.0, 1e-3);
  EXPECT_EQ(none.Error, "");
  EXPECT_EQ(none.Length, 0.0);
}
