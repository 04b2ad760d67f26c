// The packet walk (avos/engine/EmptySpace.h) on every dispatch target the
// library was built with and the CPU runs, against the scalar walk
// (numerics::EmptySpaceMap::Segments): the same segments to the bit, on a
// volume with superblocks of every kind and partial ones at its far faces,
// for random rays, rays along axes and block faces, diagonals through
// block corners (ties between axes), zero and negative direction
// components, empty rays, and packets of every size from 1 to 19 rays.
#include "avos/engine/EmptySpace.h"

#include "PatchVolume.h"
#include "TargetTest.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace an = avos::numerics;
namespace ae = avos::engine;

namespace
{
struct Ray
{
  glm::dvec3 Origin, Direction;
  double Length;
};

class PacketWalkTargets : public avostest::TargetTest
{
};

// 70 x 61 x 57 points: x < 30 all visible (whole superblocks), z > 44 zero
// (superblocks of no visible block), random 5-cell patches elsewhere (some
// visible blocks), partial blocks and superblocks at the far faces.
an::EmptySpaceMap<double> MakeMap()
{
  const int dims[3] = { 70, 61, 57 };
  const std::vector<std::uint8_t> data = avostest::PatchVolume(dims, 5, 30, 44);
  an::TransferFunction<double> tf;
  tf.AddColorKnot(0, 1, 1, 1);
  tf.AddOpacityKnot(0, 0);
  tf.AddOpacityKnot(220, 0);
  tf.AddOpacityKnot(255, 0.5);
  an::EmptySpaceMap<double> map;
  map.SetDimensions(dims);
  map.ComputeRanges(data.data());
  map.Classify(tf);
  return map;
}

std::vector<Ray> MakeRays()
{
  const double dims[3] = { 70, 61, 57 };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Ray> rays;
  for (int r = 0; r < 4000; ++r)
  {
    glm::dvec3 a, b;
    for (int c = 0; c < 3; ++c)
    {
      a[c] = u(rng) * (dims[c] - 1);
      b[c] = u(rng) * (dims[c] - 1);
    }
    switch (r % 8)
    {
      case 1: // along an axis, either way
        b = a;
        b[r % 3] = (r / 8) % 2 ? 0.0 : dims[r % 3] - 1;
        break;
      case 2: // along a block face
        a = glm::dvec3(4.0 * (r % 7), 4.0 * (r % 5), 0.0);
        b = glm::dvec3(a.x, a.y, dims[2] - 1);
        break;
      case 3: // a diagonal through block corners: every axis ties
        a = glm::dvec3(0.0);
        b = glm::dvec3(56.0);
        break;
      case 4: // in a plane: one zero component
        b[r % 3] = a[r % 3];
        break;
      case 5: // from a superblock corner, backwards
        a = glm::dvec3(64.0, 48.0, 48.0);
        break;
      default:
        break;
    }
    const double length = glm::length(b - a);
    rays.push_back(
      { a, length > 0.0 ? (b - a) / length : glm::dvec3(1, 0, 0), r % 97 == 0 ? 0.0 : length });
  }
  return rays;
}
} // namespace

TEST_P(PacketWalkTargets, SegmentsAreTheScalarWalks)
{
  EXPECT_STREQ(ae::PacketSegmentsTarget(), hwy::TargetName(this->GetParam()));
  const an::EmptySpaceMap<double> map = MakeMap();
  const std::vector<Ray> rays = MakeRays();
  std::vector<an::Interval<double>> expected;
  std::vector<std::vector<an::Interval<double>>> segments(19);
  std::vector<double> origins, directions, lengths;
  long compared = 0, nonEmpty = 0, several = 0;
  std::size_t packet = 1;
  for (std::size_t first = 0; first < rays.size(); first += packet, packet = packet % 19 + 1)
  {
    const std::size_t count = std::min(packet, rays.size() - first);
    origins.clear();
    directions.clear();
    lengths.clear();
    for (std::size_t i = 0; i < count; ++i)
    {
      const Ray& ray = rays[first + i];
      for (int a = 0; a < 3; ++a)
      {
        origins.push_back(ray.Origin[a]);
        directions.push_back(ray.Direction[a]);
      }
      lengths.push_back(ray.Length);
    }
    ae::PacketSegments(
      map, count, origins.data(), directions.data(), lengths.data(), 1e-6, segments.data());
    for (std::size_t i = 0; i < count; ++i)
    {
      const Ray& ray = rays[first + i];
      map.Segments(ray.Origin, ray.Direction, ray.Length, 1e-6, expected);
      const auto& got = segments[i];
      ASSERT_EQ(got.size(), expected.size()) << "ray " << first + i;
      for (std::size_t s = 0; s < got.size(); ++s)
      {
        ASSERT_EQ(got[s].Begin, expected[s].Begin) << "ray " << first + i << " segment " << s;
        ASSERT_EQ(got[s].End, expected[s].End) << "ray " << first + i << " segment " << s;
      }
      ++compared;
      nonEmpty += expected.empty() ? 0 : 1;
      several += expected.size() > 1 ? 1 : 0;
    }
  }
  EXPECT_EQ(compared, static_cast<long>(rays.size()));
  // The rays meet visible and hidden blocks alike.
  EXPECT_GT(nonEmpty, compared / 2);
  EXPECT_GT(several, compared / 10);
}

AVOS_ENGINE_TARGETS(PacketWalkTargets);
