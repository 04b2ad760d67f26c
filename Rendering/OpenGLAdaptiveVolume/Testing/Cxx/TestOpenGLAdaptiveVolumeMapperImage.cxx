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

#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"

#include "MethodGrid.h"
#include "avosImageTest.h"

int TestOpenGLAdaptiveVolumeMapperImage(int argc, char* argv[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  vtkNew<vtkVolumeProperty> property;
  methodgrid::MakeShell(source, property); // the CPU mapper's image tests' volume

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
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(i / 3.0, 0.0, (i + 1) / 3.0, 1.0);
    renderer->AddVolume(volume);
    renderer->AddActor(methodgrid::MakeCone());
    window->AddRenderer(renderer);
    renderer->ResetCamera();
    renderer->GetActiveCamera()->Azimuth(30.0);
    renderer->GetActiveCamera()->Elevation(20.0);
    renderer->GetActiveCamera()->OrthogonalizeViewUp();
    renderer->ResetCameraClippingRange();
  }
  return avostest::CompareWithBaseline(argc, argv, window);
}
