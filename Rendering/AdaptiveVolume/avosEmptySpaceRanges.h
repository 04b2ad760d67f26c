// The empty-space map of a volume's scalars, its block ranges rebuilt only
// when the scalars (the array or its MTime) or the dimensions change. Shared
// by vtkAdaptiveVolumeMapper and the Volume-on-Surface rays; the caller
// classifies the blocks for its transfer function. Not wrapped.
#ifndef avosEmptySpaceRanges_h
#define avosEmptySpaceRanges_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro
#include "vtkTimeStamp.h"
#include "vtkType.h"

#include "avos/numerics/EmptySpace.h"

#include <array>
#include <cstddef>

class vtkDataArray;
class vtkObject;

namespace avos
{
class AVOSRENDERINGADAPTIVEVOLUME_EXPORT EmptySpaceRanges
{
public:
  using Samples = avos::numerics::EmptySpaceMap<double>::Samples;

  /// Brings the ranges up to date for the scalars (each of their 1 to 4
  /// components, or only `component` when it is not negative, a tuple per
  /// grid point of `dimensions`, or per cell, as `samples` says). False, with
  /// nothing changed, for a scalar type the map cannot read.
  bool Update(vtkDataArray* scalars, const int dimensions[3], Samples samples = Samples::Points,
    int component = -1);

  avos::numerics::EmptySpaceMap<double>& GetMap() { return this->Map; }
  /// NaN scalars met by the last rebuild.
  std::size_t GetNaNCount() const { return this->NaNCount; }
  /// When the ranges were last rebuilt.
  vtkMTimeType GetTime() const { return this->Time.GetMTime(); }
  /// Warns on `caller` of what the last rebuild's NaN scalars do to the
  /// image (every cell with a NaN corner is empty), once: the first call
  /// after a rebuild that met some; later calls say nothing.
  void WarnOfNaNs(vtkObject* caller);

private:
  avos::numerics::EmptySpaceMap<double> Map;
  vtkDataArray* Scalars = nullptr; // identity only; its MTime guards reuse
  vtkMTimeType ScalarsTime = 0;
  std::array<int, 3> Dimensions{ { 0, 0, 0 } };
  Samples Sampled = Samples::Points;
  int Component = -1;
  vtkMTimeType NaNReported = 0; // the rebuild whose NaN notice was said
  std::size_t NaNCount = 0;
  vtkTimeStamp Time;
};
}

#endif
