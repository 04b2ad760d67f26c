// vtkVolumeOnSurfaceMapper's DrawFullSurface: a sphere in a volume whose
// scalars ramp along x, seen in perspective, close enough for the window
// edges to cut it. Cast at the 90 % level and
// drawn whole, against every vertex cast (level 0):
// - the full surface is drawn and fewer than half the rays are cast;
// - the level's vertices (vtkOriginalPointIds of the same level drawn
//   decimated) have exactly the colours of their own rays;
// - every other vertex has a convex combination of colours from around it:
//   each channel within the range the exact colours take over the vertices
//   near it (3 mean edges of the level), up to 8-bit rounding;
// - no front-facing vertex stays uncoloured (those whose nearest level
//   vertices are all out of the frustum or face away get their own ray:
//   there are some here);
// - a level list without the full surface gives the same colours, drawn
//   decimated or whole;
// - an unchanged frame casts nothing, and turning the setting off casts
//   again and draws the level.
#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSphereSource.h"
#include "vtkVolumeOnSurfaceMapper.h"
#include "vtkVolumeProperty.h"

#include "avosTestHelpers.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace
{
double Distance(const double* a, const double* b)
{
  return std::sqrt(
    (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}
}

int TestVolumeOnSurfaceFullSurface(int, char*[])
{
  avostest::Checklist Expect;
  const int size = 41;
  const double voxel = 2.0 / (size - 1);
  vtkNew<vtkImageData> volume;
  volume->SetDimensions(size, size, size);
  volume->SetOrigin(-1, -1, -1);
  volume->SetSpacing(voxel, voxel, voxel);
  volume->AllocateScalars(VTK_FLOAT, 1);
  for (int k = 0; k < size; ++k)
  {
    for (int j = 0; j < size; ++j)
    {
      for (int i = 0; i < size; ++i)
      {
        volume->GetPointData()->GetScalars()->SetTuple1(i + size * (j + size * k), 10.0 * i);
      }
    }
  }
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0, 0.9, 0.2, 0.1);
  ctf->AddRGBPoint(400, 0.1, 0.4, 0.9);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0, 0.01);
  opacity->AddPoint(400, 0.05);
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->SetColor(ctf);
  property->SetScalarOpacity(opacity);

  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(0.7);
  sphere->SetThetaResolution(96);
  sphere->SetPhiResolution(96);
  sphere->Update();
  vtkPolyData* surface = sphere->GetOutput();
  const vtkIdType n = surface->GetNumberOfPoints();

  vtkNew<vtkVolumeOnSurfaceMapper> all, spread, level;
  for (vtkVolumeOnSurfaceMapper* m : { all.Get(), spread.Get(), level.Get() })
  {
    m->SetInputData(surface);
    m->SetVolumeData(volume);
    m->SetVolumeProperty(property);
    m->SetVisibilityTest(vtkVolumeOnSurfaceMapper::NO_VISIBILITY);
    m->RemoveAllLevelOfDetailReductions();
    m->AddLevelOfDetailReduction(0.0);
    m->AddLevelOfDetailReduction(0.9);
  }
  all->SetLevelOfDetail(0);
  spread->SetLevelOfDetail(1);
  spread->DrawFullSurfaceOn();
  level->SetLevelOfDetail(1);
  vtkNew<vtkActor> actor;
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(120, 100);
  window->AddRenderer(renderer);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(0.4, 0.3, 2.0); // the window edges cut the sphere
  camera->SetFocalPoint(0, 0, 0);
  renderer->ResetCameraClippingRange();
  auto render = [&](vtkVolumeOnSurfaceMapper* m)
  {
    actor->SetMapper(m);
    window->Render();
    return m->GetColoredSurface()->GetPointData()->GetScalars();
  };

  vtkDataArray* exact = render(all);
  const vtkIdType allRays = all->GetNumberOfRaysCast();
  vtkDataArray* mixed = render(spread);
  const vtkIdType spreadRays = spread->GetNumberOfRaysCast();
  Expect(
    spread->GetLastLevelOfDetail() == 1 && spread->GetColoredSurface()->GetNumberOfPoints() == n,
    "cast at level 1, the full surface drawn");
  Expect(spreadRays > 0 && 2 * spreadRays < allRays, "fewer than half the rays");
  render(level);
  vtkPolyData* decimated = level->GetColoredSurface();
  auto* ids =
    vtkIdTypeArray::SafeDownCast(decimated->GetPointData()->GetArray("vtkOriginalPointIds"));
  Expect(ids && level->GetNumberOfRaysCast() > 0, "the level drawn decimated");
  if (!ids)
  {
    return Expect.Result();
  }

  std::vector<char> isLevel(static_cast<std::size_t>(n), 0);
  bool levelExact = true;
  for (vtkIdType v = 0; v < ids->GetNumberOfTuples(); ++v)
  {
    const vtkIdType full = ids->GetValue(v);
    isLevel[static_cast<std::size_t>(full)] = 1;
    for (int c = 0; c < 4; ++c)
    {
      levelExact = levelExact && mixed->GetComponent(full, c) == exact->GetComponent(full, c);
    }
  }
  Expect(levelExact, "the level's vertices have their own rays' colours");

  // The level's mean edge: the radius around a vertex its colour comes from.
  double edges = 0.0;
  vtkIdType edgeCount = 0;
  decimated->GetPolys()->InitTraversal();
  vtkNew<vtkIdList> cell;
  while (decimated->GetPolys()->GetNextCell(cell))
  {
    for (vtkIdType k = 0; k < cell->GetNumberOfIds(); ++k)
    {
      edges += Distance(decimated->GetPoint(cell->GetId(k)),
        decimated->GetPoint(cell->GetId((k + 1) % cell->GetNumberOfIds())));
      ++edgeCount;
    }
  }
  const double radius = 3.0 * edges / static_cast<double>(std::max<vtkIdType>(edgeCount, 1));

  vtkIdType interpolated = 0, outside = 0, uncoloured = 0;
  for (vtkIdType v = 0; v < n; ++v)
  {
    const bool front = exact->GetComponent(v, 3) > 0.0;
    uncoloured += front && mixed->GetComponent(v, 3) == 0.0 ? 1 : 0;
    if (isLevel[static_cast<std::size_t>(v)] || !front)
    {
      continue;
    }
    ++interpolated;
    double low[4] = { 255, 255, 255, 255 }, high[4] = { 0, 0, 0, 0 };
    for (vtkIdType u = 0; u < n; ++u)
    {
      if (exact->GetComponent(u, 3) > 0.0 &&
        Distance(surface->GetPoint(u), surface->GetPoint(v)) <= radius)
      {
        for (int c = 0; c < 4; ++c)
        {
          low[c] = std::min(low[c], exact->GetComponent(u, c));
          high[c] = std::max(high[c], exact->GetComponent(u, c));
        }
      }
    }
    for (int c = 0; c < 4; ++c)
    {
      const double value = mixed->GetComponent(v, c);
      outside += value < low[c] - 1.0 || value > high[c] + 1.0 ? 1 : 0;
    }
  }
  Expect(interpolated > n / 4, "most front-facing vertices interpolated");
  Expect(outside == 0, "interpolated colours within the exact colours around them");
  Expect(uncoloured == 0, "no front-facing vertex left uncoloured");

  // Levels without the full surface (the reductions are the user's): the
  // 90 % level alone gives the same colours, drawn decimated or whole.
  auto equal = [](vtkDataArray* a, vtkDataArray* b)
  {
    bool same = a && b && a->GetNumberOfTuples() == b->GetNumberOfTuples();
    for (vtkIdType v = 0; same && v < a->GetNumberOfTuples(); ++v)
    {
      for (int c = 0; c < 4; ++c)
      {
        same = same && a->GetComponent(v, c) == b->GetComponent(v, c);
      }
    }
    return same;
  };
  vtkNew<vtkVolumeOnSurfaceMapper> only;
  only->SetInputData(surface);
  only->SetVolumeData(volume);
  only->SetVolumeProperty(property);
  only->SetVisibilityTest(vtkVolumeOnSurfaceMapper::NO_VISIBILITY);
  only->RemoveAllLevelOfDetailReductions();
  only->AddLevelOfDetailReduction(0.9);
  only->SetLevelOfDetail(0);
  Expect(equal(render(only), decimated->GetPointData()->GetScalars()),
    "a level list without the full surface: the level's colours");
  only->DrawFullSurfaceOn();
  Expect(equal(render(only), mixed), "and drawn whole: the same colours as with it");

  render(spread);
  Expect(spread->GetNumberOfRaysCast() == 0, "an unchanged frame casts nothing");
  spread->DrawFullSurfaceOff();
  render(spread);
  Expect(spread->GetNumberOfRaysCast() > 0 &&
      spread->GetColoredSurface()->GetNumberOfPoints() == decimated->GetNumberOfPoints(),
    "turned off: cast again, the level drawn");
  return Expect.Result();
}
