// Gradient opacity in the piecewise method (PiecewiseGradientOpacity.h):
// - against closed forms: a field whose gradient is constant on each cell
//   (G constant per piece: the exact path), and the bilinear field s = x y,
//   whose gradient's length sqrt(y^2 + x^2) along x makes G(|g|) = |g| / M a
//   non-polynomial extinction (the models' path) with a closed-form depth,
//   vanishing where the ray crosses x = y = 0;
// - the extinction's models hold its samples;
// - against the independent oracle of GradientOpacityOracle.h on the
//   adversarial suite's volumes and transfer functions with a G whose knots
//   the rays' gradients cross, unshaded and lit, in both opacity models:
//   every channel of every ray within the tolerance;
// - refusals.
#include "avos/numerics/PiecewiseGradientOpacity.h"

#include "AdversarialCases.h"
#include "GradientOpacityOracle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using namespace avos::numerics;
namespace an = avos::numerics;

namespace
{
using Volume = TrilinearVolume<double, double>;

double MaxError(const glm::dvec4& a, const glm::dvec4& b)
{
  double e = 0.0;
  for (int c = 0; c < 4; ++c)
  {
    e = std::max(e, std::abs(a[c] - b[c]));
  }
  return e;
}

// One colour and extinction `tau` everywhere (extinction model).
TransferFunction<double> Uniform(double tau, const glm::dvec3& colour)
{
  TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, tau);
  tf.AddColorKnot(0.0, colour.r, colour.g, colour.b);
  tf.Finalize();
  return tf;
}

// G from (value, G) knots.
TransferFunction<double> Factor(std::initializer_list<std::pair<double, double>> knots)
{
  TransferFunction<double> g;
  g.AddColorKnot(0.0, 1.0, 1.0, 1.0);
  for (const auto& k : knots)
  {
    g.AddOpacityKnot(k.first, k.second);
  }
  g.Finalize();
  return g;
}

RayResult<double> Integrate(const Volume& volume, const glm::dvec3& origin,
  const glm::dvec3& direction, double D, const PiecewiseTransferFunction<double>& pieces,
  double eps, const GradientOpacity<double>& opacity, const RayShading<double>* shading = nullptr)
{
  const Interval<double> whole{ 0.0, D };
  return IntegratePiecewiseGradientOpacity(
    volume, origin, direction, &whole, 1, pieces, eps, opacity, shading, false);
}
} // namespace

// s = i^2 along x: the gradient is 2 i + 1 on cell i (world = `scale` grid
// units), G constant on each cell, each cell composites in closed form.
TEST(PiecewiseGradientOpacity, ConstantGradientPerCellAgainstItsClosedForm)
{
  const int dims[3] = { 9, 3, 3 };
  std::vector<double> data;
  for (int n = 0; n < dims[0] * dims[1] * dims[2]; ++n)
  {
    data.push_back(double((n % dims[0]) * (n % dims[0])));
  }
  const Volume volume(data.data(), dims);
  const glm::dvec3 colour(1.0, 0.5, 0.0);
  const TransferFunction<double> tf = Uniform(0.3, colour);
  PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(tf, 1e-9), "");
  const TransferFunction<double> g = Factor({ { 2.0, 1.0 }, { 18.0, 0.0 } });
  for (const double scale : { 1.0, 2.0 })
  {
    GradientOpacity<double> opacity;
    opacity.Function = &g;
    opacity.NormalMatrix = glm::dmat3(1.0 / scale);
    glm::dvec3 c(0.0);
    double T = 1.0;
    for (int i = 0; i + 1 < dims[0]; ++i)
    {
      const double factor =
        std::min(std::max(g.GetOpacityValue((2.0 * i + 1.0) / scale), 0.0), 1.0);
      c += T * -std::expm1(-0.3 * factor) * colour;
      T *= std::exp(-0.3 * factor);
    }
    const glm::dvec4 exact(c, 1.0 - T);
    for (const double eps : { 1e-2, 1e-4, 1e-8 })
    {
      const RayResult<double> r = Integrate(volume, glm::dvec3(0.0, 1.0, 1.0),
        glm::dvec3(1.0, 0.0, 0.0), dims[0] - 1.0, pieces, eps, opacity);
      ASSERT_EQ(r.Error, "");
      EXPECT_LE(MaxError(r.RGBA, exact), eps) << "scale " << scale << ", eps " << eps;
    }
  }
}

// s = x y on [-4, 4]^2 x [0, 2] (trilinear reproduces it), a ray along x at
// height y0: |g| = sqrt(y0^2 + x^2), G(m) = m / M for m <= M, tau constant:
// the depth tau / M int sqrt(y0^2 + x^2) dx in closed form, and the colour
// C (1 - e^{-depth}). At y0 = 0 the gradient vanishes at x = 0 (|g| = |x|,
// a kink of the extinction).
TEST(PiecewiseGradientOpacity, BilinearFieldAgainstItsClosedForm)
{
  const int dims[3] = { 9, 9, 3 };
  std::vector<double> data;
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        data.push_back(double(i - 4) * double(j - 4));
      }
    }
  }
  const Volume volume(data.data(), dims);
  const glm::dvec3 colour(0.2, 0.7, 1.0);
  const double tau = 0.9, M = 8.0;
  const TransferFunction<double> tf = Uniform(tau, colour);
  PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(tf, 1e-9), "");
  const TransferFunction<double> g = Factor({ { 0.0, 0.0 }, { M, 1.0 } });
  GradientOpacity<double> opacity;
  opacity.Function = &g;
  // int sqrt(a^2 + x^2) = (x sqrt(a^2 + x^2) + a^2 asinh(x / a)) / 2.
  auto primitive = [](double a, double x)
  {
    const double root = std::sqrt(a * a + x * x);
    return 0.5 * (x * root + (a > 0.0 ? a * a * std::asinh(x / a) : 0.0));
  };
  for (const double y0 : { 0.0, 0.3, 1.7, 3.5 })
  {
    const double depth = tau / M * (primitive(y0, 4.0) - primitive(y0, -4.0));
    const glm::dvec4 exact(-std::expm1(-depth) * colour, -std::expm1(-depth));
    for (const double eps : { 1e-2, 1e-3, 1e-5, 1e-8 })
    {
      RayResult<double> r = Integrate(volume, glm::dvec3(0.0, 4.0 + y0, 1.0),
        glm::dvec3(1.0, 0.0, 0.0), dims[0] - 1.0, pieces, eps, opacity);
      ASSERT_EQ(r.Error, "");
      EXPECT_LE(MaxError(r.RGBA, exact), eps) << "y0 " << y0 << ", eps " << eps;
      std::printf("y0 %.1f eps %g: error %.2e, %ld models for %ld pieces\n", y0, eps,
        MaxError(r.RGBA, exact), r.Statistics.Samples, r.Statistics.Pieces);
    }
  }
}

namespace
{
struct Outcome
{
  double MaximumError = 0.0;
  long Samples = 0;
  long Pieces = 0;
};

const double Tolerances[3] = { 1e-2, 1e-3, 1e-5 };

// Rays of case `c` at each tolerance against the oracle, lit by the sharp
// lighting where `lit`.
void Compare(
  const adversarial::Case& c, OpacityModel model, bool lit, int rays, Outcome (&outcomes)[3])
{
  TransferFunction<double> tf = c.TF;
  tf.SetOpacityModel(model, 1.0);
  tf.Finalize();
  PiecewiseTransferFunction<double> exact, pieces[3];
  EXPECT_EQ(exact.Build(tf, PiecewiseTransferFunction<double>::MinimumRelativeError), "");
  for (int e = 0; e < 3; ++e)
  {
    EXPECT_EQ(pieces[e].Build(tf, PiecewiseRelativeError(Tolerances[e])), "");
  }
  const Volume volume(c.Data.data(), c.Dimensions);
  const TransferFunction<double> g = adversarial::CrossedGradientOpacity(c);
  GradientOpacity<double> opacity;
  opacity.Function = &g;
  const ShadingModel<double> sharp = adversarial::SharpLighting();
  for (int i = 0; i < rays; ++i)
  {
    const adversarial::Ray ray = adversarial::MakeRay(c, static_cast<unsigned>(i));
    const glm::dvec3 toViewer = -ray.Direction;
    const RayShading<double> shading{ &sharp, glm::dmat3(1.0), toViewer, ray.Origin,
      ray.Direction };
    const glm::dvec4 oracle = oracles::GradientOpacityRay(volume, tf, exact, opacity, ray.Origin,
      ray.Direction, ray.Length, lit ? &sharp : nullptr, toViewer);
    for (int e = 0; e < 3; ++e)
    {
      const double eps = Tolerances[e];
      const RayResult<double> r = Integrate(volume, ray.Origin, ray.Direction, ray.Length,
        pieces[e], eps, opacity, lit ? &shading : nullptr);
      EXPECT_EQ(r.Error, "") << c.Name << ", ray " << i;
      const double error = MaxError(r.RGBA, oracle);
      EXPECT_LE(error, eps) << c.Name << ", ray " << i << ", eps " << eps << (lit ? ", lit" : "");
      outcomes[e].MaximumError = std::max(outcomes[e].MaximumError, error);
      outcomes[e].Samples += r.Statistics.Samples;
      outcomes[e].Pieces += r.Statistics.Pieces;
    }
  }
}
} // namespace

TEST(PiecewiseGradientOpacity, AdversarialSuiteWithinTheToleranceOfAnExactOracle)
{
  for (const adversarial::Case& c : adversarial::MakeSuite())
  {
    for (const OpacityModel model : { OpacityModel::Extinction, OpacityModel::Alpha })
    {
      for (const bool lit : { false, true })
      {
        Outcome outcomes[3];
        Compare(c, model, lit, 10, outcomes);
        for (int e = 0; e < 3; ++e)
        {
          const Outcome& o = outcomes[e];
          std::printf("%-32s %-10s %-5s eps %-5g max error %.2e (%.2f eps), %.1f models per "
                      "piece\n",
            c.Name.c_str(), model == OpacityModel::Alpha ? "alpha" : "extinction",
            lit ? "lit" : "unlit", Tolerances[e], o.MaximumError, o.MaximumError / Tolerances[e],
            o.Pieces ? double(o.Samples) / double(o.Pieces) : 0.0);
        }
      }
    }
  }
}

namespace
{
// ExtinctionModel on random sub-intervals of random pieces (a cubic, a
// transfer-function piece with curvature, a gradient's quadratics, some
// vanishing at a point inside, against a G with three knots and a jump)
// holds tau(q(v)) G(|g(v)|) at 64 points of each: |kappa - K| <= R_K.
template <int N>
void CheckExtinctionModels(unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const TransferFunction<double> g =
    Factor({ { 0.0, 0.1 }, { 0.8, 1.0 }, { 1.5, 0.3 }, { 1.5, 0.7 }, { 2.5, 0.0 } });
  int tight = 0;
  const int trials = 400;
  for (int trial = 0; trial < trials; ++trial)
  {
    const Cubic<double> q{ { u(rng), u(rng), 0.5 * u(rng), 0.3 * u(rng) } };
    PiecewiseTransferFunction<double>::Piece p{};
    p.Tau = 1.0 + 0.5 * u(rng);
    p.TauSlope = 0.4 * u(rng);
    p.TauCurvature = trial % 2 ? 0.2 * u(rng) : 0.0;
    p.TauCubic = trial % 2 ? 0.1 * u(rng) : 0.0;
    double G[3][3];
    for (auto& row : G)
    {
      for (double& x : row)
      {
        x = u(rng);
      }
    }
    if (trial % 4 == 0)
    {
      // Every component vanishes at v = 0.4: |g| has a kink there.
      for (auto& row : G)
      {
        row[0] = -0.4 * row[1] - 0.16 * row[2];
      }
    }
    const double v0 = 0.5 * (u(rng) + 1.0), width = std::pow(10.0, -2.0 * (u(rng) + 1.0));
    const double c = v0 + width / 2.0, r = width / 2.0 * (1.0 + 1e-15);
    const TaylorModel<double, N> K = detail::ExtinctionModel<N>(q, p, G, false, g, c, r);
    ASSERT_TRUE(K.Finite()) << "trial " << trial;
    tight += K.R < 1e-3 ? 1 : 0;
    for (int i = 0; i <= 64; ++i)
    {
      const double v = v0 + width * i / 64.0, d = q(v);
      glm::dvec3 gradient;
      for (int a = 0; a < 3; ++a)
      {
        gradient[a] = G[a][0] + v * (G[a][1] + v * G[a][2]);
      }
      const double tau = p.Tau + d * (p.TauSlope + d * (p.TauCurvature + d * p.TauCubic));
      const double kappa =
        tau * std::min(std::max(g.GetOpacityValue(glm::length(gradient)), 0.0), 1.0);
      EXPECT_LE(std::abs(K.Evaluate(v - c) - kappa), K.R + 1e-14 * std::abs(kappa))
        << "trial " << trial << ", v " << v;
    }
  }
  EXPECT_GT(tight, trials / 2) << "degree " << N;
}
} // namespace

TEST(PiecewiseGradientOpacity, ExtinctionModelsHoldTheSamples)
{
  CheckExtinctionModels<3>(21);
  CheckExtinctionModels<5>(22);
}

TEST(PiecewiseGradientOpacity, BadInput)
{
  const int dims[3] = { 2, 2, 2 };
  const std::vector<double> data(8, 1.0);
  const Volume volume(data.data(), dims);
  const TransferFunction<double> tf = Uniform(1.0, glm::dvec3(1.0));
  PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(tf, 1e-6), "");
  GradientOpacity<double> missing;
  EXPECT_EQ(
    Integrate(volume, glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0), 1.0, pieces, 1e-3, missing).Error,
    "no gradient opacity function");
  const TransferFunction<double> g = Factor({ { 0.0, 1.0 } });
  GradientOpacity<double> opacity;
  opacity.Function = &g;
  EXPECT_NE(
    Integrate(volume, glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0), 1.0, pieces, 0.0, opacity).Error,
    "");
  const RayShading<double> noModel{};
  EXPECT_EQ(Integrate(volume, glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0), 1.0, pieces, 1e-3,
              opacity, &noModel)
              .Error,
    "no shading model");
}
