// PSNR and SSIM: closed forms (identical images, constant images, a constant
// offset), SSIM's symmetry and bound, and its decrease as noise grows.
#include "avos/numerics/ImageMetrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace avos::numerics;

namespace
{
constexpr int W = 40, H = 30;

std::vector<float> Random(unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.2f, 0.8f);
  std::vector<float> image(std::size_t(W) * H * 4);
  for (float& v : image)
  {
    v = u(rng);
  }
  return image;
}

ImageChannel<float> Channel(const std::vector<float>& image, int c, int w = W, int h = H)
{
  return { image.data(), w, h, 4, c };
}
} // namespace

TEST(ImageMetrics, IdenticalImages)
{
  const auto a = Random(1);
  for (int c = 0; c < 4; ++c)
  {
    EXPECT_NEAR(SSIM(Channel(a, c), Channel(a, c)), 1.0, 1e-12);
    EXPECT_TRUE(std::isinf(PSNR(Channel(a, c), Channel(a, c))));
  }
}

TEST(ImageMetrics, ConstantImagesAndOffsets)
{
  const double m = 0.4, d = 0.05;
  const double c1 = 1e-4;
  // Constant images: no variance, SSIM is the luminance term alone.
  const double exact = (2 * m * (m + d) + c1) / (m * m + (m + d) * (m + d) + c1);
  for (int size : { W, 8 }) // the windowed and the single-window paths
  {
    std::vector<float> a(std::size_t(size) * size * 4, float(m));
    std::vector<float> b(a.size(), float(m + d));
    EXPECT_NEAR(SSIM(Channel(a, 0, size, size), Channel(b, 0, size, size)), exact, 1e-6);
    EXPECT_NEAR(PSNR(Channel(a, 0, size, size), Channel(b, 0, size, size)),
      10.0 * std::log10(1.0 / (d * d)), 1e-4);
  }
  // A constant offset of a textured image: the structure term stays 1, the
  // PSNR is that of the offset.
  const auto a = Random(2);
  auto b = a;
  for (float& v : b)
  {
    v += float(d);
  }
  EXPECT_NEAR(PSNR(Channel(a, 1), Channel(b, 1)), 10.0 * std::log10(1.0 / (d * d)), 1e-3);
  const double ssim = SSIM(Channel(a, 1), Channel(b, 1));
  EXPECT_LT(ssim, 1.0);
  EXPECT_GT(ssim, 0.98); // luminance term only, means near 0.5
}

TEST(ImageMetrics, SymmetricBoundedAndMonotone)
{
  const auto a = Random(3);
  std::mt19937 rng(4);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  std::vector<float> n(a.size());
  for (float& v : n)
  {
    v = noise(rng);
  }
  double previous = 1.0;
  for (float sigma : { 0.01f, 0.03f, 0.1f, 0.3f })
  {
    auto b = a;
    for (std::size_t i = 0; i < b.size(); ++i)
    {
      b[i] += sigma * n[i];
    }
    const double ab = SSIM(Channel(a, 2), Channel(b, 2));
    EXPECT_NEAR(ab, SSIM(Channel(b, 2), Channel(a, 2)), 1e-12);
    EXPECT_LE(ab, 1.0);
    EXPECT_LT(ab, previous);
    previous = ab;
  }
}
