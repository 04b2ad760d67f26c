#include "avosEmptySpaceRanges.h"

#include "vtkDataArray.h"
#include "vtkObject.h"
#include "vtkSMPTools.h"
#include "vtkSetGet.h"

#include <algorithm>
#include <functional>

namespace avos
{
namespace
{
// Z-layers of blocks are independent: filled in parallel.
void ForLayers(int count, const std::function<void(int, int)>& body)
{
  vtkSMPTools::For(0, count, [&](int begin, int end) { body(begin, end); });
}
}

bool EmptySpaceRanges::Update(
  vtkDataArray* scalars, const int dimensions[3], Samples samples, int component)
{
  const std::array<int, 3> dims{ { dimensions[0], dimensions[1], dimensions[2] } };
  if (scalars == this->Scalars && scalars->GetMTime() == this->ScalarsTime &&
    dims == this->Dimensions && samples == this->Sampled && component == this->Component)
  {
    return true;
  }
  this->Map.SetDimensions(dimensions);
  std::size_t nans = 0;
  const int tuple = scalars->GetNumberOfComponents();
  const int components = component >= 0 ? 1 : tuple;
  switch (scalars->GetDataType())
  {
    vtkTemplateMacro(nans = this->Map.ComputeRanges(
                       static_cast<const VTK_TT*>(scalars->GetVoidPointer(std::max(component, 0))),
                       ForLayers, samples, components, tuple));
    default:
      return false;
  }
  this->Component = component;
  this->Scalars = scalars;
  this->ScalarsTime = scalars->GetMTime();
  this->Dimensions = dims;
  this->Sampled = samples;
  this->NaNCount = nans;
  this->Time.Modified();
  return true;
}

void EmptySpaceRanges::WarnOfNaNs(vtkObject* caller)
{
  if (this->NaNCount == 0 || this->NaNReported == this->Time.GetMTime())
  {
    return;
  }
  this->NaNReported = this->Time.GetMTime();
  vtkWarningWithObjectMacro(caller,
    << "The input has " << this->NaNCount
    << (this->Sampled != Samples::Points ? " NaN cell scalars: those cells are rendered "
                                           "transparent."
                                         : " NaN scalars: the cells they touch are rendered "
                                           "transparent (with nearest interpolation, the "
                                           "regions nearest to them)."));
}
}
