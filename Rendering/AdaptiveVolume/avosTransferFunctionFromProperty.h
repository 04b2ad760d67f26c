// A vtkVolumeProperty's first-component colour and scalar opacity as the
// numerical core's TransferFunction, exactly or within a certified budget,
// shared by the classes that integrate rays (vtkAdaptiveVolumeMapper, the
// Volume-on-Surface classes, the GPU mapper). Not wrapped: it speaks the
// core's types.
#ifndef avosTransferFunctionFromProperty_h
#define avosTransferFunctionFromProperty_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro
#include "vtkType.h"                           // For vtkMTimeType

#include "avos/numerics/Mixture.h"          // For MixtureTransferFunction
#include "avos/numerics/TransferFunction.h" // For TransferFunction

#include <array>  // For std::array
#include <string> // For std::string

class vtkColorTransferFunction;
class vtkPiecewiseFunction;
class vtkVolumeProperty;

namespace avos
{
struct NodeInterpolation;

/**
 * What a conversion may spend of a class's tolerance where VTK's functions
 * are not piecewise linear (the inputs), and what it did there (the
 * outputs). With budgets of 0 nothing is certified.
 */
struct AVOSRENDERINGADAPTIVEVOLUME_EXPORT ConversionBudget
{
  // A colour (or gray) within Colour of VTK's wherever the opacity is not 0:
  // a pixel then moves by at most Colour G (1 - T) <= Colour G, its
  // emission's weights summing to its opacity, G = ColourGain.
  double Colour = 0.0;
  // Every channel of a pixel within Opacity of the one VTK's opacity gives
  // (numerics::ExtinctionBudget), for rays up to LongestRay voxel units
  // whose colours are at most ColourGain (the shading's gain, 1 unlit); the
  // opacity also takes the colours' Colour G where they certify nothing.
  double Opacity = 0.0;
  double LongestRay = 0.0;
  double ColourGain = 1.0;
  // The intervals certified (of the colour or gray function, of the
  // opacity) and those approximated without a proven bound.
  int CertifiedColour = 0;
  int CertifiedOpacity = 0;
  int Approximated = 0;
  // The pixel error the certified intervals may cause (at most Colour G +
  // Opacity): what IntegrationTolerance takes off.
  double Spent = 0.0;

  /**
   * The piecewise method's shares of its `tolerance`: ColourShare of it for
   * the colours (divided by `gain`), OpacityShare for the opacity.
   */
  static ConversionBudget ForTolerance(double tolerance, double gain, double longestRay);

  /**
   * The share of `tolerance` a gradient opacity function may take
   * (GradientShare, in Opacity), for GradientOpacityFromProperty.
   */
  static ConversionBudget ForGradientOpacity(double tolerance, double gain, double longestRay);

  /** The inputs are the same (the conversion would be too). */
  bool SameAs(const ConversionBudget& other) const;
};

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
 * Every other interval (HSV, Lab or Diverging space, a Hermite curve, a log
 * scale) is linearised within the `budget` (a proven bound:
 * numerics::LinearizeWithin against the model of avosNodeInterpolation.h,
 * checked against VTK's values at every knot): colours and gray within
 * budget->Colour wherever the opacity is not 0, the opacity by
 * numerics::ExtinctionChordTolerance within budget->Opacity. What is not
 * certified (no budget, the CIEDE2000 space, a tolerance below the 1e-7
 * jumps of VTK's own L*a*b* conversion, an alpha-model opacity curve that
 * reaches 1 (its extinction is unbounded there), more than 4096 knots per
 * half interval) is resampled with 16 sub-knots per interval, an
 * approximation without a proven bound, counted in budget->Approximated.
 * Returns an empty string, or why the property cannot be used (empty
 * functions, invalid values).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string TransferFunctionFromProperty(
  vtkVolumeProperty* property, bool extinction, double voxel,
  avos::numerics::TransferFunction<double>& tf, ConversionBudget* budget = nullptr);

/**
 * A volume of several components as VTK's mappers read it: each
 * component's transfer function (independent components), or the first
 * component's (dependent ones), and their mixture (pointing into
 * Functions: not copied).
 */
struct AVOSRENDERINGADAPTIVEVOLUME_EXPORT MixtureFunctions
{
  std::array<avos::numerics::TransferFunction<double>, 4> Functions;
  avos::numerics::MixtureTransferFunction<double> Mixture;

  MixtureFunctions() = default;
  MixtureFunctions(const MixtureFunctions&) = delete;
  MixtureFunctions& operator=(const MixtureFunctions&) = delete;
};

/**
 * The mixture (numerics/Mixture.h) of `components` (2 to 4) scalars of the
 * VTK type `scalarType`, as TransferFunctionFromProperty converts each
 * function. Independent components (the property's default): component k
 * through its own colour (RGB or gray), scalar opacity, unit distance and
 * weight (GetComponentWeight). Dependent ones: 2, the first component's
 * colour function of the first scalar and its opacity function of the
 * second; 4 (unsigned char only), the first three scalars / 255 as RGB and
 * the opacity function of the fourth. Within `budget` as
 * TransferFunctionFromProperty, each component's colours within its Colour
 * share, each opacity within Opacity over the weights' sum (at least 1),
 * so that their weighted errors add up to the shares; no component lends
 * another its unused share. Returns an empty string, or why not.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string MixtureFromProperty(vtkVolumeProperty* property,
  int components, int scalarType, bool extinction, double voxel, MixtureFunctions& out,
  ConversionBudget* budget = nullptr);

/**
 * Fills `n` with the model (avosNodeInterpolation.h) of VTK's colour
 * between nodes `index` and `index + 1` of `color`, the ends in the
 * interpolation space computed by VTK. False for a colour space it does not
 * model (CIEDE2000, Step) or an index without a next node.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT bool ModelColourInterval(
  vtkColorTransferFunction* color, int index, NodeInterpolation& n);

/**
 * The same for a vtkPiecewiseFunction (a gray or opacity function), in
 * channel 0 (the other channels hold the same values).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT bool ModelPiecewiseInterval(
  vtkPiecewiseFunction* f, int index, NodeInterpolation& n);

/**
 * The shares of a class's tolerance eps that the conversion may take where
 * it certifies: ColourShare for the colours, OpacityShare for the opacity
 * (which also takes the colours' share where they certify nothing);
 * the rays are integrated to the rest (IntegrationTolerance), so every
 * pixel stays within eps of the integral of VTK's own functions.
 */
constexpr double ColourShare = 0.5;
constexpr double OpacityShare = 0.25;
/** The share of eps a curved gradient opacity function may take. */
constexpr double GradientShare = 0.125;

/**
 * The tolerance a class integrates to after a conversion within `budget`:
 * `tolerance` less what the conversion spent.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT double IntegrationTolerance(
  double tolerance, const ConversionBudget& budget);

/**
 * The warning for `approximatedIntervals` intervals TransferFunctionFromProperty
 * could not take exactly (a sentence, no final stop), empty for none: the
 * classes say it once per conversion instead of keeping silent.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string ApproximationNotice(int approximatedIntervals);

/**
 * Empty, or a sentence (no final stop) naming the property's settings that the ray
 * integrals do not honour (never ignored): a gradient opacity of any of the
 * first `components` but the first that changes anything
 * (UsesGradientOpacity), a 2D transfer function and
 * UseClippedVoxelIntensity. Every class that integrates rays takes linear
 * and nearest interpolation, shading and the first component's gradient
 * opacity.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string UnsupportedPropertySettings(
  vtkVolumeProperty* property, int components = 1);

/**
 * Empty, or a sentence (no final stop) naming what scalars of `components`
 * components cannot take with `property`, in both mappers: a projection
 * (`composite` false), shading and gradient opacity (their gradients are
 * not modelled). Empty for one component.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string UnsupportedForComponents(
  vtkVolumeProperty* property, int components, bool composite);

/**
 * True when the gradient opacity of `component` changes anything: enabled
 * and not the constant 1 that VTK creates on first access (VTK's GPU mapper
 * accesses it).
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT bool UsesGradientOpacity(
  vtkVolumeProperty* property, int component);

/**
 * The first component's gradient opacity function G as the opacity knots of
 * `tf` (replaced; one white colour knot), taken exactly where VTK
 * interpolates it piecewise linearly. Elsewhere (a Hermite curve, a log
 * scale), where `budget` has a positive Opacity (ForGradientOpacity),
 * linearised within it: the extinction is tau G with tau at most
 * `maximumExtinction` (the scalar transfer function's largest), so a chord
 * of G within Relative G + Absolute / maximumExtinction keeps tau G within
 * the numerics::ExtinctionBudget of budget.Opacity
 * (numerics::ExtinctionChordTolerance of the extinction maximumExtinction
 * G): every pixel within budget.Opacity of the one VTK's G gives. The
 * intervals certified are counted in budget.CertifiedOpacity, the pixel
 * error they may cause in budget.Spent; the others are resampled with 16
 * knots per interval (budget.Approximated). Empty, or why not.
 */
AVOSRENDERINGADAPTIVEVOLUME_EXPORT std::string GradientOpacityFromProperty(
  vtkVolumeProperty* property, double maximumExtinction,
  avos::numerics::TransferFunction<double>& tf, ConversionBudget& budget);

/**
 * GradientOpacityFromProperty kept between frames: converted again only
 * when the first component's gradient opacity function changes (another
 * function, or its MTime) or its budget does, so that a mapper converts it,
 * and warns of what it resampled, once per change.
 */
class AVOSRENDERINGADAPTIVEVOLUME_EXPORT GradientOpacityConversion
{
public:
  /**
   * The conversion of `property`'s function within `request` for tau up to
   * `maximumExtinction` (GradientOpacityFromProperty); `approximated` is
   * what this call resampled (0 when it reused the last conversion). Empty,
   * or why the function cannot be used.
   */
  std::string Update(vtkVolumeProperty* property, double maximumExtinction,
    const ConversionBudget& request, int& approximated);
  const avos::numerics::TransferFunction<double>& Get() const { return this->Function; }
  /** What the last conversion certified and spent. */
  const ConversionBudget& GetBudget() const { return this->Budget; }

private:
  vtkPiecewiseFunction* Source = nullptr;
  vtkMTimeType SourceTime = 0;
  double MaximumExtinction = 0.0;
  ConversionBudget Request, Budget;
  std::string Error;
  avos::numerics::TransferFunction<double> Function;
};
}

#endif
