// vtkVolumeOnSurfaceFilter against a closed form: a constant volume on
// [-1, 1]^3 seen through a horizontal square at z = 0.5 from above. The
// cones point into the volume (down, opposite the square's normal); every
// ray of the 20-degree cone of a central vertex leaves through the bottom
// face after 1.5 / cos 20 world units, so its RGBA is c (1 - e^{-tau L}),
// 1 - e^{-tau L}; that cone is the closest to the observation line (eye to
// vertex, downwards). The volume in front of the square (VolumeSide
// IN_FRONT_OF_SURFACE) is 0.5 / cos 20 long. With a gradient opacity G, the
// constant volume's extinction is tau G(0). Then: a camera change only
// reassigns, a transfer-function change casts again, a camera below the
// surface sees no ray, the memory report, and bad input.
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeOnSurfaceFilter.h"
#include "vtkVolumeProperty.h"

#include "OverflowScene.h"
#include "avosTestHelpers.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

namespace
{
avostest::Checklist Expect;
} // namespace

int TestVolumeOnSurfaceFilter(int, char*[])
{
  const double color[3] = { 0.2, 0.6, 0.9 }, tau = 0.05, voxel = 1.0 / 16.0;
  vtkNew<vtkImageData> volume;
  volume->SetDimensions(33, 33, 33);
  volume->SetOrigin(-1, -1, -1);
  volume->SetSpacing(voxel, voxel, voxel);
  volume->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  volume->GetPointData()->GetScalars()->Fill(100);

  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0, color[0], color[1], color[2]);
  ctf->AddRGBPoint(255, color[0], color[1], color[2]);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0, tau);
  opacity->AddPoint(255, tau);
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->SetColor(ctf);
  property->SetScalarOpacity(opacity);

  vtkNew<vtkPlaneSource> square;
  square->SetOrigin(-0.8, -0.8, 0.5);
  square->SetPoint1(0.8, -0.8, 0.5);
  square->SetPoint2(-0.8, 0.8, 0.5);
  square->SetResolution(8, 8);

  vtkNew<vtkCamera> camera;
  camera->ParallelProjectionOn();
  camera->SetPosition(0, 0, 5);
  camera->SetFocalPoint(0, 0, 0);

  vtkNew<vtkVolumeOnSurfaceFilter> vos;
  vos->SetInputConnection(square->GetOutputPort());
  vos->SetInputData(1, volume);
  vos->SetVolumeProperty(property);
  vos->SetCamera(camera);
  vos->ExtinctionOpacityOn();

  const double secant = 1.0 / std::cos(vtkMath::RadiansFromDegrees(20.0));
  // Every central vertex's colour is the closed form for the extinction tau
  // times `factor` over L voxel units.
  auto centralColours = [&](vtkPolyData* out, double L, double factor)
  {
    vtkDataArray* colors = out->GetPointData()->GetArray("VoSColors");
    vtkDataArray* rays = out->GetPointData()->GetArray("VoSRay");
    if (!colors || !rays)
    {
      return false;
    }
    const double alpha = 1.0 - std::exp(-factor * tau * L);
    int central = 0;
    bool exact = true;
    for (vtkIdType v = 0; v < out->GetNumberOfPoints(); ++v)
    {
      double p[3];
      out->GetPoint(v, p);
      // (Their 20-degree rays stay within the volume's sides: 0.4 + 1.5 tan 20 < 1.)
      if (std::abs(p[0]) > 0.4 + 1e-6 || std::abs(p[1]) > 0.4 + 1e-6)
      {
        continue;
      }
      ++central;
      const int ray = static_cast<int>(rays->GetTuple1(v));
      exact = exact && ray >= 0 && ray < 4; // the 20-degree cone is chosen
      for (int c = 0; c < 4; ++c)
      {
        const double expected = 255.0 * (c < 3 ? color[c] * alpha : alpha);
        exact = exact && std::abs(colors->GetComponent(v, c) - expected) <= 0.5 + 1e-6;
      }
    }
    return exact && central == 25;
  };
  for (int method : { int(vtkVolumeOnSurfaceFilter::LEVOY), int(vtkVolumeOnSurfaceFilter::ADAPTIVE),
         int(vtkVolumeOnSurfaceFilter::PIECEWISE), -1 })
  {
    // -1: the piecewise method through the volume in front of the square.
    vos->SetVolumeSide(method < 0 ? vtkVolumeOnSurfaceFilter::IN_FRONT_OF_SURFACE
                                  : vtkVolumeOnSurfaceFilter::BEHIND_SURFACE);
    const double L = (method < 0 ? 0.5 : 1.5) * secant / voxel;
    vos->SetIntegrationMethod(method < 0 ? vtkVolumeOnSurfaceFilter::PIECEWISE : method);
    vos->Update();
    vtkPolyData* out = vos->GetOutput();
    vtkDataArray* colors = out->GetPointData()->GetArray("VoSColors");
    vtkDataArray* rays = out->GetPointData()->GetArray("VoSRay");
    Expect(colors && rays && out->GetPointData()->GetScalars() == colors, "output arrays");
    if (!colors || !rays)
    {
      return EXIT_FAILURE;
    }
    Expect(vos->GetNumberOfRaysCast() == 81 * 12, "12 rays per vertex cast");
    Expect(centralColours(out, L, 1.0),
      "the 25 central vertices' colours = closed form (rounded to 8 bits), from the 20-degree "
      "cone");
  }
  vos->SetVolumeSideToBehindSurface();
  vos->Update();

  avostest::ExpectedErrors errors(vos);
  // Gradient opacity: the constant volume's gradient is 0, and G(0) = 1/2
  // halves the extinction, whatever the method.
  vtkNew<vtkPiecewiseFunction> gradientOpacity;
  gradientOpacity->AddPoint(0, 0.5);
  gradientOpacity->AddPoint(10, 1.0);
  property->SetGradientOpacity(gradientOpacity);
  for (int method : { int(vtkVolumeOnSurfaceFilter::LEVOY), int(vtkVolumeOnSurfaceFilter::ADAPTIVE),
         int(vtkVolumeOnSurfaceFilter::PIECEWISE) })
  {
    vos->SetIntegrationMethod(method);
    vos->Update();
    Expect(centralColours(vos->GetOutput(), 1.5 * secant / voxel, 0.5),
      "gradient opacity: the central vertices' colours = closed form with tau / 2");
  }
  // A curved G (its sharpness moved): certified by the piecewise method (no
  // notice), resampled with a notice by the others.
  vtkNew<vtkPiecewiseFunction> curved;
  curved->AddPoint(0, 0.5, 0.5, 0.5);
  curved->AddPoint(10, 1.0);
  property->SetGradientOpacity(curved);
  vos->Update();
  Expect(errors.None("curved G") && centralColours(vos->GetOutput(), 1.5 * secant / voxel, 0.5),
    "a curved G: certified by the piecewise method, the closed form with tau / 2");
  vos->SetIntegrationMethodToLevoy();
  vos->Update();
  Expect(errors.CheckWarning("curved G, Riemann sum", "approximated"),
    "a curved G: resampled by the Riemann sum, with a notice");
  property->DisableGradientOpacityOn();
  vos->Update();

  // A camera change only reassigns; a transfer-function change casts again.
  camera->Azimuth(10);
  vos->Update();
  Expect(vos->GetNumberOfRaysCast() == 0, "camera change: assignment only");
  opacity->AddPoint(50, tau);
  vos->Update();
  Expect(vos->GetNumberOfRaysCast() == 81 * 12, "transfer-function change: rays cast again");

  // From below, the observation line runs up: no ray of the downward cones.
  camera->SetPosition(0, 0, -5);
  camera->SetViewUp(0, 1, 0);
  vos->Update();
  Expect(vos->GetOutput()->GetPointData()->GetArray("VoSRay")->GetRange()[1] == -1,
    "seen from below: no ray");
  Expect(vos->GetConesMemory() == 81 * 12 * (3 + 4) * 4, "cones memory");
  Expect(vos->GetVolumeMemory() >= 33 * 33 * 33, "volume memory");
  camera->SetPosition(0, 0, 5);

  // Empty-space skipping: with the top of the volume transparent,
  // toggling it casts again and changes no Levoy colour.
  {
    auto* scalars = volume->GetPointData()->GetScalars();
    for (vtkIdType i = 0; i < scalars->GetNumberOfTuples(); ++i)
    {
      double p[3];
      volume->GetPoint(i, p);
      scalars->SetTuple1(i, p[2] > 0.4 ? 0 : 100); // the top block row is empty
    }
    scalars->Modified();
    opacity->RemoveAllPoints();
    opacity->AddPoint(0, 0);
    opacity->AddPoint(40, 0);
    opacity->AddPoint(100, tau);
    vos->SetIntegrationMethodToLevoy();
    vos->EmptySpaceSkippingOn();
    vos->Update();
    auto copy = vtkSmartPointer<vtkDataArray>::Take(
      vos->GetOutput()->GetPointData()->GetArray("VoSColors")->NewInstance());
    copy->DeepCopy(vos->GetOutput()->GetPointData()->GetArray("VoSColors"));
    vos->EmptySpaceSkippingOff();
    vos->Update();
    Expect(vos->GetNumberOfRaysCast() == 81 * 12, "toggling skipping casts again");
    vtkDataArray* full = vos->GetOutput()->GetPointData()->GetArray("VoSColors");
    double worst = 0.0, brightest = 0.0;
    for (vtkIdType i = 0; i < full->GetNumberOfValues(); ++i)
    {
      worst = std::max(
        worst, std::abs(full->GetComponent(i / 4, i % 4) - copy->GetComponent(i / 4, i % 4)));
      brightest = std::max(brightest, full->GetComponent(i / 4, i % 4));
    }
    Expect(brightest > 10 && worst == 0.0, "skipping changes no Levoy colour");
    vos->EmptySpaceSkippingOn();
  }

  // Abort: a long previsualization (10,201 vertices x 12 rays at the
  // smallest step, about 10^9 samples) stopped by AbortExecute at its first
  // progress report leaves no output and nothing cached: the next update casts
  // every ray. Progress comes from the updating thread, in [0, 1).
  {
    vtkNew<vtkPlaneSource> fine;
    fine->SetOrigin(-0.8, -0.8, 0);
    fine->SetPoint1(0.8, -0.8, 0);
    fine->SetPoint2(-0.8, 0.8, 0);
    fine->SetResolution(100, 100);
    vos->SetInputConnection(fine->GetOutputPort());
    vos->SetIntegrationMethodToLevoy();
    vos->SetSampleDistance(0.001);
    struct Reports
    {
      vtkVolumeOnSurfaceFilter* Filter;
      std::vector<double> Fractions;
    } reports{ vos, {} };
    vtkNew<vtkCallbackCommand> onProgress;
    onProgress->SetClientData(&reports);
    onProgress->SetCallback(
      [](vtkObject*, unsigned long, void* client, void* call)
      {
        auto* r = static_cast<Reports*>(client);
        const double fraction = *static_cast<double*>(call);
        r->Fractions.push_back(fraction);
        if (fraction > 0.0 && fraction < 1.0)
        {
          r->Filter->AbortExecuteOn();
        }
      });
    const unsigned long observer = vos->AddObserver(vtkCommand::ProgressEvent, onProgress);
    vos->Update();
    std::cout << "aborted previsualization, progress reports:";
    for (double f : reports.Fractions)
    {
      std::cout << " " << f;
    }
    std::cout << "\n";
    Expect(vos->GetOutput()->GetNumberOfPoints() == 0, "an aborted previsualization: no output");
    Expect(!reports.Fractions.empty() && reports.Fractions.back() < 0.5,
      "the previsualization stopped early");
    vos->RemoveObserver(observer);
    vos->AbortExecuteOff();
    vos->SetSampleDistance(0.5);
    vos->Update();
    Expect(vos->GetNumberOfRaysCast() == 101 * 101 * 12 &&
        vos->GetOutput()->GetNumberOfPoints() == 101 * 101,
      "after an abort, every ray is cast");
    vos->SetInputConnection(square->GetOutputPort());
  }

  // Bad input.
  for (double step : { 0.0, 1e-4, 2e3, std::nan("") })
  {
    vos->SetSampleDistance(step);
    vos->Update();
    Expect(errors.Check("sample distance", "the sample distance must be within [0.001"),
      "a sample distance out of range");
  }
  vos->SetSampleDistance(0.5);
  for (double tolerance : { 0.0, 2.0, std::nan("") })
  {
    vos->SetTolerance(tolerance);
    vos->Update();
    Expect(
      errors.Check("tolerance", "the tolerance must be within (0, 1]"), "a tolerance out of range");
  }
  vos->SetTolerance(0.01);
  vos->SetCamera(nullptr);
  vos->Update();
  Expect(errors.Check("no camera", "No camera to assign the colours for"), "no camera");
  vos->SetCamera(camera);
  vos->SetVolumeProperty(nullptr);
  vos->Update();
  Expect(errors.Check("no property", "No volume property"), "no volume property");
  vos->SetVolumeProperty(property);
  vos->AddOpeningAngle(95.0);
  vos->Update();
  Expect(errors.Check("angle", "Opening angles must be in (0, 90] degrees"), "a 95-degree cone");
  vos->RemoveAllOpeningAngles();
  vos->Update();
  Expect(errors.Check("no cones", "at least one cone and one ray per cone"), "no cones");
  for (double angle : { 20.0, 45.0, 70.0 }) // the defaults
  {
    vos->AddOpeningAngle(angle);
  }
  vos->SetRaysPerCone(0);
  vos->Update();
  Expect(errors.Check("zero rays", "one ray per cone"), "zero rays per cone");
  Expect(vos->GetOutput()->GetNumberOfPoints() == 0, "empty output after an error");
  vos->SetRaysPerCone(4);

  vtkNew<vtkImageData> vectors;
  vectors->SetDimensions(4, 4, 4);
  vectors->AllocateScalars(VTK_FLOAT, 5);
  vos->SetInputData(1, vectors);
  vos->Update();
  Expect(errors.Check("five components", "1 to 4 components are supported, not 5"),
    "a volume of five components");
  vos->SetInputData(1, volume);

  // Scalars at the edge of double's range overflow between grid points: the
  // piecewise rays cannot be integrated, and the filter says so instead of
  // colouring the vertices transparent. (The adaptive and Levoy rays treat a
  // sample that is not finite as transparent, as they treat NaN data.)
  {
    const overflowscene::Scene extreme(volume, tau);
    vos->SetInputData(1, extreme.Volume);
    vos->SetVolumeProperty(extreme.Property);
    vos->SetIntegrationMethodToPiecewise();
    vos->Update();
    Expect(errors.Check("overflow", "ray(s) could not be integrated"), "overflowing rays");
    Expect(vos->GetOutput()->GetNumberOfPoints() == 0, "no output from overflowing rays");
    vos->SetInputData(1, volume);
    vos->SetVolumeProperty(property);
    vos->SetIntegrationMethodToLevoy();
  }

  vtkNew<vtkPlaneSource> far;
  far->SetCenter(10, 10, 10);
  vos->SetInputConnection(far->GetOutputPort());
  vos->Update();
  Expect(errors.Check("outside", "outside the volume"), "surface outside the volume");

  vtkNew<vtkPolyData> empty;
  vos->SetInputData(empty);
  vos->Update();
  Expect(errors.Check("empty surface", "empty"), "empty surface");

  vos->SetInputConnection(square->GetOutputPort());
  vos->Update();
  Expect(errors.None("good input again"), "recovers");
  return Expect.Result();
}
