// The constant-time lookups of a finalized transfer function (Classify,
// HasKnotIn, HasJumpIn) against the plain searches over its knots, which an
// unfinalized copy of the same knots uses. (Values agree to rounding: the
// finalized pieces store slopes, the searches interpolate between knots.)
#include "avos/numerics/TransferFunction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace avos::numerics;

namespace
{
struct Pair
{
  TransferFunction<double> Fast;  // finalized
  TransferFunction<double> Plain; // the same knots, searched
};

// Knots in [lo, hi], clustered or spread, with repeated values (jumps).
Pair RandomPair(unsigned seed, double lo, double hi, int knots)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> values;
  for (int i = 0; i < knots; ++i)
  {
    // Every third seed crowds the knots near lo: many knots per bucket.
    const double x = seed % 3 == 0 ? std::pow(u(rng), 8.0) : u(rng);
    values.push_back(lo + (hi - lo) * x);
    if (u(rng) < 0.2)
    {
      values.push_back(values.back()); // a jump
    }
  }
  std::sort(values.begin(), values.end());
  Pair p;
  for (double v : values)
  {
    const double r = u(rng), g = u(rng), b = u(rng), tau = 3.0 * u(rng);
    for (TransferFunction<double>* tf : { &p.Fast, &p.Plain })
    {
      if (seed % 2 == 0 || v < 0.5 * (lo + hi))
      {
        tf->AddColorKnot(v, r, g, b);
      }
      tf->AddOpacityKnot(v, tau);
    }
  }
  if (seed % 2 != 0)
  {
    for (TransferFunction<double>* tf : { &p.Fast, &p.Plain })
    {
      tf->AddColorKnot(hi, 1.0, 0.0, 0.0);
    }
  }
  p.Fast.Finalize();
  return p;
}

std::vector<double> Probes(const TransferFunction<double>& tf, double lo, double hi)
{
  std::vector<double> probes;
  for (double v : tf.GetKnotValues())
  {
    probes.insert(probes.end(),
      { v, std::nextafter(v, -1e300), std::nextafter(v, 1e300), v - 1e-7 * (hi - lo) });
  }
  for (int i = -10; i <= 1010; ++i)
  {
    probes.push_back(lo + (hi - lo) * i / 1000.0);
  }
  probes.insert(probes.end(),
    { -1e300, 1e300, std::numeric_limits<double>::infinity(),
      -std::numeric_limits<double>::infinity() });
  return probes;
}
} // namespace

TEST(TransferFunction, FastLookupsEqualThePlainSearches)
{
  const double ranges[][2] = { { 0.0, 1.0 }, { -1000.0, 65535.0 }, { 1e-9, 2e-9 } };
  for (unsigned seed = 0; seed < 30; ++seed)
  {
    for (const auto& range : ranges)
    {
      for (int knots : { 1, 2, 7, 300 })
      {
        const Pair p = RandomPair(seed, range[0], range[1], knots);
        const std::vector<double> probes = Probes(p.Plain, range[0], range[1]);
        for (double s : probes)
        {
          double tauFast, tauPlain;
          glm::dvec3 colorFast, colorPlain;
          p.Fast.Classify(s, tauFast, colorFast);
          p.Plain.Classify(s, tauPlain, colorPlain);
          ASSERT_NEAR(tauFast, tauPlain, 1e-9 * (1 + tauPlain)) << seed << " s " << s;
          for (int c = 0; c < 3; ++c)
          {
            ASSERT_NEAR(colorFast[c], colorPlain[c], 1e-9) << seed << " s " << s;
          }
        }
        // Intervals between probes, knots included as ends.
        std::mt19937 rng(seed);
        std::uniform_int_distribution<std::size_t> pick(0, probes.size() - 1);
        for (int i = 0; i < 2000; ++i)
        {
          const double a = probes[pick(rng)], b = probes[pick(rng)];
          ASSERT_EQ(p.Fast.HasKnotIn(a, b), p.Plain.HasKnotIn(a, b))
            << seed << " " << a << " " << b;
          ASSERT_EQ(p.Fast.HasJumpIn(a, b), p.Plain.HasJumpIn(a, b))
            << seed << " " << a << " " << b;
        }
      }
    }
  }
}

// A mutation check of the test above: the plain searches do see jumps and
// knots, so agreeing with them means something.
TEST(TransferFunction, PlainSearchesSeeKnotsAndJumps)
{
  TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(0.5, 0.0);
  tf.AddOpacityKnot(0.5, 1.0);
  tf.AddOpacityKnot(1.0, 1.0);
  tf.AddColorKnot(0.0, 0.0, 0.0, 0.0);
  tf.AddColorKnot(0.25, 1.0, 1.0, 1.0);
  tf.Finalize();
  EXPECT_TRUE(tf.HasJumpIn(0.4, 0.6));
  EXPECT_FALSE(tf.HasJumpIn(0.5, 0.6)); // open interval
  EXPECT_FALSE(tf.HasJumpIn(0.4, 0.5));
  EXPECT_TRUE(tf.HasKnotIn(0.2, 0.3));
  EXPECT_FALSE(tf.HasKnotIn(0.26, 0.49));
  EXPECT_FALSE(tf.HasJumpIn(0.2, 0.3));
}

// Cast<float>() keeps the knots, the model and finalization: tau and C of the
// float copy equal the double ones to float's rounding of their arguments
// (relative 1e-6, which would fail for any knot or model lost on the way).
TEST(TransferFunction, CastToFloatKeepsKnotsAndModel)
{
  for (OpacityModel model : { OpacityModel::Extinction, OpacityModel::Alpha })
  {
    TransferFunction<double> tf;
    tf.AddOpacityKnot(10.0, 0.0);
    tf.AddOpacityKnot(40.0, 0.3);
    tf.AddOpacityKnot(40.0, 0.6); // a jump
    tf.AddOpacityKnot(90.0, 0.9);
    tf.AddColorKnot(10.0, 0.1, 0.2, 0.3);
    tf.AddColorKnot(60.0, 0.9, 0.5, 0.1);
    tf.SetOpacityModel(model, 0.5);
    tf.Finalize();
    const TransferFunction<float> f = tf.Cast<float>();
    ASSERT_EQ(f.GetOpacityModel(), model);
    ASSERT_EQ(f.GetUnitDistance(), 0.5f);
    ASSERT_EQ(f.GetKnotValues().size(), tf.GetKnotValues().size());
    for (double s = 0.0; s <= 100.0; s += 0.37)
    {
      double tau;
      TransferFunction<double>::Color c;
      tf.Classify(s, tau, c);
      float tauF;
      TransferFunction<float>::Color cF;
      f.Classify(static_cast<float>(s), tauF, cF);
      ASSERT_NEAR(tauF, tau, 1e-6 * std::max(1.0, tau)) << s;
      for (int k = 0; k < 3; ++k)
      {
        ASSERT_NEAR(cF[k], c[k], 1e-6) << s;
      }
    }
  }
}
