// A vtkVolumeProperty's first-component colour and scalar opacity as the
// numerical core's TransferFunction, shared by the classes that integrate
// rays (vtkAdaptiveVolumeMapper, the Volume-on-Surface classes). Not wrapped:
// it speaks the core's types.
#ifndef avosTransferFunctionFromProperty_h
#define avosTransferFunctionFromProperty_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro

#include "avos/numerics/TransferFunction.h" // For TransferFunction

#include <string> // For std::string

class vtkVolumeProperty;

namespace avos
{
/**
 * Fills `tf` (replacing what it held) and finalizes it. `extinction`: the
 * opacity function holds tau per voxel unit (the paper's model); otherwise it
 * is VTK's opacity per ScalarOpacityUnitDistance. `voxel`: the world length
 * of one voxel unit. The knots are kept; where VTK does not interpolate
 * linearly in RGB (midpoint or sharpness moved, a non-RGB colour space), each
 * interval is resampled with 16 sub-knots. Returns an empty string, or why
 * the property cannot be used (empty functions, invalid values).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string TransferFunctionFromProperty(
  vtkVolumeProperty* property, bool extinction, double voxel,
  avos::numerics::TransferFunction<double>& tf);

/**
 * Empty, or a sentence (no final stop) naming the property's settings that the ray
 * integrals do not honour (never ignored): nearest interpolation, a
 * gradient opacity that changes anything (VTK's default constant 1 is
 * accepted), a 2D transfer function, UseClippedVoxelIntensity, and shading
 * unless `shading` (the caller lights the emission).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string UnsupportedPropertySettings(
  vtkVolumeProperty* property, bool shading = false);
}

#endif
