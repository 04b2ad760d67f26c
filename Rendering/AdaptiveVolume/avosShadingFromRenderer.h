// A vtkVolumeProperty's shading and a renderer's switched-on lights as the
// numerical core's ShadingModel, and the grid-to-world maps a ray's shading
// and gradient opacity read, shared by the classes that shade rays or scale
// them by gradient opacity (vtkAdaptiveVolumeMapper, the Volume on Surface
// classes). Not wrapped: it speaks the core's types.
#ifndef avosShadingFromRenderer_h
#define avosShadingFromRenderer_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro

#include "avos/numerics/Shading.h" // For ShadingModel

#include <glm/glm.hpp> // For glm::dmat3

#include <string> // For std::string
#include <vector> // For std::vector

class vtkLightCollection;
class vtkRenderer;
class vtkVolumeProperty;

namespace avos
{
namespace engine
{
struct FrameMethod;
}

/**
 * Fills `model` with the property's first component's ambient, diffuse,
 * specular and specular power, the renderer's two-sided lighting and its
 * switched-on lights in world space (each light's colours times its
 * intensity; directional: from the focal point towards the position;
 * positional: the position, the attenuation values and the spot's cone),
 * and `key` with the same as numbers (a frame's colours depend on them).
 * Returns why the lights cannot be used, or an empty string.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string ShadingFromRenderer(vtkRenderer* ren,
  vtkVolumeProperty* property, numerics::ShadingModel<double>& model, std::vector<double>& key);

/**
 * As ShadingFromRenderer, from `lights` and `twoSided` lighting: for a class
 * that lights with a renderer's lights before it renders (where VTK has not
 * yet created its automatic headlight).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string ShadingFromLights(vtkLightCollection* lights,
  bool twoSided, vtkVolumeProperty* property, numerics::ShadingModel<double>& model,
  std::vector<double>& key);

/**
 * The normal matrix of `gridToWorld` (row-major 4x4, affine): grid
 * gradients to world space, the inverse transpose of its linear part.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT glm::dmat3 NormalMatrix(const double gridToWorld[16]);

/**
 * Points `method` at `model` with the maps of `gridToWorld` (row-major 4x4,
 * affine): ray directions and positions to world space, and the normal
 * matrix (grid gradients to world: the inverse transpose of its linear
 * part).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT void ShadeWith(const numerics::ShadingModel<double>& model,
  const double gridToWorld[16], engine::FrameMethod& method);
}

#endif
