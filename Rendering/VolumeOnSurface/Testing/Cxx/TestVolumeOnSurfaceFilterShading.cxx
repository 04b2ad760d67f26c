// vtkVolumeOnSurfaceFilter shaded by a renderer's lights, against closed
// forms: the volume s = 1 - z on [-1, 1]^3 (its gradient (0, 0, -1)
// everywhere) of one colour c and one extinction tau, the surface a square
// at z = -0.5 seen from +z by a parallel camera. A central vertex's chosen
// ray runs down at the smallest cone's opening angle a, through
// 0.5 / cos a world units of the medium, so its colour is L (1 - e^{-tau
// 0.5 / cos a / voxel}) with L the lit colour along that ray: Blinn-Phong
// (VTK's coefficients, two-sided) under each light, seen along the ray
// itself, whose half vector with a light along +z makes the angle a / 2
// with the normal. Then: which changes cast the rays again (lights, or a
// camera a headlight follows) and which only assign colours (a camera under
// scene lights, nothing at all), the headlight of a renderer that has not
// rendered yet, and a shaded property without a renderer.
#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolumeOnSurfaceFilter.h"
#include "vtkVolumeProperty.h"

#include "VoSKnownAnswer.h"
#include "avosTestHelpers.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace
{
const double Colour[3] = { 0.3, 0.4, 0.2 };
const double Tau = 0.05, Voxel = 1.0 / 16.0;
const double Ka = 0.1, Kd = 0.7, Ks = 0.2, Power = 16.0;

// The lit colour of channel c seen along a ray at `angle` degrees from -z,
// with the specular coefficient ks: the headlight (white, along +z) when
// `head`, and a directional light of `keyColour` times `intensity` from
// (1, 0, 2) when `key`.
double Lit(int c, double angle, double ks, bool head, bool key, double intensity)
{
  const double keyColour[3] = { 1.0, 0.9, 0.8 };
  const double half = vtkMath::RadiansFromDegrees(angle) / 2.0;
  double diffuse = head ? 1.0 : 0.0, specular = head ? std::pow(std::cos(half), Power) : 0.0;
  if (key)
  {
    // n = (0, 0, 1), l = (1, 0, 2) / sqrt 5, towards the viewer
    // v = (sin a cos p, sin a sin p, cos a) for the ray's azimuth p: the key
    // light's specular depends on p, so the scenes with a key light have
    // ks = 0.
    diffuse += intensity * keyColour[c] * 2.0 / std::sqrt(5.0);
  }
  return std::min(Ka * Colour[c] + Kd * Colour[c] * diffuse + ks * specular, 1.0);
}
}

int TestVolumeOnSurfaceFilterShading(int, char*[])
{
  avostest::Checklist Expect;
  const auto volume = vosknown::FieldOnCube(33, [](double, double, double z) { return 1.0 - z; });
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0.0, Colour[0], Colour[1], Colour[2]);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, Tau);
  opacity->AddPoint(2.0, Tau);
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->SetColor(ctf);
  property->SetScalarOpacity(opacity);
  property->SetAmbient(Ka);
  property->SetDiffuse(Kd);
  property->SetSpecular(0.0);
  property->SetSpecularPower(Power);
  property->ShadeOn();

  vtkNew<vtkPlaneSource> square;
  square->SetOrigin(-0.8, -0.8, -0.5);
  square->SetPoint1(0.8, -0.8, -0.5);
  square->SetPoint2(-0.8, 0.8, -0.5);
  square->SetResolution(16, 16);
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkVolumeOnSurfaceFilter> vos;
  vos->SetInputConnection(square->GetOutputPort());
  vos->SetInputData(1, volume);
  vos->SetVolumeProperty(property);
  vos->SetCamera(renderer->GetActiveCamera());
  vos->ExtinctionOpacityOn();
  vos->SetTolerance(1e-3);
  avostest::ExpectedErrors errors(vos);
  int executions = 0;
  vtkNew<vtkCallbackCommand> counter;
  counter->SetClientData(&executions);
  counter->SetCallback(
    [](vtkObject*, unsigned long, void* count, void*) { ++*static_cast<int*>(count); });
  vos->AddObserver(vtkCommand::EndEvent, counter);

  // A shaded property needs the lights.
  vos->Update();
  Expect(errors.Check("no renderer", "give the renderer whose lights light the rays"),
    "shading without a renderer is refused");
  Expect(vos->GetOutput()->GetNumberOfPoints() == 0, "and nothing is output");
  vos->SetRenderer(renderer);

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(vos->GetOutputPort());
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectColorArray("VoSDisplayColors");
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  renderer->AddActor(actor);
  vtkNew<vtkRenderWindow> window;
  vosknown::ViewFromAbove(window, renderer, 64);
  vtkCamera* camera = renderer->GetActiveCamera();

  // The largest difference of a central vertex's 8-bit RGBA from the closed
  // form along rays at `angle`, lit as seen at `seen` degrees, and their
  // count (81).
  auto worst = [&](double angle, double seen, bool head, bool key, double intensity, int& checked)
  {
    vtkPolyData* out = vos->GetOutput();
    const double chord = 0.5 / std::cos(vtkMath::RadiansFromDegrees(angle)) / Voxel;
    // (The rays at up to 45 degrees of the vertices within 0.45 of the axis
    // leave through the bottom.)
    return vosknown::WorstInnerVertex(
      out, out->GetPointData()->GetArray("VoSColors"), 0.45, 1.0 - std::exp(-Tau * chord),
      [&](int c) { return Lit(c, seen, property->GetSpecular(), head, key, intensity); }, checked);
  };
  // 8-bit rounding (0.5) and eps 1e-3 (0.26).
  const double allowed = 0.8;
  int checked = 0;

  // A directional scene light and the headlight; no specular (the key
  // light's would depend on the ray's azimuth).
  vtkNew<vtkLight> key, head;
  vosknown::AddKeyAndHeadlight(renderer, key, head);
  window->Render();
  Expect(worst(20.0, 20.0, true, true, 0.8, checked) <= allowed && checked == 81,
    "each central vertex: its ray's integral lit by the key light and the headlight");
  Expect(vos->GetNumberOfRaysCast() == 289 * 12, "the cones are cast");
  key->SetIntensity(0.3);
  window->Render();
  Expect(vos->GetNumberOfRaysCast() > 0 && worst(20.0, 20.0, true, true, 0.3, checked) <= allowed,
    "a light's change casts the rays again");
  const int before = executions;
  window->Render();
  Expect(executions == before, "nothing changed: the filter does not execute");
  camera->Azimuth(1.0);
  window->Render();
  Expect(vos->GetNumberOfRaysCast() > 0, "the camera moves the headlight: the rays are cast again");

  // The key light alone, a scene light: a camera change only assigns.
  head->SwitchOff();
  window->Render();
  camera->Azimuth(-1.0);
  window->Render();
  Expect(vos->GetNumberOfRaysCast() == 0 && executions > before + 2,
    "under scene lights a camera change only assigns colours");
  Expect(worst(20.0, 20.0, false, true, 0.3, checked) <= allowed, "the key light alone");
  head->SwitchOn();

  // The headlight alone, with specular: each ray is lit as seen along
  // itself, so the angle of the cone chosen shows.
  renderer->RemoveLight(key);
  property->SetSpecular(Ks);
  for (double angle : { 20.0, 45.0 })
  {
    vos->RemoveAllOpeningAngles();
    vos->AddOpeningAngle(angle);
    window->Render();
    Expect(worst(angle, angle, true, false, 0.0, checked) <= allowed && checked == 81,
      "the specular of a ray at " + std::to_string(angle) + " degrees, seen along the ray");
    // (Seen from above, the specular would be 3.8 and 15.9 levels brighter.)
    Expect(worst(angle, 0.0, true, false, 0.0, checked) > 2.0,
      "and not as if seen along the observation line");
  }

  // A renderer that has not rendered has no light yet: the rays take the
  // headlight VTK creates at its first render, so that render casts nothing.
  vtkNew<vtkRenderer> fresh;
  vtkNew<vtkRenderWindow> freshWindow;
  vosknown::ViewFromAbove(freshWindow, fresh, 64);
  fresh->GetActiveCamera()->SetPosition(0, 0, 4); // (a light elsewhere: the rays are cast again)
  vos->SetRenderer(fresh);
  vos->SetCamera(fresh->GetActiveCamera());
  renderer->RemoveActor(actor);
  fresh->AddActor(actor);
  vos->Update();
  Expect(vos->GetNumberOfRaysCast() > 0 && worst(45.0, 45.0, true, false, 0.0, checked) <= allowed,
    "before the first render: VTK's automatic headlight");
  freshWindow->Render();
  Expect(vos->GetNumberOfRaysCast() == 0 && worst(45.0, 45.0, true, false, 0.0, checked) <= allowed,
    "the renderer's own headlight is that light: its first render casts nothing");
  Expect(errors.None("the shaded frames"), "no error or warning since the renderer was given");
  return Expect.Result();
}
