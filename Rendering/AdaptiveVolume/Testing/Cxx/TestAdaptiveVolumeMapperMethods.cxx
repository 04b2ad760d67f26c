// Image regression: the analytic sphere-distance volume (a glowing shell
// around an opaque core, VTK opacity semantics) with each integration method,
// pierced by an opaque cone: the volume must be hidden where the cone is in
// front and visible in front of it (depth-buffer compositing).
#include "MethodGrid.h"
#include "avosImageTest.h"

int TestAdaptiveVolumeMapperMethods(int argc, char* argv[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  vtkNew<vtkVolumeProperty> property;
  methodgrid::MakeShell(source, property);

  vtkNew<vtkRenderWindow> window;
  window->SetSize(300, 300);
  window->SetMultiSamples(0);
  methodgrid::Grid grid = methodgrid::Build(window, source->GetOutputPort(), property,
    vtkAdaptiveVolumeMapper::VTK_OPACITY, 30.0, 20.0,
    [](vtkRenderer* renderer) { renderer->AddActor(methodgrid::MakeCone()); });
  return avostest::CompareWithBaseline(argc, argv, window);
}
