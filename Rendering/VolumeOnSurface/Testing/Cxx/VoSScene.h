// The scene shared by the VoS image tests: an isosurface of `volume`
// (vtkFlyingEdges3D with normals) coloured with `property` for the
// renderer's camera and drawn lit, in two viewports: VoS^M
// (vtkVolumeOnSurfaceFilter) on the left, VoS^M* (vtkVolumeOnSurfaceMapper,
// full level of detail) on the right.
#ifndef VoSScene_h
#define VoSScene_h

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkFlyingEdges3D.h"
#include "vtkNew.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolumeOnSurfaceFilter.h"
#include "vtkVolumeOnSurfaceMapper.h"
#include "vtkVolumeProperty.h"

namespace vosscene
{
inline void Build(vtkRenderWindow* window, vtkAlgorithm* volume, double isovalue,
  vtkVolumeProperty* property, double azimuth, double elevation)
{
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputConnection(volume->GetOutputPort());
  contour->SetValue(0, isovalue);
  contour->ComputeNormalsOn();
  contour->ComputeScalarsOff();
  vtkNew<vtkRenderer> left, right;
  left->SetViewport(0.0, 0.0, 0.5, 1.0);
  right->SetViewport(0.5, 0.0, 1.0, 1.0);
  right->SetActiveCamera(left->GetActiveCamera());

  vtkNew<vtkVolumeOnSurfaceFilter> vos;
  vos->SetInputConnection(contour->GetOutputPort());
  vos->SetVolumeConnection(volume->GetOutputPort());
  vos->SetVolumeProperty(property);
  vos->SetCamera(left->GetActiveCamera());
  vtkNew<vtkPolyDataMapper> surfaceMapper;
  surfaceMapper->SetInputConnection(vos->GetOutputPort());
  surfaceMapper->SetColorModeToDirectScalars();
  vtkNew<vtkActor> filtered;
  filtered->SetMapper(surfaceMapper);
  left->AddActor(filtered);

  vtkNew<vtkVolumeOnSurfaceMapper> vosMapper;
  vosMapper->SetInputConnection(contour->GetOutputPort());
  vosMapper->SetVolumeConnection(volume->GetOutputPort());
  vosMapper->SetVolumeProperty(property);
  vosMapper->SetLevelOfDetail(0);
  vtkNew<vtkActor> mapped;
  mapped->SetMapper(vosMapper);
  right->AddActor(mapped);

  for (vtkRenderer* renderer : { left.Get(), right.Get() })
  {
    renderer->SetBackground(0.0, 0.0, 0.0);
    window->AddRenderer(renderer);
  }
  vtkRenderer* renderer = left;
  contour->Update();
  renderer->ResetCamera(contour->GetOutput()->GetBounds());
  renderer->GetActiveCamera()->Azimuth(azimuth);
  renderer->GetActiveCamera()->Elevation(elevation);
  renderer->GetActiveCamera()->OrthogonalizeViewUp();
  renderer->ResetCameraClippingRange();
}
}

#endif
