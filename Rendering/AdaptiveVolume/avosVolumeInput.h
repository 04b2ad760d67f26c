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
/// be of one component (up to `maximumComponents`: 4 for
/// vtkAdaptiveVolumeMapper, which renders several), one tuple per point
/// (per cell for `cellScalars`), on a grid of at least 2 points along each
/// axis with a non-zero, finite spacing. Whether cell scalars are rendered
/// is the caller's to say.
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string ValidateVolumeInput(
  vtkImageData* image, vtkDataArray* scalars, bool cellScalars, int maximumComponents = 1);
}

#endif
