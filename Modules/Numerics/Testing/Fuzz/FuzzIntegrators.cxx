// Fuzz target for the numerical core (libFuzzer: scripts/fuzz.sh; replayed on
// its corpus by the test Numerics-FuzzIntegratorsReplay in every build).
//
// The input bytes choose a small volume (2 to 6 points per axis, any doubles:
// NaN and infinities included), a transfer function (1 to 8 knots, any
// values: invalid ones must be refused), a ray, a tolerance and steps, the
// opacity model, clipping planes and cropping, and run every evaluator on it.
// Required of each: an error message, or every channel finite and in [0, 1]
// (and an extremum inside the data's range); termination within libFuzzer's
// time limit. A violation aborts (a crash for the fuzzer).
#include "avos/numerics/Clipping.h"
#include "avos/numerics/Extremum.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/Volume.h"

#include "avosFuzz.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace
{
namespace an = avos::numerics;

// Reads the input front to back; zeros once it is used up.
class Bytes
{
public:
  Bytes(const std::uint8_t* data, std::size_t size)
    : Data(data)
    , Size(size)
  {
  }
  std::uint8_t Byte() { return this->Position < this->Size ? this->Data[this->Position++] : 0; }
  // Any double, NaN and infinities included.
  double Raw()
  {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i)
    {
      bits = (bits << 8) | this->Byte();
    }
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  // A "reasonable" number in [lo, hi] most of the time, any double else.
  double In(double lo, double hi)
  {
    const std::uint8_t kind = this->Byte();
    if (kind < 16)
    {
      return this->Raw();
    }
    const int high = this->Byte();
    return lo + (hi - lo) * (high * 256 + this->Byte()) / 65535.0;
  }
  // Three numbers read in order (the order in which a function's arguments
  // are evaluated is unspecified: gcc and clang would decode an input
  // differently, and a replay would not reproduce the fuzzer's finding).
  glm::dvec3 Vector(double lo, double hi)
  {
    glm::dvec3 v;
    for (int i = 0; i < 3; ++i)
    {
      v[i] = this->In(lo, hi);
    }
    return v;
  }

private:
  const std::uint8_t* Data;
  std::size_t Size;
  std::size_t Position = 0;
};

using avosfuzz::Require;

void RequireUsable(const an::RayResult<double>& r, const char* what)
{
  if (!r.Error.empty())
  {
    return;
  }
  for (int c = 0; c < 4; ++c)
  {
    Require(std::isfinite(r.RGBA[c]) && r.RGBA[c] >= 0.0 && r.RGBA[c] <= 1.0 + 1e-12, what);
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  Bytes in(data, size);
  int dims[3];
  for (int& d : dims)
  {
    d = 2 + in.Byte() % 5;
  }
  std::vector<double> values(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
  double lo = INFINITY, hi = -INFINITY;
  for (double& v : values)
  {
    v = in.In(-10.0, 300.0);
    if (std::isfinite(v))
    {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  const an::TrilinearVolume<double, double> volume(values.data(), dims);

  an::TransferFunction<double> tf;
  const int knots = 1 + in.Byte() % 8;
  for (int k = 0; k < knots; ++k)
  {
    const double s = in.In(-20.0, 320.0);
    tf.AddOpacityKnot(s, in.In(0.0, 3.0));
    const glm::dvec3 rgb = in.Vector(0.0, 1.0);
    tf.AddColorKnot(s, rgb.r, rgb.g, rgb.b);
  }
  const bool alpha = in.Byte() & 1;
  if (alpha)
  {
    tf.SetOpacityModel(an::OpacityModel::Alpha, in.In(0.01, 4.0));
  }
  tf.Finalize();
  if (!tf.Validate().empty())
  {
    return 0; // refused with a message: nothing more to check
  }

  const glm::dvec3 origin = in.Vector(-1.0, 7.0);
  glm::dvec3 direction = in.Vector(-1.0, 1.0);
  const double length = glm::length(direction);
  if (!(length > 1e-6) || !std::isfinite(length))
  {
    direction = glm::dvec3(1.0, 0.0, 0.0);
  }
  else
  {
    direction /= length;
  }
  double t0 = 0.0, t1 = in.In(0.0, 20.0);
  if (!std::isfinite(t1) || !an::ClipToGrid(origin, direction, dims, t0, t1))
  {
    return 0;
  }
  const glm::dvec3 start = origin + t0 * direction;
  const double D = t1 - t0;
  const an::RayField<double, an::TrilinearVolume<double, double>> field{ volume, start, direction };

  const double eps = in.In(1e-6, 0.5);
  an::AdaptiveSettings<double> adaptive;
  adaptive.Tolerance = eps;
  adaptive.InitialStep = in.In(0.01, 2.0);
  adaptive.MinimumStep = in.In(0.01, 1.0);
  adaptive.MaximumStep = in.In(0.01, 4.0);
  adaptive.Coupling = in.Byte() & 1 ? an::Strategy::Coupled : an::Strategy::Decoupled;
  // The mapper's bounds (at most 1000 steps per voxel) keep a run short.
  const bool boundedSteps = adaptive.MinimumStep >= 1e-3 && adaptive.MaximumStep <= 1e3 &&
    adaptive.InitialStep >= 1e-3 && adaptive.InitialStep <= 1e3;
  if (boundedSteps)
  {
    RequireUsable(an::IntegrateAdaptive(field, tf, D, adaptive), "adaptive");
  }
  const double h = in.In(0.01, 2.0);
  if (h >= 1e-3 && h <= 1e3)
  {
    RequireUsable(an::IntegrateRiemann(field, tf, D, h, an::RiemannForm::Exponential), "riemann");
  }

  an::PiecewiseTransferFunction<double> pieces;
  if (an::ValidatePiecewiseTolerance(
        eps, alpha ? an::OpacityModel::Alpha : an::OpacityModel::Extinction)
        .empty() &&
    pieces.Build(tf, an::PiecewiseRelativeError(eps)).empty())
  {
    RequireUsable(an::IntegratePiecewise(volume, start, direction, D, pieces, eps), "piecewise");
  }

  // Clipping and cropping: sorted, disjoint parts of [0, D]; the extremum of
  // the field over them lies in the data's range.
  an::ClipRegion<double> clip;
  if (in.Byte() & 1)
  {
    const glm::dvec3 normal = in.Vector(-1.0, 1.0);
    clip.AddPlane(normal, in.In(-5.0, 5.0));
  }
  if (in.Byte() & 1)
  {
    double planes[6];
    for (double& p : planes)
    {
      p = in.In(-1.0, 7.0);
    }
    const int high = in.Byte();
    clip.SetCropping(planes, high << 8 | in.Byte());
  }
  if (clip.Validate().empty())
  {
    std::vector<an::Interval<double>> kept;
    clip.Kept(start, direction, D, kept);
    for (std::size_t i = 0; i < kept.size(); ++i)
    {
      Require(kept[i].Begin >= 0.0 && kept[i].Begin < kept[i].End && kept[i].End <= D &&
          (i == 0 || kept[i - 1].End < kept[i].Begin),
        "clip intervals");
    }
    const auto e = an::ExtremumAlongRay(volume, start, direction, kept.data(), kept.size(), true);
    Require(!e.Found ||
        (e.Value >= lo - 1e-9 * (1 + std::abs(lo)) && e.Value <= hi + 1e-9 * (1 + std::abs(hi))),
      "extremum in the data's range");
  }
  return 0;
}
