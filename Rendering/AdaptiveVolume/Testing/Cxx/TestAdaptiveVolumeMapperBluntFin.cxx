// Image regression: BluntFin (256 x 128 x 64, spacing 1 x 0.75 x 1) with its
// transfer function from the adaptive-integration paper, in the paper's
// extinction model, with each integration method. Reads the shared data
// folder (-D); skipped (exit code 125) without it.
#include "vtkTestUtilities.h"
#include "vtkTransferFunction1DReader.h"
#include "vtkVolvisRawReader.h"

#include "MethodGrid.h"
#include "avosImageTest.h"

#include <vtksys/SystemTools.hxx>

#include <iostream>

int TestAdaptiveVolumeMapperBluntFin(int argc, char* argv[])
{
  char* root = vtkTestUtilities::GetDataRoot(argc, argv);
  const std::string data = root ? root : "";
  delete[] root;
  const std::string volumeFile = data + "/volumes/BluntFin.1.256x128x64.raw";
  const std::string tfFile = data + "/tf/BluntFin.1.256x128x64.linear.tf1d";
  if (!vtksys::SystemTools::FileExists(volumeFile) || !vtksys::SystemTools::FileExists(tfFile))
  {
    std::cout << "Shared data folder '" << data << "' is absent: skipping.\n";
    return 125;
  }

  vtkNew<vtkVolvisRawReader> reader;
  reader->SetFileName(volumeFile.c_str());
  reader->SetDataSpacing(1.0, 0.75, 1.0);
  vtkNew<vtkTransferFunction1DReader> tf;
  tf->SetFileName(tfFile.c_str());
  tf->SetOpacityModelToExtinction();
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  if (!tf->FillVolumeProperty(property))
  {
    return EXIT_FAILURE;
  }

  vtkNew<vtkRenderWindow> window;
  window->SetSize(320, 240);
  window->SetMultiSamples(0);
  methodgrid::Grid grid = methodgrid::Build(window, reader->GetOutputPort(), property,
    vtkAdaptiveVolumeMapper::EXTINCTION_OPACITY, 20.0, 30.0);
  return avostest::CompareWithBaseline(argc, argv, window);
}
