#include "avosVolumeInput.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"

#include <cmath>
#include <sstream>

std::string avos::ValidateVolumeInput(vtkImageData* image, vtkDataArray* scalars, bool cellScalars)
{
  if (!image || !scalars)
  {
    return "the input has no scalars to render";
  }
  if (cellScalars)
  {
    return "cell scalars are not supported: the integrals are those of the trilinear "
           "interpolant of point scalars";
  }
  std::ostringstream message;
  if (scalars->GetNumberOfComponents() != 1)
  {
    message << "only single-component scalars are supported, not "
            << scalars->GetNumberOfComponents() << " components";
    return message.str();
  }
  const int* dims = image->GetDimensions();
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2 ||
    scalars->GetNumberOfTuples() != static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2])
  {
    message << "the input must have at least 2 points along each axis and one scalar per point; "
               "its dimensions are "
            << dims[0] << " x " << dims[1] << " x " << dims[2];
    return message.str();
  }
  const double* spacing = image->GetSpacing();
  if (spacing[0] == 0.0 || spacing[1] == 0.0 || spacing[2] == 0.0 ||
    !std::isfinite(spacing[0] * spacing[1] * spacing[2]))
  {
    message << "the input's spacing must be non-zero and finite, not (" << spacing[0] << ", "
            << spacing[1] << ", " << spacing[2] << ")";
    return message.str();
  }
  return std::string();
}
