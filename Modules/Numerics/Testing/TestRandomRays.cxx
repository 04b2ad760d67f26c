// On 10,000 seeded random rays the adaptive evaluators meet eps = 1e-2, 5e-3
// and 1e-3 on at least 99.9 % of rays per channel (double), against the
// reference evaluator. The float floor is measured and bounded.
//
// Measured here (double, h_min 1e-3), per channel R G B A, coupled and
// decoupled alike: eps 1e-2: 99.99 100.00 99.99 99.99 %; eps 5e-3: 99.97
// 99.99 100.00 99.98 %; eps 1e-3: 99.92 99.96 99.94 99.94 %. The misses are
// rays with features narrower than a step, where Simpson's estimate
// |D - S| / 15 is fooled. Float, eps 1e-3: 99.92-99.96 % within 1e-3 but only
// 80-90 % within 1e-4: single precision's floor is about 1e-4.
#include "RandomRays.h"
#include "avos/numerics/RayIntegrators.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>

using namespace avos::numerics;

namespace
{
constexpr int RayCount = 10000;

const std::vector<glm::dvec4>& References()
{
  static const std::vector<glm::dvec4> references = []
  {
    std::vector<glm::dvec4> r(RayCount);
    for (int i = 0; i < RayCount; ++i)
    {
      const auto ray = randomrays::Make<double>(i);
      r[i] = IntegrateReference(ray, ray.TF, ray.Length).RGBA;
    }
    return r;
  }();
  return references;
}

// Fraction of rays within eps per channel.
template <typename Real>
std::array<double, 4> WithinTolerance(const AdaptiveSettings<Real>& settings, double eps)
{
  const auto& references = References();
  std::array<long, 4> good{ 0, 0, 0, 0 };
  for (int i = 0; i < RayCount; ++i)
  {
    const auto ray = randomrays::Make<Real>(i);
    const auto result = IntegrateAdaptive(ray, ray.TF, ray.Length, settings);
    for (int c = 0; c < 4; ++c)
    {
      good[c] += std::abs(double(result.RGBA[c]) - references[i][c]) <= eps;
    }
  }
  std::array<double, 4> fraction;
  for (int c = 0; c < 4; ++c)
  {
    fraction[c] = double(good[c]) / RayCount;
  }
  return fraction;
}
}

class RandomRays : public testing::TestWithParam<std::tuple<double, Strategy>>
{
};

TEST_P(RandomRays, MeetTolerance)
{
  AdaptiveSettings<double> settings;
  settings.Tolerance = std::get<0>(GetParam());
  settings.MinimumStep = 1e-3;
  settings.Coupling = std::get<1>(GetParam());
  const auto fraction = WithinTolerance(settings, settings.Tolerance);
  std::printf("eps %g %s: within eps R %.4f%% G %.4f%% B %.4f%% A %.4f%%\n", settings.Tolerance,
    settings.Coupling == Strategy::Coupled ? "coupled" : "decoupled", 100 * fraction[0],
    100 * fraction[1], 100 * fraction[2], 100 * fraction[3]);
  for (int c = 0; c < 4; ++c)
  {
    EXPECT_GE(fraction[c], 0.999) << "channel " << c;
  }
}

INSTANTIATE_TEST_SUITE_P(Tolerances, RandomRays,
  testing::Combine(
    testing::Values(1e-2, 5e-3, 1e-3), testing::Values(Strategy::Coupled, Strategy::Decoupled)));

TEST(RandomRaysPaperSettings, Report)
{
  AdaptiveSettings<double> settings; // h0 0.5, h_min 0.1, h_max 2
  for (double eps : { 1e-2, 1e-3 })
  {
    settings.Tolerance = eps;
    const auto f = WithinTolerance(settings, eps);
    std::printf("paper settings, eps %g: within eps R %.3f%% G %.3f%% B %.3f%% A %.3f%%\n", eps,
      100 * f[0], 100 * f[1], 100 * f[2], 100 * f[3]);
    for (double v : f)
    {
      EXPECT_GT(v, 0.5); // sanity only: see the file comment
    }
  }
}

TEST(RandomRaysFloat, AccuracyFloor)
{
  // Single precision (the GPU's): rounding in theta and the sums limits what
  // eps can be met (see the file comment); the bound asserts that eps = 1e-3
  // still holds on 99.9 % of rays.
  AdaptiveSettings<float> settings;
  settings.Tolerance = 1e-3f;
  settings.MinimumStep = 1e-3f;
  const auto f = WithinTolerance(settings, 1e-3);
  const auto g = WithinTolerance(settings, 1e-4);
  std::printf("float, eps 1e-3: within 1e-3 R %.3f%% G %.3f%% B %.3f%% A %.3f%%; within 1e-4 "
              "R %.3f%% G %.3f%% B %.3f%% A %.3f%%\n",
    100 * f[0], 100 * f[1], 100 * f[2], 100 * f[3], 100 * g[0], 100 * g[1], 100 * g[2], 100 * g[3]);
  for (double v : f)
  {
    EXPECT_GE(v, 0.999);
  }
}
