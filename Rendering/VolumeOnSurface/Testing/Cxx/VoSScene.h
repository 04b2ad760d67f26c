// The scene shared by the VoS image tests: an isosurface of `volume`
// (vtkFlyingEdges3D with normals), coloured by vtkVolumeOnSurfaceFilter with
// `property` for the renderer's camera, drawn lit.
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
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkVolumeOnSurfaceFilter> vos;
  vos->SetInputConnection(contour->GetOutputPort());
  vos->SetVolumeConnection(volume->GetOutputPort());
  vos->SetVolumeProperty(property);
  vos->SetCamera(renderer->GetActiveCamera());
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(vos->GetOutputPort());
  mapper->SetColorModeToDirectScalars();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  renderer->AddActor(actor);
  renderer->SetBackground(0.0, 0.0, 0.0);
  window->AddRenderer(renderer);
  contour->Update();
  renderer->ResetCamera(contour->GetOutput()->GetBounds());
  renderer->GetActiveCamera()->Azimuth(azimuth);
  renderer->GetActiveCamera()->Elevation(elevation);
  renderer->GetActiveCamera()->OrthogonalizeViewUp();
  renderer->ResetCameraClippingRange();
}
}

#endif
