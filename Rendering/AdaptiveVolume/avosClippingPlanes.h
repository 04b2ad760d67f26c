// VTK clipping planes in a volume's grid coordinates, shared by the classes
// that cast rays through vtkImageData (vtkAdaptiveVolumeMapper, the
// Volume-on-Surface mapper). Not wrapped: it speaks the core's types.
#ifndef avosClippingPlanes_h
#define avosClippingPlanes_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro

#include "avos/numerics/Clipping.h" // For ClipRegion

#include <string> // For std::string

class vtkImageData;
class vtkPlaneCollection;
class vtkVolumeMapper;

namespace avos
{
/**
 * Adds each plane of `planes` (world coordinates, keeping the side its normal
 * points to; null: none) to `clip` in the grid coordinates of `gridToWorld`
 * (row-major 4x4). Returns an empty string, or why a plane cannot be used
 * (a plane with a transform).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string AddClippingPlanes(vtkPlaneCollection* planes,
  const double gridToWorld[16], avos::numerics::ClipRegion<double>& clip);

/**
 * `clip` (replaced) = what `mapper` cuts off the image `input`, in its grid
 * coordinates under `gridToWorld`: its clipping planes (AddClippingPlanes)
 * and, when on, its cropping (VTK's region planes in the volume's
 * coordinates, origin and spacing, and its 27 flags). Returns an empty
 * string, or why they cannot be used (a plane with a transform, cropping an
 * input with a direction matrix or negative spacing, planes that are not
 * finite or flags beyond the 27 regions).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string ClipRegionOfMapper(vtkVolumeMapper* mapper,
  vtkImageData* input, const double gridToWorld[16], avos::numerics::ClipRegion<double>& clip);
}

#endif
