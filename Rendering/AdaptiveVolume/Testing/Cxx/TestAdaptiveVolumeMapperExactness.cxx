// Exactness of the whole mapper, pixel by pixel: an orthographic, oblique view
// of a linear ramp s = 50 + 40 z on [-1, 1]^3 (trilinear interpolation is exact
// on it), through a piecewise-linear transfer function in the extinction
// model. Along every ray s is linear, so each pixel's RGBA has a closed form
// (Modules/Numerics/Testing/Oracles.h). The ray of each pixel is rebuilt here
// independently, from the renderer's display-to-world transform. Required:
// error within eps on every pixel for the adaptive methods, within 1e-7 for
// the reference (exact to 1e-9, the image stored in float); the Riemann sum at h = 0.5 must be
// visibly worse (the test can tell a wrong integral from a right one). Then the same with shading
// on (one directional light): the lit closed form, within the same bounds.
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkCamera.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "ObliqueScene.h"
#include "Oracles.h"

#include "avos/numerics/Shading.h"

#include <algorithm>
#include <cmath>
#include <iostream>

namespace
{
const double Shift = 50.0, Scale = 40.0;
// scalar, r, g, b, tau per voxel unit
const double Knots[][5] = { { 10, 0.2, 0.2, 0.9, 0.0 }, { 30, 0.9, 0.6, 0.1, 0.02 },
  { 50, 0.1, 0.9, 0.3, 0.3 }, { 60, 1.0, 0.2, 0.2, 0.05 }, { 85, 0.9, 0.9, 0.9, 0.4 } };
constexpr int Size = 64;

struct Run
{
  const char* Name;
  int Method;
  double Tolerance;
  double Required; // maximum error allowed on any pixel (0: must exceed 0.01)
};

// The exact RGBA of pixel (x, y): its ray, clipped to the box, in voxel units.
glm::dvec4 Exact(vtkRenderer* renderer, const avos::numerics::TransferFunction<double>& tf,
  double voxel, int x, int y)
{
  const obliquescene::PixelRay ray = obliquescene::RayOf(renderer, x, y);
  const double t0 = ray.T0, t1 = ray.T1;
  const glm::dvec3& start = ray.Start;
  const glm::dvec3& dir = ray.Direction;
  if (!(t0 < t1))
  {
    return glm::dvec4(0.0);
  }
  const double s0 = Shift + Scale * (start.z + t0 * dir.z);
  const double k = Scale * dir.z * voxel; // per voxel unit
  return oracles::LinearField(tf, s0, k, (t1 - t0) / voxel);
}
} // namespace

int TestAdaptiveVolumeMapperExactness(int, char*[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  obliquescene::MakeRamp(source, Shift, Scale);
  const double voxel = 2.0 / 32.0;
  avos::numerics::TransferFunction<double> tf;
  vtkNew<vtkVolumeProperty> property;
  obliquescene::FillProperty(Knots, property, &tf);

  obliquescene::Scene scene(source, property, Size);
  vtkAdaptiveVolumeMapper* mapper = scene.Mapper;
  mapper->SetOpacityModelToExtinction();
  vtkRenderer* renderer = scene.Renderer;
  vtkRenderWindow* window = scene.Window;

  const Run runs[] = { { "coupled eps 1e-2", vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED, 1e-2,
                         1e-2 },
    { "coupled eps 1e-3", vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED, 1e-3, 1e-3 },
    { "decoupled eps 1e-3", vtkAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED, 1e-3, 1e-3 },
    { "reference", vtkAdaptiveVolumeMapper::REFERENCE, 1e-2, 1e-7 },
    { "riemann h 0.5", vtkAdaptiveVolumeMapper::RIEMANN, 1e-2, 0.0 } };
  int failures = 0;
  for (const Run& run : runs)
  {
    mapper->SetIntegrationMethod(run.Method);
    mapper->SetTolerance(run.Tolerance);
    window->Render();
    vtkImageData* image = mapper->GetRenderedImage();
    int dims[3];
    image->GetDimensions(dims);
    if (dims[0] != Size || dims[1] != Size)
    {
      std::cerr << run.Name << ": image is " << dims[0] << " x " << dims[1] << "\n";
      return EXIT_FAILURE;
    }
    auto* rgba = vtkFloatArray::SafeDownCast(image->GetPointData()->GetScalars());
    double maxError = 0.0;
    int hits = 0;
    for (int y = 0; y < Size; ++y)
    {
      for (int x = 0; x < Size; ++x)
      {
        const glm::dvec4 exact = Exact(renderer, tf, voxel, x, y);
        hits += exact.a > 0.0;
        for (int c = 0; c < 4; ++c)
        {
          const double v = rgba->GetComponent(static_cast<vtkIdType>(y) * Size + x, c);
          maxError = std::max(maxError, std::abs(v - exact[c]));
        }
      }
    }
    // The image is stored in float: 6e-8 relative.
    std::cout << run.Name << ": " << hits << " pixels hit, max error " << maxError << ", "
              << mapper->GetMeanSamplesPerRay() << " samples per ray\n";
    const bool ok = hits > Size * Size / 4 &&
      (run.Required > 0.0 ? maxError <= run.Required + 1e-7 : maxError > 1e-2);
    if (!ok)
    {
      std::cerr << "FAIL " << run.Name << ": max error " << maxError << "\n";
      ++failures;
    }
  }

  // Shaded (Shading.h): the ramp's gradient is (0, 0, 40) per world unit
  // everywhere, so under one directional light every colour knot is lit to
  // A C + B with constants A and B, still linear in s: the closed form of the
  // transfer function with the lit knots is exact for the shaded integral.
  property->ShadeOn();
  property->SetAmbient(0.2);
  property->SetDiffuse(0.6);
  property->SetSpecular(0.3);
  property->SetSpecularPower(6.0);
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->SetPosition(0.4, -0.3, 1.0);
  light->SetFocalPoint(0.0, 0.0, 0.0);
  light->SetColor(1.0, 0.9, 0.8);
  light->SetIntensity(0.9);
  renderer->RemoveAllLights();
  renderer->AddLight(light);
  avos::numerics::ShadingModel<double> model;
  model.Ambient = 0.2;
  model.Diffuse = 0.6;
  model.Specular = 0.3;
  model.SpecularPower = 6.0;
  model.TwoSided = renderer->GetTwoSidedLighting() != 0;
  model.Lights.push_back({ glm::normalize(glm::dvec3(0.4, -0.3, 1.0)),
    0.9 * glm::dvec3(1.0, 0.9, 0.8), 0.9 * glm::dvec3(1.0, 0.9, 0.8) });
  double dop[3];
  renderer->GetActiveCamera()->GetDirectionOfProjection(dop);
  const glm::dvec3 toViewer(-dop[0], -dop[1], -dop[2]);
  avos::numerics::TransferFunction<double> lit;
  for (const auto& k : Knots)
  {
    const glm::dvec3 c = model.Shade(
      glm::dvec3(k[1], k[2], k[3]), glm::dvec3(0.0, 0.0, 1.0), toViewer, glm::dvec3(0.0));
    if (std::max({ c.r, c.g, c.b }) >= 1.0)
    {
      std::cerr << "FAIL the lit colours must stay below 1 (no clamping)\n";
      return EXIT_FAILURE;
    }
    lit.AddColorKnot(k[0], c.r, c.g, c.b);
    lit.AddOpacityKnot(k[0], k[4]);
  }
  lit.Finalize();
  const Run shaded[] = {
    { "shaded coupled eps 1e-3", vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED, 1e-3, 1e-3 },
    { "shaded decoupled eps 1e-3", vtkAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED, 1e-3, 1e-3 },
    { "shaded reference", vtkAdaptiveVolumeMapper::REFERENCE, 1e-2, 1e-7 },
    { "shaded piecewise eps 1e-2", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE, 1e-2, 1e-2 },
    { "shaded piecewise eps 1e-4", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE, 1e-4, 1e-4 },
  };
  for (const Run& run : shaded)
  {
    mapper->SetIntegrationMethod(run.Method);
    mapper->SetTolerance(run.Tolerance);
    window->Render();
    auto* rgba =
      vtkFloatArray::SafeDownCast(mapper->GetRenderedImage()->GetPointData()->GetScalars());
    double maxError = 0.0, unlitDifference = 0.0;
    for (int y = 0; y < Size && rgba; ++y)
    {
      for (int x = 0; x < Size; ++x)
      {
        const glm::dvec4 exact = Exact(renderer, lit, voxel, x, y);
        const glm::dvec4 unlit = Exact(renderer, tf, voxel, x, y);
        for (int c = 0; c < 4; ++c)
        {
          const double v = rgba->GetComponent(static_cast<vtkIdType>(y) * Size + x, c);
          maxError = std::max(maxError, std::abs(v - exact[c]));
          unlitDifference = std::max(unlitDifference, std::abs(exact[c] - unlit[c]));
        }
      }
    }
    std::cout << run.Name << ": max error " << maxError << " (the lit closed form differs from "
              << "the unlit one by up to " << unlitDifference << ")\n";
    if (!rgba || maxError > run.Required + 1e-7 || unlitDifference < 0.05)
    {
      std::cerr << "FAIL " << run.Name << ": max error " << maxError << "\n";
      ++failures;
    }
  }
  // An unchanged frame is reused; a dimmer light is a new frame.
  window->Render();
  const bool reused = mapper->GetLastRenderReused();
  light->SetIntensity(0.5);
  window->Render();
  if (!reused || mapper->GetLastRenderReused())
  {
    std::cerr << "FAIL a light change must recast, an unchanged frame must not\n";
    ++failures;
  }
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
