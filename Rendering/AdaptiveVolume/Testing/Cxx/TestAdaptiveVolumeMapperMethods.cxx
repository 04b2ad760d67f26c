// Image regression: the analytic sphere-distance volume (a glowing shell
// around an opaque core, VTK opacity semantics) with each integration method,
// pierced by an opaque cone: the volume must be hidden where the cone is in
// front and visible in front of it (depth-buffer compositing).
#include "vtkActor.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkColorTransferFunction.h"
#include "vtkConeSource.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"

#include "MethodGrid.h"
#include "avosImageTest.h"

int TestAdaptiveVolumeMapperMethods(int argc, char* argv[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
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
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetInterpolationTypeToLinear();
  property->SetScalarOpacityUnitDistance(0.05);

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
