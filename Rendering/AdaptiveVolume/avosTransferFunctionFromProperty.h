// A vtkVolumeProperty's first-component colour and scalar opacity as the
// numerical core's TransferFunction, shared by the classes that integrate
// rays (vtkAdaptiveVolumeMapper, the Volume-on-Surface classes). Not wrapped:
// it speaks the core's types.
#ifndef avosTransferFunctionFromProperty_h
#define avosTransferFunctionFromProperty_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro

#include "avos/numerics/TransferFunction.h" // For TransferFunction

#include <string> // For std::string

class vtkColorTransferFunction;
class vtkVolumeProperty;

namespace avos
{
struct NodeInterpolation;

/**
 * Fills `tf` (replacing what it held) and finalizes it. `extinction`: the
 * opacity function holds tau per voxel unit (the paper's model); otherwise it
 * is VTK's opacity per ScalarOpacityUnitDistance. `voxel`: the world length
 * of one voxel unit. The knots are kept, and VTK's function between them is
 * taken exactly where it is piecewise linear: RGB space (or a gray or
 * opacity function) on a linear scale with a sharpness below 0.01 (linear,
 * or a kink at a moved midpoint: one more knot), a sharpness above 0.99 in
 * any space (a step at the midpoint: a jump), the Step colour space. Outside
 * the nodes it is VTK's: the end values, the below- and above-range colours,
 * or 0 without clamping. Colours and opacities within 1e-12 of [0, 1] (the
 * rounding of VTK's colour-space conversions) are clamped onto it.
 * With `colourTolerance` > 0, every other colour interval (HSV, Lab or
 * Diverging space, a Hermite curve, a log scale) is linearised within
 * colourTolerance of VTK's colours wherever the opacity is not 0, a proven
 * bound (numerics::Linearize against the model of avosNodeInterpolation.h,
 * checked against GetColor at every knot): `certifiedIntervals` gets their
 * number. What is not certified (no tolerance, the CIEDE2000 space, Hermite
 * or log-scale opacity and gray functions, a tolerance below the 1e-7 jumps
 * of VTK's own L*a*b* conversion, more than 4096 knots per half interval)
 * is resampled with 16 sub-knots per interval, an approximation without a
 * proven bound: `approximatedIntervals` gets the number of such intervals.
 * Returns an empty string, or why the property cannot be used (empty
 * functions, invalid values).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string TransferFunctionFromProperty(
  vtkVolumeProperty* property, bool extinction, double voxel,
  avos::numerics::TransferFunction<double>& tf, int* approximatedIntervals = nullptr,
  double colourTolerance = 0.0, int* certifiedIntervals = nullptr);

/**
 * Fills `n` with the model (avosNodeInterpolation.h) of VTK's colour
 * between nodes `index` and `index + 1` of `color`, the ends in the
 * interpolation space computed by VTK. False for a colour space it does not
 * model (CIEDE2000, Step) or an index without a next node.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT bool ModelColourInterval(
  vtkColorTransferFunction* color, int index, NodeInterpolation& n);

/**
 * The share of a class's tolerance eps that the colour's conversion may
 * take (`colourTolerance` = ColourShare eps): a colour within delta of
 * VTK's changes a pixel by at most delta (1 - T) <= delta (the emission's
 * weights sum to the ray's opacity), so a class that integrates the
 * converted function to (1 - ColourShare) eps keeps every pixel within eps.
 */
constexpr double ColourShare = 0.5;

/**
 * The tolerance a class integrates to when its colours were converted
 * within ColourShare of `tolerance`: the rest where the conversion certified
 * an interval (`certifiedIntervals` > 0), all of it otherwise.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT double IntegrationTolerance(
  double tolerance, int certifiedIntervals);

/**
 * The warning for `approximatedIntervals` intervals TransferFunctionFromProperty
 * could not take exactly (a sentence, no final stop), empty for none: the
 * classes say it once per conversion instead of keeping silent.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string ApproximationNotice(int approximatedIntervals);

/**
 * Empty, or a sentence (no final stop) naming the property's settings that the ray
 * integrals do not honour (never ignored): nearest interpolation unless
 * `nearest` (the caller integrates the field constant per point region), a
 * gradient opacity that changes anything (VTK's default constant 1 is
 * accepted), a 2D transfer function, UseClippedVoxelIntensity, and shading
 * unless `shading` (the caller lights the emission).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string UnsupportedPropertySettings(
  vtkVolumeProperty* property, bool shading = false, bool nearest = false);
}

#endif
