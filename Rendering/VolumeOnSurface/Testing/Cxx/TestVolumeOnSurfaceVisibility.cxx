// vtkVolumeOnSurfaceMapper's depth pass (VisibilityTest DEPTH_VISIBILITY):
// two horizontal grids seen from above by a parallel camera, the upper one
// covering the left half of the lower one, 0.5 world units (8 voxels) above
// it. With the pass, the lower grid's vertices under the upper one get no ray
// (their count is known: those inside its border, less the ring sharing
// polygons with visible vertices), every
// other vertex gets the colour it gets without the pass, and the image is the
// same to the byte: what the pass leaves uncoloured is hidden. Then AUTOMATIC
// draws the pass on its first frame, to measure it. Last, polygons with no
// cast corner are not drawn: with the upper grid turned away from the eye
// (no vertex of it cast), the image is the lower grid's alone, to the byte,
// where drawing it would put black over the lower grid's left half.
#include "vtkActor.h"
#include "vtkAppendPolyData.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkReverseSense.h"
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolumeOnSurfaceMapper.h"
#include "vtkVolumeProperty.h"
#include "vtkWindowToImageFilter.h"

#include "avosTestHelpers.h"

#include <cstdlib>
#include <vector>

int TestVolumeOnSurfaceVisibility(int, char*[])
{
  avostest::Checklist Expect;
  const double voxel = 1.0 / 16.0;
  vtkNew<vtkImageData> volume;
  volume->SetDimensions(33, 33, 33);
  volume->SetOrigin(-1, -1, -1);
  volume->SetSpacing(voxel, voxel, voxel);
  volume->AllocateScalars(VTK_SHORT, 1);
  // A ramp along x, so that every column of vertices has its own colour.
  for (int k = 0; k < 33; ++k)
  {
    for (int j = 0; j < 33; ++j)
    {
      for (int i = 0; i < 33; ++i)
      {
        volume->GetPointData()->GetScalars()->SetTuple1(i + 33 * (j + 33 * k), 10 * i);
      }
    }
  }
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0, 0.9, 0.2, 0.1);
  ctf->AddRGBPoint(320, 0.1, 0.4, 0.9);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0, 0.02);
  opacity->AddPoint(320, 0.1);
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->SetColor(ctf);
  property->SetScalarOpacity(opacity);

  // Lower grid: x in [-0.9, 0.9], 31 x 31 vertices, 0.06 apart; upper grid:
  // x in [-0.9, 0], 16 x 31 vertices, at z = 0.5.
  vtkNew<vtkPlaneSource> lower;
  lower->SetOrigin(-0.9, -0.9, 0);
  lower->SetPoint1(0.9, -0.9, 0);
  lower->SetPoint2(-0.9, 0.9, 0);
  lower->SetResolution(30, 30);
  vtkNew<vtkPlaneSource> upper;
  upper->SetOrigin(-0.9, -0.9, 0.5);
  upper->SetPoint1(0.0, -0.9, 0.5);
  upper->SetPoint2(-0.9, 0.9, 0.5);
  upper->SetResolution(15, 30);
  vtkNew<vtkAppendPolyData> both;
  both->AddInputConnection(lower->GetOutputPort());
  both->AddInputConnection(upper->GetOutputPort());
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(both->GetOutputPort());

  vtkNew<vtkVolumeOnSurfaceMapper> mapper, fresh;
  for (vtkVolumeOnSurfaceMapper* m : { mapper.Get(), fresh.Get() })
  {
    m->SetInputConnection(triangles->GetOutputPort());
    m->SetVolumeData(volume);
    m->SetVolumeProperty(property);
    m->SetLevelOfDetail(0);
  }
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(200, 200);
  window->AddRenderer(renderer);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetPosition(0, 0, 5);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetParallelScale(1.0);
  renderer->ResetCameraClippingRange();

  const vtkIdType lowerCount = 31 * 31, n = lowerCount + 16 * 31;
  auto render = [&](vtkVolumeOnSurfaceMapper* m, int test, std::vector<unsigned char>& colours,
                  std::vector<unsigned char>& image)
  {
    m->SetVisibilityTest(test); // a new setting: cast again
    actor->SetMapper(m);
    window->Render();
    vtkDataArray* c = m->GetColoredSurface()->GetPointData()->GetScalars();
    colours.resize(static_cast<std::size_t>(4 * c->GetNumberOfTuples()));
    for (vtkIdType v = 0; v < c->GetNumberOfTuples(); ++v)
    {
      for (int k = 0; k < 4; ++k)
      {
        colours[static_cast<std::size_t>(4 * v + k)] =
          static_cast<unsigned char>(c->GetComponent(v, k));
      }
    }
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    grab->ReadFrontBufferOff();
    grab->ShouldRerenderOff(); // the frame just drawn, statistics kept
    grab->Update();
    auto* pixels =
      vtkUnsignedCharArray::SafeDownCast(grab->GetOutput()->GetPointData()->GetScalars());
    image.assign(pixels->GetPointer(0), pixels->GetPointer(0) + pixels->GetNumberOfValues());
  };

  std::vector<unsigned char> offColours, offImage, depthColours, depthImage;
  render(mapper, vtkVolumeOnSurfaceMapper::NO_VISIBILITY, offColours, offImage);
  // Drawn opaque with the colours' RGB (premultiplied): under the headlight
  // a horizontal grid shows them unchanged, where blending the RGBA would
  // show RGB times A. The lower grid's vertex at (0.48, 0) is pixel
  // (148, 100); the ramp changes its colour by under 3 units a pixel.
  {
    vtkPolyData* drawn = mapper->GetColoredSurface();
    vtkIdType probe = -1;
    for (vtkIdType v = 0; v < lowerCount; ++v)
    {
      const double* p = drawn->GetPoint(v);
      probe = std::abs(p[0] - 0.48) < 1e-6 && std::abs(p[1]) < 1e-6 ? v : probe;
    }
    const unsigned char* rgba = &offColours[static_cast<std::size_t>(4 * probe)];
    const unsigned char* pixel = &offImage[3 * (100 * 200 + 148)];
    bool opaque = probe >= 0 && rgba[3] < 200;
    for (int k = 0; k < 3 && opaque; ++k)
    {
      opaque = std::abs(int(pixel[k]) - int(rgba[k])) <= 3;
    }
    Expect(opaque, "the surface shows its colours' RGB, opaque");
  }
  Expect(mapper->GetNumberOfRaysCast() == n && !mapper->GetLastDepthPass() &&
      mapper->GetNumberOfHiddenVertices() == 0,
    "without the pass every vertex gets a ray");
  render(mapper, vtkVolumeOnSurfaceMapper::DEPTH_VISIBILITY, depthColours, depthImage);
  // Hidden: the lower grid's vertices under the upper grid (x = -0.9 .. -0.06,
  // all y) whose 3 x 3 pixels are all covered by it (not those on its border,
  // x = -0.9 or y = +-0.9, next to the background) and none of whose
  // polygons reaches a visible vertex (not the next ones in: x = -0.84 and
  // -0.06, y = +-0.84): x = -0.78 .. -0.12 (12 columns), y = -0.78 .. 0.78
  // (27 rows).
  Expect(mapper->GetLastDepthPass() && mapper->GetNumberOfHiddenVertices() == 12 * 27 &&
      mapper->GetNumberOfRaysCast() == n - 12 * 27,
    "the pass: the covered vertices get no ray");
  bool same = true;
  for (vtkIdType v = 0; v < n; ++v)
  {
    const double x = mapper->GetColoredSurface()->GetPoint(v)[0];
    const bool covered = v < lowerCount && x < -0.06 - 1e-9;
    for (int k = 0; k < 4 && !covered; ++k)
    {
      same = same &&
        depthColours[static_cast<std::size_t>(4 * v + k)] ==
          offColours[static_cast<std::size_t>(4 * v + k)];
    }
  }
  Expect(same, "every vertex the pass keeps has the colour it has without the pass");
  Expect(depthImage == offImage && !offImage.empty(), "the image is the same to the byte");

  render(fresh, vtkVolumeOnSurfaceMapper::AUTOMATIC_VISIBILITY, depthColours, depthImage);
  Expect(fresh->GetLastDepthPass() && depthImage == offImage,
    "automatic: the first frame measures the pass, same image");

  std::vector<unsigned char> aloneColours, aloneImage, turnedColours, turnedImage;
  vtkNew<vtkTriangleFilter> lowerTriangles;
  lowerTriangles->SetInputConnection(lower->GetOutputPort());
  vtkNew<vtkReverseSense> away;
  away->SetInputConnection(upper->GetOutputPort());
  away->ReverseCellsOn();
  away->ReverseNormalsOn();
  vtkNew<vtkAppendPolyData> turnedBoth;
  turnedBoth->AddInputConnection(lower->GetOutputPort());
  turnedBoth->AddInputConnection(away->GetOutputPort());
  vtkNew<vtkTriangleFilter> turnedTriangles;
  turnedTriangles->SetInputConnection(turnedBoth->GetOutputPort());
  vtkNew<vtkVolumeOnSurfaceMapper> alone, turned;
  alone->SetInputConnection(lowerTriangles->GetOutputPort());
  turned->SetInputConnection(turnedTriangles->GetOutputPort());
  for (vtkVolumeOnSurfaceMapper* m : { alone.Get(), turned.Get() })
  {
    m->SetVolumeData(volume);
    m->SetVolumeProperty(property);
    m->SetLevelOfDetail(0);
  }
  render(alone, vtkVolumeOnSurfaceMapper::NO_VISIBILITY, aloneColours, aloneImage);
  render(turned, vtkVolumeOnSurfaceMapper::NO_VISIBILITY, turnedColours, turnedImage);
  Expect(turned->GetNumberOfRaysCast() == lowerCount &&
      turned->GetNumberOfVisibleVertices() == lowerCount,
    "the turned grid's vertices get no ray");
  Expect(turnedImage == aloneImage && aloneImage != offImage,
    "polygons with no cast corner are not drawn: the lower grid shows through");
  return Expect.Result();
}
