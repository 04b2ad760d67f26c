#include "avosTransferFunctionFromProperty.h"

#include "avosNodeInterpolation.h"

#include "avos/numerics/Linearization.h"

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
// it (far below any tolerance the methods take, 8e-12 at least); beyond it
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
// are piecewise linear and taken exactly; a Hermite curve, a non-stepped
// interval in HSV, Lab or Diverging space, and any interval on a log scale
// are not (Curved). `linearSpace`: RGB (or a piecewise function) on a
// linear scale.
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

// VTK keeps the midpoint off the interval's ends.
double ClampMidpoint(double midpoint)
{
  return std::min(std::max(midpoint, 0.00001), 0.99999);
}

// The scalar at the (clamped) midpoint m of [x0, x1]: where the bent
// position is 0.5, in log10 x on a log scale.
double MidpointScalar(double x0, double x1, double m, bool logScale)
{
  if (logScale)
  {
    const double l0 = std::log10(x0), l1 = std::log10(x1);
    return std::min(std::max(std::pow(10.0, l0 + m * (l1 - l0)), x0), x1);
  }
  return x0 + m * (x1 - x0);
}

// The knots of one node interval [x0, x1) after the node's own: the exact
// ones of a kink or a step (at xm, the midpoint's scalar), or samples of
// VTK's function where it is curved (`value(s, out)` evaluates it;
// `approximated` counts such intervals).
template <int Channels, typename Add, typename Value>
void AddInterval(double x0, const double* v0, double x1, const double* v1, double xm, Shape shape,
  Add&& add, Value&& value, int& approximated)
{
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

// The certified conversion of a curved colour interval: knots within
// `tolerance` of VTK's colours (a proven bound, numerics::Linearize against
// the model of avosNodeInterpolation.h), at most MaximumKnots per half.
constexpr std::size_t MaximumKnots = 4096;

// VTK's own values differ from the model's exact function by their
// rounding (a few ulps through the colour-space conversions, 1e-13 at most
// for colours in [0, 1]) and by ClampRounding (RoundingTolerance).
constexpr double ReferenceSlack = 2.0 * RoundingTolerance;

// Moreland's Msh coordinates of an L*a*b* colour (as VTK's diverging map).
void LabToMsh(const double lab[3], double msh[3])
{
  msh[0] = std::sqrt(lab[0] * lab[0] + lab[1] * lab[1] + lab[2] * lab[2]);
  msh[1] = msh[0] > 0.001 ? std::acos(lab[0] / msh[0]) : 0.0;
  msh[2] = msh[1] > 0.001 ? std::atan2(lab[2], lab[1]) : 0.0;
}

// The smaller angle between two hues.
double HueDistance(double a, double b)
{
  const double twoPi = 2.0 * vtkMath::Pi();
  double d = std::abs(a - b);
  while (d >= twoPi)
  {
    d -= twoPi;
  }
  return d > vtkMath::Pi() ? twoPi - d : d;
}

// The hue an unsaturated end of magnitude m takes towards a saturated one,
// spun so that the perceived change stays about constant (Moreland 2009).
double AdjustedHue(const double saturated[3], double m)
{
  if (saturated[0] >= m - 0.1)
  {
    return saturated[2];
  }
  const double spin = saturated[1] * std::sqrt(m * m - saturated[0] * saturated[0]) /
    (saturated[0] * std::sin(saturated[1]));
  return saturated[2] > -0.3 * vtkMath::Pi() ? saturated[2] + spin : saturated[2] - spin;
}

// The ends of a diverging interval in Msh, through white between distinct
// saturated colours (each half then its own pair of ends).
void DivergingEnds(const double rgb1[3], const double rgb2[3], avos::NodeInterpolation& n)
{
  double lab[2][3], msh[2][3];
  vtkMath::RGBToLab(rgb1, lab[0]);
  vtkMath::RGBToLab(rgb2, lab[1]);
  LabToMsh(lab[0], msh[0]);
  LabToMsh(lab[1], msh[1]);
  n.Halves = msh[0][1] > 0.05 && msh[1][1] > 0.05 &&
    HueDistance(msh[0][2], msh[1][2]) > 0.33 * vtkMath::Pi();
  const double white[3] = { std::max(88.0, std::max(msh[0][0], msh[1][0])), 0.0, 0.0 };
  for (int half = 0; half < 2; ++half)
  {
    double(&ends)[2][3] = n.Ends[half];
    std::copy(n.Halves && half == 1 ? white : msh[0], (n.Halves && half == 1 ? white : msh[0]) + 3,
      ends[0]);
    std::copy(n.Halves && half == 0 ? white : msh[1], (n.Halves && half == 0 ? white : msh[1]) + 3,
      ends[1]);
    if (ends[0][1] < 0.05 && ends[1][1] > 0.05)
    {
      ends[0][2] = AdjustedHue(ends[1], ends[0][0]);
    }
    else if (ends[1][1] < 0.05 && ends[0][1] > 0.05)
    {
      ends[1][2] = AdjustedHue(ends[0], ends[1][0]);
    }
  }
}

// VTK's continuous colour function at x: what VTK's volume mappers tabulate
// (vtkColorTransferFunction::GetTable). A subclass's GetColor may differ:
// ParaView's colour maps (vtkDiscretizableColorTransferFunction, Discretize
// on by default) return one of 256 steps, which no volume mapper draws.
void ContinuousColor(vtkColorTransferFunction* color, double x, double rgb[3])
{
  color->vtkColorTransferFunction::GetColor(x, rgb);
}

// VTK takes a colour function's log scale only where every node is positive.
bool UsesLogScale(vtkColorTransferFunction* color)
{
  return color->GetScale() == VTK_CTF_LOG10 && color->GetRange()[0] > 0.0;
}
} // namespace

bool avos::ModelColourInterval(vtkColorTransferFunction* color, int index, NodeInterpolation& n)
{
  if (!color || index < 0 || index + 1 >= color->GetSize())
  {
    return false;
  }
  double node[6], next[6];
  color->GetNodeValue(index, node);
  color->GetNodeValue(index + 1, next);
  n.X1 = node[0];
  n.X2 = next[0];
  n.LogScale = UsesLogScale(color);
  n.Midpoint = ClampMidpoint(node[4]);
  n.Sharpness = node[5];
  const double* rgb[2] = { node + 1, next + 1 };
  double ends[2][3];
  switch (color->GetColorSpace())
  {
    case VTK_CTF_RGB:
      n.Space = avos::InterpolationSpace::RGB;
      std::copy(rgb[0], rgb[0] + 3, ends[0]);
      std::copy(rgb[1], rgb[1] + 3, ends[1]);
      break;
    case VTK_CTF_HSV:
      n.Space = avos::InterpolationSpace::HSV;
      vtkMath::RGBToHSV(rgb[0], ends[0]);
      vtkMath::RGBToHSV(rgb[1], ends[1]);
      if (color->GetHSVWrap() && std::abs(ends[1][0] - ends[0][0]) > 0.5)
      {
        (ends[0][0] > ends[1][0] ? ends[0][0] : ends[1][0]) -= 1.0;
      }
      break;
    case VTK_CTF_LAB:
      n.Space = avos::InterpolationSpace::Lab;
      vtkMath::RGBToLab(rgb[0], ends[0]);
      vtkMath::RGBToLab(rgb[1], ends[1]);
      break;
    case VTK_CTF_DIVERGING:
      n.Space = avos::InterpolationSpace::Diverging;
      DivergingEnds(rgb[0], rgb[1], n);
      return true;
    default:
      return false;
  }
  for (int half = 0; half < 2; ++half)
  {
    std::copy(&ends[0][0], &ends[0][0] + 6, &n.Ends[half][0][0]);
  }
  return true;
}

namespace
{

// The scalar ranges where VTK's opacity is 0 (between two nodes of opacity
// 0, whatever their curve, and beyond an end node of opacity 0, or beyond
// the nodes without clamping). The colour there changes no pixel: emission
// and projections are weighted by the opacity, so the conversion needs no
// accuracy there.
using Ranges = std::vector<std::pair<double, double>>;

Ranges TransparentRanges(vtkPiecewiseFunction* opacity)
{
  Ranges ranges;
  // [lo, hi], joined to the last range where they touch.
  auto add = [&ranges](double lo, double hi)
  {
    if (!ranges.empty() && ranges.back().second == lo)
    {
      ranges.back().second = hi;
    }
    else
    {
      ranges.push_back({ lo, hi });
    }
  };
  const int n = opacity ? opacity->GetSize() : 0;
  const double inf = std::numeric_limits<double>::infinity();
  const bool clamped = n > 0 && opacity->GetClamping();
  double node[4], previous[4] = { 0.0, 1.0, 0.0, 0.0 };
  for (int i = 0; i < n; ++i)
  {
    opacity->GetNodeValue(i, node);
    const bool clear = node[1] == 0.0;
    if (i == 0 && (clear || !clamped))
    {
      add(-inf, node[0]);
    }
    if (i > 0 && clear && previous[1] == 0.0)
    {
      add(previous[0], node[0]);
    }
    if (i + 1 == n && (clear || !clamped))
    {
      add(node[0], inf);
    }
    std::copy(node, node + 4, previous);
  }
  return ranges;
}

// Knots for a modelled interval `n`, from VTK's limit at X1 to its value at
// X2 (`value(x)`, std::array of Channels, the first channels of the
// model), each side of the midpoint's scalar xm (where the model has a
// kink) linearized on its own within `tolerance(enclosure)`, one chord
// where `exempt`. False, with nothing added, where the bound cannot be
// certified.
template <int Channels, typename Tolerance, typename Value, typename Exempt, typename Add>
bool AddLinearized(const avos::NodeInterpolation& n, double xm, Tolerance&& tolerance,
  Value&& value, Exempt&& exempt, Add&& add)
{
  using Jet = avos::numerics::Jet<double>;
  auto enclose = [&n](const avos::numerics::Bounds<double>& x)
  {
    Jet rgb[3];
    avos::interpolation::Evaluate(n, Jet::Variable(x), rgb);
    std::array<Jet, Channels> out;
    std::copy(rgb, rgb + Channels, out.begin());
    return out;
  };
  // At X1 the limit from the right (VTK gives the node's own colour there,
  // which the colour-space round trip may move by 1e-4).
  auto limit = [&](double x) { return value(x == n.X1 ? std::nextafter(n.X1, n.X2) : x); };
  std::vector<avos::numerics::LinearKnot<double, Channels>> knots;
  if (!avos::numerics::LinearizeWithin<double, Channels>(
        n.X1, xm, tolerance, ReferenceSlack, enclose, limit, knots, MaximumKnots, exempt) ||
    !avos::numerics::LinearizeWithin<double, Channels>(
      xm, n.X2, tolerance, ReferenceSlack, enclose, limit, knots, MaximumKnots, exempt))
  {
    return false;
  }
  add(n.X1, limit(n.X1).data());
  for (const auto& k : knots)
  {
    add(k.X, k.Value.data());
  }
  return true;
}

// True on [l, r] inside one of the `transparent` ranges.
bool Inside(const Ranges& transparent, double l, double r)
{
  return std::any_of(transparent.begin(), transparent.end(),
    [l, r](const std::pair<double, double>& t) { return t.first <= l && r <= t.second; });
}

// A colour within `tolerance` of VTK's everywhere: its whole error budget.
auto Within(double tolerance)
{
  return [tolerance](const auto&) { return tolerance; };
}

// A curved colour interval within `tolerance` of VTK's colours (one chord
// inside the `transparent` ranges).
template <typename Add>
bool AddCertifiedInterval(vtkColorTransferFunction* color, int index, double xm, double tolerance,
  const Ranges& transparent, Add&& add)
{
  avos::NodeInterpolation n;
  if (!avos::ModelColourInterval(color, index, n))
  {
    return false;
  }
  auto value = [color](double x)
  {
    std::array<double, 3> rgb;
    ContinuousColor(color, x, rgb.data());
    for (double& c : rgb)
    {
      c = ClampRounding(c);
    }
    return rgb;
  };
  return AddLinearized<3>(
    n, xm, Within(tolerance), value,
    [&transparent](double l, double r) { return Inside(transparent, l, r); }, add);
}

// A curved interval of a piecewise function within `tolerance(enclosure)`
// of VTK's values (one chord where `exempt`).
template <typename Tolerance, typename Exempt, typename Add>
bool AddCertifiedInterval(
  vtkPiecewiseFunction* f, int index, double xm, Tolerance&& tolerance, Exempt&& exempt, Add&& add)
{
  avos::NodeInterpolation n;
  if (!avos::ModelPiecewiseInterval(f, index, n))
  {
    return false;
  }
  return AddLinearized<1>(
    n, xm, tolerance,
    [f](double x) { return std::array<double, 1>{ ClampRounding(f->GetValue(x)) }; }, exempt, add);
}

// A vtkPiecewiseFunction (a gray colour or the opacity) as knots, `add(s,
// value)` each: exact where VTK interpolates piecewise linearly, certified
// where `certify(index, xm, add)` can, resampled elsewhere; 0 outside the
// nodes without clamping. Returns why it cannot be used, or an empty
// string.
template <typename Add, typename Certify>
std::string ConvertPiecewise(
  vtkPiecewiseFunction* f, Add&& add, Certify&& certify, int& approximated)
{
  auto addValue = [&](double s, const double* v) { add(s, v[0]); };
  const int n = f ? f->GetSize() : 0;
  if (n == 0)
  {
    return "is empty";
  }
  const bool logScale = f->GetUseLogScale() != 0;
  if (logScale && !(f->GetRange()[0] > 0.0))
  {
    return "has a log scale and a node at or below 0";
  }
  double node[4], next[4];
  f->GetNodeValue(0, node);
  if (!f->GetClamping() && node[1] != 0.0)
  {
    add(node[0], 0.0);
  }
  for (int i = 0; i < n; ++i)
  {
    f->GetNodeValue(i, node);
    addValue(node[0], node + 1);
    if (i + 1 < n)
    {
      f->GetNodeValue(i + 1, next);
      const double xm = MidpointScalar(node[0], next[0], ClampMidpoint(node[2]), logScale);
      const Shape shape = ShapeOf(node[2], node[3], !logScale);
      if (shape == Shape::Curved && next[0] > node[0] && certify(i, xm, addValue))
      {
        continue;
      }
      AddInterval<1>(
        node[0], node + 1, next[0], next + 1, xm, shape, addValue,
        [f](double s, double* v) { v[0] = f->GetValue(s); }, approximated);
    }
  }
  if (!f->GetClamping() && node[1] != 0.0)
  {
    add(node[0], 0.0);
  }
  return std::string();
}

// VTK's gray function as colour knots, as ConvertColor converts colours.
std::string ConvertGray(vtkPiecewiseFunction* gray, const Ranges& transparent, TransferFunction& tf,
  avos::ConversionBudget& budget)
{
  const std::string error = ConvertPiecewise(
    gray,
    [&](double s, double v)
    {
      const double g = ClampRounding(v);
      tf.AddColorKnot(s, g, g, g);
    },
    [&](int i, double xm, auto&& add)
    {
      const bool certified = budget.Colour > 0.0 &&
        AddCertifiedInterval(
          gray, i, xm, Within(budget.Colour),
          [&transparent](double l, double r) { return Inside(transparent, l, r); }, add);
      budget.CertifiedColour += certified ? 1 : 0;
      return certified;
    },
    budget.Approximated);
  return error.empty() ? error : "the gray transfer function " + error;
}

// VTK's colour function of `component` as knots: exact where VTK
// interpolates piecewise linearly, certified within budget.Colour (when
// positive) where it does not (wherever the opacity of the same scalar is
// not 0, when `sameScalar`: else everywhere), resampled otherwise. Outside
// the nodes, what VTK gives there: the end colours, the below- and
// above-range colours, or black without clamping.
std::string ConvertColor(vtkVolumeProperty* property, int component, bool sameScalar,
  TransferFunction& tf, avos::ConversionBudget& budget)
{
  const Ranges transparent =
    sameScalar ? TransparentRanges(property->GetScalarOpacity(component)) : Ranges();
  if (property->GetColorChannels(component) == 1)
  {
    return ConvertGray(property->GetGrayTransferFunction(component), transparent, tf, budget);
  }
  vtkColorTransferFunction* color = property->GetRGBTransferFunction(component);
  const int n = color ? color->GetSize() : 0;
  if (n == 0)
  {
    return "the colour transfer function is empty";
  }
  // The knots in order; at one scalar only the first (the limit from the
  // left) and the last (from the right) matter.
  std::vector<std::pair<double, std::array<double, 3>>> knots;
  auto addColour = [&](double s, const double* rgb)
  {
    const std::array<double, 3> c{ ClampRounding(rgb[0]), ClampRounding(rgb[1]),
      ClampRounding(rgb[2]) };
    if (knots.size() >= 2 && knots.back().first == s && knots[knots.size() - 2].first == s)
    {
      knots.back().second = c;
    }
    else if (knots.empty() || knots.back().first != s || knots.back().second != c)
    {
      knots.push_back({ s, c });
    }
  };
  const int space = color->GetColorSpace();
  const bool logScale = UsesLogScale(color);
  double first[6], last[6];
  color->GetNodeValue(0, first);
  color->GetNodeValue(n - 1, last);
  double below[3] = { 0.0, 0.0, 0.0 }, above[3] = { 0.0, 0.0, 0.0 };
  if (color->GetClamping())
  {
    std::copy(first + 1, first + 4, below);
    std::copy(last + 1, last + 4, above);
    if (color->GetUseBelowRangeColor())
    {
      color->GetBelowRangeColor(below);
    }
    if (color->GetUseAboveRangeColor())
    {
      color->GetAboveRangeColor(above);
    }
  }
  addColour(first[0], below);
  for (int i = 0; i < n; ++i)
  {
    double node[6], next[6];
    color->GetNodeValue(i, node);
    addColour(node[0], node + 1);
    if (i + 1 == n)
    {
      break;
    }
    color->GetNodeValue(i + 1, next);
    const double xm = MidpointScalar(node[0], next[0], ClampMidpoint(node[4]), logScale);
    const Shape shape = ShapeOf(node[4], node[5], space == VTK_CTF_RGB && !logScale);
    if (shape != Shape::Step && space == VTK_CTF_STEP)
    {
      // Step space: the interval takes the next node's colour.
      addColour(node[0], next + 1);
      continue;
    }
    if (shape == Shape::Curved && budget.Colour > 0.0 && next[0] > node[0] &&
      AddCertifiedInterval(color, i, xm, budget.Colour, transparent, addColour))
    {
      ++budget.CertifiedColour;
      continue;
    }
    AddInterval<3>(
      node[0], node + 1, next[0], next + 1, xm, shape, addColour,
      [color](double s, double* rgb) { ContinuousColor(color, s, rgb); }, budget.Approximated);
  }
  addColour(last[0], above);
  for (const auto& k : knots)
  {
    tf.AddColorKnot(k.first, k.second[0], k.second[1], k.second[2]);
  }
  return std::string();
}

// An opacity-like function `f` as the opacity knots of `tf`: exact where
// VTK interpolates it piecewise linearly, certified within `pixel`
// (numerics::ExtinctionBudget for rays up to budget.LongestRay and colours
// up to budget.ColourGain) for the extinction `extinction(v)` of slope at
// most `slope(v)` below v where it does not, resampled otherwise. Returns
// ConvertPiecewise's error.
template <typename Extinction, typename Slope>
std::string ConvertWithin(vtkPiecewiseFunction* f, double pixel, TransferFunction& tf,
  avos::ConversionBudget& budget, Extinction&& extinction, Slope&& slope)
{
  namespace an = avos::numerics;
  const bool certifying = pixel > 0.0 && budget.LongestRay > 0.0;
  const auto share = an::ExtinctionBudget<double>::Within(
    pixel, std::max(budget.LongestRay, 1.0), std::max(budget.ColourGain, 1.0));
  auto tolerance = [&](const std::array<an::Jet<double>, 1>& j)
  { return an::ExtinctionChordTolerance(j[0].V, ReferenceSlack, share, extinction, slope); };
  return ConvertPiecewise(
    f, [&tf](double s, double v) { tf.AddOpacityKnot(s, ClampRounding(v)); },
    [&](int i, double xm, auto&& add)
    {
      const bool certified = certifying &&
        AddCertifiedInterval(
          f, i, xm, tolerance, [](double, double) { return false; }, add);
      budget.CertifiedOpacity += certified ? 1 : 0;
      return certified;
    },
    budget.Approximated);
}

// VTK's opacity function of `component` as knots, certified within `pixel`
// for the extinctions `tf`'s opacity model gives (ConvertWithin).
std::string ConvertOpacity(vtkVolumeProperty* property, int component, double pixel,
  TransferFunction& tf, avos::ConversionBudget& budget)
{
  const std::string error = ConvertWithin(
    property->GetScalarOpacity(component), pixel, tf, budget,
    [&tf](double v) { return tf.ToExtinction(v); },
    [&tf](double v) { return tf.ExtinctionSlope(v); });
  return error.empty() ? error : "the scalar opacity function " + error;
}

} // namespace

bool avos::UsesGradientOpacity(vtkVolumeProperty* property, int component)
{
  if (property->GetDisableGradientOpacity(component) || !property->HasGradientOpacity(component))
  {
    return false;
  }
  vtkPiecewiseFunction* f = property->GetStoredGradientOpacity(component);
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

std::string avos::GradientOpacityFromProperty(vtkVolumeProperty* property, double maximumExtinction,
  TransferFunction& tf, ConversionBudget& budget)
{
  tf = TransferFunction();
  tf.AddColorKnot(0.0, 1.0, 1.0, 1.0);
  // The extinction tau G, tau <= maximumExtinction: a chord of G within
  // Relative G + Absolute / maximumExtinction keeps it within the budget.
  const double tau = std::max(maximumExtinction, 0.0);
  const std::string error = ConvertWithin(
    property->GetGradientOpacity(0), budget.Opacity, tf, budget,
    [tau](double v) { return tau * v; }, [tau](double) { return tau; });
  budget.Spent = budget.CertifiedOpacity > 0 ? budget.Opacity : 0.0;
  if (!error.empty())
  {
    return "the gradient opacity function " + error;
  }
  tf.Finalize();
  return tf.Validate();
}

std::string avos::GradientOpacityConversion::Update(vtkVolumeProperty* property,
  double maximumExtinction, const ConversionBudget& request, int& approximated)
{
  approximated = 0;
  vtkPiecewiseFunction* source = property->GetGradientOpacity(0);
  if (source != this->Source || source->GetMTime() != this->SourceTime ||
    maximumExtinction != this->MaximumExtinction || !request.SameAs(this->Request))
  {
    this->Budget = request;
    this->Error =
      GradientOpacityFromProperty(property, maximumExtinction, this->Function, this->Budget);
    approximated = this->Budget.Approximated;
    this->Source = source;
    this->SourceTime = source->GetMTime();
    this->MaximumExtinction = maximumExtinction;
    this->Request = request;
  }
  return this->Error;
}

std::string avos::UnsupportedPropertySettings(vtkVolumeProperty* property, int components)
{
  if (!property)
  {
    return std::string();
  }
  if (property->GetTransferFunctionMode() != vtkVolumeProperty::TF_1D)
  {
    return "A 2D transfer function (ParaView's Use 2D Transfer Function) is not supported: colour "
           "and opacity are functions of the scalar, the opacity scaled by the first component's "
           "gradient opacity (vtkVolumeProperty::SetGradientOpacity)";
  }
  for (int k = 1; k < components; ++k)
  {
    if (UsesGradientOpacity(property, k))
    {
      return "Gradient opacity is supported on the first component only: no gradient opacity "
             "for the others";
    }
  }
  if (property->GetUseClippedVoxelIntensity())
  {
    return "UseClippedVoxelIntensity (VTK's GPU mapper's fill of clipped voxels for gradients) is "
           "not supported: clipping cuts the rays exactly";
  }
  return std::string();
}

std::string avos::UnsupportedForComponents(
  vtkVolumeProperty* property, int components, bool composite)
{
  if (components < 2)
  {
    return std::string();
  }
  const std::string what = "scalars of " + std::to_string(components) + " components";
  if (!composite)
  {
    return "Scalars of " + std::to_string(components) +
      " components are rendered with the composite blend mode only, not with projections";
  }
  if (property && property->GetShade(0))
  {
    return "Cannot shade " + what +
      " (their gradients are not modelled); turn the property's Shade off";
  }
  if (property && UsesGradientOpacity(property, 0))
  {
    return "Gradient opacity is not supported with " + what +
      "; disable the property's gradient opacity";
  }
  return std::string();
}

avos::ConversionBudget avos::ConversionBudget::ForTolerance(
  double tolerance, double gain, double longestRay)
{
  ConversionBudget budget;
  budget.ColourGain = std::max(gain, 1.0);
  budget.Colour = ColourShare * tolerance / budget.ColourGain;
  budget.Opacity = OpacityShare * tolerance;
  budget.LongestRay = longestRay;
  return budget;
}

avos::ConversionBudget avos::ConversionBudget::ForGradientOpacity(
  double tolerance, double gain, double longestRay)
{
  ConversionBudget budget;
  budget.ColourGain = std::max(gain, 1.0);
  budget.Opacity = GradientShare * tolerance;
  budget.LongestRay = longestRay;
  return budget;
}

bool avos::ConversionBudget::SameAs(const ConversionBudget& other) const
{
  return this->Colour == other.Colour && this->Opacity == other.Opacity &&
    this->LongestRay == other.LongestRay && this->ColourGain == other.ColourGain;
}

bool avos::ModelPiecewiseInterval(vtkPiecewiseFunction* f, int index, NodeInterpolation& n)
{
  if (!f || index < 0 || index + 1 >= f->GetSize())
  {
    return false;
  }
  double node[4], next[4];
  f->GetNodeValue(index, node);
  f->GetNodeValue(index + 1, next);
  n.X1 = node[0];
  n.X2 = next[0];
  n.LogScale = f->GetUseLogScale() != 0;
  n.Midpoint = ClampMidpoint(node[2]);
  n.Sharpness = node[3];
  n.Space = avos::InterpolationSpace::RGB;
  for (auto& half : n.Ends)
  {
    std::fill(half[0], half[0] + 3, node[1]);
    std::fill(half[1], half[1] + 3, next[1]);
  }
  n.Clip[0] = std::min(node[1], next[1]);
  n.Clip[1] = std::max(node[1], next[1]);
  return true;
}

double avos::IntegrationTolerance(double tolerance, const ConversionBudget& budget)
{
  return tolerance - budget.Spent;
}

std::string avos::ApproximationNotice(int approximatedIntervals)
{
  if (approximatedIntervals <= 0)
  {
    return std::string();
  }
  return std::to_string(approximatedIntervals) +
    " interval(s) of the transfer function where VTK does not interpolate linearly (another "
    "colour space than RGB, a sharpness between 0.01 and 0.99, a log scale) are approximated by "
    "16 linear pieces each, without a proven bound: the tolerance is not certified there (only "
    "the piecewise method certifies such intervals, except in the CIEDE2000 colour space and "
    "for an opacity curve that reaches 1 in VTK's opacity model)";
}

namespace
{
// Component k's functions into `tf` (replaced): its colours (unless
// `colours`, RGB components: white) within b.Colour, then its opacity within
// opacityShare() (a pixel's share, ConvertOpacity; it may depend on what the
// colours spent); `sameScalar`: the colour and the opacity read the same
// scalar.
template <typename Share>
std::string ConvertComponent(vtkVolumeProperty* property, int k, bool extinction, double voxel,
  bool colours, bool sameScalar, Share&& opacityShare, TransferFunction& tf,
  avos::ConversionBudget& b)
{
  tf = TransferFunction();
  // The opacity model first: the opacity's certification takes its extinction.
  if (!extinction)
  {
    tf.SetOpacityModel(
      avos::numerics::OpacityModel::Alpha, property->GetScalarOpacityUnitDistance(k) / voxel);
  }
  std::string error;
  if (colours)
  {
    error = ConvertColor(property, k, sameScalar, tf, b);
  }
  else
  {
    tf.AddColorKnot(0.0, 1.0, 1.0, 1.0);
  }
  const double opacity = opacityShare();
  if (error.empty())
  {
    error = ConvertOpacity(property, k, opacity, tf, b);
  }
  if (error.empty())
  {
    error = tf.Validate();
  }
  tf.Finalize();
  return error;
}

// Resets what a conversion reports.
avos::ConversionBudget& Reset(avos::ConversionBudget* budget, avos::ConversionBudget& none)
{
  avos::ConversionBudget& b = budget ? *budget : none;
  b.CertifiedColour = b.CertifiedOpacity = b.Approximated = 0;
  b.Spent = 0.0;
  return b;
}
} // namespace

std::string avos::TransferFunctionFromProperty(vtkVolumeProperty* property, bool extinction,
  double voxel, TransferFunction& tf, ConversionBudget* budget)
{
  tf = TransferFunction();
  if (!property)
  {
    return "no volume property";
  }
  ConversionBudget none;
  ConversionBudget& b = Reset(budget, none);
  // The opacity takes its share and what the colours left.
  double opacity = 0.0;
  auto share = [&b, &opacity]()
  {
    const double colours = b.Colour * b.ColourGain;
    b.Spent = b.CertifiedColour > 0 ? colours : 0.0;
    opacity = b.Opacity + colours - b.Spent;
    return opacity;
  };
  const std::string error =
    ConvertComponent(property, 0, extinction, voxel, true, true, share, tf, b);
  b.Spent += b.CertifiedOpacity > 0 ? opacity : 0.0;
  return error;
}

std::string avos::MixtureFromProperty(vtkVolumeProperty* property, int components, int scalarType,
  bool extinction, double voxel, MixtureFunctions& out, ConversionBudget* budget)
{
  if (!property)
  {
    return "no volume property";
  }
  ConversionBudget none;
  ConversionBudget& b = Reset(budget, none);
  const bool independent = property->GetIndependentComponents() != 0;
  if (!independent && components != 2 && components != 4)
  {
    return "dependent components must be 2 (the colour of the first, the opacity of the second) "
           "or 4 (RGB and opacity), not " +
      std::to_string(components);
  }
  if (!independent && components == 4 && scalarType != VTK_UNSIGNED_CHAR)
  {
    return "4 dependent components (RGB and opacity) must be unsigned char, as VTK's mappers "
           "take them";
  }
  // Each component's opacity within the share over the weights' sum (at
  // least 1): their weighted extinctions' errors add up to the share. No
  // component takes another's unused colour share.
  double weights = 0.0;
  for (int k = 0; k < components && independent; ++k)
  {
    weights += std::max(property->GetComponentWeight(k), 0.0);
  }
  const double opacity = b.Opacity / std::max(weights, 1.0);
  std::string error;
  for (int k = 0; k < (independent ? components : 1) && error.empty(); ++k)
  {
    error = ConvertComponent(
      property, k, extinction, voxel, independent || components == 2, independent,
      [opacity]() { return opacity; }, out.Functions[static_cast<std::size_t>(k)], b);
    if (!error.empty() && independent)
    {
      error = "component " + std::to_string(k) + ": " + error;
    }
  }
  b.Spent = (b.CertifiedColour > 0 ? b.Colour * b.ColourGain : 0.0) +
    (b.CertifiedOpacity > 0 ? b.Opacity : 0.0);
  if (!error.empty())
  {
    return error;
  }
  if (independent)
  {
    const avos::numerics::TransferFunction<double>* functions[4];
    double w[4];
    for (int k = 0; k < components; ++k)
    {
      functions[k] = &out.Functions[static_cast<std::size_t>(k)];
      w[k] = property->GetComponentWeight(k);
    }
    out.Mixture.SetIndependent(components, functions, w);
  }
  else if (components == 2)
  {
    out.Mixture.SetColourOpacity(out.Functions[0]);
  }
  else
  {
    out.Mixture.SetRGBOpacity(out.Functions[0], 1.0 / 255.0);
  }
  return out.Mixture.Validate();
}
