// vtkVolumeOnSurfaceFilter in a piecewise (distributed) pipeline: asked for
// piece p of 2, it gets that piece of the surface (a sphere source's) but the
// whole volume (an analytic source that would otherwise give half its
// extent), so every vertex of every piece takes the colour it has on the
// whole surface; the pieces together hold every vertex. A volume whose
// producer also feeds the surface (a piece request replaces the whole one)
// is reported.
#include "vtkAnalyticVolumeSource.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkContourFilter.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolumeOnSurfaceFilter.h"
#include "vtkVolumeProperty.h"

#include "avosTestHelpers.h"

#include <array>
#include <cmath>
#include <iostream>
#include <map>

namespace
{
avostest::Checklist Expect;

// A vertex's position to 1e-9: the sphere source computes a piece's
// points from the piece's own angles (last-bit differences).
using Key = std::array<long long, 3>;

// VoSColors by vertex position.
std::map<Key, std::array<int, 4>> Colours(vtkPolyData* surface)
{
  std::map<Key, std::array<int, 4>> colours;
  auto* rgba = vtkUnsignedCharArray::SafeDownCast(surface->GetPointData()->GetArray("VoSColors"));
  for (vtkIdType i = 0; rgba && i < surface->GetNumberOfPoints(); ++i)
  {
    double p[3];
    surface->GetPoint(i, p);
    const Key key = { std::llround(p[0] * 1e9), std::llround(p[1] * 1e9),
      std::llround(p[2] * 1e9) };
    colours[key] = { rgba->GetValue(4 * i), rgba->GetValue(4 * i + 1), rgba->GetValue(4 * i + 2),
      rgba->GetValue(4 * i + 3) };
  }
  return colours;
}
} // namespace

int TestVolumeOnSurfacePieces(int, char*[])
{
  vtkNew<vtkAnalyticVolumeSource> volume;
  volume->SetFunctionToSphereDistance();
  volume->SetDimensions(33, 33, 33);
  volume->SetBounds(-1, 1, -1, 1, -1, 1);

  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(0.0, 1.0, 0.2, 0.1);
  ctf->AddRGBPoint(1.8, 0.1, 0.3, 1.0);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.02);
  opacity->AddPoint(1.8, 0.3);
  vtkNew<vtkVolumeProperty> property;
  property->SetInterpolationTypeToLinear();
  property->SetColor(ctf);
  property->SetScalarOpacity(opacity);

  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(0.5);
  sphere->SetThetaResolution(24);
  sphere->SetPhiResolution(16);

  vtkNew<vtkCamera> camera;
  camera->SetPosition(0.3, 0.4, 5);
  camera->SetFocalPoint(0, 0, 0);

  vtkNew<vtkVolumeOnSurfaceFilter> vos;
  vos->SetInputConnection(sphere->GetOutputPort());
  vos->SetVolumeConnection(volume->GetOutputPort());
  vos->SetVolumeProperty(property);
  vos->SetCamera(camera);

  vos->Update();
  const auto whole = Colours(vos->GetOutput());
  int wholeExtent[6];
  vtkImageData::SafeDownCast(vos->GetInputDataObject(1, 0))->GetExtent(wholeExtent);
  long seen = 0, coloured = 0;
  for (const auto& c : whole)
  {
    coloured += c.second[3] > 0 ? 1 : 0;
  }
  Expect(coloured > static_cast<long>(whole.size()) / 2, "the whole surface sees the volume");

  std::map<Key, std::array<int, 4>> pieces;
  for (int piece : { 0, 1 })
  {
    vos->UpdatePiece(piece, 2, 0);
    vtkPolyData* out = vos->GetOutput();
    int extent[6];
    vtkImageData::SafeDownCast(vos->GetInputDataObject(1, 0))->GetExtent(extent);
    bool sameExtent = true;
    for (int i = 0; i < 6; ++i)
    {
      sameExtent = sameExtent && extent[i] == wholeExtent[i];
    }
    const auto colours = Colours(out);
    bool equal = !colours.empty();
    for (const auto& c : colours)
    {
      const auto found = whole.find(c.first);
      equal = equal && found != whole.end() && found->second == c.second;
      pieces[c.first] = c.second;
    }
    seen += static_cast<long>(colours.size());
    const std::string what = "piece " + std::to_string(piece) + " of 2";
    std::cout << what << ": " << colours.size() << " of " << whole.size() << " vertices\n";
    Expect(sameExtent, what + ": the whole volume requested");
    Expect(colours.size() < whole.size(), what + ": a part of the surface");
    Expect(equal, what + ": every vertex coloured as on the whole surface");
  }
  Expect(pieces.size() == whole.size() && seen >= static_cast<long>(whole.size()),
    "the pieces hold every vertex");

  // The volume's producer also feeding the surface (source -> contour ->
  // filter): the contour's piece request replaces the whole one, and the
  // filter says so instead of colouring with a piece of the volume.
  {
    vtkNew<vtkContourFilter> contour;
    contour->SetInputConnection(volume->GetOutputPort());
    contour->SetValue(0, 0.5);
    vtkNew<vtkVolumeOnSurfaceFilter> shared;
    shared->SetInputConnection(contour->GetOutputPort());
    shared->SetVolumeConnection(volume->GetOutputPort());
    shared->SetVolumeProperty(property);
    shared->SetCamera(camera);
    avostest::ExpectedErrors errors(shared);
    shared->Update();
    Expect(errors.None("shared producer, one piece"), "one piece: the whole volume, no error");
    Expect(shared->GetOutput()->GetNumberOfPoints() > 0, "one piece: coloured");
    shared->UpdatePiece(0, 2, 0);
    Expect(errors.Check("shared producer, piece 0 of 2", "producer of its own"),
      "a shared producer's piece is reported");
  }
  return Expect.Result();
}
