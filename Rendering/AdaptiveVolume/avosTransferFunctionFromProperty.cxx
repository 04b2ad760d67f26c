#include "avosTransferFunctionFromProperty.h"

#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"

#include <algorithm>

namespace
{
using TransferFunction = avos::numerics::TransferFunction<double>;

// Sub-knots per node interval where VTK's function is not piecewise linear.
constexpr int ResampledKnots = 16;

// VTK's colour-space conversions round: an HSV value of 1 comes back as
// 1 + 2.2e-16. Colours and opacities within this of [0, 1] are clamped onto
// it (far below any tolerance the methods take, 8e-7 at least); beyond it
// they are refused by TransferFunction::Validate.
constexpr double RoundingTolerance = 1e-12;

double ClampRounding(double v)
{
  if (v < 0.0 && v >= -RoundingTolerance)
  {
    return 0.0;
  }
  return v > 1.0 && v <= 1.0 + RoundingTolerance ? 1.0 : v;
}

// How VTK interpolates between two nodes (vtkPiecewiseFunction::GetValue,
// vtkColorTransferFunction::GetColor in RGB space): the normalised position
// x in [0, 1] is first bent at the midpoint m (x' = 0.5 x / m below it,
// 0.5 + 0.5 (x - m) / (1 - m) above), then a sharpness below 0.01 keeps x'
// (linear in x': piecewise linear in x, a kink at m), one above 0.99 makes
// a step at x' = 0.5 (the first value below m, the second from m on, in
// any colour space), and any other a Hermite curve in x'. The first three
// are piecewise linear and taken exactly; a Hermite curve, and a
// non-stepped interval in HSV, Lab or Diverging space, are not (Curved).
enum class Shape
{
  Linear,
  Kink,
  Step,
  Curved
};

Shape ShapeOf(double midpoint, double sharpness, bool linearSpace)
{
  // A step holds the nodes' own values in every colour space.
  if (sharpness > 0.99)
  {
    return Shape::Step;
  }
  if (!linearSpace || sharpness >= 0.01)
  {
    return Shape::Curved;
  }
  return midpoint == 0.5 ? Shape::Linear : Shape::Kink;
}

// The knots of one node interval [x0, x1) after the node's own: the exact
// ones of a kink or a step, or samples of VTK's function where it is curved
// (`value(s, out)` evaluates it; `approximated` counts such intervals).
template <int Channels, typename Add, typename Value>
void AddInterval(double x0, const double* v0, double x1, const double* v1, double midpoint,
  Shape shape, Add&& add, Value&& value, int& approximated)
{
  // VTK keeps the midpoint off the interval's ends.
  const double m = std::min(std::max(midpoint, 0.00001), 0.99999);
  const double xm = x0 + m * (x1 - x0);
  double mean[Channels];
  for (int c = 0; c < Channels; ++c)
  {
    mean[c] = v0[c] + 0.5 * (v1[c] - v0[c]);
  }
  switch (shape)
  {
    case Shape::Linear:
      return;
    case Shape::Kink:
      add(xm, mean);
      return;
    case Shape::Step:
      add(xm, v0);
      add(xm, v1);
      return;
    case Shape::Curved:
      ++approximated;
      for (int k = 1; k < ResampledKnots; ++k)
      {
        const double s = x0 + (x1 - x0) * k / ResampledKnots;
        double v[Channels];
        value(s, v);
        add(s, v);
      }
      return;
  }
}

// VTK's colour function as knots: exact where VTK interpolates piecewise
// linearly, resampled where it does not.
std::string ConvertColor(vtkVolumeProperty* property, TransferFunction& tf, int& approximated)
{
  auto addColour = [&](double s, const double* rgb)
  { tf.AddColorKnot(s, ClampRounding(rgb[0]), ClampRounding(rgb[1]), ClampRounding(rgb[2])); };
  if (property->GetColorChannels(0) == 1)
  {
    vtkPiecewiseFunction* gray = property->GetGrayTransferFunction(0);
    const int n = gray ? gray->GetSize() : 0;
    if (n == 0)
    {
      return "the gray transfer function is empty";
    }
    auto addGray = [&](double s, const double* v)
    {
      const double g = ClampRounding(v[0]);
      tf.AddColorKnot(s, g, g, g);
    };
    for (int i = 0; i < n; ++i)
    {
      double node[4], next[4];
      gray->GetNodeValue(i, node);
      addGray(node[0], node + 1);
      if (i + 1 < n)
      {
        gray->GetNodeValue(i + 1, next);
        AddInterval<1>(
          node[0], node + 1, next[0], next + 1, node[2], ShapeOf(node[2], node[3], true), addGray,
          [gray](double s, double* v) { v[0] = gray->GetValue(s); }, approximated);
      }
    }
    return std::string();
  }
  vtkColorTransferFunction* color = property->GetRGBTransferFunction(0);
  const int n = color ? color->GetSize() : 0;
  if (n == 0)
  {
    return "the colour transfer function is empty";
  }
  const bool linearSpace = color->GetColorSpace() == VTK_CTF_RGB;
  for (int i = 0; i < n; ++i)
  {
    double node[6], next[6];
    color->GetNodeValue(i, node);
    addColour(node[0], node + 1);
    if (i + 1 < n)
    {
      color->GetNodeValue(i + 1, next);
      AddInterval<3>(
        node[0], node + 1, next[0], next + 1, node[4], ShapeOf(node[4], node[5], linearSpace),
        addColour, [color](double s, double* rgb) { color->GetColor(s, rgb); }, approximated);
    }
  }
  return std::string();
}

std::string ConvertOpacity(vtkVolumeProperty* property, TransferFunction& tf, int& approximated)
{
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity(0);
  const int n = opacity ? opacity->GetSize() : 0;
  if (n == 0)
  {
    return "the scalar opacity function is empty";
  }
  auto add = [&](double s, const double* v) { tf.AddOpacityKnot(s, ClampRounding(v[0])); };
  for (int i = 0; i < n; ++i)
  {
    double node[4], next[4];
    opacity->GetNodeValue(i, node);
    add(node[0], node + 1);
    if (i + 1 < n)
    {
      opacity->GetNodeValue(i + 1, next);
      AddInterval<1>(
        node[0], node + 1, next[0], next + 1, node[2], ShapeOf(node[2], node[3], true), add,
        [opacity](double s, double* v) { v[0] = opacity->GetValue(s); }, approximated);
    }
  }
  return std::string();
}

// True when the gradient opacity changes anything: enabled and not the
// constant 1 that VTK creates on first access (VTK's GPU mapper accesses it).
bool UsesGradientOpacity(vtkVolumeProperty* property)
{
  if (property->GetDisableGradientOpacity(0) || !property->HasGradientOpacity(0))
  {
    return false;
  }
  vtkPiecewiseFunction* f = property->GetStoredGradientOpacity(0);
  for (int i = 0; f && i < f->GetSize(); ++i)
  {
    double node[4];
    f->GetNodeValue(i, node);
    if (node[1] != 1.0)
    {
      return true;
    }
  }
  return false;
}
} // namespace

std::string avos::UnsupportedPropertySettings(vtkVolumeProperty* property, bool shading)
{
  if (!property)
  {
    return std::string();
  }
  if (property->GetInterpolationType() != VTK_LINEAR_INTERPOLATION)
  {
    return "Only trilinear interpolation is supported (the integrals are those of the trilinear "
           "field): call the property's SetInterpolationTypeToLinear()";
  }
  if (property->GetTransferFunctionMode() != vtkVolumeProperty::TF_1D ||
    UsesGradientOpacity(property))
  {
    return "Only one-dimensional transfer functions of the scalar are supported: no gradient "
           "opacity, no 2D transfer function";
  }
  if (property->GetUseClippedVoxelIntensity())
  {
    return "UseClippedVoxelIntensity (VTK's GPU mapper's fill of clipped voxels for gradients) is "
           "not supported: clipping cuts the rays exactly";
  }
  if (property->GetShade(0) && !shading)
  {
    return "Shading is not supported (emission-absorption model): turn the property's Shade off";
  }
  return std::string();
}

std::string avos::ApproximationNotice(int approximatedIntervals)
{
  if (approximatedIntervals <= 0)
  {
    return std::string();
  }
  return std::to_string(approximatedIntervals) +
    " interval(s) of the transfer function (a sharpness between 0.01 and 0.99, or HSV, Lab or "
    "Diverging colour space) are approximated by 16 linear pieces each, without a proven bound: "
    "the tolerance is not certified there";
}

std::string avos::TransferFunctionFromProperty(vtkVolumeProperty* property, bool extinction,
  double voxel, TransferFunction& tf, int* approximatedIntervals)
{
  tf = TransferFunction();
  if (!property)
  {
    return "no volume property";
  }
  int approximated = 0;
  std::string error = ConvertColor(property, tf, approximated);
  if (error.empty())
  {
    error = ConvertOpacity(property, tf, approximated);
  }
  if (approximatedIntervals)
  {
    *approximatedIntervals = approximated;
  }
  if (!extinction)
  {
    tf.SetOpacityModel(
      avos::numerics::OpacityModel::Alpha, property->GetScalarOpacityUnitDistance(0) / voxel);
  }
  if (error.empty())
  {
    error = tf.Validate();
  }
  tf.Finalize();
  return error;
}
