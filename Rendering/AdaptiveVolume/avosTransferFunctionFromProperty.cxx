#include "avosTransferFunctionFromProperty.h"

#include "vtkColorTransferFunction.h"
#include "vtkMath.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

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

// The knots of one node interval [x0, x1) of an HSV colour function with a
// sharpness below 0.01, after the node's own, within `tolerance` of VTK's
// colours (a proven bound). VTK interpolates h, s and v linearly in the
// midpoint-bent position x' (the hue the short way round when HSVWrap is
// on, then back into [0, 1)) and converts to RGB by vtkMath::HSVToRGB, where
// each channel is v (1 - s + s g(h)) with g linear between multiples of 1/6
// of the hue: between those breakpoints, the bend and the wrap, each channel
// is a cubic in x. On such a part of width w a cubic's second derivative is
// linear, so its largest |p''| is at an end (M2, from the cubic through four
// equally spaced values, plus their rounding's share), and n equal linear
// pieces with (w / n)^2 M2 / 8 <= tolerance / 2 stay within tolerance / 2 of
// it. False (nothing added) when a part would need more than MaximumKnots.
constexpr int MaximumKnots = 4096;

template <typename Add>
bool AddHSVInterval(double x0, const double* rgb0, double x1, const double* rgb1, double midpoint,
  bool wrap, double tolerance, Add&& add)
{
  double h0[3], h1[3];
  vtkMath::RGBToHSV(rgb0, h0);
  vtkMath::RGBToHSV(rgb1, h1);
  if (wrap && std::abs(h1[0] - h0[0]) > 0.5)
  {
    (h0[0] > h1[0] ? h0[0] : h1[0]) -= 1.0;
  }
  const double m = std::min(std::max(midpoint, 0.00001), 0.99999);
  const double xm = x0 + m * (x1 - x0);
  // x' (0 to 1, 0.5 at the midpoint) to x, and the colour at x'.
  auto toX = [&](double t)
  { return t < 0.5 ? x0 + 2.0 * t * (xm - x0) : xm + (2.0 * t - 1.0) * (x1 - xm); };
  auto colourAt = [&](double t, double* rgb)
  {
    double hsv[3];
    for (int k = 0; k < 3; ++k)
    {
      hsv[k] = h0[k] + t * (h1[k] - h0[k]);
    }
    hsv[0] += hsv[0] < 0.0 ? 1.0 : 0.0;
    vtkMath::HSVToRGB(hsv, rgb);
  };
  std::vector<double> breaks{ 0.0, 0.5, 1.0 };
  for (int k = -6; k <= 6 && h1[0] != h0[0]; ++k)
  {
    const double t = (k / 6.0 - h0[0]) / (h1[0] - h0[0]);
    if (t > 0.0 && t < 1.0)
    {
      breaks.push_back(t);
    }
  }
  std::sort(breaks.begin(), breaks.end());
  std::vector<std::pair<double, std::array<double, 3>>> knots;
  for (std::size_t b = 0; b + 1 < breaks.size(); ++b)
  {
    const double ta = breaks[b], tb = breaks[b + 1];
    if (!(tb > ta))
    {
      continue;
    }
    const double w = toX(tb) - toX(ta);
    double f[4][3];
    for (int j = 0; j < 4; ++j)
    {
      colourAt(ta + (tb - ta) * j / 3.0, f[j]);
    }
    // |p''| at both ends of the cubic through the four values, h = w / 3,
    // and what rounding of the values (a few ulps of 1) can add to it.
    const double h = w / 3.0;
    double m2 = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      const double a = 2 * f[0][c] - 5 * f[1][c] + 4 * f[2][c] - f[3][c];
      const double e = -f[0][c] + 4 * f[1][c] - 5 * f[2][c] + 2 * f[3][c];
      m2 = std::max(m2, std::max(std::abs(a), std::abs(e)) / (h * h));
    }
    m2 += 12.0 * 4.0 * std::numeric_limits<double>::epsilon() / (h * h);
    const double pieces = std::ceil(w * std::sqrt(m2 / (4.0 * tolerance)));
    if (!(pieces <= MaximumKnots))
    {
      return false;
    }
    const int n = std::max(1, static_cast<int>(pieces));
    for (int k = 1; k <= n; ++k)
    {
      const double t = ta + (tb - ta) * k / n;
      std::array<double, 3> rgb;
      colourAt(t, rgb.data());
      knots.push_back({ toX(t), rgb });
    }
  }
  knots.pop_back(); // the next node's own
  for (const auto& k : knots)
  {
    add(k.first, k.second.data());
  }
  return true;
}

// A vtkPiecewiseFunction (a gray colour or the opacity) as knots, `add(s,
// value)` each: exact where VTK interpolates piecewise linearly, resampled
// where it does not.
template <typename Add>
void ConvertPiecewise(vtkPiecewiseFunction* f, Add&& add, int& approximated)
{
  auto addValue = [&](double s, const double* v) { add(s, v[0]); };
  const int n = f->GetSize();
  for (int i = 0; i < n; ++i)
  {
    double node[4], next[4];
    f->GetNodeValue(i, node);
    addValue(node[0], node + 1);
    if (i + 1 < n)
    {
      f->GetNodeValue(i + 1, next);
      AddInterval<1>(
        node[0], node + 1, next[0], next + 1, node[2], ShapeOf(node[2], node[3], true), addValue,
        [f](double s, double* v) { v[0] = f->GetValue(s); }, approximated);
    }
  }
}

// VTK's colour function as knots: exact where VTK interpolates piecewise
// linearly, resampled where it does not.
std::string ConvertColor(vtkVolumeProperty* property, TransferFunction& tf, int& approximated,
  double colourTolerance, int& certified)
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
    ConvertPiecewise(
      gray,
      [&](double s, double v)
      {
        const double g = ClampRounding(v);
        tf.AddColorKnot(s, g, g, g);
      },
      approximated);
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
      const Shape shape = ShapeOf(node[4], node[5], linearSpace);
      if (shape == Shape::Curved && colourTolerance > 0.0 && node[5] < 0.01 &&
        color->GetColorSpace() == VTK_CTF_HSV &&
        AddHSVInterval(node[0], node + 1, next[0], next + 1, node[4], color->GetHSVWrap() != 0,
          colourTolerance, addColour))
      {
        ++certified;
        continue;
      }
      AddInterval<3>(
        node[0], node + 1, next[0], next + 1, node[4], shape, addColour,
        [color](double s, double* rgb) { color->GetColor(s, rgb); }, approximated);
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
  ConvertPiecewise(
    opacity, [&](double s, double v) { tf.AddOpacityKnot(s, ClampRounding(v)); }, approximated);
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

double avos::IntegrationTolerance(double tolerance, int certifiedIntervals)
{
  return tolerance * (certifiedIntervals > 0 ? 1.0 - ColourShare : 1.0);
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
  double voxel, TransferFunction& tf, int* approximatedIntervals, double colourTolerance,
  int* certifiedIntervals)
{
  tf = TransferFunction();
  if (!property)
  {
    return "no volume property";
  }
  int approximated = 0, certified = 0;
  std::string error = ConvertColor(property, tf, approximated, colourTolerance, certified);
  if (error.empty())
  {
    error = ConvertOpacity(property, tf, approximated);
  }
  if (approximatedIntervals)
  {
    *approximatedIntervals = approximated;
  }
  if (certifiedIntervals)
  {
    *certifiedIntervals = certified;
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
