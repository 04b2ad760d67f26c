// Nearest interpolation and cell scalars through the whole mapper, pixel by
// pixel: random scalars on [-1, 1]^3 (9^3 points, 8^3 cells), read as VTK's
// GPU mapper reads them: point scalars with the property's default
// interpolation (nearest: each point's value fills the part of the box
// nearest to it), cell scalars with nearest interpolation (constant on each
// cell) and with linear interpolation (a texture of one texel per cell,
// clamped to its edge). The oblique orthographic view of the closed-form
// tests; each pixel's ray is rebuilt from the renderer. The constant fields'
// rays are cut at the faces of the regions here and composited in closed
// form (a region of length L and value v: T c(v) (1 - e^{-tau(v) L})); the
// linear cell field is the texture's values on the point grid refined by 2,
// built here, integrated by the numerical core's reference (1e-9). Required:
// the piecewise method within eps on every pixel, the reference within
// 1e-5, the maximum intensity projection exact to the float image; the
// Riemann sum at h = 0.5 must be visibly off (the oracle tells a wrong
// field from a right one); shading such a field is refused.
#include "vtkAdaptiveVolumeMapper.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTrivialProducer.h"
#include "vtkVolumeProperty.h"

#include "ObliqueScene.h"
#include "avosTestHelpers.h"

#include "avos/numerics/Extremum.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Volume.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace
{
// scalar, r, g, b, tau per voxel unit
const double Knots[][5] = { { 10, 0.2, 0.2, 0.9, 0.0 }, { 30, 0.9, 0.6, 0.1, 0.02 },
  { 50, 0.1, 0.9, 0.3, 0.3 }, { 60, 1.0, 0.2, 0.2, 0.05 }, { 85, 0.9, 0.9, 0.9, 0.4 } };
constexpr int Size = 64;
constexpr int Points = 9;
constexpr double Voxel = 2.0 / (Points - 1);

// The volume's values, per cell or per point, and how VTK reads them.
struct Field
{
  bool Cells;
  std::vector<double> Values;
  bool Linear = false; // cell scalars between their centres

  int PerAxis() const { return this->Cells ? Points - 1 : Points; }

  // The value at grid coordinates g: the cell holding g, or the point
  // nearest to it.
  double At(const glm::dvec3& g) const
  {
    const int n = this->PerAxis();
    int c[3];
    for (int a = 0; a < 3; ++a)
    {
      const double x = this->Cells ? std::floor(g[a]) : std::floor(g[a] + 0.5);
      c[a] = std::min(std::max(static_cast<int>(x), 0), n - 1);
    }
    return this->Values[c[0] + n * (c[1] + n * c[2])];
  }
};

// The regions pixel (x, y)'s ray crosses, as (length in voxel units, value)
// front to back.
std::vector<std::pair<double, double>> Regions(vtkRenderer* renderer, const Field& f, int x, int y)
{
  std::vector<std::pair<double, double>> regions;
  const obliquescene::PixelRay ray = obliquescene::RayOf(renderer, x, y);
  if (!(ray.T0 < ray.T1))
  {
    return regions;
  }
  // Grid coordinates: g = (p + 1) / Voxel, u in voxel units from the entry.
  const glm::dvec3 g0 = (ray.Start + ray.T0 * ray.Direction + 1.0) / Voxel;
  const glm::dvec3& d = ray.Direction;
  const double U = (ray.T1 - ray.T0) / Voxel;
  std::vector<double> u{ 0.0, U };
  const double offset = f.Cells ? 0.0 : 0.5;
  for (int a = 0; a < 3; ++a)
  {
    for (int m = 0; m < Points; ++m)
    {
      const double t = (m + offset - g0[a]) / d[a];
      if (t > 0.0 && t < U)
      {
        u.push_back(t);
      }
    }
  }
  std::sort(u.begin(), u.end());
  for (std::size_t i = 0; i + 1 < u.size(); ++i)
  {
    regions.emplace_back(u[i + 1] - u[i], f.At(g0 + 0.5 * (u[i] + u[i + 1]) * d));
  }
  return regions;
}

glm::dvec4 Composite(const std::vector<std::pair<double, double>>& regions,
  const avos::numerics::TransferFunction<double>& tf)
{
  glm::dvec3 color(0.0);
  double T = 1.0;
  for (const auto& r : regions)
  {
    double tau;
    glm::dvec3 c;
    tf.Classify(r.second, tau, c);
    const double alpha = -std::expm1(-tau * r.first);
    color += T * alpha * c;
    T *= 1.0 - alpha;
  }
  return glm::dvec4(color, 1.0 - T);
}

glm::dvec4 Maximum(const std::vector<std::pair<double, double>>& regions,
  const avos::numerics::TransferFunction<double>& tf)
{
  if (regions.empty())
  {
    return glm::dvec4(0.0);
  }
  double s = regions.front().second;
  for (const auto& r : regions)
  {
    s = std::max(s, r.second);
  }
  const double alpha = std::min(std::max(tf.GetOpacityValue(s), 0.0), 1.0);
  return glm::dvec4(tf.GetColor(s) * alpha, alpha);
}

// VTK's linear texture of cell scalars at grid coordinates g: texel
// centres at the cell centres, clamped to the edge.
double Texture(const Field& f, const glm::dvec3& g)
{
  const int n = Points - 1;
  int i0[3], i1[3];
  double w[3];
  for (int a = 0; a < 3; ++a)
  {
    const double u = std::min(std::max(g[a] - 0.5, 0.0), n - 1.0);
    i0[a] = std::min(static_cast<int>(std::floor(u)), n - 1);
    i1[a] = std::min(i0[a] + 1, n - 1);
    w[a] = u - i0[a];
  }
  double v = 0.0;
  for (int c = 0; c < 8; ++c)
  {
    const int x = c & 1, y = (c >> 1) & 1, z = (c >> 2) & 1;
    v += (x ? w[0] : 1 - w[0]) * (y ? w[1] : 1 - w[1]) * (z ? w[2] : 1 - w[2]) *
      f.Values[(x ? i1[0] : i0[0]) + n * ((y ? i1[1] : i0[1]) + n * (z ? i1[2] : i0[2]))];
  }
  return v;
}

// The linear cell field's RGBA along pixel (x, y)'s ray: the texture on the
// grid refined by 2 (trilinear there), by the core's reference.
glm::dvec4 LinearCells(vtkRenderer* renderer, const std::vector<double>& refined,
  const avos::numerics::PiecewiseTransferFunction<double>& pieces,
  const avos::numerics::TransferFunction<double>& tf, bool maximum, int x, int y)
{
  namespace an = avos::numerics;
  const obliquescene::PixelRay ray = obliquescene::RayOf(renderer, x, y);
  if (!(ray.T0 < ray.T1))
  {
    return glm::dvec4(0.0);
  }
  const int dims[3] = { 2 * Points - 1, 2 * Points - 1, 2 * Points - 1 };
  const an::TrilinearVolume<double, double> volume(refined.data(), dims);
  const glm::dvec3 o = 2.0 * (ray.Start + ray.T0 * ray.Direction + 1.0) / Voxel;
  const glm::dvec3 d = 2.0 * ray.Direction;
  const double U = (ray.T1 - ray.T0) / Voxel;
  if (maximum)
  {
    const an::Interval<double> whole{ 0.0, U };
    const an::RayExtremum<double> e = an::ExtremumAlongRay(volume, o, d, &whole, 1, true);
    const double alpha = std::min(std::max(tf.GetOpacityValue(e.Value), 0.0), 1.0);
    return glm::dvec4(tf.GetColor(e.Value) * alpha, alpha);
  }
  return an::IntegratePiecewise(volume, o, d, U, pieces, 1e-9, false).RGBA;
}

struct Run
{
  const char* Name;
  int Method;
  int Blend;
  double Required; // maximum error on any pixel (0: must exceed 1e-2)
};
} // namespace

int TestAdaptiveVolumeMapperCellFields(int, char*[])
{
  avos::numerics::TransferFunction<double> tf;
  vtkNew<vtkVolumeProperty> property;
  obliquescene::FillProperty(Knots, property, &tf);
  tf.Finalize();
  obliquescene::Cube cube(Points);
  vtkImageData* image = cube.Image;
  obliquescene::Scene scene(cube.Producer, property, Size);
  vtkAdaptiveVolumeMapper* mapper = scene.Mapper;
  mapper->SetOpacityModelToExtinction();
  avostest::ExpectedErrors errors(mapper);

  // VTK's default interpolation is nearest: a pipeline that never sets it.
  const int defaultInterpolation = vtkNew<vtkVolumeProperty>()->GetInterpolationType();
  if (defaultInterpolation != VTK_NEAREST_INTERPOLATION)
  {
    std::cerr << "FAIL VTK's default interpolation is no longer nearest\n";
    return EXIT_FAILURE;
  }
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> value(0.0, 95.0);
  const Run runs[] = {
    { "piecewise eps 1e-3", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE,
      vtkVolumeMapper::COMPOSITE_BLEND, 1e-3 },
    { "piecewise eps 1e-2", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE,
      vtkVolumeMapper::COMPOSITE_BLEND, 1e-2 },
    { "reference", vtkAdaptiveVolumeMapper::REFERENCE, vtkVolumeMapper::COMPOSITE_BLEND, 1e-5 },
    { "maximum intensity", vtkAdaptiveVolumeMapper::PIECEWISE_ADAPTIVE,
      vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND, 1e-7 },
    { "riemann h 0.5", vtkAdaptiveVolumeMapper::RIEMANN, vtkVolumeMapper::COMPOSITE_BLEND, 0.0 },
  };
  struct Case
  {
    const char* Name;
    bool Cells;
    int Interpolation;
  };
  const Case cases[] = { { "point scalars, default (nearest) interpolation", false,
                           defaultInterpolation },
    { "cell scalars, nearest interpolation", true, VTK_NEAREST_INTERPOLATION },
    { "cell scalars, linear interpolation", true, VTK_LINEAR_INTERPOLATION } };
  avos::numerics::PiecewiseTransferFunction<double> reference;
  if (!reference.Build(tf, avos::numerics::PiecewiseRelativeError(1e-9)).empty())
  {
    std::cerr << "FAIL the reference pieces\n";
    return EXIT_FAILURE;
  }
  int failures = 0;
  for (const Case& c : cases)
  {
    Field field{ c.Cells, {}, c.Interpolation == VTK_LINEAR_INTERPOLATION };
    const int n = field.PerAxis();
    vtkNew<vtkDoubleArray> scalars;
    scalars->SetName("values");
    for (int i = 0; i < n * n * n; ++i)
    {
      field.Values.push_back(value(rng));
      scalars->InsertNextValue(field.Values.back());
    }
    image->GetPointData()->Initialize();
    image->GetCellData()->Initialize();
    (c.Cells ? static_cast<vtkDataSetAttributes*>(image->GetCellData()) : image->GetPointData())
      ->SetScalars(scalars);
    image->Modified();
    property->SetInterpolationType(c.Interpolation);
    std::vector<double> refined;
    for (int k = 0; field.Linear && k < 2 * Points - 1; ++k)
    {
      for (int j = 0; j < 2 * Points - 1; ++j)
      {
        for (int i = 0; i < 2 * Points - 1; ++i)
        {
          refined.push_back(Texture(field, 0.5 * glm::dvec3(i, j, k)));
        }
      }
    }
    for (const Run& run : runs)
    {
      mapper->SetIntegrationMethod(run.Method);
      mapper->SetBlendMode(run.Blend);
      mapper->SetTolerance(run.Required >= 1e-3 ? run.Required : 1e-2);
      scene.Window->Render();
      auto* rgba =
        vtkFloatArray::SafeDownCast(mapper->GetRenderedImage()->GetPointData()->GetScalars());
      if (!rgba || !errors.None(run.Name))
      {
        std::cerr << "FAIL " << c.Name << ", " << run.Name << ": nothing rendered\n";
        ++failures;
        continue;
      }
      double maxError = 0.0;
      int hits = 0;
      for (int y = 0; y < Size; ++y)
      {
        for (int x = 0; x < Size; ++x)
        {
          const auto regions = Regions(scene.Renderer, field, x, y);
          const bool maximum = run.Blend == vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND;
          const glm::dvec4 exact = field.Linear
            ? LinearCells(scene.Renderer, refined, reference, tf, maximum, x, y)
            : (maximum ? Maximum(regions, tf) : Composite(regions, tf));
          hits += regions.empty() ? 0 : 1;
          for (int k = 0; k < 4; ++k)
          {
            const double v = rgba->GetComponent(static_cast<vtkIdType>(y) * Size + x, k);
            maxError = std::max(maxError, std::abs(v - exact[k]));
          }
        }
      }
      std::cout << c.Name << ", " << run.Name << ": " << hits << " pixels hit, max error "
                << maxError << "\n";
      // The image is stored in float: 6e-8 relative.
      const bool ok = hits > Size * Size / 4 &&
        (run.Required > 0.0 ? maxError <= run.Required + 1e-7 : maxError > 1e-2);
      if (!ok)
      {
        std::cerr << "FAIL " << c.Name << ", " << run.Name << ": max error " << maxError << "\n";
        ++failures;
      }
    }
    // No gradient inside a cell: shading is refused, never ignored.
    mapper->SetIntegrationMethodToReference();
    mapper->SetBlendModeToComposite();
    property->ShadeOn();
    scene.Window->Render();
    if (!errors.Check(c.Name, "Cannot shade: only point scalars with linear interpolation"))
    {
      ++failures;
    }
    property->ShadeOff();
  }
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
