// The known-answer scenes of the VoS^M* tests: a field sampled on n^3 points
// over [-1, 1]^3 (double scalars), and a parallel camera looking down -z
// from +z at it, so that each vertex's ray runs straight down.
#ifndef VoSKnownAnswer_h
#define VoSKnownAnswer_h

#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"

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
