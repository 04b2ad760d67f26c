// avos-compare: image quality of one image against a reference, per channel:
// PSNR (peak 1, values in [0, 1]) and SSIM (Wang et al., 8x8 windows) from
// the numerical core's ImageMetrics, plus mean and max absolute error.
//
//   avos-compare IMAGE REFERENCE [--json]
//
// Any format OpenImageIO reads (PNG, EXR, ...); both images must have the
// same size and number of channels. 8-bit images are compared on [0, 1].
#include <OpenImageIO/imageio.h>

#include "avos/numerics/ImageMetrics.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace
{
struct Image
{
  int Width = 0;
  int Height = 0;
  int Channels = 0;
  std::vector<float> Pixels;
};

bool Read(const std::string& path, Image& image)
{
  auto in = OIIO::ImageInput::open(path);
  if (!in)
  {
    std::cerr << "error: cannot read '" << path << "': " << OIIO::geterror() << "\n";
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  image.Width = spec.width;
  image.Height = spec.height;
  image.Channels = spec.nchannels;
  image.Pixels.resize(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  if (image.Pixels.empty() ||
    !in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.Pixels.data()))
  {
    std::cerr << "error: cannot read the pixels of '" << path << "': " << in->geterror() << "\n";
    return false;
  }
  return true;
}

std::string Value(double v)
{
  return std::isfinite(v) ? std::to_string(v) : (std::string(v > 0 ? "" : "-") + "inf");
}
} // namespace

int main(int argc, char* argv[])
{
  std::vector<std::string> paths;
  bool json = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--json")
    {
      json = true;
    }
    else if (arg == "-h" || arg == "--help")
    {
      std::cout << "usage: avos-compare IMAGE REFERENCE [--json]\n";
      return EXIT_SUCCESS;
    }
    else if (arg.rfind("--", 0) == 0)
    {
      std::cerr << "error: unknown option " << arg << "\n";
      return 2;
    }
    else
    {
      paths.push_back(arg);
    }
  }
  if (paths.size() != 2)
  {
    std::cerr << "usage: avos-compare IMAGE REFERENCE [--json]\n";
    return 2;
  }
  Image a, b;
  if (!Read(paths[0], a) || !Read(paths[1], b))
  {
    return EXIT_FAILURE;
  }
  if (a.Width != b.Width || a.Height != b.Height || a.Channels != b.Channels)
  {
    std::cerr << "error: the images differ in shape: " << a.Width << "x" << a.Height << "x"
              << a.Channels << " and " << b.Width << "x" << b.Height << "x" << b.Channels << "\n";
    return EXIT_FAILURE;
  }
  std::vector<double> psnr, ssim, mean, maximum;
  for (int c = 0; c < a.Channels; ++c)
  {
    const avos::numerics::ImageChannel<float> x{ a.Pixels.data(), a.Width, a.Height, a.Channels,
      c };
    const avos::numerics::ImageChannel<float> y{ b.Pixels.data(), b.Width, b.Height, b.Channels,
      c };
    psnr.push_back(avos::numerics::PSNR(x, y));
    ssim.push_back(avos::numerics::SSIM(x, y));
    double sum = 0.0, top = 0.0;
    for (std::size_t i = static_cast<std::size_t>(c); i < a.Pixels.size();
         i += static_cast<std::size_t>(a.Channels))
    {
      const double e = std::abs(double(a.Pixels[i]) - double(b.Pixels[i]));
      sum += e;
      top = std::max(top, e);
    }
    mean.push_back(sum / (static_cast<double>(a.Width) * a.Height));
    maximum.push_back(top);
  }
  auto list = [&](const std::vector<double>& v, const char* quote)
  {
    std::string out;
    for (std::size_t i = 0; i < v.size(); ++i)
    {
      const std::string text = Value(v[i]);
      out += (i ? ", " : "") + (std::isfinite(v[i]) ? text : quote + text + quote);
    }
    return out;
  };
  if (json)
  {
    std::cout << "{\"channels\": " << a.Channels << ", \"psnr\": [" << list(psnr, "\"")
              << "], \"ssim\": [" << list(ssim, "\"") << "], \"mean_error\": [" << list(mean, "\"")
              << "], \"max_error\": [" << list(maximum, "\"") << "]}\n";
  }
  else
  {
    std::cout << "PSNR (dB): " << list(psnr, "") << "\nSSIM: " << list(ssim, "")
              << "\nmean |error|: " << list(mean, "") << "\nmax |error|: " << list(maximum, "")
              << "\n";
  }
  return EXIT_SUCCESS;
}
