// Image regression: the analytic sphere-distance volume (a glowing shell
// around an opaque core, VTK opacity semantics) with each integration method,
// pierced by an opaque cone: the volume must be hidden where the cone is in
// front and visible in front of it (depth-buffer compositing).
#include "vtkActor.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkConeSource.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"

#include "MethodGrid.h"
#include "avosImageTest.h"

int TestAdaptiveVolumeMapperMethods(int argc, char* argv[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  vtkNew<vtkVolumeProperty> property;
  methodgrid::MakeShell(source, property);

  vtkNew<vtkConeSource> cone;
  cone->SetResolution(24);
  cone->SetHeight(3.6);
  cone->SetRadius(0.3);
  cone->SetDirection(1.0, 0.6, -0.4);
  vtkNew<vtkPolyDataMapper> coneMapper;
  coneMapper->SetInputConnection(cone->GetOutputPort());

  vtkNew<vtkRenderWindow> window;
  window->SetSize(300, 300);
  window->SetMultiSamples(0);
  methodgrid::Grid grid = methodgrid::Build(window, source->GetOutputPort(), property,
    vtkAdaptiveVolumeMapper::VTK_OPACITY, 30.0, 20.0,
    [&](vtkRenderer* renderer)
    {
      vtkNew<vtkActor> actor;
      actor->SetMapper(coneMapper);
      actor->GetProperty()->SetColor(0.9, 0.2, 0.2);
      renderer->AddActor(actor);
    });
  return avostest::CompareWithBaseline(argc, argv, window);
}
