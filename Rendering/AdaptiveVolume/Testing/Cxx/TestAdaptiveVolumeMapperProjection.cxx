// Maximum and minimum intensity projection, pixel by pixel against closed
// forms: on the ramp s = 50 + 40 z of TestAdaptiveVolumeMapperExactness (an
// orthographic, oblique view) a ray's maximum (minimum) is s at its end of
// largest (smallest) z, and the pixel is VTK's projection of it: colour times
// the opacity function's value there, that value as alpha. Required: within
// the float image's rounding (1e-6) on every pixel, with and without a
// clipping plane (the projection covers only the kept part). VTK's
// fixed-point mapper, sampling, must agree within its scalar rounding on 90 %
// of the pixels and nowhere exceed the exact maximum by more than that
// rounding. The average and additive modes are refused.
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
} // namespace

int TestAdaptiveVolumeMapperProjection(int, char*[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  obliquescene::MakeRamp(source, Shift, Scale);
  vtkNew<vtkVolumeProperty> property;
  obliquescene::FillProperty(Knots, property);

  vtkNew<vtkAdaptiveVolumeMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  obliquescene::Scene scene(volume, Size);
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

  // Average and additive: refused, nothing drawn.
  volume->SetMapper(mapper);
  int errors = 0;
  vtkNew<vtkCallbackCommand> onError;
  onError->SetClientData(&errors);
  onError->SetCallback(
    [](vtkObject*, unsigned long, void* counter, void*) { ++*static_cast<int*>(counter); });
  mapper->AddObserver(vtkCommand::ErrorEvent, onError);
  for (const int mode :
    { vtkVolumeMapper::AVERAGE_INTENSITY_BLEND, vtkVolumeMapper::ADDITIVE_BLEND })
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
