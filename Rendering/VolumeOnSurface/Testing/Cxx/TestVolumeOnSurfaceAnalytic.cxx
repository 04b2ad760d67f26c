// Image regression: the Marschner-Lobb isosurface at 0.5 coloured by VoS^M (left) and VoS^M*
// (right) with the volume seen through it (a translucent ramp of the same signal).
#include "vtkAnalyticVolumeSource.h"
#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"

#include "VoSScene.h"
#include "avosImageTest.h"

int TestVolumeOnSurfaceAnalytic(int argc, char* argv[])
{
  vtkNew<vtkAnalyticVolumeSource> volume;
  volume->SetFunctionToMarschnerLobb();
  volume->SetDimensions(41, 41, 41);
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 0.1, 0.2, 1.0);
  color->AddRGBPoint(0.5, 1.0, 0.6, 0.1);
  color->AddRGBPoint(1.0, 1.0, 1.0, 1.0);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(0.3, 0.05);
  opacity->AddPoint(1.0, 0.3);
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(0.05); // one voxel

  vtkNew<vtkRenderWindow> window;
  window->SetSize(300, 150);
  window->SetMultiSamples(0);
  vosscene::Build(window, volume, 0.5, property, 20.0, 30.0);
  return avostest::CompareWithBaseline(argc, argv, window);
}
