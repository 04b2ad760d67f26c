// Clipping planes and cropping, pixel by pixel against closed forms: the
// scene of TestAdaptiveVolumeMapperExactness (an orthographic, oblique view of
// s = 50 + 40 z on [-1, 1]^3, extinction model) with an oblique clipping
// plane and VTK's "cross" cropping (several kept parts per ray). Each pixel's
// ray is rebuilt here from the renderer, cut by the plane and the cropping
// regions independently of the mapper, and each kept part integrated in
// closed form (Oracles.h), front to back. Required: the error-controlled
// methods within their tolerance on every pixel, the reference within 1e-5;
// on a constant volume (where a Riemann sum is exact) the Riemann sum within
// the engine's 1e-4; without the planes the error must be large (the test
// sees a missing cut). VTK's fixed-point mapper, given the same planes, must
// cover the same pixels (the same kept side and regions).
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkFixedPointRayCastImage.h"
#include "vtkFixedPointVolumeRayCastMapper.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlane.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTransform.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "ObliqueScene.h"
#include "Oracles.h"
#include "avosTestHelpers.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

namespace
{
const double Shift = 50.0;
// scalar, r, g, b, tau per voxel unit
const double Knots[][5] = { { 10, 0.2, 0.2, 0.9, 0.0 }, { 30, 0.9, 0.6, 0.1, 0.02 },
  { 50, 0.1, 0.9, 0.3, 0.3 }, { 60, 1.0, 0.2, 0.2, 0.05 }, { 85, 0.9, 0.9, 0.9, 0.4 } };
constexpr int Size = 64;
const double Voxel = 2.0 / 32.0;
const double PlaneOrigin[3] = { 0.1, 0.0, 0.0 };
const double PlaneNormal[3] = { 1.0, 0.4, -0.3 };
const double Crop[6] = { -0.6, 0.5, -0.8, 0.3, -0.7, 0.6 };
const int CropFlags = 0x0417410; // VTK_CROP_CROSS

bool RegionKept(const glm::dvec3& p)
{
  int region = 0;
  for (int a = 0, w = 1; a < 3; ++a, w *= 3)
  {
    region += w * (p[a] < Crop[2 * a] ? 0 : (p[a] > Crop[2 * a + 1] ? 2 : 1));
  }
  return (CropFlags >> region) & 1;
}

// The exact RGBA of pixel (x, y) of the clipped and cropped scene, for the
// field s = Shift + scale z (the view is oblique: no direction component is 0).
glm::dvec4 Exact(vtkRenderer* renderer, const avos::numerics::TransferFunction<double>& tf,
  double scale, int x, int y)
{
  const obliquescene::PixelRay ray = obliquescene::RayOf(renderer, x, y);
  double t0 = ray.T0, t1 = ray.T1;
  const glm::dvec3& start = ray.Start;
  const glm::dvec3& dir = ray.Direction;
  std::vector<double> cuts;
  // Keep n . (p - o) >= 0.
  const glm::dvec3 n(PlaneNormal[0], PlaneNormal[1], PlaneNormal[2]);
  const glm::dvec3 o(PlaneOrigin[0], PlaneOrigin[1], PlaneOrigin[2]);
  const double along = glm::dot(n, dir), t = glm::dot(n, o - start) / along;
  if (along > 0.0)
  {
    t0 = std::max(t0, t);
  }
  else
  {
    t1 = std::min(t1, t);
  }
  for (int c = 0; c < 6; ++c)
  {
    cuts.push_back((Crop[c] - start[c / 2]) / dir[c / 2]);
  }
  if (!(t0 < t1))
  {
    return glm::dvec4(0.0);
  }
  cuts.push_back(t0);
  cuts.push_back(t1);
  std::sort(cuts.begin(), cuts.end());
  glm::dvec3 color(0.0);
  double T = 1.0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
  {
    const double a = std::max(cuts[i], t0), b = std::min(cuts[i + 1], t1);
    if (!(b > a) || !RegionKept(start + 0.5 * (a + b) * dir))
    {
      continue;
    }
    const double s0 = Shift + scale * (start.z + a * dir.z);
    const glm::dvec4 part = oracles::LinearField(tf, s0, scale * dir.z * Voxel, (b - a) / Voxel);
    color += T * glm::dvec3(part);
    T *= 1.0 - part.a;
  }
  return glm::dvec4(color, 1.0 - T);
}

struct Run
{
  const char* Name;
  int Method;
  double Tolerance;
  double Scale;    // of the field: 0 for the constant volume
  bool Clipped;    // the mapper has the plane and the cropping
  double Required; // largest error allowed on any pixel (0: must exceed 0.05)
};
} // namespace

int TestAdaptiveVolumeMapperClipping(int, char*[])
{
  vtkNew<vtkAnalyticVolumeSource> source; // the function and scale set per run
  obliquescene::MakeRamp(source, Shift, 40.0);
  avos::numerics::TransferFunction<double> tf;
  vtkNew<vtkVolumeProperty> property;
  obliquescene::FillProperty(Knots, property, &tf);

  vtkNew<vtkPlane> plane;
  plane->SetOrigin(PlaneOrigin[0], PlaneOrigin[1], PlaneOrigin[2]);
  plane->SetNormal(PlaneNormal[0], PlaneNormal[1], PlaneNormal[2]);
  obliquescene::Scene scene(source, property, Size);
  vtkAdaptiveVolumeMapper* mapper = scene.Mapper;
  vtkVolume* volume = scene.Volume;
  mapper->SetOpacityModelToExtinction();
  mapper->SetCroppingRegionPlanes(Crop);
  mapper->SetCroppingRegionFlags(CropFlags);
  vtkRenderer* renderer = scene.Renderer;
  vtkRenderWindow* window = scene.Window;

  const Run runs[] = {
    { "piecewise eps 1e-3", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE, 1e-3, 40.0, true, 1e-3 },
    { "coupled eps 1e-3", vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED, 1e-3, 40.0, true, 1e-3 },
    { "reference", vtkAdaptiveVolumeMapper::REFERENCE, 1e-2, 40.0, true, 1e-5 },
    { "riemann h 0.5, constant", vtkAdaptiveVolumeMapper::RIEMANN, 1e-4, 0.0, true, 1e-4 },
    { "piecewise, constant", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE, 1e-3, 0.0, true, 1e-3 },
    { "piecewise, planes removed", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE, 1e-3, 40.0, false,
      0.0 },
  };
  int failures = 0;
  for (const Run& run : runs)
  {
    source->SetFunction(
      run.Scale == 0.0 ? vtkAnalyticVolumeSource::CONSTANT : vtkAnalyticVolumeSource::LINEAR_RAMP);
    source->SetScalarScale(run.Scale == 0.0 ? 1.0 : run.Scale);
    mapper->RemoveAllClippingPlanes();
    if (run.Clipped)
    {
      mapper->AddClippingPlane(plane);
    }
    mapper->SetCropping(run.Clipped);
    mapper->SetIntegrationMethod(run.Method);
    mapper->SetTolerance(run.Tolerance);
    window->Render();
    auto* rgba =
      vtkFloatArray::SafeDownCast(mapper->GetRenderedImage()->GetPointData()->GetScalars());
    if (!rgba || rgba->GetNumberOfTuples() != Size * Size)
    {
      std::cerr << run.Name << ": no image\n";
      return EXIT_FAILURE;
    }
    double maxError = 0.0;
    int hits = 0;
    for (int y = 0; y < Size; ++y)
    {
      for (int x = 0; x < Size; ++x)
      {
        // Always the clipped and cropped scene's closed form.
        const glm::dvec4 exact = Exact(renderer, tf, run.Scale, x, y);
        hits += exact.a > 0.0;
        for (int c = 0; c < 4; ++c)
        {
          const double v = rgba->GetComponent(static_cast<vtkIdType>(y) * Size + x, c);
          maxError = std::max(maxError, std::abs(v - exact[c]));
        }
      }
    }
    std::cout << run.Name << ": " << hits << " pixels hit, max error " << maxError << "\n";
    const bool ok = hits > Size * Size / 8 &&
      (run.Required > 0.0 ? maxError <= run.Required + 1e-7 : maxError > 0.05);
    if (!ok)
    {
      std::cerr << "FAIL " << run.Name << ": max error " << maxError << "\n";
      ++failures;
    }
  }

  // What the mapper cannot cut exactly is refused, nothing drawn: a plane with
  // a transform, cropping of a volume with a direction matrix.
  {
    avostest::ExpectedErrors errors(mapper);
    auto refused = [&](const char* what, const char* message)
    {
      window->Render();
      if (!errors.Check(what, message) || mapper->GetRenderedImage()->GetNumberOfPoints() != 0)
      {
        ++failures;
      }
    };
    vtkNew<vtkPlane> moved;
    moved->SetNormal(0, 0, 1);
    vtkNew<vtkTransform> shift;
    shift->Translate(0, 0, 0.5);
    moved->SetTransform(shift);
    mapper->RemoveAllClippingPlanes();
    mapper->AddClippingPlane(moved);
    refused("transformed plane", "Clipping planes with a transform are not supported");
    mapper->RemoveAllClippingPlanes();
    source->Update();
    vtkNew<vtkImageData> turned;
    turned->DeepCopy(source->GetOutput());
    turned->SetDirectionMatrix(0, -1, 0, 1, 0, 0, 0, 0, 1);
    mapper->SetInputData(turned);
    mapper->SetCropping(1);
    refused("cropping a turned volume",
      "Cropping needs an input with positive spacing and no "
      "direction matrix");
    mapper->SetInputConnection(source->GetOutputPort());
  }

  // VTK's fixed-point mapper with the same plane and cropping covers the same
  // pixels (its image is placed in the viewport as in the agreement test).
  source->SetFunction(vtkAnalyticVolumeSource::LINEAR_RAMP);
  source->SetScalarScale(40.0);
  vtkNew<vtkFixedPointVolumeRayCastMapper> fixedPoint;
  fixedPoint->SetInputConnection(source->GetOutputPort());
  fixedPoint->AddClippingPlane(plane);
  fixedPoint->SetCropping(1);
  fixedPoint->SetCroppingRegionPlanes(Crop);
  fixedPoint->SetCroppingRegionFlags(CropFlags);
  fixedPoint->SetAutoAdjustSampleDistances(0);
  fixedPoint->SetImageSampleDistance(1.0);
  fixedPoint->SetSampleDistance(0.25 * Voxel);
  // VTK's model: alpha per unit distance, here per voxel unit.
  vtkNew<vtkPiecewiseFunction> alpha;
  for (const auto& k : Knots)
  {
    alpha->AddPoint(k[0], -std::expm1(-k[4]));
  }
  vtkNew<vtkVolumeProperty> vtkProperty;
  vtkProperty->SetColor(property->GetRGBTransferFunction());
  vtkProperty->SetScalarOpacity(alpha);
  vtkProperty->SetScalarOpacityUnitDistance(Voxel);
  vtkProperty->SetInterpolationTypeToLinear();
  volume->SetMapper(fixedPoint);
  volume->SetProperty(vtkProperty);
  window->Render();
  vtkFixedPointRayCastImage* cast = fixedPoint->GetRayCastImage();
  const int* memory = cast->GetImageMemorySize();
  const int* used = cast->GetImageInUseSize();
  const int* origin = cast->GetImageOrigin();
  std::vector<double> covered(Size * Size, 0.0);
  for (int y = 0; y < used[1]; ++y)
  {
    for (int x = 0; x < used[0]; ++x)
    {
      const int vx = x + origin[0], vy = y + origin[1];
      if (vx >= 0 && vy >= 0 && vx < Size && vy < Size)
      {
        covered[vy * Size + vx] = cast->GetImage()[4 * (y * memory[0] + x) + 3] / 32767.0;
      }
    }
  }
  int disagree = 0, visible = 0;
  for (int y = 0; y < Size; ++y)
  {
    for (int x = 0; x < Size; ++x)
    {
      const bool ours = Exact(renderer, tf, 40.0, x, y).a > 0.02;
      visible += ours;
      // Edges may differ by a pixel: only clear coverage counts.
      disagree += ours != (covered[y * Size + x] > 0.02);
    }
  }
  std::cout << "fixed point: " << disagree << " of " << visible
            << " covered pixels differ in coverage\n";
  if (visible < Size * Size / 8 || disagree > visible / 20)
  {
    std::cerr << "FAIL the fixed-point mapper keeps other parts of the volume\n";
    ++failures;
  }
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
