// VoS^M* shaded (the property's Shade under the renderer's lights) with a
// known answer: the volume is s = 1 - z on [-1, 1]^3, the transfer function
// a constant medium where s > 0.8 (z < 0.2) and transparent elsewhere, the
// isosurface the plane z = 0.2, seen from +z with a parallel camera. The
// gradient is (0, 0, -1) everywhere, so each ray's lit colour is one
// constant L (Blinn-Phong under a directional scene light and the headlight,
// two-sided) and a vertex's colour is L (1 - e^{-tau 1.2 / voxel}), its
// opacity 1 - e^{-tau 1.2 / voxel}: the chord from the plane down to z = -1.
// With a gradient opacity G, |grad s| = 1 per world unit and G(1) = 1/2
// halves tau. Changing a light with the camera still recasts the rays;
// unshaded, the colour is c (1 - e^{...}).
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolumeOnSurfaceMapper.h"
#include "vtkVolumeProperty.h"

#include "VoSKnownAnswer.h"
#include "avosTestHelpers.h"

#include <algorithm>
#include <cmath>

int TestVolumeOnSurfaceShading(int, char*[])
{
  avostest::Checklist Expect;
  const int n = 33;
  const double voxel = 2.0 / (n - 1), tau = 0.05, chord = 1.2;
  const double color[3] = { 0.3, 0.4, 0.2 };
  const auto volume = vosknown::FieldOnCube(n, [](double, double, double z) { return 1.0 - z; });
  // A step (sharpness 1) at the midpoint of [0.78, 0.82]: s = 0.8.
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.78, 0.0, 0.5, 1.0);
  opacity->AddPoint(0.82, tau);
  opacity->AddPoint(2.0, tau);
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0.0, color[0], color[1], color[2]);
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->SetColor(ctf);
  property->SetScalarOpacity(opacity);
  const double ka = 0.1, kd = 0.7, ks = 0.2, power = 16.0;
  property->SetAmbient(ka);
  property->SetDiffuse(kd);
  property->SetSpecular(ks);
  property->SetSpecularPower(power);
  property->ShadeOn();

  vtkNew<vtkRenderer> renderer;
  vtkVolumeOnSurfaceMapper* mapper = vosknown::MapperOnIsosurface(volume, property, 0.8, renderer);
  vtkNew<vtkLight> key, head;
  vosknown::AddKeyAndHeadlight(renderer, key, head);
  vtkNew<vtkRenderWindow> window;
  vosknown::ViewFromAbove(window, renderer, 64);

  // The lit colour: n = (0, 0, -1), the viewer and the headlight along +z,
  // the key light along (1, 0, 2) / sqrt 5.
  auto lit = [&](int c, double intensity)
  {
    const double nl = 2.0 / std::sqrt(5.0);
    const double hz = (2.0 / std::sqrt(5.0) + 1.0) /
      std::sqrt(1.0 / 5.0 + std::pow(2.0 / std::sqrt(5.0) + 1.0, 2.0));
    const double keyColour[3] = { 1.0, 0.9, 0.8 };
    const double D = intensity * keyColour[c];
    const double L =
      ka * color[c] + kd * color[c] * (D * nl + 1.0) + ks * (D * std::pow(hz, power) + 1.0);
    return std::min(std::max(L, 0.0), 1.0);
  };
  // The largest difference of an inner vertex's 8-bit RGBA from the closed
  // form (`shaded`: with L, otherwise with the colour itself; the extinction
  // tau times `factor`).
  auto worst = [&](bool shaded, double intensity, int& checked, double factor = 1.0)
  {
    window->Render();
    vtkPolyData* surface = mapper->GetColoredSurface();
    const double alpha = 1.0 - std::exp(-factor * tau * chord / voxel);
    return vosknown::WorstInnerVertex(
      surface, surface->GetPointData()->GetScalars(), 0.9, alpha,
      [&](int c) { return shaded ? lit(c, intensity) : color[c]; }, checked);
  };
  int checked = 0;
  vtkNew<vtkPiecewiseFunction> gradient;
  gradient->AddPoint(0.0, 1.0);
  gradient->AddPoint(2.0, 0.0);
  for (int method : { vtkVolumeOnSurfaceMapper::PIECEWISE, vtkVolumeOnSurfaceMapper::ADAPTIVE,
         vtkVolumeOnSurfaceMapper::LEVOY })
  {
    mapper->SetIntegrationMethod(method);
    // 8-bit rounding (0.5) and eps 1e-3 (0.26); the Riemann sum's last
    // partial step and the adaptive rule's estimate add up to 3.
    const double allowed = method == vtkVolumeOnSurfaceMapper::PIECEWISE ? 0.8 : 3.0;
    property->DisableGradientOpacityOn();
    const double w = worst(true, 0.8, checked);
    Expect(checked > 500, "the plane's inner vertices are checked");
    Expect(w <= allowed, "each vertex's colour = the lit ray integral behind it");
    property->DisableGradientOpacityOff();
    property->SetGradientOpacity(gradient);
    Expect(worst(true, 0.8, checked, 0.5) <= allowed,
      "with gradient opacity G(1) = 1/2, the lit ray integral with tau / 2");
  }
  property->DisableGradientOpacityOn();
  // A light changed, the camera still: the rays are cast again.
  mapper->SetIntegrationMethodToPiecewise();
  key->SetIntensity(0.3);
  Expect(worst(true, 0.3, checked) <= 0.8, "a light's change recolours the surface");
  // Unshaded: the colour itself, far from the lit one.
  property->ShadeOff();
  Expect(worst(false, 0.3, checked) <= 0.8, "unshaded, the colour itself");
  property->ShadeOn();
  Expect(worst(false, 0.3, checked) > 20.0, "shading changes the colours");
  return Expect.Result();
}
