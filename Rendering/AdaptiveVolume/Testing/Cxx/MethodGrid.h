// One window, four viewports: the same volume and property rendered by
// vtkAdaptiveVolumeMapper with each integration method (Riemann, coupled,
// decoupled, reference; left to right, bottom to top), for image regression
// tests that cover every method with one baseline; and the volume they render.
#ifndef MethodGrid_h
#define MethodGrid_h

#include "vtkActor.h"
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAlgorithmOutput.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkConeSource.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <functional>
#include <vector>

namespace methodgrid
{
struct Grid
{
  std::vector<vtkSmartPointer<vtkAdaptiveVolumeMapper>> Mappers;
  std::vector<vtkSmartPointer<vtkVolume>> Volumes;
  std::vector<vtkSmartPointer<vtkRenderer>> Renderers;
};

// The analytic sphere-distance volume (40^3, scalars 0..173) as a glowing
// shell around an opaque core, in VTK's opacity semantics.
inline void MakeShell(vtkAnalyticVolumeSource* source, vtkVolumeProperty* property)
{
  source->SetFunctionToSphereDistance();
  source->SetDimensions(40, 40, 40);
  source->SetScalarScale(100.0); // distance 0..1.73 -> scalars 0..173
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 1.0, 0.9, 0.3);
  color->AddRGBPoint(50.0, 0.9, 0.3, 0.1);
  color->AddRGBPoint(80.0, 0.2, 0.4, 1.0);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.8);
  opacity->AddPoint(30.0, 0.0);
  opacity->AddPoint(70.0, 0.0);
  opacity->AddPoint(80.0, 0.3);
  opacity->AddPoint(95.0, 0.0);
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetInterpolationTypeToLinear();
  property->SetScalarOpacityUnitDistance(0.05);
}

// An opaque red cone piercing the shell: where it is in front the volume must
// be hidden, behind it drawn (depth-buffer compositing).
inline vtkSmartPointer<vtkActor> MakeCone()
{
  vtkNew<vtkConeSource> cone;
  cone->SetResolution(24);
  cone->SetHeight(3.6);
  cone->SetRadius(0.3);
  cone->SetDirection(1.0, 0.6, -0.4);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(cone->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.9, 0.2, 0.2);
  return actor;
}

// Fills `window` (sized by the caller) with the four viewports. `decorate`
// may add props to each renderer; the camera is reset, then turned.
inline Grid Build(vtkRenderWindow* window, vtkAlgorithmOutput* volume, vtkVolumeProperty* property,
  int opacityModel, double azimuth, double elevation,
  const std::function<void(vtkRenderer*)>& decorate = nullptr)
{
  Grid grid;
  const int methods[4] = { vtkAdaptiveVolumeMapper::RIEMANN,
    vtkAdaptiveVolumeMapper::ADAPTIVE_COUPLED, vtkAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED,
    vtkAdaptiveVolumeMapper::REFERENCE };
  for (int i = 0; i < 4; ++i)
  {
    auto mapper = vtkSmartPointer<vtkAdaptiveVolumeMapper>::New();
    mapper->SetInputConnection(volume);
    mapper->SetIntegrationMethod(methods[i]);
    mapper->SetOpacityModel(opacityModel);
    auto actor = vtkSmartPointer<vtkVolume>::New();
    actor->SetMapper(mapper);
    actor->SetProperty(property);
    auto renderer = vtkSmartPointer<vtkRenderer>::New();
    renderer->SetViewport(0.5 * (i % 2), 0.5 * (i / 2), 0.5 * (i % 2) + 0.5, 0.5 * (i / 2) + 0.5);
    renderer->AddVolume(actor);
    if (decorate)
    {
      decorate(renderer);
    }
    window->AddRenderer(renderer);
    renderer->ResetCamera();
    renderer->GetActiveCamera()->Azimuth(azimuth);
    renderer->GetActiveCamera()->Elevation(elevation);
    renderer->GetActiveCamera()->OrthogonalizeViewUp();
    renderer->GetActiveCamera()->Zoom(1.6);
    renderer->ResetCameraClippingRange();
    grid.Mappers.push_back(mapper);
    grid.Volumes.push_back(actor);
    grid.Renderers.push_back(renderer);
  }
  return grid;
}
} // namespace methodgrid

#endif
