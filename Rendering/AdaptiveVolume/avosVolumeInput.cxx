#include "avosVolumeInput.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"

#include <cmath>
#include <sstream>

std::string avos::ValidateVolumeInput(
  vtkImageData* image, vtkDataArray* scalars, bool cellScalars, int maximumComponents)
{
  if (!image || !scalars)
  {
    return "the input has no scalars to render";
  }
  std::ostringstream message;
  const int components = scalars->GetNumberOfComponents();
  if (components < 1 || components > maximumComponents)
  {
    if (maximumComponents == 1)
    {
      message << "only single-component scalars are supported by this class, not " << components
              << " components (vtkAdaptiveVolumeMapper renders 2 to 4)";
    }
    else
    {
      message << "1 to " << maximumComponents << " components are supported, not " << components;
    }
    return message.str();
  }
  const int* dims = image->GetDimensions();
  const int c = cellScalars ? 1 : 0;
  if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2 ||
    scalars->GetNumberOfTuples() !=
      static_cast<vtkIdType>(dims[0] - c) * (dims[1] - c) * (dims[2] - c))
  {
    message << "the input must have at least 2 points along each axis and one scalar per "
            << (cellScalars ? "cell" : "point") << "; its dimensions are " << dims[0] << " x "
            << dims[1] << " x " << dims[2] << " points, with " << scalars->GetNumberOfTuples()
            << " scalars";
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
