// Fuzz target for vtkTransferFunction1DReader (libFuzzer: scripts/fuzz.sh;
// replayed on its corpus by the test IO-FuzzTransferFunction1DReaderReplay).
//
// The input is the file's content. Required: Update() fails with an error
// message and empty functions, or succeeds silently with at least one colour
// and one opacity knot, finite and strictly increasing scalar values, colours
// in [0, 1] and extinctions >= 0; FillVolumeProperty in VTK's opacity model
// then gives opacities in [0, 1]. A violation aborts (a crash for the fuzzer).
#include "vtkColorTransferFunction.h"
#include "vtkNew.h"
#include "vtkOutputWindow.h"
#include "vtkPiecewiseFunction.h"
#include "vtkTestErrorObserver.h"
#include "vtkTransferFunction1DReader.h"
#include "vtkVolumeProperty.h"

#include "avosFuzz.h"

#include <cmath>
#include <cstdint>
#include <string>

namespace
{
using avosfuzz::Require;

// One file per process, rewritten for every input.
const std::string& InputPath()
{
  static const std::string path = avosfuzz::TemporaryFolder("avos-fuzz-tf1d") + "/input.tf1d";
  return path;
}

// Knots of a function are finite and strictly increasing; each value passes `valid`.
template <typename Valid>
void RequireKnots(double* nodes, int count, int stride, Valid valid, const char* what)
{
  for (int i = 0; i < count; ++i)
  {
    const double* node = nodes + static_cast<std::ptrdiff_t>(i) * stride;
    Require(std::isfinite(node[0]) && (i == 0 || node[0] > node[-stride]), what);
    for (int c = 1; c < stride; ++c)
    {
      Require(valid(node[c]), what);
    }
  }
}
} // namespace

// Once, before the first input: the errors go to observers, not the terminal.
extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  vtkOutputWindow::GetInstance()->SetDisplayModeToNever();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  avosfuzz::WriteFile(InputPath(), data, size);

  vtkNew<vtkTransferFunction1DReader> reader;
  vtkNew<vtkTest::ErrorObserver> errors;
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->SetFileName(InputPath().c_str());
  const bool read = reader->Update();
  vtkColorTransferFunction* color = reader->GetColorTransferFunction();
  vtkPiecewiseFunction* extinction = reader->GetExtinctionFunction();
  if (!read)
  {
    Require(errors->GetError() && !errors->GetErrorMessage().empty(), "a failure says why");
    Require(color->GetSize() == 0 && extinction->GetSize() == 0, "a failure leaves no knots");
    return 0;
  }
  Require(!errors->GetError(), "a success raises no error");
  Require(color->GetSize() > 0 && extinction->GetSize() > 0, "knots after a success");
  RequireKnots(
    color->GetDataPointer(), color->GetSize(), 4, [](double c) { return c >= 0.0 && c <= 1.0; },
    "colour knots");
  RequireKnots(
    extinction->GetDataPointer(), extinction->GetSize(), 2,
    [](double e) { return std::isfinite(e) && e >= 0.0; }, "extinction knots");

  reader->SetOpacityModel(vtkTransferFunction1DReader::OPACITY_MODEL_VTK);
  vtkNew<vtkVolumeProperty> property;
  Require(reader->FillVolumeProperty(property), "the property filled");
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity();
  RequireKnots(
    opacity->GetDataPointer(), opacity->GetSize(), 2, [](double a) { return a >= 0.0 && a <= 1.0; },
    "VTK opacities");
  return 0;
}
