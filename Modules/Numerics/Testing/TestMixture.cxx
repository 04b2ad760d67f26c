// Volumes of several components (Mixture.h): the medium against closed
// forms, the piecewise method within eps of an independent oracle on the
// adversarial mixtures, the sampled methods through the same medium, NaN
// and bad input.
#include "MixtureCases.h"

#include "avos/numerics/Mixture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace an = avos::numerics;

namespace
{
using Volume = an::TrilinearVolume<double, double>;
using Volumes = an::ComponentVolumes<double, Volume>;

// A ramp of extinction `tau` everywhere (extinction model) and colours
// from `low` at 0 to `high` at 255.
an::TransferFunction<double> Ramp(double tau, const glm::dvec3& low, const glm::dvec3& high)
{
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, tau);
  tf.AddOpacityKnot(255.0, tau);
  tf.AddColorKnot(0.0, low.r, low.g, low.b);
  tf.AddColorKnot(255.0, high.r, high.g, high.b);
  tf.Finalize();
  return tf;
}

// An extinction rising from 0 at 0 to 2 at 255 (extinction model), of one
// colour.
an::TransferFunction<double> Rising(const glm::dvec3& colour)
{
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(255.0, 2.0);
  tf.AddColorKnot(0.0, colour.r, colour.g, colour.b);
  tf.Finalize();
  return tf;
}

// An 8 x 3 x 3 grid of `components` interleaved values, component k
// value(k, i) along x (constant across y and z): linear fields stay linear
// under trilinear interpolation.
std::vector<double> AlongX(int components, double (*value)(int, int))
{
  std::vector<double> data;
  for (int n = 0; n < 8 * 3 * 3; ++n)
  {
    for (int k = 0; k < components; ++k)
    {
      data.push_back(value(k, n % 8));
    }
  }
  return data;
}

constexpr int Dims[3] = { 8, 3, 3 };

Volumes MakeVolumes(const std::vector<double>& data, int components)
{
  return Volumes(components, [&](int k) { return Volume(data.data() + k, Dims, components); });
}

// int_0^D (P + Q t) tau e^{-tau t} dt / tau (premultiplied) and alpha: the
// closed form of a constant extinction with a colour linear in t.
glm::dvec4 LinearColourConstantExtinction(
  const glm::dvec3& P, const glm::dvec3& Q, double tau, double D)
{
  const double E = std::exp(-tau * D);
  return glm::dvec4(P * (1.0 - E) + Q * ((1.0 - E * (1.0 + tau * D)) / tau), 1.0 - E);
}

an::RayResult<double> PiecewiseAlongX(const Volumes& volumes,
  const an::MixtureTransferFunction<double>& mixture, double eps, double relativeError = 1e-7)
{
  an::PiecewiseMixture<double> pieces;
  EXPECT_EQ(pieces.Build(mixture, relativeError), "");
  const an::Interval<double> whole{ 0.0, 7.0 };
  return an::IntegratePiecewiseMixture(
    volumes, glm::dvec3(0.0, 1.0, 1.0), glm::dvec3(1.0, 0.0, 0.0), &whole, 1, pieces, eps);
}

void ExpectWithin(const glm::dvec4& got, const glm::dvec4& want, double eps)
{
  for (int c = 0; c < 4; ++c)
  {
    EXPECT_NEAR(got[c], want[c], eps) << "channel " << c;
  }
}
} // namespace

// Classify against hand-computed media: the independent mixture's
// extinction is the weighted sum, its colour the extinction-weighted mean;
// the dependent ones read their colour and opacity where they say; NaN
// leaves a component out (independent) or empties the sample (dependent).
TEST(Mixture, ClassifiesEachMix)
{
  const an::TransferFunction<double> a = Ramp(2.0, glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0));
  const an::TransferFunction<double> b =
    Ramp(0.5, glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(0.0, 1.0, 0.0));
  const an::TransferFunction<double>* f[2] = { &a, &b };
  const double w[2] = { 1.0, 2.0 };
  an::MixtureTransferFunction<double> m;
  m.SetIndependent(2, f, w);
  ASSERT_EQ(m.Validate(), "");
  double tau;
  glm::dvec3 c;
  m.Classify(glm::dvec4(255.0, 7.0, 0.0, 0.0), tau, c);
  EXPECT_DOUBLE_EQ(tau, 2.0 + 2.0 * 0.5);
  EXPECT_NEAR(c.r, 2.0 / 3.0, 1e-15); // (2 (1, 0, 0) + 1 (0, 1, 0)) / 3
  EXPECT_NEAR(c.g, 1.0 / 3.0, 1e-15);
  m.Classify(glm::dvec4(std::nan(""), 7.0, 0.0, 0.0), tau, c);
  EXPECT_DOUBLE_EQ(tau, 1.0);
  EXPECT_NEAR(c.g, 1.0, 1e-15);

  // Colour of s_0, opacity of s_1 through one function.
  an::TransferFunction<double> both;
  both.AddOpacityKnot(0.0, 0.0);
  both.AddOpacityKnot(100.0, 4.0);
  both.AddColorKnot(0.0, 0.0, 0.0, 1.0);
  both.AddColorKnot(100.0, 1.0, 0.0, 0.0);
  both.Finalize();
  m.SetColourOpacity(both);
  ASSERT_EQ(m.Validate(), "");
  m.Classify(glm::dvec4(25.0, 50.0, 0.0, 0.0), tau, c);
  EXPECT_DOUBLE_EQ(tau, 2.0);
  EXPECT_DOUBLE_EQ(c.r, 0.25);
  EXPECT_DOUBLE_EQ(c.b, 0.75);
  m.Classify(glm::dvec4(std::nan(""), 50.0, 0.0, 0.0), tau, c);
  EXPECT_EQ(tau, 0.0);

  // RGB times the scale, opacity of s_3.
  m.SetRGBOpacity(both, 1.0 / 255.0);
  ASSERT_EQ(m.Validate(), "");
  m.Classify(glm::dvec4(255.0, 51.0, 0.0, 100.0), tau, c);
  EXPECT_DOUBLE_EQ(tau, 4.0);
  EXPECT_DOUBLE_EQ(c.r, 1.0);
  EXPECT_DOUBLE_EQ(c.g, 0.2);
  EXPECT_EQ(m.GetMaximumColor(), 1.0);
}

// Two independent components of constant extinction whose colours are
// linear along the ray: tau = w0 tau0 + w1 tau1 and the emission is linear
// in t, so the integral has a closed form; both terms are visible on every
// piece (the emissions' series). Within eps at 1e-3 and 1e-6, and within
// 1e-9 at the reference's tolerance.
TEST(Mixture, TwoIndependentComponentsAgainstTheirClosedForm)
{
  const std::vector<double> data =
    AlongX(2, [](int k, int i) { return k == 0 ? 10.0 + 20.0 * i : 200.0 - 15.0 * i; });
  const Volumes volumes = MakeVolumes(data, 2);
  const glm::dvec3 high0(1.0, 0.5, 0.2), low1(0.2, 1.0, 0.0), high1(0.8, 0.0, 1.0);
  const an::TransferFunction<double> tf0 = Ramp(0.3, glm::dvec3(0.0), high0);
  const an::TransferFunction<double> tf1 = Ramp(0.7, low1, high1);
  const an::TransferFunction<double>* f[2] = { &tf0, &tf1 };
  const double w[2] = { 1.0, 0.5 };
  an::MixtureTransferFunction<double> mixture;
  mixture.SetIndependent(2, f, w);
  // E(t) = 0.3 C0(10 + 20 t) + 0.35 C1(200 - 15 t) = P + Q t.
  const glm::dvec3 C0at0 = high0 * (10.0 / 255.0), C0slope = high0 * (20.0 / 255.0);
  const glm::dvec3 C1at0 = low1 + (high1 - low1) * (200.0 / 255.0);
  const glm::dvec3 C1slope = (high1 - low1) * (-15.0 / 255.0);
  const double tau = 0.3 + 0.35;
  const glm::dvec3 P = (0.3 * C0at0 + 0.35 * C1at0) / tau;
  const glm::dvec3 Q = (0.3 * C0slope + 0.35 * C1slope) / tau;
  const glm::dvec4 exact = LinearColourConstantExtinction(P, Q, tau, 7.0);
  for (const double eps : { 1e-3, 1e-6, an::PiecewiseReferenceTolerance<double>() })
  {
    const an::RayResult<double> r = PiecewiseAlongX(volumes, mixture, eps);
    ASSERT_EQ(r.Error, "");
    ExpectWithin(r.RGBA, exact, std::max(eps, 1e-9));
    EXPECT_EQ(r.Statistics.Pieces, 7); // a piece per cell: no knot inside
  }
}

// Optically thick pieces of two visible terms whose emission is proportional
// to the extinction, where the midpoint of [E, 1] is far outside the share:
// - both terms white, their extinctions varying apart (the mean colour, no
//   spread around it): every channel equals alpha;
// - each term's colour constant, red and blue, their extinctions constant
//   (the split bound: no term's colour spreads, the shares of the extinction
//   do not vary): the closed form of a constant colour.
// Within eps, and without the series: one accepted step per piece.
TEST(Mixture, ThickPiecesOfAConstantMeanColourNeedNoSeries)
{
  const std::vector<double> data =
    AlongX(2, [](int k, int i) { return k == 0 ? 30.0 * i : 250.0 - 10.0 * i; });
  const Volumes volumes = MakeVolumes(data, 2);
  const glm::dvec3 white(1.0), red(1.0, 0.0, 0.0), blue(0.0, 0.0, 1.0);
  const an::TransferFunction<double> rising = Rising(white);
  const an::TransferFunction<double> flat = Ramp(0.5, white, white);
  const an::TransferFunction<double> reds = Ramp(0.3, red, red), blues = Ramp(0.7, blue, blue);
  const double w[2] = { 1.0, 1.0 };
  const an::TransferFunction<double>* whites[2] = { &rising, &flat };
  const an::TransferFunction<double>* colours[2] = { &reds, &blues };
  an::MixtureTransferFunction<double> grey, coloured;
  grey.SetIndependent(2, whites, w);
  coloured.SetIndependent(2, colours, w);
  const double E = std::exp(-7.0);
  const glm::dvec4 exact((0.3 * red + 0.7 * blue) * (1.0 - E), 1.0 - E);
  for (const double eps : { 1e-2, 1e-3, 1e-6 })
  {
    const an::RayResult<double> g = PiecewiseAlongX(volumes, grey, eps);
    ASSERT_EQ(g.Error, "");
    ExpectWithin(g.RGBA, glm::dvec4(g.RGBA.a, g.RGBA.a, g.RGBA.a, g.RGBA.a), eps);
    EXPECT_GT(g.RGBA.a, 0.99);
    EXPECT_EQ(g.Statistics.Accepted, g.Statistics.Pieces) << "eps " << eps;
    const an::RayResult<double> c = PiecewiseAlongX(volumes, coloured, eps);
    ASSERT_EQ(c.Error, "");
    ExpectWithin(c.RGBA, exact, eps);
    EXPECT_EQ(c.Statistics.Accepted, c.Statistics.Pieces) << "eps " << eps;
  }
}

// Thick pieces whose terms' colours are constant but whose shares of the
// extinction vary along them: red of extinction 60 x / 255 (rising along the
// ray) and blue of 0.5, against the integral in closed form up to a
// quadrature (theta = 30 x^2 / 255 + x / 2, 7-point Gauss-Legendre on 700
// intervals: exact to rounding). A bound blind to the shares' variation
// lets the mean colour err by 0.013 in red and blue here.
TEST(Mixture, VaryingSharesOfTheExtinctionWithinTolerance)
{
  const std::vector<double> data =
    AlongX(2, [](int k, int i) { return k == 0 ? 30.0 * i : 100.0; });
  const Volumes volumes = MakeVolumes(data, 2);
  const glm::dvec3 red(1.0, 0.0, 0.0), blue(0.0, 0.0, 1.0);
  const an::TransferFunction<double> rising = Rising(red);
  const an::TransferFunction<double> blues = Ramp(0.5, blue, blue);
  const an::TransferFunction<double>* f[2] = { &rising, &blues };
  const double w[2] = { 1.0, 1.0 };
  an::MixtureTransferFunction<double> mixture;
  mixture.SetIndependent(2, f, w);
  glm::dvec4 exact(0.0);
  using G = an::detail::GaussLegendre<double>;
  for (int j = 0; j < 700; ++j)
  {
    for (int i = 0; i < 7; ++i)
    {
      const double x = 0.01 * (j + 0.5 + 0.5 * G::N7[i]);
      const double T = std::exp(-(30.0 * x * x / 255.0 + 0.5 * x));
      exact += 0.005 * G::W7[i] * T * glm::dvec4((60.0 / 255.0) * x * red + 0.5 * blue, 0.0);
    }
  }
  exact.a = 1.0 - std::exp(-(30.0 * 49.0 / 255.0 + 3.5));
  for (const double eps : { 1e-2, 1e-3, 1e-6 })
  {
    const an::RayResult<double> r = PiecewiseAlongX(volumes, mixture, eps);
    ASSERT_EQ(r.Error, "");
    ExpectWithin(r.RGBA, exact, eps);
  }
}

// The dependent mixtures against the same closed form: the colour of s_0
// (or the RGB of s_0..s_2) linear along the ray, the opacity of a constant
// s_1 (s_3): one term, by parts with the colour's own cubic.
TEST(Mixture, DependentComponentsAgainstTheirClosedForm)
{
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(200.0, 1.6);
  tf.AddColorKnot(0.0, 0.0, 0.2, 1.0);
  tf.AddColorKnot(255.0, 1.0, 0.6, 0.0);
  tf.Finalize();
  const double tau = 1.6 * 100.0 / 200.0;
  {
    const std::vector<double> data =
      AlongX(2, [](int k, int i) { return k == 0 ? 30.0 + 25.0 * i : 100.0; });
    an::MixtureTransferFunction<double> mixture;
    mixture.SetColourOpacity(tf);
    const glm::dvec3 low(0.0, 0.2, 1.0), high(1.0, 0.6, 0.0);
    const glm::dvec4 exact = LinearColourConstantExtinction(
      low + (high - low) * (30.0 / 255.0), (high - low) * (25.0 / 255.0), tau, 7.0);
    for (const double eps : { 1e-3, 1e-6 })
    {
      const an::RayResult<double> r = PiecewiseAlongX(MakeVolumes(data, 2), mixture, eps);
      ASSERT_EQ(r.Error, "");
      ExpectWithin(r.RGBA, exact, eps);
    }
  }
  {
    const std::vector<double> data = AlongX(4,
      [](int k, int i)
      { return k == 3 ? 100.0 : (k == 0 ? 10.0 * i : (k == 1 ? 255.0 - 30.0 * i : 128.0)); });
    an::MixtureTransferFunction<double> mixture;
    mixture.SetRGBOpacity(tf, 1.0 / 255.0);
    const glm::dvec4 exact = LinearColourConstantExtinction(
      glm::dvec3(0.0, 1.0, 128.0 / 255.0), glm::dvec3(10.0, -30.0, 0.0) / 255.0, tau, 7.0);
    for (const double eps : { 1e-3, 1e-6 })
    {
      const an::RayResult<double> r = PiecewiseAlongX(MakeVolumes(data, 4), mixture, eps);
      ASSERT_EQ(r.Error, "");
      ExpectWithin(r.RGBA, exact, eps);
    }
  }
}

// A second component that shows nothing (an opacity of 0 everywhere, or a
// weight of 0) leaves the first's image: every ray of the adversarial
// suite's cases within eps of the first component's exact integral alone.
TEST(Mixture, TransparentSecondComponentGivesTheFirstsImage)
{
  adversarial::Case other = adversarial::MakeVolume("smooth", adversarial::Smooth, 4);
  other.TF = adversarial::Random(3, 16, 0.0); // colours, no opacity
  for (const adversarial::Case& first : adversarial::MakeSuite())
  {
    an::PiecewiseTransferFunction<double> exactPieces;
    ASSERT_EQ(exactPieces.Build(first.TF, 1e-7), "");
    mixture::Case both = mixture::Interleave(first.Name, { first, other });
    for (const bool byWeight : { false, true })
    {
      if (byWeight)
      {
        both.TF[1] = adversarial::Random(3, 16, 5.0);
        both.Weights[1] = 0.0;
      }
      const double eps = 1e-3;
      an::PiecewiseMixture<double> pieces;
      ASSERT_EQ(pieces.Build(both.Mixture(), an::PiecewiseRelativeError(eps)), "");
      for (unsigned i = 0; i < 40; ++i)
      {
        const adversarial::Ray ray = adversarial::MakeRay(first, i);
        const glm::dvec4 exact = adversarial::Integrate(first, exactPieces, ray,
          adversarial::Method::Reference, an::PiecewiseReferenceTolerance<double>())
                                   .RGBA;
        const an::RayResult<double> r = mixture::Piecewise(both, pieces, ray, eps);
        ASSERT_EQ(r.Error, "");
        ExpectWithin(r.RGBA, exact, eps);
      }
    }
  }
}

// A mixture in which one component alone shows is that component's medium
// with its extinction times its weight: bitwise the single component's
// rays with the weight in its knots (a weight of 2 scales them exactly), in
// both opacity models, and the sampled methods' medium (the function with
// the weight folded in) sums as the mixture does; with both showing, no
// single medium.
TEST(Mixture, OneVisibleComponentIsASingleComponent)
{
  for (const an::OpacityModel model : { an::OpacityModel::Extinction, an::OpacityModel::Alpha })
  {
    const adversarial::Case first = adversarial::MakeVolume("smooth", adversarial::Smooth, 4);
    adversarial::Case second = adversarial::MakeVolume("two", adversarial::TwoMaterial, 5);
    // The weight in the knots: twice the extinction knots (the extinction
    // model), or half the unit distance (twice -ln(1 - alpha) per unit
    // distance): exact scalings by 2.
    an::TransferFunction<double> visible = adversarial::Random(7, 12, 0.4);
    an::TransferFunction<double> doubled =
      adversarial::Random(7, 12, model == an::OpacityModel::Extinction ? 0.8 : 0.4);
    visible.SetOpacityModel(model);
    doubled.SetOpacityModel(model, model == an::OpacityModel::Extinction ? 1.0 : 0.5);
    visible.Finalize();
    doubled.Finalize();
    second.TF = adversarial::Random(3, 16, 0.0); // colours, no opacity
    for (const int shown : { 0, 1 })
    {
      std::vector<adversarial::Case> parts = { first, second };
      if (shown == 1)
      {
        std::swap(parts[0], parts[1]);
      }
      mixture::Case both = mixture::Interleave("one shows", parts);
      both.TF[shown] = visible;
      both.Weights[shown] = 2.0;
      const double eps = 1e-3;
      an::PiecewiseMixture<double> pieces;
      ASSERT_EQ(pieces.Build(both.Mixture(), an::PiecewiseRelativeError(eps)), "");
      ASSERT_NE(pieces.GetSingle(), nullptr);
      EXPECT_EQ(pieces.GetSingleComponent(), shown);
      an::PiecewiseTransferFunction<double> single;
      ASSERT_EQ(single.Build(doubled, an::PiecewiseRelativeError(eps)), "");
      const Volumes volumes = both.MakeVolumes();
      for (unsigned i = 0; i < 20; ++i)
      {
        const adversarial::Ray ray = mixture::MakeRay(both, i);
        const an::RayResult<double> r = mixture::Piecewise(both, pieces, ray, eps);
        const an::Interval<double> whole{ 0.0, ray.Length };
        const an::RayResult<double> alone =
          an::IntegratePiecewise(volumes[shown], ray.Origin, ray.Direction, &whole, 1, single, eps);
        ASSERT_EQ(r.Error, "");
        EXPECT_EQ(r.RGBA, alone.RGBA) << "ray " << i;
        // The sampled methods' medium: the function with the weight in it,
        // the mixture's sum to rounding.
        const an::MixtureTransferFunction<double> medium = both.Mixture();
        ASSERT_NE(medium.GetSingle(), nullptr);
        EXPECT_EQ(medium.GetSingleComponent(), shown);
        const an::RayField<double, Volumes> field{ volumes, ray.Origin, ray.Direction };
        const an::RayField<double, Volume> one{ volumes[shown], ray.Origin, ray.Direction };
        const glm::dvec4 mixed =
          an::IntegrateRiemann(field, medium, ray.Length, 0.5, an::RiemannForm::Exponential).RGBA;
        const glm::dvec4 sampled = an::IntegrateRiemann(
          one, *medium.GetSingle(), ray.Length, 0.5, an::RiemannForm::Exponential)
                                     .RGBA;
        ExpectWithin(sampled, mixed, 1e-12);
      }
      both.TF[1 - shown] = visible;
      ASSERT_EQ(pieces.Build(both.Mixture(), an::PiecewiseRelativeError(eps)), "");
      EXPECT_EQ(pieces.GetSingle(), nullptr);
      EXPECT_EQ(both.Mixture().GetSingle(), nullptr);
    }
  }
}

// The adversarial mixtures (thin spikes, steps, extinction up to 20 per
// voxel, three components, both dependent mixtures): every channel of every
// ray within eps of the oracle at 1e-2, 1e-3 and 1e-5, and the Riemann sum
// at a step of 0.5 off by far more somewhere (the suite is not lenient).
TEST(Mixture, AdversarialMixturesWithinTolerance)
{
  constexpr unsigned Rays = 24;
  double riemannWorst = 0.0;
  for (const mixture::Case& c : mixture::MakeSuite())
  {
    std::vector<glm::dvec4> exact;
    for (unsigned i = 0; i < Rays; ++i)
    {
      exact.push_back(mixture::Exact(c, mixture::MakeRay(c, i)));
    }
    const Volumes volumes = c.MakeVolumes();
    const an::MixtureTransferFunction<double> mix = c.Mixture();
    for (const double eps : { 1e-2, 1e-3, 1e-5 })
    {
      an::PiecewiseMixture<double> pieces;
      ASSERT_EQ(pieces.Build(mix, an::PiecewiseRelativeError(eps)), "");
      double worst = 0.0, samples = 0.0;
      for (unsigned i = 0; i < Rays; ++i)
      {
        const adversarial::Ray ray = mixture::MakeRay(c, i);
        const an::RayResult<double> r = mixture::Piecewise(c, pieces, ray, eps);
        ASSERT_EQ(r.Error, "") << c.Name;
        for (int ch = 0; ch < 4; ++ch)
        {
          worst = std::max(worst, std::abs(r.RGBA[ch] - exact[i][ch]));
        }
        samples += static_cast<double>(r.Statistics.Pieces);
        if (eps == 1e-2)
        {
          const an::RayField<double, Volumes> field{ volumes, ray.Origin, ray.Direction };
          const an::RayResult<double> riemann =
            an::IntegrateRiemann(field, mix, ray.Length, 0.5, an::RiemannForm::Exponential);
          for (int ch = 0; ch < 4; ++ch)
          {
            riemannWorst = std::max(riemannWorst, std::abs(riemann.RGBA[ch] - exact[i][ch]));
          }
        }
      }
      std::printf("%-70s eps %.0e: max error %.2e, %.1f pieces per ray\n", c.Name.c_str(), eps,
        worst, samples / Rays);
      EXPECT_LE(worst, eps) << c.Name;
    }
  }
  EXPECT_GT(riemannWorst, 1e-2);
}

// The sampled methods through a mixture: the adaptive reference within
// 1e-6 of the oracle, the Riemann sum first order (halving the step halves
// its error, within a factor).
TEST(Mixture, SampledMethodsTakeTheSameMedium)
{
  const std::vector<mixture::Case> suite = mixture::MakeSuite();
  const mixture::Case& c = suite[2]; // three components
  const Volumes volumes = c.MakeVolumes();
  const an::MixtureTransferFunction<double> mix = c.Mixture();
  for (unsigned i = 0; i < 6; ++i)
  {
    const adversarial::Ray ray = mixture::MakeRay(c, i);
    const glm::dvec4 exact = mixture::Exact(c, ray);
    const an::RayField<double, Volumes> field{ volumes, ray.Origin, ray.Direction };
    const an::RayResult<double> reference = an::IntegrateReference(field, mix, ray.Length);
    ASSERT_EQ(reference.Error, "");
    ExpectWithin(reference.RGBA, exact, 1e-6);
    an::AdaptiveSettings<double> coupled;
    coupled.Tolerance = 1e-3;
    coupled.FieldMaximum = 255.0;
    const an::RayResult<double> adaptive = an::IntegrateAdaptive(field, mix, ray.Length, coupled);
    ASSERT_EQ(adaptive.Error, "");
    EXPECT_GT(adaptive.Statistics.Samples, 0);
  }
  // First order on a ray through smooth data and functions: the error at
  // h / 2 is about half the error at h.
  adversarial::Case a = adversarial::MakeVolume("smooth", adversarial::Smooth, 1);
  adversarial::Case b = adversarial::MakeVolume("smooth", adversarial::Smooth, 2);
  a.TF = Ramp(0.05, glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(0.0, 0.0, 1.0));
  b.TF = Ramp(0.02, glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(1.0, 1.0, 0.0));
  const mixture::Case smooth = mixture::Interleave("smooth", { a, b });
  const Volumes sv = smooth.MakeVolumes();
  const an::MixtureTransferFunction<double> smix = smooth.Mixture();
  const adversarial::Ray ray{ glm::dvec3(0.0, 20.3, 19.7), glm::dvec3(1.0, 0.0, 0.0), 39.0 };
  const glm::dvec4 exact = mixture::Exact(smooth, ray);
  const an::RayField<double, Volumes> field{ sv, ray.Origin, ray.Direction };
  auto error = [&](double h)
  {
    const glm::dvec4 rgba =
      an::IntegrateRiemann(field, smix, ray.Length, h, an::RiemannForm::Exponential).RGBA;
    return std::abs(rgba.r - exact.r) + std::abs(rgba.g - exact.g) + std::abs(rgba.a - exact.a);
  };
  const double e1 = error(0.02), e2 = error(0.01);
  EXPECT_GT(e1, 1e-6);
  EXPECT_NEAR(e1 / e2, 2.0, 0.5);
}

// VTK's alpha model: each component's extinction -ln(1 - alpha) / d
// approximated within a relative eps / 8 (Pieces.h), their sum and the
// emissions too; within eps of the oracle.
TEST(Mixture, AlphaModelWithinTolerance)
{
  mixture::Case c = mixture::MakeSuite()[2];
  for (int k = 0; k < 3; ++k)
  {
    c.TF[k] = adversarial::Random(30 + k, 12, 0.95);
    c.TF[k].SetOpacityModel(an::OpacityModel::Alpha, 1.5);
    c.TF[k].Finalize();
  }
  for (const double eps : { 1e-2, 1e-3 })
  {
    an::PiecewiseMixture<double> pieces;
    ASSERT_EQ(pieces.Build(c.Mixture(), an::PiecewiseRelativeError(eps)), "");
    for (unsigned i = 0; i < 12; ++i)
    {
      const adversarial::Ray ray = mixture::MakeRay(c, i);
      const an::RayResult<double> r = mixture::Piecewise(c, pieces, ray, eps);
      ASSERT_EQ(r.Error, "");
      ExpectWithin(r.RGBA, mixture::Exact(c, ray), eps);
    }
  }
}

// A NaN corner of one component empties its term in the cells it touches,
// the other component shows there still, in the piecewise and the sampled
// methods alike; a NaN in a dependent mixture empties those cells.
TEST(Mixture, NaNLeavesItsComponentOut)
{
  std::vector<double> data =
    AlongX(2, [](int k, int i) { return k == 0 ? 10.0 + 20.0 * i : 200.0 - 15.0 * i; });
  for (int n = 0; n < 8 * 3 * 3; ++n)
  {
    if (n % 8 == 3)
    {
      data[2 * n + 1] = std::nan(""); // component 1 undefined in cells 2 and 3
    }
  }
  const an::TransferFunction<double> tf0 = Ramp(0.3, glm::dvec3(0.0), glm::dvec3(1.0));
  const an::TransferFunction<double> tf1 =
    Ramp(0.7, glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(1.0, 0.0, 0.0));
  const an::TransferFunction<double>* f[2] = { &tf0, &tf1 };
  const double w[2] = { 1.0, 1.0 };
  an::MixtureTransferFunction<double> mixture;
  mixture.SetIndependent(2, f, w);
  const an::RayResult<double> r = PiecewiseAlongX(MakeVolumes(data, 2), mixture, 1e-6);
  ASSERT_EQ(r.Error, "");
  // The same ray with component 1's extinction removed from cells 2 and 3:
  // component 0 alone there, both elsewhere (three parts composited).
  const double T1 = std::exp(-(0.3 + 0.7) * 2.0), T2 = std::exp(-0.3 * 2.0);
  EXPECT_NEAR(1.0 - r.RGBA.a, T1 * T2 * std::exp(-(0.3 + 0.7) * 3.0), 1e-6);
  const Volumes volumes = MakeVolumes(data, 2);
  const an::RayField<double, Volumes> field{ volumes, glm::dvec3(0.0, 1.0, 1.0),
    glm::dvec3(1.0, 0.0, 0.0) };
  const an::RayResult<double> reference = an::IntegrateReference(field, mixture, 7.0);
  ExpectWithin(reference.RGBA, r.RGBA, 1e-5);

  an::MixtureTransferFunction<double> dependent;
  dependent.SetColourOpacity(tf1);
  const an::RayResult<double> d = PiecewiseAlongX(MakeVolumes(data, 2), dependent, 1e-6);
  ASSERT_EQ(d.Error, "");
  // Component 1 is the opacity: tau 0.7 outside cells 2 and 3, nothing there.
  EXPECT_NEAR(1.0 - d.RGBA.a, std::exp(-0.7 * 5.0), 1e-6);
}

// Bad input gets a clear error, never a result.
TEST(Mixture, RefusesBadInput)
{
  const an::TransferFunction<double> tf = Ramp(1.0, glm::dvec3(0.0), glm::dvec3(1.0));
  const an::TransferFunction<double>* f[4] = { &tf, &tf, &tf, &tf };
  an::MixtureTransferFunction<double> m;
  const double negative[2] = { 1.0, -1.0 };
  m.SetIndependent(2, f, negative);
  EXPECT_NE(m.Validate(), "");
  const double nan[2] = { 1.0, std::nan("") };
  m.SetIndependent(2, f, nan);
  EXPECT_NE(m.Validate(), "");
  const double ones[5] = { 1.0, 1.0, 1.0, 1.0, 1.0 };
  m.SetIndependent(0, f, ones);
  EXPECT_NE(m.Validate(), "");
  m.SetRGBOpacity(tf, 2.0);
  EXPECT_NE(m.Validate(), "");
  an::TransferFunction<double> empty;
  const an::TransferFunction<double>* g[2] = { &tf, &empty };
  m.SetIndependent(2, g, ones);
  EXPECT_NE(m.Validate(), "");
  an::PiecewiseMixture<double> pieces;
  EXPECT_NE(pieces.Build(m, 1e-3), "");

  // A mixture built for two components, a volume of three; a bad tolerance.
  m.SetIndependent(2, f, ones);
  ASSERT_EQ(pieces.Build(m, 1e-3), "");
  const std::vector<double> data = AlongX(3, [](int, int i) { return 10.0 * i; });
  const Volumes three = MakeVolumes(data, 3);
  const an::Interval<double> whole{ 0.0, 7.0 };
  EXPECT_NE(an::IntegratePiecewiseMixture(
              three, glm::dvec3(0.0, 1.0, 1.0), glm::dvec3(1.0, 0.0, 0.0), &whole, 1, pieces, 1e-3)
              .Error,
    "");
  const std::vector<double> pair = AlongX(2, [](int, int i) { return 10.0 * i; });
  const Volumes two = MakeVolumes(pair, 2);
  EXPECT_NE(an::IntegratePiecewiseMixture(
              two, glm::dvec3(0.0, 1.0, 1.0), glm::dvec3(1.0, 0.0, 0.0), &whole, 1, pieces, 0.0)
              .Error,
    "");
}
