// The known-answer scenes of the VoS^M* tests: a field sampled on n^3 points
// over [-1, 1]^3 (double scalars), VoS^M* on one of its isosurfaces, and a
// parallel camera looking down -z from +z at it, so that each vertex's ray
// runs straight down.
#ifndef VoSKnownAnswer_h
#define VoSKnownAnswer_h

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkFlyingEdges3D.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeOnSurfaceMapper.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>

namespace vosknown
{
// field(x, y, z) on n^3 points over [-1, 1]^3; the voxel is 2 / (n - 1).
template <typename F>
vtkSmartPointer<vtkImageData> FieldOnCube(int n, F&& field)
{
  const double voxel = 2.0 / (n - 1);
  auto volume = vtkSmartPointer<vtkImageData>::New();
  volume->SetDimensions(n, n, n);
  volume->SetOrigin(-1, -1, -1);
  volume->SetSpacing(voxel, voxel, voxel);
  volume->AllocateScalars(VTK_DOUBLE, 1);
  vtkDataArray* scalars = volume->GetPointData()->GetScalars();
  for (vtkIdType i = 0; i < volume->GetNumberOfPoints(); ++i)
  {
    double p[3];
    volume->GetPoint(i, p);
    scalars->SetTuple1(i, field(p[0], p[1], p[2]));
  }
  return volume;
}

// VoS^M* (extinction opacity, the full mesh, eps 1e-3) on the isosurface
// `isovalue` of `volume` with its normals, an actor of `renderer`.
inline vtkSmartPointer<vtkVolumeOnSurfaceMapper> MapperOnIsosurface(
  vtkImageData* volume, vtkVolumeProperty* property, double isovalue, vtkRenderer* renderer)
{
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(volume);
  contour->SetValue(0, isovalue);
  contour->ComputeNormalsOn();
  auto mapper = vtkSmartPointer<vtkVolumeOnSurfaceMapper>::New();
  mapper->SetInputConnection(contour->GetOutputPort());
  mapper->SetVolumeData(volume);
  mapper->SetVolumeProperty(property);
  mapper->ExtinctionOpacityOn();
  mapper->SetLevelOfDetail(0);
  mapper->SetTolerance(1e-3);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  renderer->AddActor(actor);
  return mapper;
}

// The largest difference of the 8-bit RGBA `colours` of the vertices of
// `surface` with |x| and |y| at most `inner` from 255 (rgb(c) alpha, alpha)
// (c < 3; 255 when there are no colours), their count in `checked`.
template <typename RGB>
double WorstInnerVertex(
  vtkPolyData* surface, vtkDataArray* colours, double inner, double alpha, RGB&& rgb, int& checked)
{
  double w = colours ? 0.0 : 255.0;
  checked = 0;
  for (vtkIdType v = 0; colours && v < surface->GetNumberOfPoints(); ++v)
  {
    double p[3];
    surface->GetPoint(v, p);
    if (std::abs(p[0]) > inner || std::abs(p[1]) > inner)
    {
      continue;
    }
    ++checked;
    for (int c = 0; c < 4; ++c)
    {
      const double exact = 255.0 * (c < 3 ? rgb(c) * alpha : alpha);
      w = std::max(w, std::abs(colours->GetComponent(v, c) - exact));
    }
  }
  return w;
}

// The shaded scenes' lights, added to `renderer`: `key`, a directional
// scene light from (1, 0, 2) towards the origin, of colour (1, 0.9, 0.8)
// and intensity 0.8, and `head`, a headlight.
inline void AddKeyAndHeadlight(vtkRenderer* renderer, vtkLight* key, vtkLight* head)
{
  key->SetLightTypeToSceneLight();
  key->SetPosition(1, 0, 2);
  key->SetFocalPoint(0, 0, 0);
  key->SetColor(1.0, 0.9, 0.8);
  key->SetIntensity(0.8);
  head->SetLightTypeToHeadlight();
  renderer->AddLight(key);
  renderer->AddLight(head);
}

// An off-screen size x size window showing `renderer` from +z, parallel,
// the cube filling it.
inline void ViewFromAbove(vtkRenderWindow* window, vtkRenderer* renderer, int size)
{
  window->SetOffScreenRendering(1);
  window->SetSize(size, size);
  window->AddRenderer(renderer);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetPosition(0, 0, 5);
  camera->SetFocalPoint(0, 0, 0);
  camera->SetParallelScale(1.1);
  renderer->ResetCameraClippingRange();
}
}

#endif
