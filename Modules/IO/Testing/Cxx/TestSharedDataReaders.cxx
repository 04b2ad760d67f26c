// Reads every file of the shared data folder (-D): each .tf1d keeps its knots
// exactly (checked against an independent parse), each raw volume has the
// dimensions of its name and real content, each .vti has its density array.
// Skipped (exit code 125) when the shared folder is absent.
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkTransferFunction1DReader.h"
#include "vtkVolvisRawReader.h"
#include "vtkXMLImageDataReader.h"

#include "avosTestHelpers.h"

#include <vtksys/Directory.hxx>
#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <vector>

namespace
{
std::vector<std::string> ListFiles(const std::string& dir, const std::string& extension)
{
  std::vector<std::string> files;
  vtksys::Directory listing;
  if (listing.Load(dir))
  {
    for (unsigned long i = 0; i < listing.GetNumberOfFiles(); ++i)
    {
      const std::string name = listing.GetFile(i);
      if (vtksys::SystemTools::GetFilenameLastExtension(name) == extension)
      {
        files.push_back(dir + "/" + name);
      }
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

bool CheckTransferFunction(const std::string& path)
{
  // Independent parse: the knot counts and values as iostream reads them.
  std::ifstream in(path);
  std::string kind;
  int flag = 0, n = 0;
  in >> kind >> flag >> n;
  std::vector<std::vector<double>> colors(n, std::vector<double>(4));
  for (auto& knot : colors)
    in >> knot[0] >> knot[1] >> knot[2] >> knot[3];
  int m = 0;
  in >> m;
  std::vector<std::vector<double>> taus(m, std::vector<double>(2));
  for (auto& knot : taus)
    in >> knot[0] >> knot[1];

  vtkNew<vtkTransferFunction1DReader> reader;
  avostest::ExpectedErrors errors(reader);
  reader->SetFileName(path.c_str());
  bool ok = reader->Update() && errors.None(path);
  ok &= reader->GetColorTransferFunction()->GetSize() == n &&
    reader->GetExtinctionFunction()->GetSize() == m && n > 0 && m > 0;
  for (int i = 0; ok && i < n; ++i)
  {
    double node[6];
    reader->GetColorTransferFunction()->GetNodeValue(i, node);
    ok &= node[0] == colors[i][3] && node[1] == colors[i][0] && node[2] == colors[i][1] &&
      node[3] == colors[i][2];
  }
  for (int i = 0; ok && i < m; ++i)
  {
    double node[4];
    reader->GetExtinctionFunction()->GetNodeValue(i, node);
    ok &= node[0] == taus[i][1] && node[1] == taus[i][0];
  }
  std::cout << (ok ? "ok   " : "FAIL ") << path << ": " << n << " colour, " << m
            << " opacity knots\n";
  return ok;
}

bool CheckImage(const std::string& path, vtkImageData* image, const int dims[3])
{
  int outDims[3];
  image->GetDimensions(outDims);
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  double range[2] = { 0, 0 };
  if (scalars)
  {
    scalars->GetRange(range);
  }
  const bool ok = scalars && outDims[0] == dims[0] && outDims[1] == dims[1] &&
    outDims[2] == dims[2] && range[1] > range[0];
  std::cout << (ok ? "ok   " : "FAIL ") << path << ": " << outDims[0] << "x" << outDims[1] << "x"
            << outDims[2] << ", range [" << range[0] << ", " << range[1] << "]\n";
  return ok;
}
}

int TestSharedDataReaders(int argc, char* argv[])
{
  char* root = vtkTestUtilities::GetDataRoot(argc, argv);
  const std::string data = root ? root : "";
  delete[] root;
  if (!vtksys::SystemTools::FileIsDirectory(data + "/volumes") ||
    !vtksys::SystemTools::FileIsDirectory(data + "/tf"))
  {
    std::cout << "Shared data folder '" << data << "' is absent: skipping.\n";
    return 125;
  }

  bool ok = true;
  const auto tfs = ListFiles(data + "/tf", ".tf1d");
  const auto raws = ListFiles(data + "/volumes", ".raw");
  const auto vtis = ListFiles(data + "/volumes", ".vti");
  ok &= !tfs.empty() && !raws.empty() && !vtis.empty();
  for (const auto& path : tfs)
  {
    ok &= CheckTransferFunction(path);
  }
  for (const auto& path : raws)
  {
    vtkNew<vtkVolvisRawReader> reader;
    avostest::ExpectedErrors errors(reader);
    reader->SetFileName(path.c_str());
    reader->Update();
    int components = 0, dims[3];
    ok &= vtkVolvisRawReader::ParseFileName(path.c_str(), components, dims) && errors.None(path) &&
      CheckImage(path, reader->GetOutput(), dims);
  }
  for (const auto& path : vtis)
  {
    vtkNew<vtkXMLImageDataReader> reader;
    avostest::ExpectedErrors errors(reader);
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkImageData* image = reader->GetOutput();
    int dims[3];
    image->GetDimensions(dims);
    ok &= errors.None(path) && image->GetPointData()->GetArray("density") != nullptr &&
      dims[0] > 1 && dims[1] > 1 && dims[2] > 1 && CheckImage(path, image, dims);
  }
  std::cout << tfs.size() << " transfer functions, " << raws.size() << " raw and " << vtis.size()
            << " VTI volumes\n";
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
