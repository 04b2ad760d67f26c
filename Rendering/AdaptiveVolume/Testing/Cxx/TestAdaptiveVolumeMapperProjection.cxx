// Maximum and minimum intensity projection, pixel by pixel against closed
// forms: on the ramp s = 50 + 40 z of TestAdaptiveVolumeMapperExactness (an
// orthographic, oblique view) a ray's maximum (minimum) is s at its end of
// largest (smallest) z, and the pixel is VTK's projection of it: colour times
// the opacity function's value there, that value as alpha. Required: within
// the float image's rounding (1e-6) on every pixel, with and without a
// clipping plane (the projection covers only the kept part). VTK's
// fixed-point mapper, sampling, must agree within its scalar rounding on 90 %
// of the pixels and nowhere exceed the exact maximum by more than that
// rounding. Then the additive and average projections against their closed
// forms, and the isosurface and slice modes refused.
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkCallbackCommand.h"
#include "vtkFixedPointRayCastImage.h"
#include "vtkFixedPointVolumeRayCastMapper.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPlane.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "ObliqueScene.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <vector>

namespace
{
const double Shift = 50.0, Scale = 40.0;
// scalar, r, g, b, opacity
const double Knots[][5] = { { 10, 0.2, 0.2, 0.9, 0.0 }, { 30, 0.9, 0.6, 0.1, 0.2 },
  { 50, 0.1, 0.9, 0.3, 0.5 }, { 60, 1.0, 0.2, 0.2, 0.3 }, { 85, 0.9, 0.9, 0.9, 0.9 } };
constexpr int Size = 64;

double Lerp(double s, int column)
{
  const int n = sizeof(Knots) / sizeof(Knots[0]);
  if (s <= Knots[0][0])
  {
    return Knots[0][column];
  }
  for (int i = 0; i + 1 < n; ++i)
  {
    if (s <= Knots[i + 1][0])
    {
      const double w = (s - Knots[i][0]) / (Knots[i + 1][0] - Knots[i][0]);
      return Knots[i][column] + w * (Knots[i + 1][column] - Knots[i][column]);
    }
  }
  return Knots[n - 1][column];
}

// The exact RGBA of pixel (x, y); `clipped`: only z <= 0.25 is kept.
glm::dvec4 Exact(vtkRenderer* renderer, bool maximum, bool clipped, int x, int y)
{
  const obliquescene::PixelRay ray = obliquescene::RayOf(renderer, x, y);
  double t0 = ray.T0, t1 = ray.T1;
  const glm::dvec3& start = ray.Start;
  const glm::dvec3& dir = ray.Direction;
  if (clipped)
  {
    const double t = (0.25 - start.z) / dir.z;
    (dir.z > 0.0 ? t1 : t0) = dir.z > 0.0 ? std::min(t1, t) : std::max(t0, t);
  }
  if (!(t0 < t1))
  {
    return glm::dvec4(0.0);
  }
  const double z0 = start.z + t0 * dir.z, z1 = start.z + t1 * dir.z;
  const double s = Shift + Scale * (maximum ? std::max(z0, z1) : std::min(z0, z1));
  const double alpha = Lerp(s, 4);
  return glm::dvec4(Lerp(s, 1) * alpha, Lerp(s, 2) * alpha, Lerp(s, 3) * alpha, alpha);
}
// The additive (A = int tau n dt) or average projection of pixel (x, y), by
// composite Simpson between the points where s crosses a knot or the range
// (the integrand is smooth between them): the mapper's model is VTK's, tau =
// -ln(1 - alpha) per unit distance (1 world unit = 16 voxel units), n the
// scalar normalised to the data's range [10, 90], alpha_h the opacity of a
// slab of h voxel units. Returns {value, length in the range (voxel units)}.
std::array<double, 2> Accumulated(
  vtkRenderer* renderer, bool additive, double r0, double r1, double h, int x, int y)
{
  const obliquescene::PixelRay ray = obliquescene::RayOf(renderer, x, y);
  if (!(ray.T0 < ray.T1))
  {
    return { 0.0, 0.0 };
  }
  const double voxel = 2.0 / 32.0;
  auto scalar = [&](double t) { return Shift + Scale * (ray.Start.z + t * ray.Direction.z); };
  std::vector<double> cuts{ ray.T0, ray.T1 };
  std::vector<double> values{ r0, r1 };
  for (const auto& k : Knots)
  {
    values.push_back(k[0]);
  }
  for (double v : values)
  {
    const double t = (v - Shift) / Scale;
    const double at = (t - ray.Start.z) / ray.Direction.z;
    if (at > ray.T0 && at < ray.T1)
    {
      cuts.push_back(at);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  double value = 0.0, length = 0.0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
  {
    const double a = cuts[i], b = cuts[i + 1];
    const double mid = scalar(0.5 * (a + b));
    if (!additive && !(mid >= r0 && mid <= r1))
    {
      continue;
    }
    auto f = [&](double t)
    {
      const double sv = scalar(t);
      const double tau = -std::log(1.0 - Lerp(sv, 4)) / 16.0; // per voxel unit
      const double weight = additive ? tau : -std::expm1(-tau * h);
      return weight * (sv - 10.0) / 80.0;
    };
    const int n = 4000;
    const double step = (b - a) / n;
    double sum = f(a) + f(b);
    for (int j = 1; j < n; ++j)
    {
      sum += (j % 2 ? 4.0 : 2.0) * f(a + j * step);
    }
    value += sum * step / 3.0 / voxel;
    length += (b - a) / voxel;
  }
  return { additive ? value : (length > 0.0 ? value / length : 0.0), length };
}
} // namespace

int TestAdaptiveVolumeMapperProjection(int, char*[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  obliquescene::MakeRamp(source, Shift, Scale);
  vtkNew<vtkVolumeProperty> property;
  obliquescene::FillProperty(Knots, property);

  obliquescene::Scene scene(source, property, Size);
  vtkAdaptiveVolumeMapper* mapper = scene.Mapper;
  vtkVolume* volume = scene.Volume;
  vtkRenderer* renderer = scene.Renderer;
  vtkRenderWindow* window = scene.Window;

  vtkNew<vtkPlane> plane; // keeps z <= 0.25
  plane->SetOrigin(0.0, 0.0, 0.25);
  plane->SetNormal(0.0, 0.0, -1.0);
  int failures = 0;
  std::vector<double> ours(4 * Size * Size);
  for (const bool clipped : { false, true })
  {
    for (const bool maximum : { true, false })
    {
      mapper->RemoveAllClippingPlanes();
      if (clipped)
      {
        mapper->AddClippingPlane(plane);
      }
      if (maximum)
      {
        mapper->SetBlendModeToMaximumIntensity();
      }
      else
      {
        mapper->SetBlendModeToMinimumIntensity();
      }
      window->Render();
      auto* rgba =
        vtkFloatArray::SafeDownCast(mapper->GetRenderedImage()->GetPointData()->GetScalars());
      if (!rgba || rgba->GetNumberOfTuples() != Size * Size)
      {
        std::cerr << "no image\n";
        return EXIT_FAILURE;
      }
      double maxError = 0.0;
      int hits = 0;
      for (int p = 0; p < Size * Size; ++p)
      {
        const glm::dvec4 exact = Exact(renderer, maximum, clipped, p % Size, p / Size);
        hits += exact.a > 0.0;
        for (int c = 0; c < 4; ++c)
        {
          ours[4 * p + c] = rgba->GetComponent(p, c);
          maxError = std::max(maxError, std::abs(ours[4 * p + c] - exact[c]));
        }
      }
      std::cout << (maximum ? "maximum" : "minimum") << (clipped ? ", clipped" : "") << ": " << hits
                << " pixels hit, max error " << maxError << "\n";
      if (hits < Size * Size / 8 || !(maxError <= 1e-6))
      {
        std::cerr << "FAIL max error " << maxError << "\n";
        ++failures;
      }
    }
  }

  // VTK's fixed-point maximum intensity projection of the same scene.
  mapper->RemoveAllClippingPlanes();
  mapper->SetBlendModeToMaximumIntensity();
  window->Render();
  for (int p = 0; p < Size * Size; ++p)
  {
    for (int c = 0; c < 4; ++c)
    {
      ours[4 * p + c] =
        mapper->GetRenderedImage()->GetPointData()->GetScalars()->GetComponent(p, c);
    }
  }
  vtkNew<vtkFixedPointVolumeRayCastMapper> fixedPoint;
  fixedPoint->SetInputConnection(source->GetOutputPort());
  fixedPoint->SetBlendModeToMaximumIntensity();
  fixedPoint->SetAutoAdjustSampleDistances(0);
  fixedPoint->SetImageSampleDistance(1.0);
  fixedPoint->SetSampleDistance(2.0 / 32.0 * 0.5);
  volume->SetMapper(fixedPoint);
  window->Render();
  vtkFixedPointRayCastImage* cast = fixedPoint->GetRayCastImage();
  const int* memory = cast->GetImageMemorySize();
  const int* used = cast->GetImageInUseSize();
  const int* origin = cast->GetImageOrigin();
  // The fixed-point mapper rounds the scalar up to the next integer before
  // its table lookup (see ../shared/notes/anchors.md): up to one scalar unit
  // times the steepest opacity slope here (0.024), and it misses some edge
  // pixels of the box.
  const double Rounding = 0.025;
  double worst = 0.0;
  int close = 0;
  int count = 0;
  for (int y = 0; y < used[1]; ++y)
  {
    for (int x = 0; x < used[0]; ++x)
    {
      const int vx = x + origin[0], vy = y + origin[1];
      const int p = vy * Size + vx;
      if (vx < 0 || vy < 0 || vx >= Size || vy >= Size || ours[4 * p + 3] <= 0.0)
      {
        continue;
      }
      const double alpha = cast->GetImage()[4 * (y * memory[0] + x) + 3] / 32767.0;
      close += std::abs(alpha - ours[4 * p + 3]) <= Rounding;
      worst = std::max(worst, alpha - ours[4 * p + 3]);
      ++count;
    }
  }
  std::cout << "fixed point: " << close << " of " << count << " pixels within " << Rounding
            << " in alpha, largest excess over the exact maximum " << worst << "\n";
  if (count < Size * Size / 4 || close < 0.9 * count || worst > Rounding)
  {
    std::cerr << "FAIL the fixed-point projection disagrees\n";
    ++failures;
  }

  // Additive and average (VTK's meaning, integrated): grey, opaque where
  // the ray meets the volume (the average: its range), against the closed
  // forms above. Additive: the pieces' extinction is within r = eps / 8 of
  // VTK's, so A within r A; average within eps.
  volume->SetMapper(mapper);
  mapper->RemoveAllClippingPlanes();
  const double eps = 1e-4, r0 = 30.0, r1 = 70.0;
  mapper->SetTolerance(eps);
  mapper->SetAverageIPScalarRange(r0, r1);
  for (const bool additive : { true, false })
  {
    mapper->SetBlendMode(
      additive ? vtkVolumeMapper::ADDITIVE_BLEND : vtkVolumeMapper::AVERAGE_INTENSITY_BLEND);
    window->Render();
    auto* rgba =
      vtkFloatArray::SafeDownCast(mapper->GetRenderedImage()->GetPointData()->GetScalars());
    double maxError = 0.0, brightest = 0.0;
    int met = 0;
    for (int p = 0; rgba && p < Size * Size; ++p)
    {
      const std::array<double, 2> exact =
        Accumulated(renderer, additive, r0, r1, mapper->GetSampleDistance(), p % Size, p / Size);
      const double grey = std::min(exact[0], 1.0);
      const double alpha = exact[1] > 0.0 ? 1.0 : 0.0;
      met += exact[1] > 0.0;
      brightest = std::max(brightest, grey);
      const double bound = (additive ? eps / 8.0 * exact[0] : eps) + 1e-6;
      for (int c = 0; c < 4; ++c)
      {
        const double error = std::abs(rgba->GetComponent(p, c) - (c < 3 ? grey * alpha : alpha));
        maxError = std::max(maxError, error / bound);
      }
    }
    std::cout << (additive ? "additive" : "average") << ": " << met << " pixels, brightest "
              << brightest << ", largest error / its bound " << maxError << "\n";
    // (alpha_h is small at h = 0.5 voxel: the average stays dim.)
    if (!rgba || met < Size * Size / 4 || brightest < (additive ? 0.05 : 0.01) || maxError > 1.0)
    {
      std::cerr << "FAIL the " << (additive ? "additive" : "average") << " projection\n";
      ++failures;
    }
  }

  // The blend modes the mapper cannot render: refused, nothing drawn.
  int errors = 0;
  vtkNew<vtkCallbackCommand> onError;
  onError->SetClientData(&errors);
  onError->SetCallback(
    [](vtkObject*, unsigned long, void* counter, void*) { ++*static_cast<int*>(counter); });
  mapper->AddObserver(vtkCommand::ErrorEvent, onError);
  for (const int mode : { vtkVolumeMapper::ISOSURFACE_BLEND, vtkVolumeMapper::SLICE_BLEND })
  {
    mapper->SetBlendMode(mode);
    window->Render();
    if (mapper->GetRenderedImage()->GetNumberOfPoints() != 0)
    {
      std::cerr << "FAIL blend mode " << mode << " rendered\n";
      ++failures;
    }
  }
  if (errors != 2)
  {
    std::cerr << "FAIL " << errors << " errors for two refused blend modes\n";
    ++failures;
  }
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
