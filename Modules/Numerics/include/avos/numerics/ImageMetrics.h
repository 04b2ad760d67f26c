// Image quality against a reference, for comparing rendering techniques on
// the same camera: PSNR and SSIM (Z. Wang, A. C. Bovik, H. R. Sheikh and
// E. P. Simoncelli, "Image quality assessment: from error visibility to
// structural similarity", IEEE TIP 2004), on one channel of interleaved
// images with values in [0, L].
#ifndef avos_numerics_ImageMetrics_h
#define avos_numerics_ImageMetrics_h

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace avos
{
namespace numerics
{

// One channel of an interleaved image, row-major.
template <typename T>
struct ImageChannel
{
  const T* Data;
  int Width;
  int Height;
  int Components; // interleaved channels per pixel
  int Channel;

  double operator()(int x, int y) const
  {
    return double(this->Data[(std::size_t(y) * this->Width + x) * this->Components + this->Channel]);
  }
};

// 10 log10(L^2 / MSE); +inf for identical channels.
template <typename T>
double PSNR(const ImageChannel<T>& a, const ImageChannel<T>& b, double range = 1.0)
{
  double sum = 0.0;
  for (int y = 0; y < a.Height; ++y)
  {
    for (int x = 0; x < a.Width; ++x)
    {
      const double d = a(x, y) - b(x, y);
      sum += d * d;
    }
  }
  const double mse = sum / (double(a.Width) * a.Height);
  return mse > 0.0 ? 10.0 * std::log10(range * range / mse)
                   : std::numeric_limits<double>::infinity();
}

// Mean SSIM with the paper's parameters: an 11x11 Gaussian window of
// standard deviation 1.5 (normalised), K1 = 0.01, K2 = 0.03, over every
// position where the window fits in the image. Images smaller than the
// window use one window covering them, unweighted.
template <typename T>
double SSIM(const ImageChannel<T>& a, const ImageChannel<T>& b, double range = 1.0)
{
  const double c1 = (0.01 * range) * (0.01 * range);
  const double c2 = (0.03 * range) * (0.03 * range);
  int size = 11;
  std::vector<double> w;
  if (a.Width < size || a.Height < size)
  {
    size = 0; // one unweighted window over the whole image
  }
  else
  {
    w.resize(std::size_t(size) * size);
    double total = 0.0;
    for (int j = 0; j < size; ++j)
    {
      for (int i = 0; i < size; ++i)
      {
        const double dx = i - 5, dy = j - 5;
        total += w[std::size_t(j) * size + i] = std::exp(-(dx * dx + dy * dy) / (2.0 * 1.5 * 1.5));
      }
    }
    for (double& v : w)
    {
      v /= total;
    }
  }
  auto window = [&](int x0, int y0, int wx, int wy, bool weighted)
  {
    double mx = 0, my = 0, sxx = 0, syy = 0, sxy = 0, total = 0;
    for (int j = 0; j < wy; ++j)
    {
      for (int i = 0; i < wx; ++i)
      {
        const double g = weighted ? w[std::size_t(j) * wx + i] : 1.0;
        const double p = a(x0 + i, y0 + j), q = b(x0 + i, y0 + j);
        mx += g * p;
        my += g * q;
        sxx += g * p * p;
        syy += g * q * q;
        sxy += g * p * q;
        total += g;
      }
    }
    mx /= total;
    my /= total;
    const double vx = sxx / total - mx * mx, vy = syy / total - my * my;
    const double cxy = sxy / total - mx * my;
    return ((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2));
  };
  if (size == 0)
  {
    return window(0, 0, a.Width, a.Height, false);
  }
  double sum = 0.0;
  long count = 0;
  for (int y = 0; y + size <= a.Height; ++y)
  {
    for (int x = 0; x + size <= a.Width; ++x)
    {
      sum += window(x, y, size, size, true);
      ++count;
    }
  }
  return sum / double(count);
}

} // namespace numerics
} // namespace avos

#endif
