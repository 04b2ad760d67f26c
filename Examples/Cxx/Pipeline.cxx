// reader -> volume property from a .tf1d -> AVoS's adaptive volume mapper
// (piecewise integration, error below 1e-3 per channel) -> PNG; with --gpu
// the paper's GPU version instead (coupled adaptive Simpson in GLSL, eps 1e-3).
//
//   avos-example-pipeline [--gpu] VOLUME.raw TF.tf1d OUTPUT.png
//   avos-example-pipeline [--gpu] OUTPUT.png   (analytic sphere, built-in transfer function)
#include "avosVersion.h"
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkCamera.h"
#include "vtkNew.h"
#include "vtkOpenGLAdaptiveVolumeMapper.h"
#include "vtkPNGWriter.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTransferFunction1DReader.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkVolvisRawReader.h"
#include "vtkWindowToImageFilter.h"

#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  const bool gpu = argc > 1 && std::string(argv[1]) == "--gpu";
  if (gpu)
  {
    --argc;
    ++argv;
  }
  if (argc != 2 && argc != 4)
  {
    std::cerr << "usage: avos-example-pipeline [--gpu] [VOLUME.raw TF.tf1d] OUTPUT.png\n";
    return EXIT_FAILURE;
  }

  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  vtkNew<vtkAdaptiveVolumeMapper> cpuMapper;
  cpuMapper->SetIntegrationMethodToPiecewiseAdaptive();
  cpuMapper->SetTolerance(1e-3);
  vtkNew<vtkOpenGLAdaptiveVolumeMapper> gpuMapper;
  gpuMapper->SetIntegrationMethodToAdaptiveCoupled();
  gpuMapper->SetTolerance(1e-3);
  vtkVolumeMapper* mapper = gpu ? static_cast<vtkVolumeMapper*>(gpuMapper) : cpuMapper;
  vtkNew<vtkVolvisRawReader> reader;
  vtkNew<vtkAnalyticVolumeSource> sphere;
  if (argc == 4)
  {
    reader->SetFileName(argv[1]);
    mapper->SetInputConnection(reader->GetOutputPort());
    vtkNew<vtkTransferFunction1DReader> tf;
    tf->SetFileName(argv[2]);
    tf->SetOpacityModelToVTK(); // VTK's mappers take alpha per unit distance
    if (!tf->FillVolumeProperty(property))
    {
      return EXIT_FAILURE;
    }
  }
  else
  {
    sphere->SetScalarScale(100.0);
    mapper->SetInputConnection(sphere->GetOutputPort());
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0.0, 0.5);
    opacity->AddPoint(40.0, 0.0);
    opacity->AddPoint(80.0, 0.05);
    opacity->AddPoint(95.0, 0.0);
    property->SetScalarOpacity(opacity);
    property->SetScalarOpacityUnitDistance(0.05);
  }

  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(volume);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(400, 300);
  window->AddRenderer(renderer);
  renderer->ResetCamera();
  renderer->GetActiveCamera()->Azimuth(30.0);
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  writer->SetFileName(argv[argc - 1]);
  writer->Write();
  if (gpu)
  {
    // The mapper's own check: empty when it could draw this scene.
    const std::string problem = gpuMapper->CheckRenderable(renderer, property);
    std::cout << "AVoS " << AVOS_VERSION << " on the GPU: "
              << (problem.empty() ? "drawn" : problem) << "\n";
    return problem.empty() ? EXIT_SUCCESS : EXIT_FAILURE;
  }
  std::cout << "AVoS " << AVOS_VERSION << ": " << cpuMapper->GetRaysCast() << " rays, "
            << cpuMapper->GetMeanPiecesPerRay() << " pieces per ray\n";
  return cpuMapper->GetRaysCast() > 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
