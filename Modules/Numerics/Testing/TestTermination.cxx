// Termination and defined results under adversarial input: every run stays
// within MaximumAttempts(D, settings) and 5 samples per attempt, and gives a
// finite RGBA in [0, 1].
#include "RandomRays.h"
#include "avos/numerics/RayIntegrators.h"

#include <gtest/gtest.h>

#include <limits>

using namespace avos::numerics;

namespace
{
template <typename Real>
void ExpectBoundedAndFinite(const RayResult<Real>& r, Real D, const AdaptiveSettings<Real>& s)
{
  EXPECT_TRUE(r.Error.empty()) << r.Error;
  EXPECT_LE(r.Statistics.Attempts(), MaximumAttempts(D, s));
  EXPECT_LE(r.Statistics.Samples, 5 * r.Statistics.Attempts() + 1);
  for (int c = 0; c < 4; ++c)
  {
    EXPECT_TRUE(std::isfinite(r.RGBA[c]));
    EXPECT_GE(r.RGBA[c], Real(-1e-6));
    EXPECT_LE(r.RGBA[c], Real(1 + 1e-6));
  }
}

template <typename Real>
TransferFunction<Real> Spike(Real tau)
{
  TransferFunction<Real> tf;
  tf.AddColorKnot(Real(0), Real(1), Real(0.5), Real(0));
  tf.AddOpacityKnot(Real(0), Real(0));
  tf.AddOpacityKnot(Real(0.5), Real(0));
  tf.AddOpacityKnot(Real(0.5), tau); // step up
  tf.AddOpacityKnot(Real(0.5001), Real(0));
  tf.AddOpacityKnot(Real(1), Real(0));
  return tf;
}

template <typename Real>
void Adversarial()
{
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();
  for (Real tau : { Real(1), Real(1e3), Real(1e6) })
  {
    const auto tf = Spike(tau);
    auto oscillating = [](Real t) { return Real(0.5) + Real(0.5) * std::sin(Real(37) * t); };
    auto nanField = [&](Real t) { return t > Real(3) && t < Real(4) ? nan : Real(0.5); };
    auto infField = [&](Real t) { return t > Real(2) ? inf : -inf; };
    for (Real eps : { Real(1e-2), Real(1e-15) })
    {
      for (Real D : { Real(0), Real(0.01), Real(10), Real(300) })
      {
        AdaptiveSettings<Real> s;
        s.Tolerance = eps;
        for (Strategy strategy : { Strategy::Coupled, Strategy::Decoupled })
        {
          s.Coupling = strategy;
          ExpectBoundedAndFinite(IntegrateAdaptive(oscillating, tf, D, s), D, s);
          ExpectBoundedAndFinite(IntegrateAdaptive(nanField, tf, D, s), D, s);
          ExpectBoundedAndFinite(IntegrateAdaptive(infField, tf, D, s), D, s);
        }
        s.MinimumStep = s.MaximumStep = Real(0.7); // h_min = h_max
        ExpectBoundedAndFinite(IntegrateAdaptive(oscillating, tf, D, s), D, s);
        s.MinimumStep = Real(1e-6);
        s.MaximumStep = Real(4);
        s.InitialStep = Real(1000); // h0 > D
        ExpectBoundedAndFinite(IntegrateAdaptive(oscillating, tf, D, s), D, s);
      }
    }
  }
}
}

TEST(Termination, AdversarialDouble)
{
  Adversarial<double>();
}

TEST(Termination, AdversarialFloat)
{
  Adversarial<float>();
}

TEST(Termination, NaNScalarsAreTransparent)
{
  TransferFunction<double> tf;
  tf.AddColorKnot(0, 1, 1, 1);
  tf.AddOpacityKnot(0, 0.5);
  auto allNaN = [](double) { return std::numeric_limits<double>::quiet_NaN(); };
  const auto r = IntegrateAdaptive(allNaN, tf, 10.0, AdaptiveSettings<double>());
  EXPECT_EQ(r.RGBA, glm::dvec4(0.0));
  EXPECT_EQ(IntegrateRiemann(allNaN, tf, 10.0, 0.5, RiemannForm::Linear).RGBA, glm::dvec4(0.0));
}

TEST(Termination, OpaqueAlphaIsFinite)
{
  // VTK's model with alpha = 1: finite extinction, an opaque ray, no NaN.
  TransferFunction<double> tf;
  tf.SetOpacityModel(OpacityModel::Alpha, 0.5);
  tf.AddColorKnot(0, 0.25, 0.5, 1);
  tf.AddOpacityKnot(0, 1.0);
  EXPECT_TRUE(std::isfinite(tf.GetExtinction(0.3)));
  const auto r =
    IntegrateAdaptive([](double) { return 0.3; }, tf, 10.0, AdaptiveSettings<double>());
  EXPECT_NEAR(r.RGBA[3], 1.0, 1e-12);
  EXPECT_NEAR(r.RGBA[2], 1.0, 0.01);
  EXPECT_TRUE(r.Statistics.Terminated);
}

TEST(Termination, InvalidInputIsReported)
{
  TransferFunction<double> tf;
  auto field = [](double) { return 0.0; };
  EXPECT_NE(IntegrateAdaptive(field, tf, 1.0, AdaptiveSettings<double>()).Error, "");
  tf.AddColorKnot(0, 1, 1, 1);
  tf.AddOpacityKnot(0, 1);
  AdaptiveSettings<double> s;
  s.Tolerance = 0;
  EXPECT_NE(IntegrateAdaptive(field, tf, 1.0, s).Error, "");
  s = AdaptiveSettings<double>();
  s.MinimumStep = 3;
  s.MaximumStep = 2;
  EXPECT_NE(IntegrateAdaptive(field, tf, 1.0, s).Error, "");
  s = AdaptiveSettings<double>();
  EXPECT_NE(IntegrateAdaptive(field, tf, std::nan(""), s).Error, "");
  EXPECT_NE(IntegrateAdaptive(field, tf, -1.0, s).Error, "");
  EXPECT_NE(IntegrateRiemann(field, tf, 1.0, 0.0, RiemannForm::Linear).Error, "");
  EXPECT_NE(IntegrateSimpson(field, tf, 1.0, -1.0).Error, "");
  TransferFunction<double> bad;
  bad.AddColorKnot(0, 2, 0, 0);
  bad.AddOpacityKnot(0, 1);
  EXPECT_NE(IntegrateAdaptive(field, bad, 1.0, s).Error, "");
}

TEST(Statistics, StepsRecordedAndCounted)
{
  TransferFunction<double> tf;
  tf.AddColorKnot(0, 1, 0, 0);
  tf.AddOpacityKnot(0, 0);
  tf.AddOpacityKnot(1, 1);
  std::vector<StepRecord<double>> steps;
  AdaptiveSettings<double> s;
  s.Tolerance = 1e-3;
  s.EarlyTermination = false;
  auto field = [](double t) { return 0.5 + 0.5 * std::sin(t); };
  const auto r = IntegrateAdaptive(field, tf, 20.0, s, &steps);
  // The logged steps tile [0, D] without gaps; their opacity grows to the
  // ray's alpha.
  ASSERT_FALSE(steps.empty());
  double t = 0, opacity = 0;
  for (const auto& step : steps)
  {
    EXPECT_NEAR(step.Start, t, 1e-12);
    EXPECT_GE(step.Opacity, opacity);
    t = step.Start + step.Length;
    opacity = step.Opacity;
  }
  EXPECT_NEAR(t, 20.0, 1e-12);
  EXPECT_DOUBLE_EQ(opacity, r.RGBA.a);
  // Riemann logs its steps too.
  steps.clear();
  const Interval<double> whole{ 0.0, 20.0 };
  const auto riemann =
    IntegrateRiemann(field, tf, 20.0, 0.5, RiemannForm::Exponential, &whole, 1, 0.0, &steps);
  ASSERT_EQ(steps.size(), 40u);
  EXPECT_DOUBLE_EQ(steps.back().Opacity, riemann.RGBA.a);
  EXPECT_GT(r.Statistics.Accepted, 0);
  EXPECT_GE(r.Statistics.SmallestStep, s.MinimumStep);
  EXPECT_LE(r.Statistics.LargestStep, s.MaximumStep);
  EXPECT_GT(r.Statistics.Samples, 0);
}

// The one-search lookup of a finalized transfer function gives what the
// plain evaluators give, at knots, jumps, between knots, outside, at +-inf.
TEST(TransferFunction, ClassifyMatchesTheEvaluators)
{
  for (unsigned seed = 0; seed < 40; ++seed)
  {
    auto tf = randomrays::Make<double>(seed).TF; // finalized, jumps in odd seeds
    std::vector<double> probes = tf.GetKnotValues();
    for (double v : tf.GetKnotValues())
    {
      probes.push_back(v - 1e-9);
      probes.push_back(v + 0.37);
    }
    probes.push_back(-1e300);
    probes.push_back(std::numeric_limits<double>::infinity());
    probes.push_back(-std::numeric_limits<double>::infinity());
    for (double s : probes)
    {
      double tau;
      glm::dvec3 color;
      tf.Classify(s, tau, color);
      EXPECT_NEAR(tau, tf.GetExtinction(s), 1e-12 * (1 + tau)) << "seed " << seed << " s " << s;
      for (int c = 0; c < 3; ++c)
      {
        EXPECT_NEAR(color[c], tf.GetColor(s)[c], 1e-12) << "seed " << seed << " s " << s;
      }
    }
  }
}
