// The piecewise method with shading (PiecewiseShading.h) against the
// independent oracle of ShadedOracle.h: every channel of every ray within the
// tolerance, on the adversarial suite's volumes and transfer functions, lit
// adversarially (specular power 128, one- and two-sided lighting, coloured
// lights, an anisotropic grid, a point light inside the volume, a spot whose
// cone's edge the rays cross), in both opacity models; a gradient vanishing
// inside a cell; the lit colour's enclosures; and refusals.
#include "avos/numerics/PiecewiseShading.h"

#include "AdversarialCases.h"
#include "ShadedOracle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace avos::numerics;
namespace an = avos::numerics;

namespace
{
double MaxError(const glm::dvec4& a, const glm::dvec4& b)
{
  double e = 0.0;
  for (int c = 0; c < 4; ++c)
  {
    e = std::max(e, std::abs(a[c] - b[c]));
  }
  return e;
}

// VTK's defaults with a headlight, and an adversarial model: a sharp
// highlight, one-sided lighting, two coloured lights.
ShadingModel<double> Headlight(const glm::dvec3& toViewer)
{
  ShadingModel<double> m;
  m.Lights.push_back({ toViewer, glm::dvec3(1.0), glm::dvec3(1.0) });
  return m;
}

ShadingModel<double> Sharp()
{
  return adversarial::SharpLighting();
}

// Positional lights in a volume of dimensions `dims` (grid = world): a point
// light inside it and a narrow spot aimed at its centre from outside, whose
// cone's edge the rays cross (a jump of the lit colour).
ShadingModel<double> Lamps(const int dims[3])
{
  const glm::dvec3 centre = 0.5 * glm::dvec3(dims[0] - 1, dims[1] - 1, dims[2] - 1);
  ShadingModel<double> m;
  m.SpecularPower = 32.0;
  Light<double> bulb;
  bulb.Positional = true;
  bulb.Position = centre + glm::dvec3(0.31, -0.17, 0.23);
  bulb.Attenuation = glm::dvec3(0.5, 0.1, 0.05);
  bulb.Diffuse = glm::dvec3(1.0, 0.9, 0.7);
  bulb.Specular = glm::dvec3(1.0);
  m.Lights.push_back(bulb);
  Light<double> spot = bulb;
  spot.Position = centre + glm::dvec3(-0.7, 1.1, 1.6) * double(dims[0] + dims[1] + dims[2]);
  spot.Axis = glm::normalize(centre - spot.Position);
  spot.Attenuation = glm::dvec3(1.0, 0.0, 0.0);
  spot.ConeAngle = 4.0;
  spot.Exponent = 8.0;
  spot.Diffuse = glm::dvec3(0.4, 0.6, 1.0);
  m.Lights.push_back(spot);
  return m;
}

enum class Lighting
{
  Headlight,
  Sharp,
  Lamps
};

const char* Name(Lighting l)
{
  return l == Lighting::Headlight ? "headlight" : l == Lighting::Sharp ? "sharp" : "lamps";
}

struct Outcome
{
  double MaximumError = 0.0;
  long Samples = 0;
  long Pieces = 0;
};

// Rays of adversarial case `c` with `model` at `eps` against the oracle.
Outcome Compare(const adversarial::Case& c, Lighting lighting, const glm::dmat3& normalMatrix,
  double eps, OpacityModel opacity, int rays)
{
  an::TransferFunction<double> tf = c.TF;
  tf.SetOpacityModel(opacity, 1.0);
  tf.Finalize();
  PiecewiseTransferFunction<double> pieces, exact;
  EXPECT_EQ(pieces.Build(tf, PiecewiseRelativeError(eps)), "");
  EXPECT_EQ(exact.Build(tf, PiecewiseTransferFunction<double>::MinimumRelativeError), "");
  const TrilinearVolume<double, double> volume(c.Data.data(), c.Dimensions);
  Outcome o;
  for (int i = 0; i < rays; ++i)
  {
    const adversarial::Ray ray = adversarial::MakeRay(c, static_cast<unsigned>(i));
    const glm::dvec3 toViewer = -ray.Direction;
    const ShadingModel<double> model = lighting == Lighting::Sharp ? Sharp()
      : lighting == Lighting::Lamps                                ? Lamps(c.Dimensions)
                                                                   : Headlight(toViewer);
    const RayShading<double> shading{ &model, normalMatrix, toViewer, ray.Origin, ray.Direction };
    const Interval<double> whole{ 0.0, ray.Length };
    // No early termination: the oracle integrates the whole ray.
    const RayResult<double> r = IntegratePiecewiseShaded(
      volume, ray.Origin, ray.Direction, &whole, 1, pieces, eps, shading, false);
    EXPECT_EQ(r.Error, "") << c.Name << ", ray " << i;
    const glm::dvec4 oracle = oracles::ShadedRay(
      volume, tf, exact, ray.Origin, ray.Direction, ray.Length, model, normalMatrix, toViewer);
    const double e = MaxError(r.RGBA, oracle);
    EXPECT_LE(e, eps) << c.Name << ", ray " << i << ", " << Name(lighting);
    o.MaximumError = std::max(o.MaximumError, e);
    o.Samples += r.Statistics.Samples;
    o.Pieces += r.Statistics.Pieces;
  }
  return o;
}
} // namespace

TEST(PiecewiseShading, AdversarialSuiteWithinTheToleranceOfAnExactOracle)
{
  // An anisotropic grid: spacing (1, 2, 0.5), so gradients map to world by
  // the inverse transpose diag(1, 0.5, 2).
  const glm::dmat3 anisotropic(
    glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(0.0, 0.5, 0.0), glm::dvec3(0.0, 0.0, 2.0));
  for (const adversarial::Case& c : adversarial::MakeSuite())
  {
    for (double eps : { 1e-2, 1e-3 })
    {
      for (Lighting lighting : { Lighting::Headlight, Lighting::Sharp, Lighting::Lamps })
      {
        const bool sharp = lighting == Lighting::Sharp;
        const Outcome o = Compare(c, lighting, sharp ? anisotropic : glm::dmat3(1.0), eps,
          lighting == Lighting::Headlight ? OpacityModel::Extinction : OpacityModel::Alpha, 6);
        std::printf("%-34s eps %g %-9s max error %.2e, %.1f samples per piece\n", c.Name.c_str(),
          eps, Name(lighting), o.MaximumError,
          o.Pieces ? double(o.Samples) / double(o.Pieces) : 0.0);
      }
    }
  }
}

// Gradients that vanish inside a cell, on rays through where they do:
// - a saddle, s = (x - m)(y - m') + (y - m')(z - m'') + (z - m'')(x - m),
//   which trilinear interpolation reproduces, its gradient 0 at the point m
//   alone: one-sided lighting flips the normal there (the lit colour jumps),
//   two-sided lighting has a kink;
// - s = |x - m|^2 sampled with m a cell's centre: that cell's corners are
//   equal, its gradient 0 throughout (ambient only).
TEST(PiecewiseShading, GradientVanishingInsideACell)
{
  const int dims[3] = { 6, 6, 6 };
  const glm::dvec3 saddle(2.3, 2.6, 2.45), centre(2.5);
  for (bool point : { true, false })
  {
    std::vector<double> data;
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i)
        {
          const glm::dvec3 x = glm::dvec3(i, j, k) - (point ? saddle : centre);
          data.push_back(point ? x.x * x.y + x.y * x.z + x.z * x.x : glm::dot(x, x));
        }
    const TrilinearVolume<double, double> volume(data.data(), dims);
    const glm::dvec3 m = point ? saddle : centre;
    ASSERT_LT(glm::length(volume.Gradient(m)), 1e-14);
    // Beside m: a gradient at the saddle, none in the flat cell.
    ASSERT_EQ(glm::length(volume.Gradient(m + glm::dvec3(0.1, 0.0, 0.0))) > 0.05, point);
    an::TransferFunction<double> tf;
    tf.AddOpacityKnot(-8.0, 0.0);
    tf.AddOpacityKnot(0.0, 0.8);
    tf.AddOpacityKnot(8.0, 0.1);
    tf.AddOpacityKnot(20.0, 0.0);
    tf.AddColorKnot(-8.0, 0.3, 1.0, 0.3);
    tf.AddColorKnot(0.0, 1.0, 0.8, 0.3);
    tf.AddColorKnot(20.0, 0.2, 0.4, 1.0);
    tf.Finalize();
    PiecewiseTransferFunction<double> pieces, exact;
    ASSERT_EQ(exact.Build(tf, 1e-7), "");
    std::mt19937 rng(5);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (double eps : { 1e-2, 1e-3 })
    {
      ASSERT_EQ(pieces.Build(tf, PiecewiseRelativeError(eps)), "");
      for (int i = 0; i < 8; ++i)
      {
        const glm::dvec3 d = glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng)));
        double t0 = -1e9, t1 = 1e9;
        ASSERT_TRUE(ClipToGrid(m, d, dims, t0, t1));
        const glm::dvec3 origin = m + t0 * d;
        ShadingModel<double> model = Sharp();
        model.TwoSided = i % 2 == 0;
        const RayShading<double> shading{ &model, glm::dmat3(1.0), -d };
        const Interval<double> whole{ 0.0, t1 - t0 };
        const RayResult<double> r =
          IntegratePiecewiseShaded(volume, origin, d, &whole, 1, pieces, eps, shading, false);
        ASSERT_EQ(r.Error, "");
        const glm::dvec4 oracle =
          oracles::ShadedRay(volume, tf, exact, origin, d, t1 - t0, model, glm::dmat3(1.0), -d);
        EXPECT_LE(MaxError(r.RGBA, oracle), eps) << (point ? "saddle" : "flat") << ", ray " << i;
        EXPECT_GT(oracle.a, 0.1) << "the ray crosses the visible centre";
      }
    }
  }
}

// The certificate itself: over random sub-intervals of random pieces, the
// lit colour's Taylor model (its polynomial P and remainder R) holds every
// sample of the lit colour, |L(v) - P(v - c)| <= R, built from the
// gradient's components or from its polynomials (as ShadedPiece builds it),
// for both degrees ShadedPiece uses. Most models are tight (R < 1e-6: the
// test is not won by infinite remainders).
template <int N>
void CheckLitModels(unsigned seed)
{
  using Model = TaylorModel<double, N>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int dims[3] = { 3, 3, 3 };
  const ShadingModel<double> models[3] = { Headlight(glm::dvec3(0.0, 0.0, 1.0)), Sharp(),
    Lamps(dims) };
  const glm::dvec3 toViewer = glm::normalize(glm::dvec3(0.2, 0.1, 1.0));
  long tight = 0;
  const int trials = 3000;
  for (int trial = 0; trial < trials; ++trial)
  {
    const ShadingModel<double>& model = models[trial % 3];
    // The sample's world position: a line through the lamps' volume (the
    // point light at distance 0.1 .. 1 of it, the spot's cone crossed).
    const glm::dvec3 p0 = glm::dvec3(1.0) + glm::dvec3(u(rng), u(rng), u(rng));
    const glm::dvec3 dir = glm::dvec3(u(rng), u(rng), u(rng));
    double G[3][3], C[3][2];
    for (int a = 0; a < 3; ++a)
    {
      for (int k = 0; k < 3; ++k)
      {
        G[a][k] = u(rng);
      }
      C[a][0] = 0.5 + 0.5 * u(rng);
      C[a][1] = 0.3 * u(rng);
    }
    const double v0 = u(rng), h = std::pow(10.0, -3.0 * (u(rng) + 1.0)); // 1e-6 .. 1
    const double c = v0 + h / 2.0, r = h / 2.0 * (1.0 + 1e-15);
    Model colour[3], gradient[3], position[3], lit[3], fromPolynomials[3];
    for (int a = 0; a < 3; ++a)
    {
      const double line[2] = { C[a][0], C[a][1] };
      const double place[2] = { p0[a], dir[a] };
      colour[a] = Model::Polynomial(line, c, r);
      gradient[a] = Model::Polynomial(G[a], c, r);
      position[a] = Model::Polynomial(place, c, r);
    }
    LitColour(model, colour, gradient, toViewer, position, lit);
    LitColourOf(model, colour, detail::GradientPolynomials<double, N>(G, c, r, false), toViewer,
      position, fromPolynomials);
    bool allTight = true;
    for (int k = 0; k < 3; ++k)
    {
      allTight = allTight && fromPolynomials[k].R < 1e-6;
    }
    tight += allTight ? 1 : 0;
    for (int i = 0; i <= 16; ++i)
    {
      const double v = v0 + h * i / 16.0;
      double col[3], grad[3], pos[3], value[3];
      for (int k = 0; k < 3; ++k)
      {
        col[k] = C[k][0] + C[k][1] * v;
        grad[k] = G[k][0] + v * (G[k][1] + v * G[k][2]);
        pos[k] = p0[k] + v * dir[k];
      }
      LitColour(model, col, grad, toViewer, pos, value);
      for (int k = 0; k < 3; ++k)
      {
        // The samples' own rounding: a few ulps of the terms.
        const double slack = 1e-14;
        ASSERT_LE(std::abs(lit[k].Evaluate(v - c) - value[k]), lit[k].R + slack)
          << "trial " << trial << ", channel " << k;
        ASSERT_LE(
          std::abs(fromPolynomials[k].Evaluate(v - c) - value[k]), fromPolynomials[k].R + slack)
          << "trial " << trial << ", channel " << k << ", from the quadratics";
      }
    }
  }
  EXPECT_GT(tight, trials / 2) << "degree " << N;
}

TEST(PiecewiseShading, LitColourModelsHoldTheSamples)
{
  CheckLitModels<3>(17);
  CheckLitModels<5>(18);
}

// On a smooth stretch (a gradient far from 0 and from the kinks, one
// directional light) the lit colour's remainder shrinks as r^(N+1): halving
// the sub-interval from 2 r to r divides it by about 2^(N+1) (r large enough
// that the remainder is above rounding's 1e-14).
template <int N>
double RemainderRatio(double r)
{
  using Model = TaylorModel<double, N>;
  ShadingModel<double> model;
  model.Lights.push_back(
    { glm::normalize(glm::dvec3(0.2, 0.3, 1.0)), glm::dvec3(1.0), glm::dvec3(1.0) });
  const double G[3][3] = { { 1.0, 0.3, -0.2 }, { 0.5, -0.4, 0.1 }, { 0.8, 0.2, 0.3 } };
  const glm::dvec3 toViewer(0.0, 0.0, 1.0);
  auto remainder = [&](double radius)
  {
    Model colour[3], lit[3];
    for (int k = 0; k < 3; ++k)
    {
      colour[k] = Model(0.6);
    }
    LitColourOf(model, colour, detail::GradientPolynomials<double, N>(G, 0.3, radius, false),
      toViewer, static_cast<const Model*>(nullptr), lit);
    return std::max(lit[0].R, std::max(lit[1].R, lit[2].R));
  };
  return remainder(2.0 * r) / remainder(r);
}

TEST(PiecewiseShading, RemainderShrinksAsTheDegreePlusOne)
{
  EXPECT_NEAR(RemainderRatio<3>(0.01) / 16.0, 1.0, 0.3);
  EXPECT_NEAR(RemainderRatio<5>(0.02) / 64.0, 1.0, 0.3);
}

// The kinks' cuts: the roots of g.l in (0, l) for each directional light,
// and of g.h only where the specular power is below the degree + 1. Here g.l
// = (v - 0.25)(v - 0.75) for the light along z, g.h's roots at 0.5 and 2.
TEST(PiecewiseShading, KinkCutsAtTheRootsOfTheFacingQuadratics)
{
  // g = ((v - 0.5)(v - 2), 0, (v - 0.25)(v - 0.75)): G[a][k] v^k.
  const double G[3][3] = { { 1.0, -2.5, 1.0 }, { 0.0, 0.0, 0.0 }, { 0.1875, -1.0, 1.0 } };
  ShadingModel<double> model;
  model.Lights.push_back({ glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(1.0), glm::dvec3(1.0) });
  const glm::dvec3 toViewer(1.0, 0.0, 0.0); // h = (1, 0, 1) / sqrt 2
  detail::KinkCuts<double> smooth;
  smooth.Find(G, 1.0, model, toViewer, 3);
  ASSERT_EQ(smooth.Count, 2) << "power 10: n.h is left to the models";
  EXPECT_NEAR(smooth.At[0], 0.25, 1e-15);
  EXPECT_NEAR(smooth.At[1], 0.75, 1e-15);
  model.SpecularPower = 1.0;
  detail::KinkCuts<double> sharp;
  sharp.Find(G, 1.0, model, toViewer, 3);
  ASSERT_EQ(sharp.Count, 3);
  // g.h = ((v - 0.5)(v - 2) + (v - 0.25)(v - 0.75)) / sqrt 2 = (2 v^2 - 3.5 v + 1.1875) / sqrt 2
  const double root = (3.5 - std::sqrt(3.5 * 3.5 - 8.0 * 1.1875)) / 4.0;
  EXPECT_NEAR(sharp.At[0], 0.25, 1e-15);
  EXPECT_NEAR(sharp.At[1], root, 1e-15);
  EXPECT_NEAR(sharp.At[2], 0.75, 1e-15);
}

// A dim medium (dT at most the share: the constant 1/2 suffices) entered
// with a tiny predicted length: the sub-intervals must grow (each dim one
// doubles the length; their error ratio, 0.87 here, predicts nothing), not
// stay at the floor until the piece is refused.
TEST(PiecewiseShading, DimPiecesGrowFromATinyLength)
{
  const Cubic<double> q{ { 0.5, 0.1, 0.0, 0.0 } };
  PiecewiseTransferFunction<double>::Piece p{};
  p.Tau = 0.0024; // Ta tau (1 - scale) <= scale / L with scale 0.00275, L = 1
  p.ColourSlope = glm::dvec3(0.0, 0.05, 0.0);
  const detail::PieceDepth<double> depth(q, p.Tau, 0.0, 0.0, 0.0);
  const double G[3][3] = { { 1.0, 0.2, 0.0 }, { 0.3, 0.0, 0.1 }, { -0.5, 0.0, 0.0 } };
  const ShadingModel<double> model = Headlight(glm::dvec3(0.0, 0.0, 1.0));
  const RayShading<double> shading{ &model, glm::dmat3(1.0), glm::dvec3(0.0, 0.0, 1.0) };
  glm::dvec3 color(0.0);
  double overdraft = 0.0, length = 1e-13;
  RayStatistics<double> stats;
  ASSERT_TRUE(detail::ShadedPiece<3>(q, p, depth, 1.0, std::exp(-depth(1.0)), 1.0, G,
    glm::dvec3(0.0), shading, detail::ShadedBudget<double>{ 0.00275, 1.0, 0.0005 }, color,
    overdraft, length, stats));
  EXPECT_LT(stats.Accepted, 60) << "about log2(1e13) doublings";
  EXPECT_EQ(overdraft, 0.0);
}

// A piece of the Bonsai's shaded reference frame (VTK's opacity model, eps
// 1e-10) through a point where the gradient nearly vanishes: there rounding,
// not the length, bounds the lit colour's remainder (6.6e-11 for every
// sub-interval of 1e-12 near v = 0.5942) while dT and the share shrink with
// the length. The excess comes from the reserve; the piece was refused after
// 65,536 enclosures before. Its colour within eps of Gauss-Legendre on the
// lit emission.
TEST(PiecewiseShading, RoundingBoundRemainderNearAVanishingGradient)
{
  const double G[3][3] = { { -0.09389241827518191, 0.2495281957350427, -0.1540144432100467 },
    { -0.093892418275161482, 0.24952819573502275, -0.15401444321004668 },
    { -0.0088157862095597957, 0.029671886501895024, -0.024967167636920914 } };
  const Cubic<double> q{ { 0.064483546149858739, 0.03826474897635012, -0.053888744681511676,
    0.024335825844787599 } };
  PiecewiseTransferFunction<double>::Piece p{};
  p.Tau = 0.092151348466954955;
  p.TauSlope = 0.03298279502691906;
  p.TauCurvature = 0.00054392597255437211;
  p.TauCubic = 1.2039165313726178e-05;
  p.Colour = glm::dvec3(0.0, 0.13657936448989377, 0.0);
  p.ColourSlope = glm::dvec3(0.0, 0.046666666666666662, 0.0);
  ShadingModel<double> model;
  model.Lights.push_back({ glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(1.0), glm::dvec3(1.0) });
  const glm::dvec3 toViewer(0.15801002384950427, 0.1580100238495043, 0.97471311919259518);
  const RayShading<double> shading{ &model, glm::dmat3(1.0), toViewer };
  const detail::PieceDepth<double> depth(q, p.Tau, p.TauSlope, p.TauCurvature, p.TauCubic);
  const double l = 0.59421811343176856, Ta = 0.056332376512750727, eps = 1e-10;
  const detail::ShadedBudget<double> budget{ 0.275 * eps, 0.016042034169031581, 0.05 * eps };
  glm::dvec3 color(0.0);
  double overdraft = 0.0, length = 0.01949365330294207;
  RayStatistics<double> stats;
  ASSERT_TRUE(detail::ShadedPiece<5>(q, p, depth, l, std::exp(-depth(l)), Ta, G, glm::dvec3(0.0),
    shading, budget, color, overdraft, length, stats));
  EXPECT_LE(overdraft, 1e-14) << "the excesses are tiny (dT is)";
  EXPECT_LT(stats.Samples, 2000);
  for (int c = 0; c < 3; ++c)
  {
    auto lit = [&](double v)
    {
      glm::dvec3 g;
      for (int a = 0; a < 3; ++a)
      {
        g[a] = G[a][0] + v * (G[a][1] + v * G[a][2]);
      }
      const double s = q(v);
      const double tau = p.Tau + s * (p.TauSlope + s * (p.TauCurvature + s * p.TauCubic));
      return model.Shade(p.Colour + p.ColourSlope * s, g, toViewer, glm::dvec3(0.0))[c] * tau * Ta *
        std::exp(-depth(v));
    };
    // The kink of |n.l| where the gradient nearly vanishes: split there.
    const double kink = 0.59421671;
    const double oracle = detail::AdaptiveGauss(0.0, kink, 1e-15, 0, lit) +
      detail::AdaptiveGauss(kink, l, 1e-15, 0, lit);
    EXPECT_NEAR(color[c], oracle, eps) << "channel " << c;
  }
}

TEST(PiecewiseShading, BadInput)
{
  const int dims[3] = { 2, 2, 2 };
  const double data[8] = { 0, 1, 0, 1, 0, 1, 0, 1 };
  const TrilinearVolume<double, double> volume(data, dims);
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 1.0);
  tf.AddColorKnot(0.0, 1.0, 1.0, 1.0);
  tf.Finalize();
  PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(tf, 1e-3), "");
  const Interval<double> whole{ 0.0, 1.0 };
  const glm::dvec3 o(0.0, 0.5, 0.5), d(1.0, 0.0, 0.0);
  ShadingModel<double> model = Sharp();
  RayShading<double> shading{ nullptr, glm::dmat3(1.0), -d };
  EXPECT_EQ(IntegratePiecewiseShaded(volume, o, d, &whole, 1, pieces, 1e-3, shading).Error,
    "no shading model");
  shading.Model = &model;
  model.Specular = -1.0;
  EXPECT_NE(IntegratePiecewiseShaded(volume, o, d, &whole, 1, pieces, 1e-3, shading).Error, "");
  model.Specular = 0.5;
  EXPECT_NE(IntegratePiecewiseShaded(volume, o, d, &whole, 1, pieces, 0.0, shading).Error, "");
  const RayResult<double> r =
    IntegratePiecewiseShaded(volume, o, d, &whole, 1, pieces, 1e-3, shading);
  EXPECT_EQ(r.Error, "");
  EXPECT_GT(r.RGBA.a, 0.5);
}
