#include "avosEmptySpaceRanges.h"

#include "vtkDataArray.h"
#include "vtkSMPTools.h"

#include <atomic>

namespace avos
{
namespace
{
// Z-layers of blocks are independent: filled in parallel.
template <typename Storage>
std::size_t ComputeRanges(avos::numerics::EmptySpaceMap<double>& map, const Storage* data)
{
  std::atomic<std::size_t> nans(0);
  vtkSMPTools::For(0, map.GetNumberOfBlocks(2),
    [&](int begin, int end) { nans += map.ComputeRanges(data, begin, end); });
  return nans;
}
}

bool EmptySpaceRanges::Update(vtkDataArray* scalars, const int dimensions[3])
{
  const std::array<int, 3> dims{ { dimensions[0], dimensions[1], dimensions[2] } };
  if (scalars == this->Scalars && scalars->GetMTime() == this->ScalarsTime &&
    dims == this->Dimensions)
  {
    return true;
  }
  this->Map.SetDimensions(dimensions);
  std::size_t nans = 0;
  switch (scalars->GetDataType())
  {
    vtkTemplateMacro(
      nans = ComputeRanges(this->Map, static_cast<const VTK_TT*>(scalars->GetVoidPointer(0))));
    default:
      return false;
  }
  this->Scalars = scalars;
  this->ScalarsTime = scalars->GetMTime();
  this->Dimensions = dims;
  this->NaNCount = nans;
  this->Time.Modified();
  return true;
}
}
