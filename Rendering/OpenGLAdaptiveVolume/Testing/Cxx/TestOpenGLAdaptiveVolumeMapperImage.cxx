// Image regression of the GPU mapper: the analytic shell volume (a glowing
// shell around an opaque core, VTK's opacity model) drawn by the Riemann sum,
// the coupled and the decoupled rule (eps 1e-3), each pierced by an opaque
// cone that VTK's GPU ray caster hands the shader through the depth buffer:
// the volume must be hidden where the cone is in front and drawn in front of
// it. VTK's default threshold: every pixel is computed on its own, and
// llvmpipe and GPUs differ only by float rounding (below 1e-5 per channel
// against the core, TestOpenGLAdaptiveVolumeMapperAgainstCore), far under
// one 8-bit step.
#include "vtkOpenGLAdaptiveVolumeMapper.h"

#include "vtkActor.h"
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
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "avosImageTest.h"

int TestOpenGLAdaptiveVolumeMapperImage(int argc, char* argv[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  source->SetFunctionToSphereDistance();
  source->SetDimensions(40, 40, 40);
  source->SetScalarScale(100.0); // distance 0..1.73 -> scalars 0..173
  vtkNew<vtkColorTransferFunction> colour;
  colour->AddRGBPoint(0.0, 1.0, 0.9, 0.3);
  colour->AddRGBPoint(50.0, 0.9, 0.3, 0.1);
  colour->AddRGBPoint(80.0, 0.2, 0.4, 1.0);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.8);
  opacity->AddPoint(30.0, 0.0);
  opacity->AddPoint(70.0, 0.0);
  opacity->AddPoint(80.0, 0.3);
  opacity->AddPoint(95.0, 0.0);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(colour);
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
  window->SetSize(450, 150);
  window->SetMultiSamples(0);
  const int methods[3] = { vtkOpenGLAdaptiveVolumeMapper::RIEMANN,
    vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_COUPLED,
    vtkOpenGLAdaptiveVolumeMapper::ADAPTIVE_DECOUPLED };
  for (int i = 0; i < 3; ++i)
  {
    vtkNew<vtkOpenGLAdaptiveVolumeMapper> mapper;
    mapper->SetInputConnection(source->GetOutputPort());
    mapper->SetIntegrationMethod(methods[i]);
    mapper->SetTolerance(1e-3);
    mapper->SetRiemannStep(0.25);
    mapper->SetAutoAdjustSampleDistances(0);
    vtkNew<vtkVolume> volume; // one per mapper: the shader replacements live on it
    volume->SetMapper(mapper);
    volume->SetProperty(property);
    vtkNew<vtkActor> actor;
    actor->SetMapper(coneMapper);
    actor->GetProperty()->SetColor(0.9, 0.2, 0.2);
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(i / 3.0, 0.0, (i + 1) / 3.0, 1.0);
    renderer->AddVolume(volume);
    renderer->AddActor(actor);
    window->AddRenderer(renderer);
    renderer->ResetCamera();
    renderer->GetActiveCamera()->Azimuth(30.0);
    renderer->GetActiveCamera()->Elevation(20.0);
    renderer->GetActiveCamera()->OrthogonalizeViewUp();
    renderer->ResetCameraClippingRange();
  }
  return avostest::CompareWithBaseline(argc, argv, window);
}
