// The one rule for what volume AVoS's classes render, shared by
// vtkAdaptiveVolumeMapper, vtkOpenGLAdaptiveVolumeMapper and the
// Volume-on-Surface filter and mapper. Not wrapped.
#ifndef avosVolumeInput_h
#define avosVolumeInput_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro

#include <string>

class vtkDataArray;
class vtkImageData;

namespace avos
{
/// Why `scalars` of `image` cannot be rendered, or empty: they must exist,
/// be point scalars (`cellScalars` false) of one component, one per point
/// of at least 2 points along each axis, on a non-zero, finite spacing.
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string ValidateVolumeInput(
  vtkImageData* image, vtkDataArray* scalars, bool cellScalars);
}

#endif
