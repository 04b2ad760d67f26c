// The volumes vtkVolumeOnSurfaceFilter colours a surface with, beyond one
// component of point scalars with linear interpolation, read as
// vtkAdaptiveVolumeMapper reads them (avosVolumeRay.h), by every method:
// - several components: a transparent second component gives the first
//   one's colours to the bit; a mirrored pair of weight 1/2 each is the one
//   component (the extinctions and emissions add up); weights 1 differ;
//   swapping the components and their functions changes nothing; the
//   dependent pair (colour of the first, opacity of the second) and RGBA
//   (colour direct, opacity of the fourth) against one component with the
//   same colour and opacity;
// - nearest interpolation and cell scalars: point scalars nearest and cell
//   scalars nearest on the dual grid (the same field where the volume shows)
//   agree, as do point scalars linear and cell scalars linear between the
//   cells' centres; nearest differs from linear (by 7-9 counts on this
//   coarse grid, beyond 4 times the bound).
// Colours are 8-bit (VoSColors): within eps (two certified rays: 2 eps) and
// the rounding of a count, 255 * 2 eps + 1 counts; the Riemann sums read the
// same samples, within a count.
#include "vtkAnalyticVolumeSource.h"
#include "vtkCamera.h"
#include "vtkCellData.h"
#include "vtkColorTransferFunction.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolumeOnSurfaceFilter.h"
#include "vtkVolumeProperty.h"

#include "avosTestHelpers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace
{
avostest::Checklist Expect;

using Colours = std::vector<std::array<int, 4>>;

// The largest difference of two colourings, in counts (a large value for
// different sizes).
int Difference(const Colours& a, const Colours& b)
{
  if (a.size() != b.size() || a.empty())
  {
    return 1000;
  }
  int worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    for (int c = 0; c < 4; ++c)
    {
      worst = std::max(worst, std::abs(a[i][c] - b[i][c]));
    }
  }
  return worst;
}

// The volume `like`'s grid (moved by `shift` world units, with `grow` more
// points along each axis) holding `components` values per point (per cell
// for `cells`): value(k, x, y, z) at each point or cell centre.
vtkSmartPointer<vtkImageData> Volume(vtkImageData* like, int components, bool cells, double shift,
  int grow, int type, const std::function<double(int, double, double, double)>& value)
{
  auto volume = vtkSmartPointer<vtkImageData>::New();
  int dims[3];
  like->GetDimensions(dims);
  volume->SetDimensions(dims[0] + grow, dims[1] + grow, dims[2] + grow);
  volume->SetSpacing(like->GetSpacing());
  const double* o = like->GetOrigin();
  volume->SetOrigin(o[0] + shift, o[1] + shift, o[2] + shift);
  vtkSmartPointer<vtkDataArray> array;
  array.TakeReference(vtkDataArray::CreateDataArray(type));
  array->SetName("s");
  array->SetNumberOfComponents(components);
  const vtkIdType n = cells ? volume->GetNumberOfCells() : volume->GetNumberOfPoints();
  array->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    if (cells)
    {
      double pcoords[3], weights[8];
      int sub = 0;
      vtkCell* cell = volume->GetCell(i);
      sub = cell->GetParametricCenter(pcoords);
      cell->EvaluateLocation(sub, pcoords, p, weights);
    }
    else
    {
      volume->GetPoint(i, p);
    }
    for (int k = 0; k < components; ++k)
    {
      array->SetComponent(i, k, value(k, p[0], p[1], p[2]));
    }
  }
  if (cells)
  {
    volume->GetCellData()->SetScalars(array);
  }
  else
  {
    volume->GetPointData()->SetScalars(array);
  }
  return volume;
}

double Distance(double x, double y, double z)
{
  return std::sqrt(x * x + y * y + z * z);
}

struct Scene
{
  vtkNew<vtkSphereSource> Sphere;
  vtkNew<vtkCamera> Camera;
  vtkNew<vtkVolumeOnSurfaceFilter> VoS;

  Scene()
  {
    this->Sphere->SetRadius(0.5);
    this->Sphere->SetThetaResolution(24);
    this->Sphere->SetPhiResolution(16);
    this->Camera->SetPosition(0.3, 0.4, 5);
    this->Camera->SetFocalPoint(0, 0, 0);
    this->VoS->SetInputConnection(this->Sphere->GetOutputPort());
    this->VoS->SetCamera(this->Camera);
    this->VoS->SetTolerance(1e-3);
  }

  // Integrates by `method`; returns the largest difference, in counts, of
  // two colourings of the same integral: a count for the Riemann sums (the
  // same samples), else 2 eps and a count.
  int Use(int method)
  {
    this->VoS->SetIntegrationMethod(method);
    return method == vtkVolumeOnSurfaceFilter::LEVOY
      ? 1
      : static_cast<int>(std::floor(255.0 * 2.0 * this->VoS->GetTolerance())) + 1;
  }

  // VoSColors of the surface for `volume` and `property` (empty after an
  // error, which is printed).
  Colours Colour(vtkImageData* volume, vtkVolumeProperty* property)
  {
    avostest::ExpectedErrors errors(this->VoS);
    this->VoS->SetInputData(1, volume);
    this->VoS->SetVolumeProperty(property);
    this->VoS->Update();
    Colours colours;
    if (!errors.None("colouring"))
    {
      return colours;
    }
    auto* rgba = vtkUnsignedCharArray::SafeDownCast(
      this->VoS->GetOutput()->GetPointData()->GetArray("VoSColors"));
    for (vtkIdType i = 0; rgba && i < rgba->GetNumberOfTuples(); ++i)
    {
      colours.push_back({ rgba->GetValue(4 * i), rgba->GetValue(4 * i + 1),
        rgba->GetValue(4 * i + 2), rgba->GetValue(4 * i + 3) });
    }
    return colours;
  }
};

// A property of `components` independent components (component k: colour
// `colours[k]`, opacity `opacities[k]`, weight `weights[k]`).
vtkSmartPointer<vtkVolumeProperty> Property(int components,
  const std::vector<vtkColorTransferFunction*>& colours,
  const std::vector<vtkPiecewiseFunction*>& opacities, const std::vector<double>& weights)
{
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  property->SetInterpolationTypeToLinear();
  for (int k = 0; k < components; ++k)
  {
    property->SetColor(k, colours[k]);
    property->SetScalarOpacity(k, opacities[k]);
    property->SetComponentWeight(k, weights[k]);
  }
  return property;
}

const int Methods[] = { vtkVolumeOnSurfaceFilter::LEVOY, vtkVolumeOnSurfaceFilter::ADAPTIVE,
  vtkVolumeOnSurfaceFilter::PIECEWISE };

const char* MethodName(int method)
{
  return method == vtkVolumeOnSurfaceFilter::LEVOY ? "Levoy"
    : method == vtkVolumeOnSurfaceFilter::ADAPTIVE ? "adaptive"
                                                   : "piecewise";
}
} // namespace

int TestVolumeOnSurfaceComponents(int, char*[])
{
  vtkNew<vtkAnalyticVolumeSource> source;
  source->SetFunctionToSphereDistance();
  source->SetDimensions(33, 33, 33);
  source->SetBounds(-1, 1, -1, 1, -1, 1);
  source->Update();
  vtkImageData* grid = source->GetOutput();

  vtkNew<vtkColorTransferFunction> blue, red;
  blue->AddRGBPoint(0.0, 1.0, 0.2, 0.1);
  blue->AddRGBPoint(1.8, 0.1, 0.3, 1.0);
  red->AddRGBPoint(0.0, 0.9, 0.1, 0.1);
  red->AddRGBPoint(1.8, 1.0, 0.8, 0.2);
  vtkNew<vtkPiecewiseFunction> opacity, shell, none;
  opacity->AddPoint(0.0, 0.02);
  opacity->AddPoint(1.8, 0.3);
  shell->AddPoint(0.0, 0.0);
  shell->AddPoint(0.6, 0.0);
  shell->AddPoint(0.9, 0.4);
  shell->AddPoint(1.8, 0.0);
  none->AddPoint(0.0, 0.0);
  none->AddPoint(1.8, 0.0);

  auto s = [](int, double x, double y, double z) { return Distance(x, y, z); };
  auto t = [](int, double x, double y, double z) { return 1.8 - Distance(x, y, z); };
  const auto one = Volume(grid, 1, false, 0.0, 0, VTK_DOUBLE, s);
  const auto pair = Volume(grid, 2, false, 0.0, 0, VTK_DOUBLE,
    [&](int k, double x, double y, double z) { return k == 0 ? s(k, x, y, z) : t(k, x, y, z); });
  const auto swapped = Volume(grid, 2, false, 0.0, 0, VTK_DOUBLE,
    [&](int k, double x, double y, double z) { return k == 1 ? s(k, x, y, z) : t(k, x, y, z); });
  const auto mirrored = Volume(grid, 2, false, 0.0, 0, VTK_DOUBLE, s);

  const auto single = Property(1, { blue }, { opacity }, { 1.0 });
  const auto transparent = Property(2, { blue, red }, { opacity, none }, { 1.0, 1.0 });
  const auto halves = Property(2, { blue, blue }, { opacity, opacity }, { 0.5, 0.5 });
  const auto wholes = Property(2, { blue, blue }, { opacity, opacity }, { 1.0, 1.0 });
  const auto both = Property(2, { blue, red }, { opacity, shell }, { 1.0, 0.7 });
  const auto bothSwapped = Property(2, { red, blue }, { shell, opacity }, { 0.7, 1.0 });
  auto dependent = Property(1, { blue }, { opacity }, { 1.0 });
  dependent->IndependentComponentsOff();

  // RGBA of unsigned char: a constant colour, the opacity of the fourth.
  const double rgb[3] = { 40, 200, 120 };
  auto byte = [](double d) { return std::round(d / 1.8 * 255.0); };
  const auto bytes = Volume(grid, 1, false, 0.0, 0, VTK_UNSIGNED_CHAR,
    [&](int, double x, double y, double z) { return byte(Distance(x, y, z)); });
  const auto rgba = Volume(grid, 4, false, 0.0, 0, VTK_UNSIGNED_CHAR,
    [&](int k, double x, double y, double z) { return k < 3 ? rgb[k] : byte(Distance(x, y, z)); });
  vtkNew<vtkColorTransferFunction> constant;
  constant->AddRGBPoint(0.0, rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0);
  constant->AddRGBPoint(255.0, rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0);
  vtkNew<vtkPiecewiseFunction> byteOpacity;
  byteOpacity->AddPoint(0.0, 0.02);
  byteOpacity->AddPoint(255.0, 0.3);
  const auto byteSingle = Property(1, { constant }, { byteOpacity }, { 1.0 });
  auto byteDependent = Property(1, { blue }, { byteOpacity }, { 1.0 });
  byteDependent->IndependentComponentsOff();

  Scene scene;
  for (int method : Methods)
  {
    const int bound = scene.Use(method);
    const std::string name = MethodName(method);
    const Colours reference = scene.Colour(one, single);
    const int lit = std::count_if(
      reference.begin(), reference.end(), [](const std::array<int, 4>& c) { return c[3] > 20; });
    Expect(lit > static_cast<int>(reference.size()) / 2, name + ": the volume colours the surface");

    const int solo = Difference(scene.Colour(pair, transparent), reference);
    const int half = Difference(scene.Colour(mirrored, halves), reference);
    const int whole = Difference(scene.Colour(mirrored, wholes), reference);
    const Colours mixed = scene.Colour(pair, both);
    const int swap = Difference(scene.Colour(swapped, bothSwapped), mixed);
    const int second = Difference(mixed, reference);
    const int colourOpacity = Difference(scene.Colour(mirrored, dependent), reference);
    const int direct =
      Difference(scene.Colour(rgba, byteDependent), scene.Colour(bytes, byteSingle));
    std::cout << name << " (bound " << bound << " counts): transparent second " << solo
              << ", halves " << half << ", weights 1 " << whole << ", swapped " << swap
              << ", second shown " << second << ", dependent pair " << colourOpacity << ", RGBA "
              << direct << "\n";
    Expect(solo == 0, name + ": a transparent second component gives the first one's colours");
    Expect(half <= bound, name + ": a mirrored pair of weights 1/2 is the one component");
    Expect(whole > 10, name + ": weights 1 double the medium");
    Expect(swap <= bound, name + ": swapping the components and their functions");
    Expect(second > 10, name + ": a visible second component shows");
    Expect(colourOpacity <= bound, name + ": dependent pair of one scalar");
    Expect(direct <= bound, name + ": RGBA against a constant colour");
  }

  // Fields: a coarse grid, the volume transparent within half a cell of its
  // boundary (distance 1 at the faces' centres), so that the dual grid's
  // wider box adds nothing.
  vtkNew<vtkAnalyticVolumeSource> coarseSource;
  coarseSource->SetFunctionToSphereDistance();
  coarseSource->SetDimensions(9, 9, 9);
  coarseSource->SetBounds(-1, 1, -1, 1, -1, 1);
  coarseSource->Update();
  vtkImageData* coarse = coarseSource->GetOutput();
  const double h = coarse->GetSpacing()[0];
  vtkNew<vtkPiecewiseFunction> inner;
  inner->AddPoint(0.0, 0.3);
  inner->AddPoint(0.8, 0.05);
  inner->AddPoint(0.85, 0.0);
  inner->AddPoint(1.8, 0.0);
  const auto linear = Property(1, { blue }, { inner }, { 1.0 });
  auto nearest = Property(1, { blue }, { inner }, { 1.0 });
  nearest->SetInterpolationTypeToNearest();
  const auto points = Volume(coarse, 1, false, 0.0, 0, VTK_DOUBLE, s);
  // Cell (i, j, k) of the dual grid is centred on point (i, j, k).
  const auto cells = Volume(coarse, 1, true, -0.5 * h, 1, VTK_DOUBLE, s);
  for (int method : Methods)
  {
    const int bound = scene.Use(method);
    const std::string name = MethodName(method);
    const Colours pointsLinear = scene.Colour(points, linear);
    const int perCell = Difference(scene.Colour(cells, nearest), scene.Colour(points, nearest));
    const int centres = Difference(scene.Colour(cells, linear), pointsLinear);
    const int blocky = Difference(scene.Colour(points, nearest), pointsLinear);
    std::cout << name << " fields (bound " << bound << " counts): cells and points nearest "
              << perCell << ", cell centres and points linear " << centres
              << ", nearest and linear " << blocky << "\n";
    Expect(perCell <= bound, name + ": cell scalars nearest are point scalars nearest");
    Expect(centres <= bound, name + ": cell scalars linear are point scalars linear");
    Expect(blocky > 4 * bound, name + ": nearest interpolation is honoured");
  }
  return Expect.Result();
}
