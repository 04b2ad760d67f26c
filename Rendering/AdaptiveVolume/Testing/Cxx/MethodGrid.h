// One window, four viewports: the same volume and property rendered by
// vtkAdaptiveVolumeMapper with each integration method (Riemann, coupled,
// decoupled, reference; left to right, bottom to top), for image regression
// tests that cover every method with one baseline.
#ifndef MethodGrid_h
#define MethodGrid_h

#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCamera.h"
#include "vtkNew.h"
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
