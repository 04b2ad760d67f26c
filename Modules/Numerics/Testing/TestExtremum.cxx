// Exact maximum and minimum intensity projection (Extremum.h): on the field
// f = (x - a)(y - b) (in the trilinear span, so interpolation reproduces it)
// every ray's extremum is a quadratic's, known in closed form; a dense
// sampling never exceeds it; undefined cells are passed over.
#include "AdversarialCases.h"

#include "avos/numerics/EmptySpace.h"
#include "avos/numerics/Extremum.h"
#include "avos/numerics/Volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace an = avos::numerics;

namespace
{
constexpr double A = 7.3, B = 5.1;
double Field(const glm::dvec3& p)
{
  return (p.x - A) * (p.y - B);
}

std::vector<double> Grid(const int dims[3])
{
  std::vector<double> data;
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        data.push_back(Field(glm::dvec3(i, j, k)));
      }
    }
  }
  return data;
}
} // namespace

TEST(Extremum, QuadraticAlongEveryRayIsExact)
{
  const int dims[3] = { 17, 13, 9 };
  const std::vector<double> data = Grid(dims);
  const an::TrilinearVolume<double, double> volume(data.data(), dims);
  std::mt19937 rng(5);
  for (int trial = 0; trial < 1000; ++trial)
  {
    const adversarial::Ray ray = adversarial::RandomRay(dims, rng, 1.0);
    // f(t) = (x0 + t dx - A)(y0 + t dy - B) = c0 + c1 t + c2 t^2.
    const double px = ray.Origin.x - A, py = ray.Origin.y - B;
    const double dx = ray.Direction.x, dy = ray.Direction.y;
    const double c0 = px * py, c1 = px * dy + py * dx, c2 = dx * dy;
    double hi = std::max(c0, c0 + ray.Length * (c1 + ray.Length * c2));
    double lo = std::min(c0, c0 + ray.Length * (c1 + ray.Length * c2));
    if (c2 != 0.0)
    {
      const double v = -c1 / (2.0 * c2);
      if (v > 0.0 && v < ray.Length)
      {
        hi = std::max(hi, c0 + v * (c1 + v * c2));
        lo = std::min(lo, c0 + v * (c1 + v * c2));
      }
    }
    const an::Interval<double> whole{ 0.0, ray.Length };
    const auto mip = an::ExtremumAlongRay(volume, ray.Origin, ray.Direction, &whole, 1, true);
    const auto minip = an::ExtremumAlongRay(volume, ray.Origin, ray.Direction, &whole, 1, false);
    ASSERT_TRUE(mip.Found && minip.Found);
    EXPECT_NEAR(mip.Value, hi, 1e-11 * (1.0 + std::abs(hi))) << "trial " << trial;
    EXPECT_NEAR(minip.Value, lo, 1e-11 * (1.0 + std::abs(lo))) << "trial " << trial;
    // A sampled projection (step 0.05) never exceeds the exact one.
    for (double t = 0.0; t <= ray.Length; t += 0.05)
    {
      const double f = volume(ray.Origin + t * ray.Direction);
      ASSERT_LE(f, mip.Value + 1e-12);
      ASSERT_GE(f, minip.Value - 1e-12);
    }
  }
}

// Segments restrict the projection; NaN cells are passed over.
TEST(Extremum, SegmentsAndUndefinedCells)
{
  const int dims[3] = { 9, 3, 3 };
  std::vector<double> data(9 * 3 * 3);
  for (std::size_t n = 0; n < data.size(); ++n)
  {
    data[n] = static_cast<double>(n % 9); // s = x on the grid
  }
  const an::TrilinearVolume<double, double> volume(data.data(), dims);
  const glm::dvec3 origin(0.0, 1.0, 1.0), direction(1.0, 0.0, 0.0);
  const an::Interval<double> parts[2] = { { 1.0, 2.5 }, { 4.0, 5.25 } };
  const auto mip = an::ExtremumAlongRay(volume, origin, direction, parts, 2, true);
  const auto minip = an::ExtremumAlongRay(volume, origin, direction, parts, 2, false);
  EXPECT_DOUBLE_EQ(mip.Value, 5.25);
  EXPECT_DOUBLE_EQ(minip.Value, 1.0);

  std::vector<double> undefined(data.size(), std::numeric_limits<double>::quiet_NaN());
  const an::TrilinearVolume<double, double> nan(undefined.data(), dims);
  const an::Interval<double> whole{ 0.0, 8.0 };
  EXPECT_FALSE(an::ExtremumAlongRay(nan, origin, direction, &whole, 1, true).Found);
}

// Searching the blocks best first (ExtremumByBlocks: EmptySpaceMap::Spans
// sorted by range, stopping at the first block that cannot beat the
// extremum so far) finds the same value as the whole ray, on random data
// (noise with rare spikes).
TEST(Extremum, BestFirstBlocksFindTheSameExtremum)
{
  const int dims[3] = { 37, 29, 21 };
  std::mt19937 rng(8);
  std::uniform_int_distribution<int> value(0, 255);
  std::vector<unsigned char> data(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
  for (auto& v : data)
  {
    v = static_cast<unsigned char>(value(rng) / 4 + (rng() % 50 == 0 ? 180 : 0));
  }
  const an::TrilinearVolume<double, unsigned char> volume(data.data(), dims);
  an::EmptySpaceMap<double> map;
  map.SetDimensions(dims);
  map.ComputeRanges(data.data());
  std::vector<an::EmptySpaceMap<double>::Span> spans;
  for (int trial = 0; trial < 500; ++trial)
  {
    const adversarial::Ray ray = adversarial::RandomRay(dims, rng, 1.0);
    const an::Interval<double> whole{ 0.0, ray.Length };
    for (const bool maximum : { true, false })
    {
      const auto plain =
        an::ExtremumAlongRay(volume, ray.Origin, ray.Direction, &whole, 1, maximum);
      const auto best = an::ExtremumByBlocks(
        volume, map, ray.Origin, ray.Direction, ray.Length, 1e-6, &whole, 1, maximum, spans);
      ASSERT_TRUE(plain.Found && best.Found);
      // The same cells' cubics from other entry points: equal up to rounding.
      EXPECT_NEAR(best.Value, plain.Value, 1e-12 * (1.0 + std::abs(plain.Value)))
        << "trial " << trial;
    }
  }
}
