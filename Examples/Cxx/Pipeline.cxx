// reader -> volume property from a .tf1d -> AVoS's adaptive volume mapper
// (piecewise integration, error below 1e-3 per channel) -> PNG.
//
//   avos-example-pipeline VOLUME.raw TF.tf1d OUTPUT.png
//   avos-example-pipeline OUTPUT.png   (analytic sphere, built-in transfer function)
#include "avosVersion.h"
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkCamera.h"
#include "vtkNew.h"
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

int main(int argc, char* argv[])
{
  if (argc != 2 && argc != 4)
  {
    std::cerr << "usage: " << argv[0] << " [VOLUME.raw TF.tf1d] OUTPUT.png\n";
    return EXIT_FAILURE;
  }

  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  vtkNew<vtkAdaptiveVolumeMapper> mapper;
  mapper->SetIntegrationMethodToPiecewiseAdaptive();
  mapper->SetTolerance(1e-3);
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
  std::cout << "AVoS " << AVOS_VERSION << ": " << mapper->GetRaysCast() << " rays, "
            << mapper->GetMeanPiecesPerRay() << " pieces per ray\n";
  return mapper->GetRaysCast() > 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
