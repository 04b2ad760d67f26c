// The isosurface path of the VoS pipeline: volume -> vtkFlyingEdges3D (with
// normals) -> vtkOpenMeshDecimation -> .vtp, with the triangle counts and
// times of each stage.
//
//   avos-example-isosurface VOLUME.vti|VOLUME.raw ISOVALUE REDUCTION OUTPUT.vtp
#include "vtkFlyingEdges3D.h"
#include "vtkNew.h"
#include "vtkOpenMeshDecimation.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTimerLog.h"
#include "vtkVolvisRawReader.h"
#include "vtkXMLImageDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  if (argc != 5)
  {
    std::cerr << "usage: " << argv[0] << " VOLUME.vti|VOLUME.raw ISOVALUE REDUCTION OUTPUT.vtp\n";
    return EXIT_FAILURE;
  }
  const std::string input = argv[1];
  vtkSmartPointer<vtkAlgorithm> reader;
  if (input.size() > 4 && input.substr(input.size() - 4) == ".raw")
  {
    auto raw = vtkSmartPointer<vtkVolvisRawReader>::New();
    raw->SetFileName(input.c_str());
    reader = raw;
  }
  else
  {
    auto xml = vtkSmartPointer<vtkXMLImageDataReader>::New();
    xml->SetFileName(input.c_str());
    reader = xml;
  }
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputConnection(reader->GetOutputPort());
  contour->SetValue(0, std::atof(argv[2]));
  contour->ComputeNormalsOn();
  vtkNew<vtkOpenMeshDecimation> decimate;
  decimate->SetInputConnection(contour->GetOutputPort());
  decimate->SetTargetReduction(std::atof(argv[3]));

  vtkNew<vtkTimerLog> timer;
  reader->Update();
  timer->StartTimer();
  contour->Update();
  timer->StopTimer();
  std::cout << "isosurface: " << contour->GetOutput()->GetNumberOfPolys() << " triangles in "
            << timer->GetElapsedTime() << " s\n";
  timer->StartTimer();
  decimate->Update();
  timer->StopTimer();
  std::cout << "decimated: " << decimate->GetOutput()->GetNumberOfPolys() << " triangles ("
            << 100.0 * decimate->GetAchievedReduction() << " % fewer) in "
            << timer->GetElapsedTime() << " s\n";

  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputConnection(decimate->GetOutputPort());
  writer->SetFileName(argv[4]);
  return writer->Write() ? EXIT_SUCCESS : EXIT_FAILURE;
}
