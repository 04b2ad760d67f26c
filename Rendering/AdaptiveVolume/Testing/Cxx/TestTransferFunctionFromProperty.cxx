// avos::TransferFunctionFromProperty against VTK's own evaluation
// (vtkPiecewiseFunction::GetValue, vtkColorTransferFunction::GetColor) at
// 20,000 scalars per function: where VTK interpolates piecewise linearly (a
// moved midpoint with sharpness 0, a step with sharpness 1, in any colour
// space for the step) the knots reproduce it to rounding and nothing is
// reported approximated; a Hermite curve or an HSV interpolation is
// reported; VTK's rounding above 1 is clamped, a real excess refused.
#include "avosTransferFunctionFromProperty.h"

#include "vtkColorTransferFunction.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"

#include "avosTestHelpers.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace
{
avostest::Checklist Expect;

using TF = avos::numerics::TransferFunction<double>;

// The largest of `error(s)` over 20,001 scalars of [lo, hi], away from the
// given jump positions (where either side's value is right).
template <typename Error>
double Largest(double lo, double hi, std::initializer_list<double> jumps, Error&& error)
{
  double worst = 0.0;
  for (int i = 0; i <= 20000; ++i)
  {
    const double s = lo + (hi - lo) * i / 20000.0;
    if (std::none_of(jumps.begin(), jumps.end(), [s](double j) { return std::abs(s - j) < 1e-9; }))
    {
      worst = std::max(worst, error(s));
    }
  }
  return worst;
}

// The knots against VTK's own evaluation.
double OpacityError(const TF& tf, vtkPiecewiseFunction* f, double lo, double hi,
  std::initializer_list<double> jumps = {})
{
  return Largest(
    lo, hi, jumps, [&](double s) { return std::abs(tf.GetOpacityValue(s) - f->GetValue(s)); });
}

double ColourError(const TF& tf, vtkColorTransferFunction* f, double lo, double hi,
  std::initializer_list<double> jumps = {})
{
  return Largest(lo, hi, jumps,
    [&](double s)
    {
      double rgb[3];
      f->GetColor(s, rgb);
      const auto c = tf.GetColor(s);
      return std::max(
        { std::abs(c[0] - rgb[0]), std::abs(c[1] - rgb[1]), std::abs(c[2] - rgb[2]) });
    });
}

struct Case
{
  vtkNew<vtkColorTransferFunction> Colour;
  vtkNew<vtkPiecewiseFunction> Opacity;
  vtkNew<vtkVolumeProperty> Property;
  TF Function;
  int Approximated = -1;

  Case()
  {
    this->Property->SetColor(this->Colour);
    this->Property->SetScalarOpacity(this->Opacity);
  }

  std::string Convert()
  {
    return avos::TransferFunctionFromProperty(
      this->Property, true, 1.0, this->Function, &this->Approximated);
  }
};
} // namespace

int TestTransferFunctionFromProperty(int, char*[])
{
  {
    // Moved midpoints with sharpness 0: a kink, taken exactly.
    Case c;
    c.Opacity->AddPoint(0.0, 0.0, 0.3, 0.0);
    c.Opacity->AddPoint(10.0, 0.8, 0.85, 0.0);
    c.Opacity->AddPoint(30.0, 0.1);
    c.Colour->AddRGBPoint(0.0, 0.0, 0.2, 1.0, 0.2, 0.0);
    c.Colour->AddRGBPoint(30.0, 1.0, 0.6, 0.0);
    Expect(c.Convert().empty(), "midpoints convert");
    Expect(c.Approximated == 0, "midpoints are exact, nothing approximated");
    Expect(OpacityError(c.Function, c.Opacity, -5.0, 35.0) < 1e-12, "opacity kinks as VTK's");
    Expect(ColourError(c.Function, c.Colour, -5.0, 35.0) < 1e-12, "colour kinks as VTK's");
  }
  {
    // Sharpness 1: a step at the midpoint, in RGB and in HSV space.
    Case c;
    c.Opacity->AddPoint(0.0, 0.1, 0.7, 1.0);
    c.Opacity->AddPoint(10.0, 0.9);
    c.Colour->SetColorSpaceToHSV();
    c.Colour->AddRGBPoint(0.0, 1.0, 0.0, 0.0, 0.25, 1.0);
    c.Colour->AddRGBPoint(10.0, 0.0, 0.0, 1.0);
    Expect(c.Convert().empty(), "steps convert");
    Expect(c.Approximated == 0, "steps are exact, in HSV space too");
    Expect(OpacityError(c.Function, c.Opacity, -1.0, 11.0, { 7.0 }) < 1e-12, "opacity step");
    Expect(ColourError(c.Function, c.Colour, -1.0, 11.0, { 2.5 }) < 1e-12, "HSV colour step");
  }
  {
    // A Hermite curve and an HSV interpolation: approximated, and said so.
    Case c;
    c.Opacity->AddPoint(0.0, 0.0, 0.5, 0.5);
    c.Opacity->AddPoint(10.0, 1.0);
    c.Colour->SetColorSpaceToHSV();
    c.Colour->AddRGBPoint(0.0, 1.0, 0.0, 0.0);
    c.Colour->AddRGBPoint(10.0, 0.0, 0.0, 1.0);
    Expect(c.Convert().empty(), "curves convert");
    Expect(c.Approximated == 2, "the curve and the HSV interval are reported approximated");
    Expect(avos::ApproximationNotice(c.Approximated).find("2 interval(s)") == 0 &&
        avos::ApproximationNotice(0).empty(),
      "the classes' warning names the count, and there is none without approximation");
  }
  {
    // HSV interpolation with a colour tolerance: linearised within it, a
    // proven bound, on intervals with the hue wrapped and not, moved
    // midpoints, and greys (hue 0).
    Case c;
    c.Opacity->AddPoint(0.0, 0.1);
    c.Opacity->AddPoint(100.0, 0.5);
    c.Colour->SetColorSpaceToHSV();
    c.Colour->AddRGBPoint(0.0, 1.0, 0.0, 0.0);
    c.Colour->AddRGBPoint(20.0, 0.1, 0.2, 1.0, 0.3, 0.0); // the short way: through magenta
    c.Colour->AddRGBPoint(45.0, 0.9, 0.8, 0.1);
    c.Colour->AddRGBPoint(60.0, 0.5, 0.5, 0.5, 0.8, 0.0); // a grey
    c.Colour->AddRGBPoint(100.0, 0.0, 0.6, 0.3);
    for (double tolerance : { 1e-3, 1e-4, 1e-5 })
    {
      int certified = 0;
      Expect(avos::TransferFunctionFromProperty(
               c.Property, true, 1.0, c.Function, &c.Approximated, tolerance, &certified)
               .empty(),
        "HSV converts with a colour tolerance");
      Expect(certified == 4 && c.Approximated == 0, "every HSV interval certified");
      Expect(ColourError(c.Function, c.Colour, -5.0, 105.0) <= tolerance,
        "HSV colours within the colour tolerance of VTK's");
      Expect(c.Function.GetKnotValues().size() < 20000, "a bounded number of knots");
    }
  }
  {
    // VTK's rounding above 1 is clamped; a real excess is refused.
    Case c;
    c.Opacity->AddPoint(0.0, 0.0);
    c.Opacity->AddPoint(10.0, 1.0);
    c.Colour->AddRGBPoint(0.0, 1.0 + 2.2e-16, 0.5, 0.0);
    c.Colour->AddRGBPoint(10.0, 0.0, 0.5, 1.0);
    Expect(c.Convert().empty(), "a colour of 1 + 2.2e-16 is clamped, not refused");
    Expect(c.Function.GetColor(0.0)[0] == 1.0, "clamped onto 1");
    c.Colour->AddRGBPoint(5.0, 1.0 + 1e-6, 0.5, 0.5);
    Expect(!c.Convert().empty(), "a colour of 1 + 1e-6 is refused");
  }
  return Expect.Result();
}
