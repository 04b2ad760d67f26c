// vtkVolumeOnSurfaceMapper (VoS^M*) against a closed form: a constant volume
// on [-1, 1]^3 and a horizontal grid at z = 0 seen from above by a parallel
// camera; every vertex's ray runs straight up to the top face, 1 world unit,
// so its RGBA is c (1 - e^{-tau L}), 1 - e^{-tau L}. Then: an unchanged frame
// casts nothing, back-facing and off-screen vertices cost nothing, a coarser
// level of detail reuses the colours already computed for the same view, and
// bad input is reported.
#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlane.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTriangleFilter.h"
#include "vtkVolumeOnSurfaceMapper.h"
#include "vtkVolumeProperty.h"

#include "OverflowScene.h"
#include "avosTestHelpers.h"

#include <cmath>
#include <vector>

int TestVolumeOnSurfaceMapper(int, char*[])
{
  avostest::Checklist Expect;
  const double color[3] = { 0.9, 0.5, 0.1 }, tau = 0.04, voxel = 1.0 / 16.0;
  vtkNew<vtkImageData> volume;
  volume->SetDimensions(33, 33, 33);
  volume->SetOrigin(-1, -1, -1);
  volume->SetSpacing(voxel, voxel, voxel);
  volume->AllocateScalars(VTK_SHORT, 1);
  volume->GetPointData()->GetScalars()->Fill(300);
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0, color[0], color[1], color[2]);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0, tau);
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->SetColor(ctf);
  property->SetScalarOpacity(opacity);

  // A grid at z = 0.5 in the volume [-1, 1]^3, seen from +z: 1.5 world
  // units of volume behind it, 0.5 in front.
  vtkNew<vtkPlaneSource> grid;
  grid->SetOrigin(-0.9, -0.9, 0.5);
  grid->SetPoint1(0.9, -0.9, 0.5);
  grid->SetPoint2(-0.9, 0.9, 0.5);
  grid->SetResolution(30, 30);
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(grid->GetOutputPort());

  vtkNew<vtkVolumeOnSurfaceMapper> mapper;
  mapper->SetInputConnection(triangles->GetOutputPort());
  mapper->SetVolumeData(volume);
  mapper->SetVolumeProperty(property);
  mapper->ExtinctionOpacityOn();
  mapper->SetLevelOfDetail(0);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(64, 64);
  window->AddRenderer(renderer);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetPosition(0, 0, 5);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetParallelScale(1.2);
  renderer->ResetCameraClippingRange();

  const vtkIdType n = 31 * 31;
  // Each vertex's ray runs from the vertex away from the eye through the
  // 1.5 world units behind the grid (the paper's VoS^M*).
  const double alpha = 1.0 - std::exp(-tau * 1.5 / voxel);
  // The largest difference of any vertex's 8-bit colour from the closed form
  // of a constant medium of opacity `a`: colour times a, a.
  auto worstAgainst = [&](double a)
  {
    vtkDataArray* colors = mapper->GetColoredSurface()->GetPointData()->GetScalars();
    double worst = 0.0;
    for (vtkIdType v = 0; v < n; ++v)
    {
      for (int c = 0; c < 4; ++c)
      {
        const double exact = 255.0 * (c < 3 ? color[c] * a : a);
        worst = std::max(worst, std::abs(colors->GetComponent(v, c) - exact));
      }
    }
    return worst;
  };
  for (int method : { vtkVolumeOnSurfaceMapper::LEVOY, vtkVolumeOnSurfaceMapper::ADAPTIVE,
         vtkVolumeOnSurfaceMapper::PIECEWISE })
  {
    mapper->SetIntegrationMethod(method);
    window->Render();
    Expect(mapper->GetNumberOfVisibleVertices() == n && mapper->GetNumberOfRaysCast() == n,
      "every vertex visible, one ray each");
    Expect(worstAgainst(alpha) <= 0.5 + 1e-6, "colours = closed form (rounded to 8 bits)");
  }
  window->Render();
  Expect(mapper->GetNumberOfRaysCast() == 0, "an unchanged frame casts nothing");
  // The volume in front of the surface instead: the 0.5 world units between
  // the grid and the volume's boundary towards the eye.
  mapper->SetVolumeSideToInFrontOfSurface();
  window->Render();
  Expect(mapper->GetNumberOfRaysCast() == n &&
      worstAgainst(1.0 - std::exp(-tau * 0.5 / voxel)) <= 0.5 + 1e-6,
    "in front of the surface: the closed form of 0.5 world units");
  mapper->SetVolumeSideToBehindSurface();
  // NaN scalars, as the CPU mapper takes them: a cell with a NaN corner is
  // transparent. A NaN layer at z = -0.875 empties the cells on both sides
  // of it (0.125 world units of the 1.5 behind the grid): the piecewise rays
  // give the closed form of 1.375, the sampled ones within a step of it. The
  // count is said once, as by the CPU mapper.
  {
    avostest::ExpectedErrors nanNotice(mapper);
    vtkNew<vtkImageData> holed;
    holed->SetDimensions(33, 33, 33);
    holed->SetOrigin(-1, -1, -1);
    holed->SetSpacing(voxel, voxel, voxel);
    holed->AllocateScalars(VTK_FLOAT, 1);
    vtkDataArray* values = holed->GetPointData()->GetScalars();
    values->Fill(300);
    for (vtkIdType p = 0; p < 33 * 33; ++p)
    {
      values->SetTuple1(2 * 33 * 33 + p, std::nan(""));
    }
    mapper->SetVolumeData(holed);
    const double shortened = 1.0 - std::exp(-tau * 1.375 / voxel);
    for (int method : { vtkVolumeOnSurfaceMapper::PIECEWISE, vtkVolumeOnSurfaceMapper::LEVOY,
           vtkVolumeOnSurfaceMapper::ADAPTIVE })
    {
      mapper->SetIntegrationMethod(method);
      window->Render();
      Expect(method == vtkVolumeOnSurfaceMapper::PIECEWISE
          ? nanNotice.CheckWarning("NaN notice", "The input has 1089 NaN scalars")
          : nanNotice.None("NaN notice said once"),
        "the NaN scalars are counted once");
      Expect(worstAgainst(shortened) <=
          (method == vtkVolumeOnSurfaceMapper::PIECEWISE ? 0.5 + 1e-6 : 3.0),
        "NaN cells are transparent for the rays behind the surface");
    }
    mapper->SetVolumeData(volume);
    mapper->SetIntegrationMethodToLevoy();
  }

  // A clipping plane keeping z >= 0.5 - h cuts the rays too: each leaves the
  // kept volume after h world units (closed form), and moving the plane
  // casts again.
  vtkNew<vtkPlane> plane;
  plane->SetNormal(0, 0, 1);
  mapper->AddClippingPlane(plane);
  for (double h : { 0.5, 0.25 })
  {
    plane->SetOrigin(0, 0, 0.5 - h);
    window->Render();
    Expect(mapper->GetNumberOfRaysCast() == n, "a new or moved plane casts again");
    Expect(worstAgainst(1.0 - std::exp(-tau * h / voxel)) <= 0.5 + 1e-6,
      "clipped colours = closed form (rounded to 8 bits)");
  }
  mapper->RemoveAllClippingPlanes();
  window->Render();
  Expect(mapper->GetNumberOfRaysCast() == n, "removing the plane casts again");

  // A coarser level for the same view: colours come from the full level.
  vtkPolyData* fullDrawing = mapper->GetColoredSurface();
  mapper->SetLevelOfDetail(2); // 90 % decimated
  window->Render();
  Expect(mapper->GetLastLevelOfDetail() == 2, "level 2 drawn");
  Expect(mapper->GetColoredSurface()->GetNumberOfPolys() < 200, "level 2 is decimated");
  Expect(mapper->GetNumberOfRaysCast() == 0 &&
      mapper->GetNumberOfReusedColors() == mapper->GetNumberOfVisibleVertices(),
    "a coarser level reuses the colours");
  // Back to the full level: each level keeps its own drawing (the surface
  // handed to OpenGL, its geometry uploaded once), which comes back with
  // its colours rewritten.
  vtkPolyData* coarseDrawing = mapper->GetColoredSurface();
  mapper->SetLevelOfDetail(0);
  window->Render();
  Expect(coarseDrawing != fullDrawing && mapper->GetColoredSurface() == fullDrawing &&
      mapper->GetNumberOfRaysCast() == 0 && worstAgainst(alpha) <= 0.5 + 1e-6,
    "a level drawn again: its own drawing, its colours rewritten");

  // Memory (Tables III, IV): the short scalars, and surfaces that shrink
  // with the levels' decimation.
  Expect(mapper->GetVolumeMemory() >= 33 * 33 * 33 * 2 &&
      mapper->GetVolumeMemory() < 33 * 33 * 33 * 2 + 4096,
    "volume memory is its scalars");
  Expect(mapper->GetSurfaceMemory(0) > 1.5 * mapper->GetSurfaceMemory(1) &&
      mapper->GetSurfaceMemory(1) > mapper->GetSurfaceMemory(2) &&
      mapper->GetSurfaceMemory(2) > 0 && mapper->GetSurfaceMemory(3) == 0 &&
      mapper->GetSurfaceMemory(-1) == 0,
    "surface memory shrinks with decimation; none for missing levels");

  // Zoomed in: off-screen vertices cost nothing.
  camera->SetParallelScale(0.4);
  window->Render();
  Expect(mapper->GetNumberOfVisibleVertices() > 0 && mapper->GetNumberOfVisibleVertices() < n / 4,
    "off-screen vertices are skipped");
  camera->SetParallelScale(1.2);

  // From below, every vertex faces away.
  camera->SetPosition(0, 0, -5);
  renderer->ResetCameraClippingRange();
  window->Render();
  Expect(mapper->GetNumberOfVisibleVertices() == 0 && mapper->GetNumberOfRaysCast() == 0,
    "back-facing vertices cost nothing");

  // Automatic level: a high desired update rate with a known cost per ray
  // picks a coarser level.
  camera->SetPosition(0, 0, 5);
  renderer->ResetCameraClippingRange();
  mapper->SetLevelOfDetail(-1);
  window->SetDesiredUpdateRate(1e6);
  window->Render();
  Expect(mapper->GetLastLevelOfDetail() == 2, "interaction: the coarsest level");
  window->SetDesiredUpdateRate(0.0001);
  window->Render();
  Expect(mapper->GetLastLevelOfDetail() == 0, "still: the full surface");
  // Screen density: the grid covers 1.8 / 2.4 of the 64 pixels each way, so
  // its 31 x 31 cast vertices have 48^2 / 961 pixels each: above the default
  // 2, the full surface is kept.
  // (Within 1e-6 relative: VTK's camera matrices carry rounding of 5e-8.)
  Expect(std::abs(mapper->GetScreenPixelsPerVertex() / (48.0 * 48.0 / n) - 1.0) < 1e-6,
    "covered pixels per vertex = closed form");
  // Five times farther: 0.096 pixels per vertex; the 90 % level (about 100
  // vertices, about 1 pixel each) is enough, unless the rule is off.
  camera->SetParallelScale(6.0);
  window->Render();
  Expect(std::abs(mapper->GetScreenPixelsPerVertex() / (9.6 * 9.6 / n) - 1.0) < 1e-6,
    "covered pixels per vertex, zoomed out");
  Expect(mapper->GetLastLevelOfDetail() == 2, "a small surface: the coarsest level suffices");
  mapper->SetPixelsPerVertex(0.0);
  window->Render();
  Expect(mapper->GetLastLevelOfDetail() == 0, "density rule off: the full surface");
  mapper->SetPixelsPerVertex(2.0);
  camera->SetParallelScale(1.2);

  // Empty-space skipping: a blob behind the grid in a transparent volume. The
  // rays cross transparent blocks; a Riemann sum gives the same bytes with
  // and without skipping, the adaptive rule stays within its tolerance.
  {
    vtkNew<vtkImageData> blob;
    blob->SetDimensions(33, 33, 33);
    blob->SetOrigin(-1, -1, -1);
    blob->SetSpacing(voxel, voxel, voxel);
    blob->AllocateScalars(VTK_SHORT, 1);
    for (int k = 0; k < 33; ++k)
    {
      for (int j = 0; j < 33; ++j)
      {
        for (int i = 0; i < 33; ++i)
        {
          const double x = -1 + i * voxel, y = -1 + j * voxel, z = -1 + k * voxel;
          const bool inside = x * x + y * y + (z + 0.2) * (z + 0.2) < 0.2;
          blob->GetPointData()->GetScalars()->SetTuple1(i + 33 * (j + 33 * k), inside ? 300 : 0);
        }
      }
    }
    vtkNew<vtkPiecewiseFunction> ramp;
    ramp->AddPoint(0, 0);
    ramp->AddPoint(100, 0);
    ramp->AddPoint(300, tau);
    vtkNew<vtkVolumeProperty> blobProperty;
    blobProperty->SetInterpolationTypeToLinear();
    blobProperty->SetColor(ctf);
    blobProperty->SetScalarOpacity(ramp);
    mapper->SetVolumeData(blob);
    mapper->SetVolumeProperty(blobProperty);
    mapper->SetLevelOfDetail(0);
    auto colours = [&]()
    {
      window->Render();
      vtkDataArray* c = mapper->GetColoredSurface()->GetPointData()->GetScalars();
      std::vector<double> values(static_cast<std::size_t>(4 * n));
      for (vtkIdType v = 0; v < n; ++v)
      {
        for (int k = 0; k < 4; ++k)
        {
          values[static_cast<std::size_t>(4 * v + k)] = c->GetComponent(v, k);
        }
      }
      return values;
    };
    for (int method : { vtkVolumeOnSurfaceMapper::LEVOY, vtkVolumeOnSurfaceMapper::ADAPTIVE,
           vtkVolumeOnSurfaceMapper::PIECEWISE })
    {
      const bool adaptive = method != vtkVolumeOnSurfaceMapper::LEVOY;
      mapper->SetIntegrationMethod(method);
      mapper->EmptySpaceSkippingOn();
      const std::vector<double> skipped = colours();
      mapper->EmptySpaceSkippingOff();
      const std::vector<double> full = colours();
      double worst = 0.0, brightest = 0.0;
      for (std::size_t i = 0; i < full.size(); ++i)
      {
        worst = std::max(worst, std::abs(skipped[i] - full[i]));
        brightest = std::max(brightest, full[i]);
      }
      Expect(brightest > 50, "the blob colours some vertices");
      Expect(adaptive ? worst <= 255 * 2 * mapper->GetTolerance() + 1 : worst == 0.0,
        adaptive ? "adaptive and piecewise: skipping stays within the tolerance"
                 : "Riemann: skipping changes no colour");
    }
    mapper->EmptySpaceSkippingOn();
    mapper->SetIntegrationMethodToLevoy();
    mapper->SetVolumeData(volume);
    mapper->SetVolumeProperty(property);
  }

  // Bad input.
  avostest::ExpectedErrors errors(mapper);
  vtkNew<vtkImageData> pairs;
  pairs->SetDimensions(4, 4, 4);
  pairs->AllocateScalars(VTK_FLOAT, 2);
  pairs->GetPointData()->GetScalars()->Fill(0.0);
  mapper->SetVolumeData(pairs);
  property->ShadeOn();
  camera->Azimuth(1);
  window->Render();
  Expect(errors.Check("two components, shaded", "cannot shade scalars of 2 components"),
    "a shaded volume of two components");
  property->ShadeOff();
  vtkNew<vtkPiecewiseFunction> ramp;
  ramp->AddPoint(0.0, 0.0);
  ramp->AddPoint(1.0, 1.0);
  property->SetGradientOpacity(ramp);
  camera->Azimuth(1);
  window->Render();
  Expect(errors.Check("two components, gradient opacity",
           "gradient opacity is not supported with scalars of 2 components"),
    "gradient opacity on a volume of two components");
  property->DisableGradientOpacityOn();
  mapper->SetVolumeData(volume);
  // Scalars at the edge of double's range overflow between grid points: the
  // piecewise rays cannot be integrated and the frame says so (nothing drawn)
  // instead of colouring the vertices transparent.
  {
    const overflowscene::Scene extreme(volume, tau);
    mapper->SetVolumeData(extreme.Volume);
    mapper->SetVolumeProperty(extreme.Property);
    mapper->SetIntegrationMethodToPiecewise();
    camera->Azimuth(1);
    window->Render();
    Expect(errors.Check("overflow", "ray(s) could not be integrated"), "overflowing rays");
    mapper->SetVolumeData(volume);
    mapper->SetVolumeProperty(property);
    mapper->SetIntegrationMethodToLevoy();
  }
  // An HSV colour map: the piecewise method converts it within a proven
  // bound (no warning); the Riemann sum's conversion is not certified and
  // says so.
  {
    vtkNew<vtkColorTransferFunction> hsv;
    hsv->SetColorSpaceToHSV();
    hsv->AddRGBPoint(0, 0.0, 0.0, 1.0);
    hsv->AddRGBPoint(600, 1.0, 0.0, 0.0);
    property->SetColor(hsv);
    mapper->SetIntegrationMethodToPiecewise();
    camera->Azimuth(1);
    window->Render();
    Expect(errors.None("HSV colours, piecewise"), "an HSV map is certified for the piecewise rays");
    mapper->SetIntegrationMethodToLevoy();
    camera->Azimuth(1);
    window->Render();
    Expect(errors.CheckWarning("HSV colours, Riemann", "not certified"),
      "an HSV map is reported approximated for the Riemann rays");
    property->SetColor(ctf);
  }
  vtkNew<vtkPolyData> empty;
  mapper->SetInputData(empty);
  window->Render(); // the renderer skips an actor without bounds: ask directly
  mapper->Render(renderer, actor);
  Expect(errors.Check("empty surface", "empty"), "empty surface");
  return Expect.Result();
}
