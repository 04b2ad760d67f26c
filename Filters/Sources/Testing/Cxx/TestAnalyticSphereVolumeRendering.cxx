// Image regression: the analytic sphere-distance volume through VTK's
// fixed-point CPU ray caster, a glowing shell with an opaque core. This checks
// the whole harness (source -> volume mapper -> window -> baseline) until the
// project's own mapper has its own tests.
#include "vtkAnalyticVolumeSource.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkFixedPointVolumeRayCastMapper.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRegressionTestImage.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

int TestAnalyticSphereVolumeRendering(int argc, char* argv[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  source->SetFunctionToSphereDistance();
  source->SetDimensions(48, 48, 48);
  source->SetScalarScale(100.0); // distance 0..1.73 -> scalars 0..173

  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 1.0, 0.9, 0.3);
  color->AddRGBPoint(50.0, 0.9, 0.3, 0.1);
  color->AddRGBPoint(80.0, 0.2, 0.4, 1.0);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.8);
  opacity->AddPoint(30.0, 0.0);
  opacity->AddPoint(70.0, 0.0);
  opacity->AddPoint(80.0, 0.08);
  opacity->AddPoint(95.0, 0.0);

  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetInterpolationTypeToLinear();
  property->SetScalarOpacityUnitDistance(0.05);

  vtkNew<vtkFixedPointVolumeRayCastMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  mapper->SetSampleDistance(0.01);
  mapper->SetNumberOfThreads(1); // deterministic image whatever the machine
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);

  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  renderer->SetBackground(0.0, 0.0, 0.0);
  vtkNew<vtkRenderWindow> window;
  window->SetSize(200, 200);
  window->SetMultiSamples(0);
  window->AddRenderer(renderer);
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(window);

  renderer->ResetCamera();
  renderer->GetActiveCamera()->Azimuth(30.0);
  renderer->GetActiveCamera()->Elevation(20.0);
  window->Render();

  const int result = vtkRegressionTestImage(window);
  if (result == vtkRegressionTester::DO_INTERACTOR)
  {
    interactor->Start();
  }
  return result == vtkRegressionTester::FAILED ? EXIT_FAILURE : EXIT_SUCCESS;
}
