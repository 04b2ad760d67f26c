// Clipping planes and cropping regions (Clipping.h): the kept intervals hold
// exactly the points the planes and regions keep (checked point by point on
// random rays, planes and flags), their ends lie on the planes, and a clipped
// or cropped constant volume integrates to its closed form.
#include "AdversarialCases.h"

#include "avos/numerics/Clipping.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace an = avos::numerics;
using Region = an::ClipRegion<double>;
using Intervals = std::vector<an::Interval<double>>;

namespace
{
// What the region keeps at p, by definition (not through Kept).
bool Keeps(
  const std::vector<Region::HalfSpace>& planes, const double* crop, int flags, const glm::dvec3& p)
{
  for (const auto& h : planes)
  {
    if (glm::dot(h.Normal, p) + h.Offset < 0.0)
    {
      return false;
    }
  }
  if (!crop)
  {
    return true;
  }
  int region = 0;
  for (int a = 0, w = 1; a < 3; ++a, w *= 3)
  {
    region += w * (p[a] < crop[2 * a] ? 0 : (p[a] > crop[2 * a + 1] ? 2 : 1));
  }
  return (flags >> region) & 1;
}

bool Inside(const Intervals& kept, double t)
{
  for (const auto& i : kept)
  {
    if (t >= i.Begin && t <= i.End)
    {
      return true;
    }
  }
  return false;
}
} // namespace

// Random rays, up to three random planes, random cropping planes and flags:
// every point of the ray farther than 1e-9 from an interval end is kept
// exactly when the definition keeps it; every end is 0, D or a root of a
// plane's equation.
TEST(Clipping, KeptIntervalsMatchTheDefinition)
{
  const int dims[3] = { 20, 16, 12 };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), box(0.0, 20.0);
  for (int trial = 0; trial < 2000; ++trial)
  {
    const adversarial::Ray ray = adversarial::RandomRay(dims, rng, 1.0);
    std::vector<Region::HalfSpace> planes;
    Region region;
    for (int p = trial % 4; p > 0; --p)
    {
      const glm::dvec3 n(unit(rng), unit(rng), unit(rng));
      const glm::dvec3 o(box(rng), 0.8 * box(rng), 0.6 * box(rng));
      planes.push_back({ n, -glm::dot(n, o) });
      region.AddPlane(n, -glm::dot(n, o));
    }
    double crop[6];
    const bool cropping = trial % 3 != 0;
    const int flags = static_cast<int>(rng() & Region::AllRegions);
    if (cropping)
    {
      for (int a = 0; a < 3; ++a)
      {
        const double x = box(rng) * dims[a] / 20.0, y = box(rng) * dims[a] / 20.0;
        crop[2 * a] = std::min(x, y);
        crop[2 * a + 1] = std::max(x, y);
      }
      region.SetCropping(crop, flags);
    }
    ASSERT_EQ(region.Validate(), "");
    Intervals kept;
    region.Kept(ray.Origin, ray.Direction, ray.Length, kept);
    for (std::size_t i = 0; i < kept.size(); ++i)
    {
      ASSERT_LT(kept[i].Begin, kept[i].End);
      ASSERT_GE(kept[i].Begin, 0.0);
      ASSERT_LE(kept[i].End, ray.Length);
      if (i > 0)
      {
        ASSERT_LT(kept[i - 1].End, kept[i].Begin); // disjoint, merged when touching
      }
    }
    for (int s = 0; s <= 400; ++s)
    {
      const double t = ray.Length * s / 400.0;
      bool nearEnd = false;
      for (const auto& i : kept)
      {
        nearEnd = nearEnd || std::abs(t - i.Begin) < 1e-9 || std::abs(t - i.End) < 1e-9;
      }
      if (nearEnd)
      {
        continue;
      }
      const glm::dvec3 p = ray.Origin + t * ray.Direction;
      ASSERT_EQ(Inside(kept, t), Keeps(planes, cropping ? crop : nullptr, flags, p))
        << "trial " << trial << ", t " << t;
    }
    // Ends on planes: some plane's equation (or cropping coordinate) is zero there.
    for (const auto& i : kept)
    {
      for (const double t : { i.Begin, i.End })
      {
        if (t == 0.0 || t == ray.Length)
        {
          continue;
        }
        const glm::dvec3 p = ray.Origin + t * ray.Direction;
        double closest = std::numeric_limits<double>::infinity();
        for (const auto& h : planes)
        {
          closest = std::min(closest, std::abs(glm::dot(h.Normal, p) + h.Offset));
        }
        for (int c = 0; cropping && c < 6; ++c)
        {
          closest = std::min(closest, std::abs(p[c / 2] - crop[c]));
        }
        EXPECT_LT(closest, 1e-12) << "trial " << trial;
      }
    }
  }
}

TEST(Clipping, ParallelPlanesKeepAllOrNothing)
{
  Region region;
  region.AddPlane({ 1.0, 0.0, 0.0 }, -5.0); // x >= 5
  Intervals kept;
  region.Kept({ 6.0, 0.0, 0.0 }, { 0.0, 1.0, 0.0 }, 10.0, kept);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].Begin, 0.0);
  EXPECT_EQ(kept[0].End, 10.0);
  region.Kept({ 4.0, 0.0, 0.0 }, { 0.0, 1.0, 0.0 }, 10.0, kept);
  EXPECT_TRUE(kept.empty());
}

TEST(Clipping, Intersect)
{
  const Intervals a{ { 0.0, 2.0 }, { 3.0, 5.0 }, { 6.0, 9.0 } };
  const Intervals b{ { 1.0, 3.5 }, { 4.0, 7.0 } };
  Intervals out;
  Region::Intersect(a, b, out);
  const Intervals expected{ { 1.0, 2.0 }, { 3.0, 3.5 }, { 4.0, 5.0 }, { 6.0, 7.0 } };
  ASSERT_EQ(out.size(), expected.size());
  for (std::size_t i = 0; i < out.size(); ++i)
  {
    EXPECT_EQ(out[i].Begin, expected[i].Begin);
    EXPECT_EQ(out[i].End, expected[i].End);
  }
}

TEST(Clipping, RefusesUnusableSettings)
{
  Region zero;
  zero.AddPlane({ 0.0, 0.0, 0.0 }, 1.0);
  EXPECT_NE(zero.Validate(), "");
  Region nan;
  nan.AddPlane({ 1.0, 0.0, 0.0 }, std::numeric_limits<double>::quiet_NaN());
  EXPECT_NE(nan.Validate(), "");
  const double reversed[6] = { 5.0, 1.0, 0.0, 1.0, 0.0, 1.0 };
  Region crop;
  crop.SetCropping(reversed, 1 << 13);
  EXPECT_NE(crop.Validate(), "");
  const double planes[6] = { 1.0, 5.0, 0.0, 1.0, 0.0, 1.0 };
  Region flags;
  flags.SetCropping(planes, 1 << 27);
  EXPECT_NE(flags.Validate(), "");
  flags.SetCropping(planes, 1 << 13);
  EXPECT_EQ(flags.Validate(), "");
}

// A constant volume (tau 0.3 per voxel unit, colour c) along x from 0 to 19:
// clipped to x >= 7.5 and cropped to the sub-volume x in [2, 12], the
// piecewise method (segments = the kept part) gives alpha = 1 - e^{-tau L},
// I = c alpha with L = 12 - 7.5, exactly.
TEST(Clipping, ClippedConstantVolumeIntegratesToItsClosedForm)
{
  const int dims[3] = { 20, 4, 4 };
  const std::vector<double> data(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], 0.5);
  const an::TrilinearVolume<double, double> volume(data.data(), dims);
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.3);
  tf.AddOpacityKnot(1.0, 0.3);
  tf.AddColorKnot(0.0, 0.9, 0.4, 0.1);
  tf.Finalize();
  an::PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(tf, an::PiecewiseRelativeError(1e-10)), "");

  Region region;
  region.AddPlane({ 2.0, 0.0, 0.0 }, -15.0); // 2 x - 15 >= 0: x >= 7.5
  const double crop[6] = { 2.0, 12.0, -1.0, 10.0, -1.0, 10.0 };
  region.SetCropping(crop, 1 << 13); // VTK's CroppingRegionFlags for a sub-volume
  const glm::dvec3 origin(0.0, 1.5, 1.5), direction(1.0, 0.0, 0.0);
  Intervals kept;
  region.Kept(origin, direction, 19.0, kept);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_DOUBLE_EQ(kept[0].Begin, 7.5);
  EXPECT_DOUBLE_EQ(kept[0].End, 12.0);
  const auto r = an::IntegratePiecewise(
    volume, origin, direction, kept.data(), kept.size(), pieces, 1e-10, false);
  ASSERT_EQ(r.Error, "");
  const double alpha = -std::expm1(-0.3 * 4.5);
  EXPECT_NEAR(r.RGBA.a, alpha, 1e-12);
  EXPECT_NEAR(r.RGBA.r, 0.9 * alpha, 1e-12);
  EXPECT_NEAR(r.RGBA.b, 0.1 * alpha, 1e-12);

  // VTK_CROP_FENCE (0x2ebfeba) keeps regions 12, 13 and 14, the three this
  // ray crosses: only the plane clips.
  Region fence;
  fence.AddPlane({ 2.0, 0.0, 0.0 }, -15.0);
  fence.SetCropping(crop, 0x2ebfeba);
  fence.Kept(origin, direction, 19.0, kept);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_DOUBLE_EQ(kept[0].Begin, 7.5);
  EXPECT_DOUBLE_EQ(kept[0].End, 19.0);
}
