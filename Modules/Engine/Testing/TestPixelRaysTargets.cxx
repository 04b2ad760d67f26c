// A row of pixel rays (avos/engine/PixelRays.h, RowRays) on every dispatch
// target the library was built with and the CPU runs, against the scalar
// PixelRay: the same pixels meet the box, with the same origins, directions
// and lengths to the bit; on a perspective camera looking at a 41 x 33 x 27
// grid from outside (pixels off the box, rays grazing it), with a depth
// buffer of background, surfaces inside and in front of the box, and the
// near plane itself; whole rows and runs that end inside a vector.
#include "avos/engine/PixelRays.h"

#include "TargetTest.h"

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

namespace ae = avos::engine;

namespace
{
class PixelRaysTargets : public avostest::TargetTest
{
};

// Row-major copy of a glm (column-major) matrix.
void RowMajor(const glm::dmat4& m, double out[16])
{
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      out[4 * r + c] = m[c][r];
    }
  }
}
} // namespace

TEST_P(PixelRaysTargets, RowsAreThePixelRays)
{
  EXPECT_STREQ(ae::RowRaysTarget(), hwy::TargetName(this->GetParam()));
  const int width = 67, height = 45;
  // World = grid scaled by 0.5 and shifted; a camera outside, looking at it.
  const glm::dmat4 gridToWorld =
    glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(-3.0, 1.0, 2.0)), glm::dvec3(0.5));
  const glm::dmat4 view =
    glm::lookAt(glm::dvec3(30.0, 14.0, 40.0), glm::dvec3(7.0, 9.0, 8.0), glm::dvec3(0.0, 1.0, 0.0));
  const glm::dmat4 projection =
    glm::perspective(glm::radians(40.0), double(width) / height, 0.5, 200.0);
  ae::FrameRays frame;
  RowMajor(glm::inverse(projection * view), frame.NDCToWorld);
  RowMajor(glm::inverse(gridToWorld), frame.WorldToGrid);
  frame.Voxel = 0.5;
  frame.Dimensions[0] = 41;
  frame.Dimensions[1] = 33;
  frame.Dimensions[2] = 27;
  frame.Width = width;
  frame.Height = height;
  std::vector<float> depth(static_cast<std::size_t>(width) * height);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (float& z : depth)
  {
    const float r = u(rng);
    z = r < 0.5f ? 1.0f : (r < 0.55f ? 0.0f : 0.9f + 0.1f * u(rng));
  }
  frame.Depth = depth.data();

  std::vector<int> xs(width);
  std::vector<double> origins(3 * width), directions(3 * width), lengths(width);
  long hits = 0, misses = 0;
  for (int y = 0; y < height; ++y)
  {
    for (const auto& run : { std::pair<int, int>{ 0, width }, { 5, 21 }, { 30, 31 } })
    {
      const int count = ae::RowRays(frame, y, run.first, run.second, xs.data(), origins.data(),
        directions.data(), lengths.data());
      int k = 0;
      for (int x = run.first; x < run.second; ++x)
      {
        double origin[3], direction[3], D;
        if (!ae::PixelRay(frame, x, y, origin, direction, D))
        {
          ++misses;
          continue;
        }
        ++hits;
        ASSERT_LT(k, count) << "pixel " << x << ", " << y;
        ASSERT_EQ(xs[k], x) << "row " << y;
        for (int a = 0; a < 3; ++a)
        {
          ASSERT_EQ(origins[3 * k + a], origin[a]) << "pixel " << x << ", " << y;
          ASSERT_EQ(directions[3 * k + a], direction[a]) << "pixel " << x << ", " << y;
        }
        ASSERT_EQ(lengths[k], D) << "pixel " << x << ", " << y;
        ++k;
      }
      ASSERT_EQ(k, count) << "row " << y << ": no ray the scalar set-up misses";
    }
  }
  // The box covers part of the frame: both answers occur often.
  EXPECT_GT(hits, 500);
  EXPECT_GT(misses, 500);
}

AVOS_ENGINE_TARGETS(PixelRaysTargets);
