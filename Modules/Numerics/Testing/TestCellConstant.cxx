// Fields constant per cell (Volume.h's CellConstantVolume): cell scalars and
// nearest interpolation of point scalars, integrated by the piecewise method
// and projected exactly, against an oracle that cuts the ray at the faces of
// the constant regions itself and composites their closed forms.
#include "AdversarialCases.h"

#include "avos/numerics/Extremum.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace an = avos::numerics;

namespace
{
using Volume = an::CellConstantVolume<double, double>;
using Layout = Volume::Layout;

struct Grid
{
  int Points[3];
  Layout Kind;
  std::vector<double> Data; // per cell or per point, x fastest

  int Values(int axis) const
  {
    return this->Kind == Layout::Cells ? Points[axis] - 1 : Points[axis];
  }

  // The value at p (point-grid coordinates), read the way VTK defines it:
  // the cell containing p, or the point nearest to it.
  double At(const glm::dvec3& p) const
  {
    int c[3];
    for (int a = 0; a < 3; ++a)
    {
      const int n = this->Values(a);
      const double x = this->Kind == Layout::Cells ? std::floor(p[a]) : std::floor(p[a] + 0.5);
      c[a] = std::min(std::max(static_cast<int>(x), 0), n - 1);
    }
    return this->Data[c[0] + this->Values(0) * (c[1] + this->Values(1) * c[2])];
  }

  // The t where the ray crosses a face between constant regions, in (0, D).
  std::vector<double> Faces(const adversarial::Ray& ray) const
  {
    std::vector<double> t{ 0.0, ray.Length };
    const double offset = this->Kind == Layout::Cells ? 0.0 : 0.5;
    for (int a = 0; a < 3; ++a)
    {
      if (ray.Direction[a] == 0.0)
      {
        continue;
      }
      for (int m = 0; m < this->Points[a]; ++m)
      {
        const double u = (m + offset - ray.Origin[a]) / ray.Direction[a];
        if (u > 0.0 && u < ray.Length)
        {
          t.push_back(u);
        }
      }
    }
    std::sort(t.begin(), t.end());
    return t;
  }
};

Grid RandomGrid(Layout kind, const int dims[3], std::mt19937& rng)
{
  Grid g{ { dims[0], dims[1], dims[2] }, kind, {} };
  std::uniform_real_distribution<double> u(0.0, 255.0);
  g.Data.resize(static_cast<std::size_t>(g.Values(0)) * g.Values(1) * g.Values(2));
  for (double& v : g.Data)
  {
    v = u(rng);
  }
  return g;
}

// The composite of the constant regions' closed forms: a region of length
// L and value v adds T c(v) (1 - e^{-tau(v) L}) and multiplies T by e^{-tau L}.
glm::dvec4 Oracle(
  const Grid& g, const adversarial::Ray& ray, const an::TransferFunction<double>& tf)
{
  const std::vector<double> t = g.Faces(ray);
  glm::dvec3 color(0.0);
  double T = 1.0;
  for (std::size_t i = 0; i + 1 < t.size(); ++i)
  {
    const double L = t[i + 1] - t[i];
    const double v = g.At(ray.Origin + 0.5 * (t[i] + t[i + 1]) * ray.Direction);
    double tau;
    glm::dvec3 c;
    tf.Classify(v, tau, c);
    const double alpha = -std::expm1(-tau * L);
    color += T * alpha * c;
    T *= 1.0 - alpha;
  }
  return glm::dvec4(color, 1.0 - T);
}

an::TransferFunction<double> Layers(an::OpacityModel model)
{
  an::TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(90.0, 0.0);
  tf.AddOpacityKnot(100.0, 0.6);
  tf.AddOpacityKnot(160.0, 0.05);
  tf.AddOpacityKnot(255.0, 0.9);
  tf.AddColorKnot(0.0, 1.0, 0.2, 0.0);
  tf.AddColorKnot(128.0, 0.1, 0.9, 0.3);
  tf.AddColorKnot(255.0, 0.0, 0.3, 1.0);
  tf.SetOpacityModel(model, 1.5);
  tf.Finalize();
  return tf;
}
} // namespace

// The walk grid's cells read the values VTK's definitions give.
TEST(CellConstant, ValuesAreTheCellsOrTheNearestPoints)
{
  std::mt19937 rng(3);
  const int dims[3] = { 5, 7, 4 };
  for (const Layout kind : { Layout::Cells, Layout::NearestPoints })
  {
    const Grid g = RandomGrid(kind, dims, rng);
    const Volume volume(g.Data.data(), dims, kind);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 2000; ++i)
    {
      const glm::dvec3 p(u(rng) * (dims[0] - 1), u(rng) * (dims[1] - 1), u(rng) * (dims[2] - 1));
      ASSERT_EQ(volume(volume.ToWalk(p)), g.At(p));
    }
    // Every walk cell's corners hold the cell's value.
    for (int k = 0; k + 1 < volume.GetDimension(2); ++k)
    {
      for (int j = 0; j + 1 < volume.GetDimension(1); ++j)
      {
        for (int i = 0; i + 1 < volume.GetDimension(0); ++i)
        {
          double c[8];
          volume.GetCorners(i, j, k, c);
          const glm::dvec3 centre(i + 0.5, j + 0.5, k + 0.5);
          for (const double v : c)
          {
            ASSERT_EQ(v, volume(centre));
          }
        }
      }
    }
    EXPECT_EQ(volume.GetDimension(0), kind == Layout::Cells ? 5 : 9);
  }
}

// One piece per region and its closed form: the reference tolerance holds
// to rounding, and eps 1e-3 holds on every ray, in both opacity models.
TEST(CellConstant, PiecewiseIsExactPerRegion)
{
  std::mt19937 rng(11);
  const int dims[3] = { 9, 6, 11 };
  for (const Layout kind : { Layout::Cells, Layout::NearestPoints })
  {
    const Grid g = RandomGrid(kind, dims, rng);
    const Volume volume(g.Data.data(), dims, kind);
    for (const an::OpacityModel model : { an::OpacityModel::Extinction, an::OpacityModel::Alpha })
    {
      const an::TransferFunction<double> tf = Layers(model);
      // (The alpha model's pieces are certified down to 1e-5.)
      const double finest =
        model == an::OpacityModel::Alpha ? 1e-5 : an::PiecewiseReferenceTolerance<double>();
      for (const double eps : { finest, 1e-3 })
      {
        an::PiecewiseTransferFunction<double> pieces;
        ASSERT_EQ(pieces.Build(tf, an::PiecewiseRelativeError(eps)), "");
        double worst = 0.0;
        for (int i = 0; i < 300; ++i)
        {
          const adversarial::Ray ray = adversarial::RandomRay(dims, rng, 0.5);
          const auto r = an::IntegratePiecewise(volume, volume.ToWalk(ray.Origin),
            volume.ToWalk(ray.Direction), ray.Length, pieces, eps, false);
          ASSERT_EQ(r.Error, "");
          const glm::dvec4 exact = Oracle(g, ray, tf);
          for (int c = 0; c < 4; ++c)
          {
            worst = std::max(worst, std::abs(r.RGBA[c] - exact[c]));
          }
        }
        EXPECT_LE(worst, eps) << "layout " << static_cast<int>(kind);
      }
    }
  }
}

// The projections take each crossed region's value: the exact extremum.
TEST(CellConstant, ExtremumIsTheCrossedRegionsExtremum)
{
  std::mt19937 rng(5);
  const int dims[3] = { 8, 8, 8 };
  for (const Layout kind : { Layout::Cells, Layout::NearestPoints })
  {
    const Grid g = RandomGrid(kind, dims, rng);
    const Volume volume(g.Data.data(), dims, kind);
    for (int i = 0; i < 300; ++i)
    {
      const adversarial::Ray ray = adversarial::RandomRay(dims, rng, 0.5);
      const std::vector<double> t = g.Faces(ray);
      double hi = -1.0;
      for (std::size_t s = 0; s + 1 < t.size(); ++s)
      {
        hi = std::max(hi, g.At(ray.Origin + 0.5 * (t[s] + t[s + 1]) * ray.Direction));
      }
      const an::Interval<double> whole{ 0.0, ray.Length };
      const auto e = an::ExtremumAlongRay(
        volume, volume.ToWalk(ray.Origin), volume.ToWalk(ray.Direction), &whole, 1, true);
      ASSERT_TRUE(e.Found);
      EXPECT_EQ(e.Value, hi);
    }
  }
}

namespace
{
// VTK's GPU mapper's linear reading of cell scalars at p (point-grid
// coordinates): a texture with one texel per cell over the box, texel
// centres at the cell centres, clamped to the edge, filtered linearly.
double Texture(const std::vector<double>& cells, const int points[3], const glm::dvec3& p)
{
  int i0[3], i1[3];
  double f[3];
  for (int a = 0; a < 3; ++a)
  {
    const int n = points[a] - 1;
    const double u = std::min(std::max(p[a] - 0.5, 0.0), n - 1.0);
    i0[a] = std::min(static_cast<int>(std::floor(u)), n - 1);
    i1[a] = std::min(i0[a] + 1, n - 1);
    f[a] = u - i0[a];
  }
  const int nx = points[0] - 1, ny = points[1] - 1;
  auto at = [&](int x, int y, int z) { return cells[x + nx * (y + ny * z)]; };
  double v = 0.0;
  for (int c = 0; c < 8; ++c)
  {
    const int x = c & 1, y = (c >> 1) & 1, z = (c >> 2) & 1;
    v += (x ? f[0] : 1 - f[0]) * (y ? f[1] : 1 - f[1]) * (z ? f[2] : 1 - f[2]) *
      at(x ? i1[0] : i0[0], y ? i1[1] : i0[1], z ? i1[2] : i0[2]);
  }
  return v;
}
} // namespace

// Cell scalars read linearly: the texture's values everywhere, and the
// piecewise method's integral that of the trilinear volume of the texture's
// values on the refined grid (the same field, built independently).
TEST(CellConstant, CellCentredIsVTKsLinearTexture)
{
  std::mt19937 rng(8);
  for (const auto& dims : { std::array<int, 3>{ 6, 5, 7 }, std::array<int, 3>{ 2, 4, 3 } })
  {
    const int* n = dims.data();
    std::vector<double> cells(static_cast<std::size_t>(n[0] - 1) * (n[1] - 1) * (n[2] - 1));
    std::uniform_real_distribution<double> value(0.0, 255.0), u(0.0, 1.0);
    for (double& v : cells)
    {
      v = value(rng);
    }
    const an::CellCentredVolume<double, double> volume(cells.data(), n);
    for (int i = 0; i < 2000; ++i)
    {
      const glm::dvec3 p(u(rng) * (n[0] - 1), u(rng) * (n[1] - 1), u(rng) * (n[2] - 1));
      ASSERT_NEAR(volume(volume.ToWalk(p)), Texture(cells, n, p), 1e-12);
    }
    const int refined[3] = { 2 * n[0] - 1, 2 * n[1] - 1, 2 * n[2] - 1 };
    std::vector<double> grid;
    for (int k = 0; k < refined[2]; ++k)
    {
      for (int j = 0; j < refined[1]; ++j)
      {
        for (int i = 0; i < refined[0]; ++i)
        {
          grid.push_back(Texture(cells, n, glm::dvec3(0.5 * i, 0.5 * j, 0.5 * k)));
        }
      }
    }
    const an::TrilinearVolume<double, double> explicitGrid(grid.data(), refined);
    const an::TransferFunction<double> tf = Layers(an::OpacityModel::Extinction);
    an::PiecewiseTransferFunction<double> pieces;
    const double eps = an::PiecewiseReferenceTolerance<double>();
    ASSERT_EQ(pieces.Build(tf, an::PiecewiseRelativeError(eps)), "");
    for (int i = 0; i < 200; ++i)
    {
      const adversarial::Ray ray = adversarial::RandomRay(n, rng, 0.5);
      const glm::dvec3 o = volume.ToWalk(ray.Origin), d = volume.ToWalk(ray.Direction);
      const auto a = an::IntegratePiecewise(volume, o, d, ray.Length, pieces, eps, false);
      const auto b = an::IntegratePiecewise(explicitGrid, o, d, ray.Length, pieces, eps, false);
      ASSERT_EQ(a.Error, "");
      for (int c = 0; c < 4; ++c)
      {
        ASSERT_NEAR(a.RGBA[c], b.RGBA[c], 1e-9);
      }
    }
  }
}
