// avos::TransferFunctionFromProperty against VTK's own evaluation
// (vtkPiecewiseFunction::GetValue, vtkColorTransferFunction::GetColor) at
// 20,000 scalars per function: where VTK interpolates piecewise linearly (a
// moved midpoint with sharpness 0, a step with sharpness 1, in any colour
// space for the step, the Step space) the knots reproduce it to rounding and
// nothing is reported approximated; with a colour tolerance, every curved
// colour interval (HSV, Lab, Diverging, Hermite curves, a log scale) is
// within it of VTK's colours; without one, or in the CIEDE2000 space, such
// intervals are reported approximated; opacity curves in both opacity
// models keep the extinction budget's hypothesis and a gray curve its
// colour budget; outside the nodes the colours and
// opacities are VTK's (clamped, range colours, none without clamping);
// VTK's rounding above 1 is clamped, a real excess refused; ParaView's
// discretized colour maps are taken as volume mappers take them
// (continuous).
#include "avosNodeInterpolation.h"
#include "avosTransferFunctionFromProperty.h"

#include "avos/numerics/Linearization.h"

#include "vtkColorTransferFunction.h"
#include "vtkDiscretizableColorTransferFunction.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolumeProperty.h"

#include "avosTestHelpers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

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
  avos::ConversionBudget Budget;
  int Approximated = -1;

  Case()
  {
    this->Property->SetColor(this->Colour);
    this->Property->SetScalarOpacity(this->Opacity);
  }

  // The extinction model (tau per voxel unit) unless `alpha`, VTK's.
  std::string Convert(avos::ConversionBudget budget = {}, bool alpha = false)
  {
    this->Budget = budget;
    const std::string error = avos::TransferFunctionFromProperty(
      this->Property, !alpha, 1.0, this->Function, &this->Budget);
    this->Approximated = this->Budget.Approximated;
    return error;
  }
};

avos::ConversionBudget ColourBudget(double tolerance)
{
  avos::ConversionBudget b;
  b.Colour = tolerance;
  return b;
}
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
    // Every colour space and curve VTK offers, certified within the colour
    // tolerance: HSV both ways round the hue, Lab, ParaView's default Cool
    // to Warm (Diverging, through white), a diverging map from a grey (its
    // hue adjusted), Hermite curves in RGB, HSV and Lab, and a log scale.
    struct Map
    {
      const char* Name;
      int Space;
      bool Log;
      std::vector<std::array<double, 6>> Nodes; // x, r, g, b, midpoint, sharpness
    };
    const std::vector<Map> maps = {
      { "HSV", VTK_CTF_HSV, false,
        { { 0, 1, 0, 0, 0.5, 0 }, { 20, 0.1, 0.2, 1, 0.3, 0 }, { 60, 0.9, 0.8, 0.1, 0.5, 0 },
          { 100, 0.5, 0.5, 0.5, 0.5, 0 } } },
      { "Lab", VTK_CTF_LAB, false,
        { { 0, 0.1, 0.1, 0.9, 0.5, 0 }, { 40, 1, 1, 0.2, 0.7, 0 },
          { 100, 0.9, 0.1, 0.1, 0.5, 0 } } },
      { "Cool to Warm", VTK_CTF_DIVERGING, false,
        { { 0, 0.231373, 0.298039, 0.752941, 0.5, 0 },
          { 100, 0.705882, 0.0156863, 0.14902, 0.5, 0 } } },
      { "diverging from grey", VTK_CTF_DIVERGING, false,
        { { 0, 0.4, 0.4, 0.4, 0.5, 0 }, { 100, 0.9, 0.2, 0.1, 0.5, 0 } } },
      { "RGB Hermite", VTK_CTF_RGB, false,
        { { 0, 0, 0, 1, 0.2, 0.5 }, { 50, 1, 0.5, 0, 0.5, 0.05 }, { 100, 0, 1, 0.3, 0.5, 0 } } },
      { "HSV Hermite", VTK_CTF_HSV, false,
        { { 0, 1, 0, 0, 0.6, 0.8 }, { 100, 0, 0.3, 1, 0.5, 0 } } },
      { "Lab Hermite", VTK_CTF_LAB, false,
        { { 0, 0.1, 0.1, 0.9, 0.5, 0.3 }, { 100, 0.9, 0.1, 0.1, 0.5, 0 } } },
      { "log scale", VTK_CTF_RGB, true,
        { { 1, 0, 0, 1, 0.5, 0 }, { 30, 0.2, 1, 0.2, 0.3, 0 }, { 1000, 1, 0.5, 0, 0.5, 0 } } },
    };
    for (const Map& map : maps)
    {
      Case c;
      c.Opacity->AddPoint(0.0, 0.1);
      c.Opacity->AddPoint(1000.0, 0.5);
      c.Colour->SetColorSpace(map.Space);
      c.Colour->SetScale(map.Log ? VTK_CTF_LOG10 : VTK_CTF_LINEAR);
      for (const auto& n : map.Nodes)
      {
        c.Colour->AddRGBPoint(n[0], n[1], n[2], n[3], n[4], n[5]);
      }
      // The model the bound is proven on is VTK's function: evaluated on
      // plain numbers it gives GetColor to rounding inside every interval.
      double modelError = 0.0;
      for (int i = 0; i + 1 < static_cast<int>(map.Nodes.size()); ++i)
      {
        avos::NodeInterpolation n;
        Expect(avos::ModelColourInterval(c.Colour, i, n), std::string(map.Name) + " is modelled");
        for (int k = 1; k <= 2000; ++k)
        {
          const double x = std::min(n.X2, n.X1 + (n.X2 - n.X1) * k / 2000.0);
          double rgb[3], model[3];
          c.Colour->GetColor(x, rgb);
          avos::interpolation::Evaluate(n, x, model);
          for (int ch = 0; ch < 3; ++ch)
          {
            modelError = std::max(modelError, std::abs(rgb[ch] - model[ch]));
          }
        }
      }
      Expect(modelError < 1e-12, std::string(map.Name) + ": the model is GetColor");
      const double lo = map.Nodes.front()[0], hi = map.Nodes.back()[0];
      for (double tolerance : { 1e-3, 1e-4, 1e-5 })
      {
        const std::string name = std::string(map.Name) + " at " + std::to_string(tolerance);
        Expect(c.Convert(ColourBudget(tolerance)).empty(), name + " converts");
        Expect(c.Budget.CertifiedColour == static_cast<int>(map.Nodes.size()) - 1 &&
            c.Budget.CertifiedOpacity == 0 && c.Approximated == 0,
          name + ": every interval certified");
        Expect(ColourError(c.Function, c.Colour, lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo)) <=
            tolerance,
          name + ": within the tolerance of VTK's colours");
        Expect(c.Function.GetKnotValues().size() < 20000, name + ": a bounded number of knots");
      }
      Expect(c.Convert().empty() && c.Approximated == static_cast<int>(map.Nodes.size()) - 1,
        std::string(map.Name) + ": resampled and reported without a tolerance");
    }
  }
  {
    // ParaView's default colour map as ParaView builds it: Cool to Warm
    // through white in a vtkDiscretizableColorTransferFunction discretized
    // to 256 colours. Volume mappers tabulate the continuous function
    // (GetTable), GetColor returns the steps: the conversion takes the
    // continuous one, certified, where the steps are 1/512 of the range away.
    vtkNew<vtkDiscretizableColorTransferFunction> paraview;
    paraview->SetColorSpaceToDiverging();
    paraview->AddRGBPoint(0.0, 0.231373, 0.298039, 0.752941);
    paraview->AddRGBPoint(127.5, 0.865003, 0.865003, 0.865003);
    paraview->AddRGBPoint(255.0, 0.705882, 0.0156863, 0.14902);
    paraview->DiscretizeOn();
    paraview->SetNumberOfValues(256);
    paraview->Build();
    Case c;
    c.Property->SetColor(paraview);
    c.Opacity->AddPoint(0.0, 0.0);
    c.Opacity->AddPoint(255.0, 1.0);
    Expect(c.Convert(ColourBudget(1e-4)).empty(), "ParaView's colour map converts");
    Expect(c.Budget.CertifiedColour == 2 && c.Approximated == 0,
      "ParaView's discretized colour map is certified (its continuous function)");
    // Off the nodes themselves, where VTK gives the node's own colour, not
    // the interpolation's limit (1.3e-4 apart at 255 here: one point, which
    // no integral sees).
    double continuous = 0.0, steps = 0.0;
    for (int i = 0; i < 20000; ++i)
    {
      const double s = 255.0 * (i + 0.5) / 20000.0;
      double smooth[3], stepped[3];
      paraview->vtkColorTransferFunction::GetColor(s, smooth);
      paraview->GetColor(s, stepped);
      const auto ours = c.Function.GetColor(s);
      for (int ch = 0; ch < 3; ++ch)
      {
        continuous = std::max(continuous, std::abs(ours[ch] - smooth[ch]));
        steps = std::max(steps, std::abs(stepped[ch] - smooth[ch]));
      }
    }
    Expect(continuous <= 1e-4, "within the tolerance of the continuous colours");
    Expect(steps > 1e-3, "GetColor's steps differ from them (the test can tell)");
  }
  {
    // CIEDE2000 (a path searched through L*a*b*) is not modelled: reported.
    Case c;
    c.Opacity->AddPoint(0.0, 0.1);
    c.Colour->SetColorSpaceToLabCIEDE2000();
    c.Colour->AddRGBPoint(0.0, 0.2, 0.3, 0.8);
    c.Colour->AddRGBPoint(10.0, 0.7, 0.0, 0.1);
    Expect(
      c.Convert(ColourBudget(1e-3)).empty() && c.Budget.CertifiedColour == 0 && c.Approximated == 1,
      "CIEDE2000 is reported approximated");
    avos::NodeInterpolation n;
    Expect(!avos::ModelColourInterval(c.Colour, 0, n) && !avos::ModelColourInterval(c.Colour, 1, n),
      "CIEDE2000 is not modelled, and the last node starts no interval");
  }
  {
    // Opacity curves (Hermite, a log scale) in both opacity models, and a
    // gray Hermite curve: certified within their budgets. The opacity's
    // converted extinction keeps the extinction budget's hypothesis,
    // |tau~ - tau| <= Relative min(tau, tau~) + Absolute, at 20,001 scalars
    // (so every pixel stays within budget.Opacity, ExtinctionBudget); the
    // gray within budget.Colour of VTK's. An alpha-model curve that reaches
    // an opacity of 1 cannot be certified: resampled and reported.
    struct Curve
    {
      const char* Name;
      bool Alpha, Log;
      std::vector<std::array<double, 4>> Nodes; // x, value, midpoint, sharpness
      bool Certifiable;
    };
    const std::vector<Curve> curves = {
      { "alpha Hermite", true, false,
        { { 0, 0, 0.3, 0.5 }, { 40, 0.8, 0.5, 0.2 }, { 100, 0.3, 0.5, 0 } }, true },
      { "alpha log scale", true, true, { { 1, 0.05, 0.5, 0 }, { 1000, 0.9, 0.5, 0 } }, true },
      { "alpha Hermite up to 1", true, false, { { 0, 0, 0.5, 0.4 }, { 100, 1.0, 0.5, 0 } }, false },
      { "extinction Hermite", false, false,
        { { 0, 0, 0.6, 0.9 }, { 50, 3.0, 0.5, 0.01 }, { 100, 1.0, 0.5, 0 } }, true },
    };
    for (const Curve& curve : curves)
    {
      Case c;
      c.Colour->AddRGBPoint(0.0, 0.2, 0.4, 1.0);
      c.Property->SetScalarOpacityUnitDistance(2.0);
      c.Opacity->SetUseLogScale(curve.Log);
      for (const auto& n : curve.Nodes)
      {
        c.Opacity->AddPoint(n[0], n[1], n[2], n[3]);
      }
      double modelError = 0.0;
      for (int i = 0; i + 1 < static_cast<int>(curve.Nodes.size()); ++i)
      {
        avos::NodeInterpolation n;
        Expect(
          avos::ModelPiecewiseInterval(c.Opacity, i, n), std::string(curve.Name) + " modelled");
        for (int k = 1; k <= 2000; ++k)
        {
          const double x = std::min(n.X2, n.X1 + (n.X2 - n.X1) * k / 2000.0);
          double model[3];
          avos::interpolation::Evaluate(n, x, model);
          modelError = std::max(modelError, std::abs(model[0] - c.Opacity->GetValue(x)));
        }
      }
      Expect(modelError < 1e-12, std::string(curve.Name) + ": the model is GetValue");
      const double lo = curve.Nodes.front()[0], hi = curve.Nodes.back()[0];
      for (double tolerance : { 1e-2, 1e-3 })
      {
        const std::string name = std::string(curve.Name) + " at " + std::to_string(tolerance);
        const auto budget = avos::ConversionBudget::ForTolerance(tolerance, 1.0, 300.0);
        Expect(c.Convert(budget, curve.Alpha).empty(), name + " converts");
        const int intervals = static_cast<int>(curve.Nodes.size()) - 1;
        if (!curve.Certifiable)
        {
          Expect(c.Budget.CertifiedOpacity == 0 && c.Approximated == 1,
            name + ": reported approximated, not certified");
          continue;
        }
        Expect(c.Budget.CertifiedOpacity == intervals && c.Approximated == 0,
          name + ": every interval certified");
        // The colours are exact: the opacity takes their share too.
        const double pixel = budget.Opacity + budget.Colour;
        Expect(
          std::abs(avos::IntegrationTolerance(tolerance, c.Budget) - (tolerance - pixel)) < 1e-15,
          name + ": the rays integrate to the rest of the tolerance");
        const auto share = avos::numerics::ExtinctionBudget<double>::Within(pixel, 300.0, 1.0);
        const TF& f = c.Function;
        Expect(Largest(lo, hi, {},
                 [&](double s)
                 {
                   const double converted = f.ToExtinction(f.GetOpacityValue(s));
                   const double exact = f.ToExtinction(c.Opacity->GetValue(s));
                   return std::abs(converted - exact) -
                     share.Relative * std::min(converted, exact) - share.Absolute;
                 }) <= 1e-12,
          name + ": the extinction within the budget's hypothesis");
        Expect(f.GetKnotValues().size() < 20000, name + ": a bounded number of knots");
      }
      Expect(c.Convert({}, curve.Alpha).empty() &&
          c.Approximated == static_cast<int>(curve.Nodes.size()) - 1,
        std::string(curve.Name) + ": resampled and reported without a budget");
    }
    // Gradient opacity curves (Hermite, a log scale): the extinction tau G,
    // tau up to the largest 2.5, within the extinction budget's hypothesis of
    // the gradient share at 20,001 magnitudes (G's own chord error within
    // Relative G + Absolute / 2.5).
    for (const bool log : { false, true })
    {
      const std::string name = log ? "gradient opacity, log scale" : "gradient opacity, Hermite";
      vtkNew<vtkPiecewiseFunction> g;
      g->SetUseLogScale(log);
      g->AddPoint(1.0, 1.0, 0.3, 0.6);
      g->AddPoint(40.0, 0.2, 0.5, 0.3);
      g->AddPoint(80.0, 0.0);
      Case c;
      c.Opacity->AddPoint(0.0, 0.3);
      c.Property->SetGradientOpacity(g);
      const double largest = 2.5;
      for (double tolerance : { 1e-2, 1e-3 })
      {
        const std::string at = name + " at " + std::to_string(tolerance);
        avos::ConversionBudget budget =
          avos::ConversionBudget::ForGradientOpacity(tolerance, 1.0, 300.0);
        Expect(budget.Opacity == avos::GradientShare * tolerance, at + ": its share");
        TF f;
        Expect(avos::GradientOpacityFromProperty(c.Property, largest, f, budget).empty(),
          at + " converts");
        Expect(budget.CertifiedOpacity == 2 && budget.Approximated == 0 &&
            budget.Spent == budget.Opacity,
          at + ": every interval certified, its share spent");
        const auto share =
          avos::numerics::ExtinctionBudget<double>::Within(budget.Opacity, 300.0, 1.0);
        Expect(Largest(1.0, 80.0, {},
                 [&](double x)
                 {
                   const double converted = largest * f.GetOpacityValue(x);
                   const double exact = largest * g->GetValue(x);
                   return std::abs(converted - exact) -
                     share.Relative * std::min(converted, exact) - share.Absolute;
                 }) <= 1e-12,
          at + ": tau G within the budget's hypothesis");
      }
      avos::ConversionBudget none;
      TF f;
      Expect(avos::GradientOpacityFromProperty(c.Property, largest, f, none).empty() &&
          none.Approximated == 2 && none.Spent == 0.0,
        name + ": resampled and reported without a budget");
    }
    // A gray Hermite curve, a colour: within budget.Colour of VTK's gray.
    Case c;
    c.Opacity->AddPoint(0.0, 0.3);
    vtkNew<vtkPiecewiseFunction> gray;
    gray->AddPoint(0.0, 0.1, 0.3, 0.6);
    gray->AddPoint(10.0, 0.9);
    c.Property->SetColor(gray);
    Expect(
      c.Convert(ColourBudget(1e-4)).empty() && c.Budget.CertifiedColour == 1 && c.Approximated == 0,
      "a gray Hermite curve is certified");
    Expect(
      Largest(0.0, 10.0, {},
        [&](double s) { return std::abs(c.Function.GetColor(s)[0] - gray->GetValue(s)); }) <= 1e-4,
      "the gray within the colour budget of VTK's");
    // Curved colours and a curved opacity: each certifies within its own
    // share, and the rays integrate to the quarter left.
    Case both;
    both.Colour->SetColorSpaceToHSV();
    both.Colour->AddRGBPoint(0.0, 1.0, 0.0, 0.0);
    both.Colour->AddRGBPoint(10.0, 0.0, 0.0, 1.0);
    both.Opacity->AddPoint(0.0, 0.0, 0.5, 0.5);
    both.Opacity->AddPoint(10.0, 0.6);
    Expect(both.Convert(avos::ConversionBudget::ForTolerance(1e-3, 1.0, 300.0)).empty() &&
        both.Budget.CertifiedColour == 1 && both.Budget.CertifiedOpacity == 1 &&
        std::abs(avos::IntegrationTolerance(1e-3, both.Budget) - 0.25e-3) < 1e-15,
      "colours and opacity certified within their own shares, the rays to the rest");
  }
  {
    // The Step space: each interval takes its second node's colour, exactly.
    Case c;
    c.Opacity->AddPoint(0.0, 0.1);
    c.Colour->SetColorSpaceToStep();
    c.Colour->AddRGBPoint(0.0, 1.0, 0.0, 0.0);
    c.Colour->AddRGBPoint(3.0, 0.0, 1.0, 0.0);
    c.Colour->AddRGBPoint(10.0, 0.0, 0.0, 1.0, 0.4, 1.0);
    c.Colour->AddRGBPoint(20.0, 1.0, 1.0, 0.0);
    Expect(c.Convert().empty() && c.Approximated == 0, "the Step space converts exactly");
    Expect(ColourError(c.Function, c.Colour, -5.0, 25.0, { 0.0, 3.0, 10.0, 14.0 }) < 1e-12,
      "the Step space as VTK's, a sharpness-1 node's step at its midpoint too");
  }
  {
    // Outside the nodes: range colours with clamping, black without; the
    // opacity 0 without clamping.
    Case c;
    c.Opacity->AddPoint(2.0, 0.3);
    c.Opacity->AddPoint(8.0, 0.6);
    c.Colour->AddRGBPoint(2.0, 0.2, 0.4, 0.6);
    c.Colour->AddRGBPoint(8.0, 0.8, 0.6, 0.4);
    c.Colour->UseBelowRangeColorOn();
    c.Colour->SetBelowRangeColor(1.0, 0.0, 1.0);
    Expect(c.Convert().empty(), "range colours convert");
    Expect(ColourError(c.Function, c.Colour, 0.0, 10.0, { 2.0, 8.0 }) < 1e-12,
      "the below-range colour and the held end colour, as VTK's");
    c.Colour->ClampingOff();
    c.Opacity->ClampingOff();
    Expect(c.Convert().empty(), "unclamped functions convert");
    Expect(ColourError(c.Function, c.Colour, 0.0, 10.0, { 2.0, 8.0 }) < 1e-12 &&
        OpacityError(c.Function, c.Opacity, 0.0, 10.0, { 2.0, 8.0 }) < 1e-12,
      "black and transparent outside the nodes without clamping, as VTK's");
    c.Opacity->UseLogScaleOn();
    c.Opacity->AddPoint(0.0, 0.1);
    Expect(c.Convert().find("log scale") != std::string::npos,
      "a log-scale opacity with a node at 0 is refused");
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
