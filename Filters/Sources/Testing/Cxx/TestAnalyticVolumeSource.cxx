// Every analytic field against its closed form, sub-extent requests, and bad
// parameters.
#include "vtkAnalyticVolumeSource.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPointData.h"

#include "avosTestHelpers.h"

#include <algorithm>
#include <cmath>

namespace
{
// Largest |sample - expected(x)| over the output's points.
template <typename F>
double MaxError(vtkImageData* image, F expected)
{
  double worst = 0.0;
  for (vtkIdType p = 0; p < image->GetNumberOfPoints(); ++p)
  {
    double x[3];
    image->GetPoint(p, x);
    const double s = image->GetPointData()->GetScalars()->GetTuple1(p);
    worst = std::max(worst, std::abs(s - expected(x)));
  }
  return worst;
}
}

int TestAnalyticVolumeSource(int, char*[])
{
  bool ok = true;
  vtkNew<vtkAnalyticVolumeSource> source;
  avostest::ExpectedErrors errors(source);
  source->SetDimensions(17, 9, 5);
  source->SetBounds(-2.0, 2.0, 0.0, 1.0, 10.0, 12.0);
  source->SetOutputScalarTypeToDouble();

  source->SetFunctionToConstant();
  source->SetScalarShift(42.5);
  source->Update();
  ok &= errors.None("constant") &&
    MaxError(source->GetOutput(), [](const double*) { return 42.5; }) == 0.0;

  source->SetFunctionToLinearRamp();
  source->SetRampAxis(2);
  source->SetScalarShift(3.0);
  source->SetScalarScale(-0.5);
  source->Update();
  const double rampError =
    MaxError(source->GetOutput(), [](const double* x) { return 3.0 - 0.5 * x[2]; });
  ok &= errors.None("ramp") && rampError < 1e-13;
  int dims[3];
  source->GetOutput()->GetDimensions(dims);
  ok &= dims[0] == 17 && dims[1] == 9 && dims[2] == 5 &&
    source->GetOutput()->GetSpacing()[0] == 0.25 && source->GetOutput()->GetOrigin()[2] == 10.0;

  source->SetFunctionToSphereDistance();
  source->SetCenter(0.5, 0.5, 11.0);
  source->SetScalarShift(0.0);
  source->SetScalarScale(1.0);
  source->Update();
  ok &= errors.None("sphere") &&
    MaxError(source->GetOutput(),
      [](const double* x)
      {
        const double c[3] = { 0.5, 0.5, 11.0 };
        return std::sqrt(vtkMath::Distance2BetweenPoints(x, c));
      }) < 1e-13;

  // Marschner-Lobb: rho(0, 0, 0) = (1 + 0.25 * 2) / 2.5 = 0.6; range within [0, 1].
  source->SetFunctionToMarschnerLobb();
  source->SetBounds(-1, 1, -1, 1, -1, 1);
  source->SetDimensions(41, 41, 41);
  source->SetOutputScalarTypeToFloat();
  source->Update();
  double range[2];
  source->GetOutput()->GetScalarRange(range);
  const double center = source->GetOutput()->GetScalarComponentAsDouble(20, 20, 20, 0);
  ok &= errors.None("Marschner-Lobb") && std::abs(center - 0.6) < 1e-6 && range[0] >= 0.0 &&
    range[1] <= 1.0 && range[1] - range[0] > 0.9;
  if (!ok)
  {
    std::cerr << "FAIL: field values (ramp error " << rampError << ", ML centre " << center
              << ", range " << range[0] << ".." << range[1] << ")\n";
  }

  // A fresh source asked for a sub-extent computes exactly that part.
  vtkNew<vtkAnalyticVolumeSource> streamed;
  streamed->SetFunctionToMarschnerLobb();
  streamed->SetDimensions(41, 41, 41);
  const int sub[6] = { 3, 7, 10, 12, 0, 40 };
  streamed->UpdateExtent(sub);
  int ext[6];
  streamed->GetOutput()->GetExtent(ext);
  const double x[3] = { -1.0 + 5 * 0.05, -1.0 + 11 * 0.05, -1.0 + 20 * 0.05 };
  const bool streamOk = ext[0] == 3 && ext[1] == 7 && ext[2] == 10 && ext[3] == 12 &&
    ext[5] == 40 && streamed->GetOutput()->GetNumberOfPoints() == 5 * 3 * 41 &&
    std::abs(streamed->GetOutput()->GetScalarComponentAsDouble(5, 11, 20, 0) -
      streamed->EvaluateFunction(x)) < 1e-6;
  if (!streamOk)
  {
    std::cerr << "FAIL: sub-extent\n";
  }
  ok &= streamOk;

  // Bad parameters: message and empty output.
  source->SetDimensions(0, 4, 4);
  source->Update();
  ok &= errors.Check("zero dimension", "Dimensions must be at least 1") &&
    source->GetOutput()->GetNumberOfPoints() == 0;
  source->SetDimensions(4, 4, 4);
  source->SetBounds(0, 1, 2, 2, 0, 1);
  source->Update();
  ok &= errors.Check("zero spacing", "zero spacing is invalid") &&
    source->GetOutput()->GetNumberOfPoints() == 0;
  source->SetBounds(0, 1, 0, 1, 0, 1);
  source->SetOutputScalarType(VTK_INT);
  source->Update();
  ok &= errors.Check("int output", "OutputScalarType must be") &&
    source->GetOutput()->GetNumberOfPoints() == 0;
  source->SetOutputScalarTypeToFloat();
  source->SetScalarScale(std::nan(""));
  source->Update();
  ok &= errors.Check("NaN scale", "must be finite");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
