// Reads .tf1d files: exact knots, both opacity models, and every malformed input.
#include "vtkColorTransferFunction.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkTransferFunction1DReader.h"
#include "vtkVolumeProperty.h"

#include "avosTestHelpers.h"

#include <cmath>
#include <utility>
#include <vector>

int TestTransferFunction1DReader(int argc, char* argv[])
{
  bool ok = true;
  const std::string path = avostest::TempPath(argc, argv, "TestTransferFunction1DReader.tf1d");
  vtkNew<vtkTransferFunction1DReader> reader;
  avostest::ExpectedErrors errors(reader);

  // A valid file with values that are not exactly representable in binary:
  // the knots must come back bit for bit as strtod reads them.
  avostest::WriteFile(path,
    "linear\n0\n3\n0.0 0.1 0.2 0\n1.0 0.5 0.3 60.25\n0.6 0.0 0.7 256\n"
    "4\n0.00 0\n0.2 60\n0.15 150.5\n1e-3 255\n");
  reader->SetFileName(path.c_str());
  ok &= reader->Update() && errors.None("valid file");
  const double colors[3][4] = { { 0, 0.0, 0.1, 0.2 }, { 60.25, 1.0, 0.5, 0.3 },
    { 256, 0.6, 0.0, 0.7 } };
  const double taus[4][2] = { { 0, 0.0 }, { 60, 0.2 }, { 150.5, 0.15 }, { 255, 1e-3 } };
  vtkColorTransferFunction* color = reader->GetColorTransferFunction();
  vtkPiecewiseFunction* tau = reader->GetExtinctionFunction();
  ok &= color->GetSize() == 3 && tau->GetSize() == 4;
  for (int i = 0; ok && i < 3; ++i)
  {
    double node[6];
    color->GetNodeValue(i, node);
    ok &= node[0] == colors[i][0] && node[1] == colors[i][1] && node[2] == colors[i][2] &&
      node[3] == colors[i][3];
  }
  for (int i = 0; ok && i < 4; ++i)
  {
    double node[4];
    tau->GetNodeValue(i, node);
    ok &= node[0] == taus[i][0] && node[1] == taus[i][1];
  }
  // Piecewise linear between knots, clamped outside.
  ok &= std::abs(tau->GetValue(105.25) - 0.175) < 1e-15 && tau->GetValue(-10) == 0.0 &&
    tau->GetValue(1000) == 1e-3;
  if (!ok)
  {
    std::cerr << "FAIL: knots of a valid file were not kept exactly\n";
  }

  // Extinction model: the knots unchanged. VTK model: alpha = 1 - exp(-tau)
  // per UnitDistance.
  vtkNew<vtkVolumeProperty> property;
  ok &= reader->FillVolumeProperty(property) && errors.None("fill extinction");
  ok &= property->GetScalarOpacity()->GetValue(60) == 0.2;
  reader->SetOpacityModelToVTK();
  reader->SetUnitDistance(0.5);
  ok &= reader->FillVolumeProperty(property) && errors.None("fill VTK");
  ok &= std::abs(property->GetScalarOpacity()->GetValue(60) - (1 - std::exp(-0.2))) < 1e-15;
  ok &= property->GetScalarOpacityUnitDistance() == 0.5;
  ok &= property->GetRGBTransferFunction()->GetSize() == 3;
  if (!ok)
  {
    std::cerr << "FAIL: FillVolumeProperty\n";
  }

  // Malformed files: each gives its message, empty functions and false.
  const std::vector<std::pair<std::string, std::string>> cases = {
    { "", "unexpected end of file while reading the interpolation kind" },
    { "cubic\n0\n1\n0 0 0 0\n1\n0 0\n", "unsupported interpolation kind 'cubic'" },
    { "linear\n0\n0\n1\n0 0\n", "has no colour knots" },
    { "linear\n0\n1\n0 0 0 0\n0\n", "has no opacity knots" },
    { "linear\n0\n-3\n", "has no colour knots" },
    { "linear\n0\n2\n0 0 0 10\n1 1 1 5\n1\n0 0\n", "colour knot values are not strictly" },
    { "linear\n0\n1\n0 0 0 0\n2\n0 5\n0 5\n", "opacity knot values are not strictly" },
    { "linear\n0\n1\n0 nan 0 0\n1\n0 0\n", "non-finite number 'nan'" },
    { "linear\n0\n1\n0 0 0 0\n1\ninf 0\n", "non-finite number 'inf'" },
    { "linear\n0\n1\n0 0 zero 0\n1\n0 0\n", "'zero' is not a number" },
    { "linear\n0\n2\n0 0 0 0\n", "unexpected end of file while reading colour" },
    { "linear\n0\n1\n0 0 0 0\n2\n0 0\n", "unexpected end of file while reading opacity" },
    { "linear\n0\n1\n0 0 0 0\n1\n0 0\n7\n", "unexpected content after the last opacity knot" },
    { "linear\n0\n1\n0 1.5 0 0\n1\n0 0\n", "outside [0, 1]" },
    { "linear\n0\n1\n0 0 0 0\n1\n-0.5 0\n", "negative extinction" },
    { "linear\n0\n1.5\n", "'1.5' is not an integer" },
    { "linear\n0\n99999999\n", "implausible number of colour knots" },
  };
  reader->SetOpacityModelToExtinction();
  for (const auto& c : cases)
  {
    avostest::WriteFile(path, c.first);
    // A different size or time forces a re-read; reset the name to be sure.
    reader->SetFileName(nullptr);
    reader->SetFileName(path.c_str());
    const bool read = reader->Update();
    ok &= !read && errors.Check("'" + c.first + "'", c.second) &&
      reader->GetColorTransferFunction()->GetSize() == 0 &&
      reader->GetExtinctionFunction()->GetSize() == 0;
  }

  reader->SetFileName(nullptr);
  ok &= !reader->Update() && errors.Check("no file name", "No FileName was set");
  reader->SetFileName("/nonexistent/dir/missing.tf1d");
  ok &= !reader->Update() && errors.Check("missing file", "no such file");
  ok &= !reader->FillVolumeProperty(property) && errors.Check("fill, missing", "no such file");
  ok &= !reader->FillVolumeProperty(nullptr) && errors.Check("null property", "property is null");

  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
