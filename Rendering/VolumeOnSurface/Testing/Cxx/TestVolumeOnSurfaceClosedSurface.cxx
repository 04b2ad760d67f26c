// VoS^M* on a closed isosurface with a known answer: the volume is 1 - r, r
// the distance to the centre of [-1, 1]^3 (65^3 points; high inside, as in
// CT data, so that the contour's normals point out), the transfer function
// a constant medium inside the sphere r < 0.6 and transparent outside (a
// step at 1 - r = 0.4), the isosurface the sphere itself, seen from +z with a
// parallel camera. A visible vertex p's ray runs from p down along -z
// through the ball: its chord is 2 p_z long, so its colour is
// c (1 - e^{-tau 2 p_z / voxel}) and its opacity 1 - e^{-tau 2 p_z / voxel}.
// Integrating towards the eye instead would leave the ball at once
// (transparent black): this test fails with the inverted direction.
// Vertices with p_z > 0.3 are checked (nearer the silhouette the ray grazes
// the ball, where the trilinear field's boundary and the chord part most).
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
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

int TestVolumeOnSurfaceClosedSurface(int, char*[])
{
  avostest::Checklist Expect;
  const int n = 65;
  const double voxel = 2.0 / (n - 1), radius = 0.6, tau = 0.02;
  const double color[3] = { 0.3, 0.8, 0.5 };
  const auto volume = vosknown::FieldOnCube(
    n, [](double x, double y, double z) { return 1.0 - std::sqrt(x * x + y * y + z * z); });
  // 0 outside, tau from 1 - r = 0.4 on: a step (sharpness 1) at the
  // midpoint of [0.38, 0.42].
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.38, 0.0, 0.5, 1.0);
  opacity->AddPoint(0.42, tau);
  opacity->AddPoint(1.0, tau);
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0.0, color[0], color[1], color[2]);
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->SetColor(ctf);
  property->SetScalarOpacity(opacity);

  vtkNew<vtkRenderer> renderer;
  vtkVolumeOnSurfaceMapper* mapper =
    vosknown::MapperOnIsosurface(volume, property, 1.0 - radius, renderer);
  vtkNew<vtkRenderWindow> window;
  vosknown::ViewFromAbove(window, renderer, 96);

  // The largest difference of a cap vertex's 8-bit RGBA from the closed form.
  auto worstOnCap = [&](int& checked)
  {
    window->Render();
    vtkPolyData* surface = mapper->GetColoredSurface();
    vtkDataArray* colors = surface->GetPointData()->GetScalars();
    double worst = 0.0;
    checked = 0;
    for (vtkIdType v = 0; v < surface->GetNumberOfPoints(); ++v)
    {
      double p[3];
      surface->GetPoint(v, p);
      if (p[2] <= 0.3)
      {
        continue;
      }
      ++checked;
      const double alpha = 1.0 - std::exp(-tau * 2.0 * p[2] / voxel);
      for (int c = 0; c < 4; ++c)
      {
        const double exact = 255.0 * (c < 3 ? color[c] * alpha : alpha);
        worst = std::max(worst, std::abs(colors->GetComponent(v, c) - exact));
      }
    }
    return worst;
  };
  int checked = 0;
  for (int method : { vtkVolumeOnSurfaceMapper::PIECEWISE, vtkVolumeOnSurfaceMapper::LEVOY })
  {
    mapper->SetIntegrationMethod(method);
    const double worst = worstOnCap(checked);
    Expect(checked > 500, "the cap's vertices are checked");
    // 8-bit rounding (0.5) and the sphere as the trilinear field and the
    // contour give it (measured 0.498 with the piecewise method); the Riemann
    // sum's first-order error in its step 0.5 adds up to 2.1.
    const double allowed = method == vtkVolumeOnSurfaceMapper::PIECEWISE ? 1.0 : 3.0;
    Expect(worst <= allowed, "each vertex's colour = the ray integral through the ball behind it");
  }
  // Integrated towards the eye, the rays leave the ball at once: the same
  // check fails by far.
  mapper->SetVolumeSideToInFrontOfSurface();
  Expect(worstOnCap(checked) > 50.0, "the inverted direction is caught");
  return Expect.Result();
}
