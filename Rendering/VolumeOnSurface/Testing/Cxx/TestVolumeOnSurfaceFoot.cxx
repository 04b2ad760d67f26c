// Image regression: Foot (../shared/data, every 4th voxel: 64^3) with its
// transfer function, the bone isosurface coloured by VoS^M (left) and VoS^M* (right). Skipped (exit
// code 125) without the shared data.
#include "vtkExtractVOI.h"
#include "vtkTestUtilities.h"
#include "vtkTransferFunction1DReader.h"
#include "vtkXMLImageDataReader.h"

#include "VoSScene.h"
#include "avosImageTest.h"

#include <vtksys/SystemTools.hxx>

#include <iostream>

int TestVolumeOnSurfaceFoot(int argc, char* argv[])
{
  char* root = vtkTestUtilities::GetDataRoot(argc, argv);
  const std::string data = root ? root : "";
  delete[] root;
  const std::string volumeFile = data + "/volumes/foot_zfp.vti";
  const std::string tfFile = data + "/tf/Foot.tf1d";
  if (!vtksys::SystemTools::FileExists(volumeFile) || !vtksys::SystemTools::FileExists(tfFile))
  {
    std::cout << "Shared data folder '" << data << "' is absent: skipping.\n";
    return 125;
  }
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(volumeFile.c_str());
  vtkNew<vtkExtractVOI> coarse;
  coarse->SetInputConnection(reader->GetOutputPort());
  coarse->SetSampleRate(4, 4, 4);
  vtkNew<vtkTransferFunction1DReader> tf;
  tf->SetFileName(tfFile.c_str());
  tf->SetOpacityModelToVTK();
  tf->SetUnitDistance(4.0); // one voxel of the coarse grid
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  if (!tf->FillVolumeProperty(property))
  {
    return EXIT_FAILURE;
  }

  vtkNew<vtkRenderWindow> window;
  window->SetSize(300, 150);
  window->SetMultiSamples(0);
  vosscene::Build(window, coarse, 80.0, property, 30.0, -20.0);
  return avostest::CompareWithBaseline(argc, argv, window);
}
