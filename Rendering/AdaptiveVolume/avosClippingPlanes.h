// VTK clipping planes in a volume's grid coordinates, shared by the classes
// that cast rays through vtkImageData (vtkAdaptiveVolumeMapper, the
// Volume-on-Surface mapper). Not wrapped: it speaks the core's types.
#ifndef avosClippingPlanes_h
#define avosClippingPlanes_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro

#include "avos/numerics/Clipping.h" // For ClipRegion

#include <string> // For std::string

class vtkPlaneCollection;

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
}

#endif
