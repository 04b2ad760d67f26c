// Gradient opacity through the whole mapper.
// - The ramp s = 50 + 40 z on [-1, 1]^3 of the closed-form tests, whose
//   gradient is 40 scalar units per world unit everywhere, and a gradient
//   opacity G with G(40) = 1/2. In the extinction model the extinction is
//   then tau / 2 everywhere: the image is the one of the opacity function
//   halved, without gradient opacity; in VTK's model, -ln(1 - alpha) / d /
//   2: the image of the unit distance doubled. Each pair rendered by the
//   reference (the piecewise method at 1e-10, with and without) within 2e-6
//   on every pixel (the float image), the piecewise method at 1e-3 and the
//   coupled rule at 1e-4 within 1e-3, and the image with G ignored more than
//   0.05 away (the test tells them apart). With the volume scaled by 2, the
//   gradient halves (world units): G(20) = 3/4.
// - Marschner-Lobb, whose gradient varies along every ray (the extinction
//   is enclosed, not exact): the piecewise method at 1e-2 and 1e-3 within
//   its tolerance of the reference on every pixel, unshaded and shaded.
// - A curved G (a sharpness moved): the piecewise method within its
//   tolerance of the image of G resampled densely, with no notice; the
//   other methods resample it with a notice said once per change of the
//   function, not every frame.
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkAnalyticVolumeSource.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeProperty.h"

#include "ObliqueScene.h"
#include "avosTestHelpers.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

namespace
{
// scalar, r, g, b, opacity
const double Knots[][5] = { { 10, 0.2, 0.2, 0.9, 0.0 }, { 30, 0.9, 0.6, 0.1, 0.02 },
  { 50, 0.1, 0.9, 0.3, 0.3 }, { 60, 1.0, 0.2, 0.2, 0.05 }, { 85, 0.9, 0.9, 0.9, 0.4 } };
constexpr int Size = 48;

std::vector<float> Render(
  obliquescene::Scene& scene, avostest::ExpectedErrors& errors, const char* what)
{
  scene.Window->Render();
  std::vector<float> values;
  auto* rgba =
    vtkFloatArray::SafeDownCast(scene.Mapper->GetRenderedImage()->GetPointData()->GetScalars());
  if (rgba && errors.None(what))
  {
    values.assign(rgba->GetPointer(0), rgba->GetPointer(0) + 4 * Size * Size);
  }
  return values;
}

double Apart(const std::vector<float>& a, const std::vector<float>& b)
{
  if (a.empty() || a.size() != b.size())
  {
    return 1e30;
  }
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    d = std::max(d, static_cast<double>(std::abs(a[i] - b[i])));
  }
  return d;
}
} // namespace

int TestAdaptiveVolumeMapperGradientOpacity(int, char*[])
{
  avostest::Checklist check;
  vtkNew<vtkAnalyticVolumeSource> source;
  obliquescene::MakeRamp(source, 50.0, 40.0);
  vtkNew<vtkVolumeProperty> property;
  obliquescene::FillProperty(Knots, property);
  obliquescene::Scene scene(source, property, Size);
  avostest::ExpectedErrors errors(scene.Mapper);
  const vtkSmartPointer<vtkPiecewiseFunction> opacity = property->GetScalarOpacity();
  // G: 1 at 0, 0 at 80: G(40) = 1/2, G(20) = 3/4.
  vtkNew<vtkPiecewiseFunction> gradient;
  gradient->AddPoint(0.0, 1.0);
  gradient->AddPoint(80.0, 0.0);

  for (const bool extinction : { true, false })
  {
    const std::string model = extinction ? "extinction model" : "VTK's model";
    extinction ? scene.Mapper->SetOpacityModelToExtinction() : scene.Mapper->SetOpacityModelToVTK();
    for (const double scale : { 1.0, 2.0 })
    {
      const double factor = 1.0 - 40.0 / scale / 80.0;
      scene.Volume->SetScale(scale);
      const std::string what = model + ", volume scaled by " + std::to_string(scale);
      // The equivalent without gradient opacity: the extinction times G.
      property->DisableGradientOpacityOn();
      vtkNew<vtkPiecewiseFunction> scaled;
      for (const auto& k : Knots)
      {
        scaled->AddPoint(k[0], extinction ? factor * k[4] : k[4]);
      }
      property->SetScalarOpacity(scaled);
      property->SetScalarOpacityUnitDistance(extinction ? 1.0 : 1.0 / factor);
      scene.Mapper->SetIntegrationMethodToReference();
      const std::vector<float> equivalent = Render(scene, errors, "equivalent");
      property->SetScalarOpacity(opacity);
      property->SetScalarOpacityUnitDistance(1.0);
      const std::vector<float> ignored = Render(scene, errors, "ignored");
      property->DisableGradientOpacityOff();
      property->SetGradientOpacity(gradient);
      const std::vector<float> reference = Render(scene, errors, "reference");
      scene.Mapper->SetIntegrationMethodToPiecewiseAdaptive();
      scene.Mapper->SetTolerance(1e-3);
      const std::vector<float> piecewise = Render(scene, errors, "piecewise");
      scene.Mapper->SetIntegrationMethodToAdaptiveCoupled();
      scene.Mapper->SetTolerance(1e-4);
      const std::vector<float> coupled = Render(scene, errors, "coupled");
      std::cout << what << ": reference " << Apart(reference, equivalent) << ", piecewise "
                << Apart(piecewise, equivalent) << ", coupled " << Apart(coupled, equivalent)
                << ", G ignored " << Apart(ignored, equivalent) << "\n";
      check(Apart(reference, equivalent) <= 2e-6, what + ": the reference is the equivalent's");
      check(Apart(piecewise, equivalent) <= 1e-3, what + ": the piecewise method within 1e-3");
      check(Apart(coupled, equivalent) <= 1e-3, what + ": the coupled rule within 1e-3");
      check(Apart(ignored, equivalent) > 0.05, what + ": G ignored is far from it");
      property->DisableGradientOpacityOn();
    }
  }
  scene.Volume->SetScale(1.0);

  // Marschner-Lobb in [0, 100]: G(|g|) varies along the rays.
  vtkNew<vtkAnalyticVolumeSource> lobb;
  lobb->SetFunctionToMarschnerLobb();
  lobb->SetDimensions(33, 33, 33);
  lobb->SetScalarScale(100.0);
  lobb->SetOutputScalarTypeToDouble();
  vtkNew<vtkVolumeProperty> lobbProperty;
  obliquescene::FillProperty(Knots, lobbProperty);
  lobbProperty->SetGradientOpacity(gradient);
  obliquescene::Scene varying(lobb, lobbProperty, Size);
  avostest::ExpectedErrors lobbErrors(varying.Mapper);
  for (const bool shade : { false, true })
  {
    lobbProperty->SetShade(shade);
    const std::string what = shade ? "Marschner-Lobb, shaded" : "Marschner-Lobb";
    varying.Mapper->SetIntegrationMethodToReference();
    const std::vector<float> reference = Render(varying, lobbErrors, "reference");
    for (const double eps : { 1e-2, 1e-3 })
    {
      varying.Mapper->SetIntegrationMethodToPiecewiseAdaptive();
      varying.Mapper->SetTolerance(eps);
      const std::vector<float> piecewise = Render(varying, lobbErrors, "piecewise");
      std::cout << what << ", eps " << eps << ": piecewise " << Apart(piecewise, reference) << "\n";
      check(Apart(piecewise, reference) <= eps + 1e-6,
        what + ": the piecewise method within its tolerance of the reference");
    }
    lobbProperty->DisableGradientOpacityOn();
    const std::vector<float> ignored = Render(varying, lobbErrors, "G ignored");
    lobbProperty->DisableGradientOpacityOff();
    std::cout << what << ": G ignored " << Apart(ignored, reference) << "\n";
    check(Apart(ignored, reference) > 0.05, what + ": G ignored is far from it");
  }

  // A curved gradient opacity function on Marschner-Lobb, certified by the
  // piecewise method (no notice), against the piecewise method at 1e-4 with
  // G resampled at 2001 magnitudes: within 1.1e-5 of VTK's G (h^2 / 8 max
  // |G''|, h = 0.04, max |G''| < 0.053 per squared scalar unit), so within
  // 1e-4 + 2e-5 of the exact image (the extinction tau G moves by at most
  // 0.51 1.1e-5 per world unit, over rays shorter than 1.8 world units: a
  // pixel by at most 2 0.51 1.8 1.1e-5).
  vtkNew<vtkPiecewiseFunction> curved;
  curved->AddPoint(0.0, 1.0, 0.5, 0.5);
  curved->AddPoint(80.0, 0.0);
  vtkNew<vtkPiecewiseFunction> dense;
  for (int i = 0; i <= 2000; ++i)
  {
    dense->AddPoint(80.0 * i / 2000.0, curved->GetValue(80.0 * i / 2000.0));
  }
  lobbProperty->SetShade(false);
  lobbProperty->SetGradientOpacity(dense);
  varying.Mapper->SetIntegrationMethodToPiecewiseAdaptive();
  varying.Mapper->SetTolerance(1e-4);
  const std::vector<float> oracle = Render(varying, lobbErrors, "resampled G at 1e-4");
  lobbProperty->SetGradientOpacity(curved);
  std::vector<float> certified;
  for (const double eps : { 1e-2, 1e-3 })
  {
    varying.Mapper->SetTolerance(eps);
    certified = Render(varying, lobbErrors, "curved G, piecewise");
    std::cout << "curved G, eps " << eps << ": piecewise " << Apart(certified, oracle) << "\n";
    check(Apart(certified, oracle) <= eps + 1.3e-4,
      "curved G: the piecewise method within its tolerance");
  }
  lobbProperty->SetGradientOpacity(gradient);
  check(Apart(certified, Render(varying, lobbErrors, "linear G")) > 0.01,
    "curved G: another image than the linear G's");

  // The other methods resample it with a notice, said once per change of
  // the function, not every frame.
  property->DisableGradientOpacityOff();
  property->SetGradientOpacity(curved);
  scene.Mapper->SetIntegrationMethodToRiemann();
  scene.Window->Render();
  check(errors.CheckWarning("curved G", "approximated"), "a curved G is resampled with a notice");
  const std::vector<float> before = Render(scene, errors, "curved G again");
  check(!before.empty(), "the notice is said once, not every frame");
  curved->AddPoint(80.0, 0.5);
  scene.Window->Render();
  check(errors.CheckWarning("curved G changed", "approximated"),
    "a changed function is converted again");
  check(Apart(Render(scene, errors, "changed G again"), before) > 0.01,
    "the image follows the changed function");

  // Refused where it is not integrated.
  scene.Mapper->SetIntegrationMethodToRiemann();
  scene.Mapper->SetBlendModeToMaximumIntensity();
  scene.Window->Render();
  check(errors.Check("projection", "Gradient opacity is not supported with projections"),
    "projections refuse gradient opacity");
  return check.Result();
}
