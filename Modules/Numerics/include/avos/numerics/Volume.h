// A scalar volume on a regular grid, sampled along rays.
//
// Coordinates are continuous indices: grid point (i, j, k) sits at (i, j, k),
// and the volume fills [0, n - 1] on each axis. The scalar between grid points
// is the trilinear interpolant of the cell's eight corners, so on any cell it
// lies between the corners' minimum and maximum: the empty-space map
// (EmptySpace.h) relies on that.
#ifndef avos_numerics_Volume_h
#define avos_numerics_Volume_h

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

namespace avos
{
namespace numerics
{

namespace detail
{
// Cell index in [0, n - 2] along an axis of n grid points and the fraction
// of x inside it, x clamped onto [0, n - 1]; a NaN lands on cell 0 (a NaN
// position is a caller's bug, never a crash).
template <typename Real>
void LocateCell(Real x, int n, int& cell, Real& fraction)
{
  const Real last = Real(n - 1);
  x = x > Real(0) ? (x < last ? x : last) : Real(0);
  cell = std::min(static_cast<int>(x), n - 2);
  fraction = x - Real(cell);
}

// The trilinear blend of a cell's corners c (x fastest) at fractions f.
template <typename Real>
Real Trilinear(const Real c[8], const Real f[3])
{
  const Real v00 = c[0] + f[0] * (c[1] - c[0]), v10 = c[2] + f[0] * (c[3] - c[2]);
  const Real v01 = c[4] + f[0] * (c[5] - c[4]), v11 = c[6] + f[0] * (c[7] - c[6]);
  const Real v0 = v00 + f[1] * (v10 - v00), v1 = v01 + f[1] * (v11 - v01);
  return v0 + f[2] * (v1 - v0);
}
} // namespace detail

template <typename Real, typename Storage>
class TrilinearVolume
{
public:
  using Point = glm::vec<3, Real>;

  // `dimensions` must be at least 2 on every axis; `data` is x fastest, a
  // value every `stride` entries (one component of interleaved tuples, read
  // in place: `data` points at the component in the first tuple).
  TrilinearVolume(const Storage* data, const int dimensions[3], int stride = 1)
    : Data(data)
    , Nx(dimensions[0])
    , Ny(dimensions[1])
    , Nz(dimensions[2])
    , Sx(stride)
    , Sy(static_cast<std::ptrdiff_t>(dimensions[0]) * stride)
    , Sz(static_cast<std::ptrdiff_t>(dimensions[0]) * dimensions[1] * stride)
  {
  }

  // Points outside the volume are clamped onto its boundary: a ray clipped to
  // the box may stray from it by rounding only.
  Real operator()(const Point& p) const
  {
    int i, j, k;
    Real f[3], c[8];
    detail::LocateCell(p.x, this->Nx, i, f[0]);
    detail::LocateCell(p.y, this->Ny, j, f[1]);
    detail::LocateCell(p.z, this->Nz, k, f[2]);
    this->GetCorners(i, j, k, c);
    return detail::Trilinear(c, f);
  }

  // Its walk grid is the point grid (see CellConstantVolume).
  Point ToWalk(const Point& p) const { return p; }

  // The gradient of the trilinear interpolant at p (grid coordinates,
  // per grid unit): exact inside a cell; on a face, that of the cell LocateCell
  // picks (the interpolant is only continuous there).
  glm::vec<3, Real> Gradient(const Point& p) const
  {
    int i, j, k;
    Real fx, fy, fz;
    detail::LocateCell(p.x, this->Nx, i, fx);
    detail::LocateCell(p.y, this->Ny, j, fy);
    detail::LocateCell(p.z, this->Nz, k, fz);
    Real c[8];
    this->GetCorners(i, j, k, c);
    // Differences along x at the four (y, z) edges, then blended.
    const Real dx00 = c[1] - c[0], dx10 = c[3] - c[2], dx01 = c[5] - c[4], dx11 = c[7] - c[6];
    const Real gx = (dx00 * (1 - fy) + dx10 * fy) * (1 - fz) + (dx01 * (1 - fy) + dx11 * fy) * fz;
    const Real x00 = c[0] + fx * dx00, x10 = c[2] + fx * dx10;
    const Real x01 = c[4] + fx * dx01, x11 = c[6] + fx * dx11;
    const Real gy = (x10 - x00) * (1 - fz) + (x11 - x01) * fz;
    const Real gz = (x01 + fy * (x11 - x01)) - (x00 + fy * (x10 - x00));
    return glm::vec<3, Real>(gx, gy, gz);
  }

  int GetDimension(int axis) const
  {
    return axis == 0 ? this->Nx : (axis == 1 ? this->Ny : this->Nz);
  }

  // The eight corners of cell (i, j, k), x fastest: c[a + 2 b + 4 c] is the
  // grid point (i + a, j + b, k + c).
  void GetCorners(int i, int j, int k, Real c[8]) const
  {
    const std::ptrdiff_t x = this->Sx, y = this->Sy, z = this->Sz;
    const Storage* p = this->Data + i * x + j * y + k * z;
    c[0] = Real(p[0]);
    c[1] = Real(p[x]);
    c[2] = Real(p[y]);
    c[3] = Real(p[y + x]);
    c[4] = Real(p[z]);
    c[5] = Real(p[z + x]);
    c[6] = Real(p[z + y]);
    c[7] = Real(p[z + y + x]);
  }

private:
  const Storage* Data;
  int Nx, Ny, Nz;
  std::ptrdiff_t Sx, Sy, Sz;
};

// A field constant on each cell of its own walk grid: VTK's cell scalars
// (one value per cell of the point grid), and point scalars read with
// nearest interpolation (each point's value fills the part of the box
// nearer to it than to any other point; on the point grid refined by 2,
// every cell lies in one such part). Its walk grid has unit cells like a
// TrilinearVolume's, so the cell walks, piece walks and integrators take it
// as they are: its cells' corners all hold the cell's value, its cubic
// along a ray is a constant, and a piece is a whole cell. A ray of the point
// grid, origin + t direction, is the ray ToWalk(origin) + t ToWalk(direction)
// here: the same t.
template <typename Real, typename Storage>
class CellConstantVolume
{
public:
  using Point = glm::vec<3, Real>;

  enum class Layout
  {
    Cells,        // `data` has (n - 1) values per axis, x fastest
    NearestPoints // `data` has n values per axis, x fastest
  };

  // `pointDimensions` (n per axis) must be at least 2 on every axis; a value
  // every `stride` entries of `data` (as TrilinearVolume's).
  CellConstantVolume(
    const Storage* data, const int pointDimensions[3], Layout layout, int stride = 1)
    : Data(data)
    , Refine(layout == Layout::NearestPoints ? 2 : 1)
  {
    for (int a = 0; a < 3; ++a)
    {
      const int n = pointDimensions[a];
      this->N[a] = layout == Layout::NearestPoints ? 2 * n - 1 : n;
    }
    const std::ptrdiff_t nx = layout == Layout::Cells ? pointDimensions[0] - 1 : pointDimensions[0];
    const std::ptrdiff_t ny = layout == Layout::Cells ? pointDimensions[1] - 1 : pointDimensions[1];
    this->Sx = stride;
    this->Sy = nx * stride;
    this->Sz = nx * ny * stride;
  }

  // Point-grid coordinates (a position or a direction) to the walk grid's.
  Point ToWalk(const Point& p) const { return p * Real(this->Refine); }

  // The value at p (walk-grid coordinates; clamped onto the box). On a face
  // between cells it is one of theirs: a set no ray spends length in.
  Real operator()(const Point& p) const
  {
    int c[3];
    Real f;
    for (int a = 0; a < 3; ++a)
    {
      detail::LocateCell(p[a], this->N[a], c[a], f);
    }
    return this->Value(c[0], c[1], c[2]);
  }

  // Zero inside every cell (the field's jumps at faces have no gradient).
  glm::vec<3, Real> Gradient(const Point&) const { return glm::vec<3, Real>(Real(0)); }

  // Walk-grid points along an axis.
  int GetDimension(int axis) const { return this->N[axis]; }

  void GetCorners(int i, int j, int k, Real c[8]) const
  {
    const Real v = this->Value(i, j, k);
    std::fill(c, c + 8, v);
  }

private:
  // The value of walk cell (i, j, k): with nearest points, cell i of the
  // refined grid, [i / 2, (i + 1) / 2], is nearest to point (i + 1) / 2.
  Real Value(int i, int j, int k) const
  {
    const int r = this->Refine - 1;
    return Real(
      this
        ->Data[((i + r) >> r) * this->Sx + ((j + r) >> r) * this->Sy + ((k + r) >> r) * this->Sz]);
  }

  const Storage* Data;
  int Refine;
  int N[3] = { 0, 0, 0 };
  std::ptrdiff_t Sx = 1, Sy = 0, Sz = 0;
};

// Cell scalars read as VTK's GPU mapper reads them with linear
// interpolation: the trilinear interpolant of the values at the cell
// centres, clamped at the outer half cells (a texture with one texel per
// cell over the box, clamped to its edge). On the point grid refined by 2
// it is trilinear in every cell: a refined point at a cell centre holds the
// cell's value, one on a face between centres the mean of the cells beside
// it (per axis, clamped at the box), so the walks and integrators take it
// as a TrilinearVolume of that grid. Walk coordinates as CellConstantVolume's.
template <typename Real, typename Storage>
class CellCentredVolume
{
public:
  using Point = glm::vec<3, Real>;

  // `data` has (n - 1) values per axis, x fastest, a value every `stride`
  // entries (as TrilinearVolume's); `pointDimensions` (n per axis) must be
  // at least 2 on every axis.
  CellCentredVolume(const Storage* data, const int pointDimensions[3], int stride = 1)
    : Data(data)
  {
    for (int a = 0; a < 3; ++a)
    {
      this->Cells[a] = pointDimensions[a] - 1;
      this->N[a] = 2 * pointDimensions[a] - 1;
    }
    this->Sx = stride;
    this->Sy = static_cast<std::ptrdiff_t>(this->Cells[0]) * stride;
    this->Sz = static_cast<std::ptrdiff_t>(this->Cells[0]) * this->Cells[1] * stride;
  }

  Point ToWalk(const Point& p) const { return p * Real(2); }

  // The interpolant at p (walk-grid coordinates, clamped onto the box).
  Real operator()(const Point& p) const
  {
    int cell[3];
    Real f[3];
    for (int a = 0; a < 3; ++a)
    {
      detail::LocateCell(p[a], this->N[a], cell[a], f[a]);
    }
    Real c[8];
    this->GetCorners(cell[0], cell[1], cell[2], c);
    return detail::Trilinear(c, f);
  }

  // Shading reads no gradient of this field (the engine refuses it): zero.
  glm::vec<3, Real> Gradient(const Point&) const { return glm::vec<3, Real>(Real(0)); }

  int GetDimension(int axis) const { return this->N[axis]; }

  // The refined grid's values at the corners of walk cell (i, j, k): each
  // the tensor-product mean of the cells beside it (Weights).
  void GetCorners(int i, int j, int k, Real c[8]) const
  {
    int lo[3][2], hi[3][2];
    this->Weights(i, 0, lo[0], hi[0]);
    this->Weights(j, 1, lo[1], hi[1]);
    this->Weights(k, 2, lo[2], hi[2]);
    for (int corner = 0; corner < 8; ++corner)
    {
      const int a = corner & 1, b = (corner >> 1) & 1, d = (corner >> 2) & 1;
      Real sum = Real(0);
      for (int z = 0; z < 2; ++z)
      {
        for (int y = 0; y < 2; ++y)
        {
          for (int x = 0; x < 2; ++x)
          {
            sum += Real(this->Data[(x ? hi : lo)[0][a] * this->Sx + (y ? hi : lo)[1][b] * this->Sy +
              (z ? hi : lo)[2][d] * this->Sz]);
          }
        }
      }
      c[corner] = sum * Real(0.125);
    }
  }

private:
  // Along `axis`, the two cells whose mean is the value at refined points
  // q = index (slot 0) and index + 1 (slot 1): at a centre (q odd) cell
  // (q - 1) / 2 twice; on a face (q even) cells q / 2 - 1 and q / 2, clamped
  // into the box (both the same cell at its ends).
  void Weights(int index, int axis, int lo[2], int hi[2]) const
  {
    const int last = this->Cells[axis] - 1;
    for (int s = 0; s < 2; ++s)
    {
      const int q = index + s;
      if (q & 1)
      {
        lo[s] = hi[s] = (q - 1) / 2;
      }
      else
      {
        lo[s] = std::max(q / 2 - 1, 0);
        hi[s] = std::min(q / 2, last);
      }
    }
  }

  const Storage* Data;
  int Cells[3] = { 0, 0, 0 };
  int N[3] = { 0, 0, 0 };
  std::ptrdiff_t Sx = 1, Sy = 0, Sz = 0;
};

// Clips the ray start + t step, t in [t0, t1], to the grid's box
// [0, n - 1]^3 (slabs). False when it misses; t0 and t1 narrowed otherwise.
// Infinite bounds are allowed (an unbounded ray); a non-finite start or step,
// a NaN bound, or a part that stays infinite (a zero step) misses: a NaN would
// pass every slab comparison and leave [t0, t1] as long as the caller gave it.
template <typename Real>
bool ClipToGrid(const glm::vec<3, Real>& start, const glm::vec<3, Real>& step,
  const int dimensions[3], Real& t0, Real& t1)
{
  if (std::isnan(t0) || std::isnan(t1))
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    if (!std::isfinite(start[a]) || !std::isfinite(step[a]))
    {
      return false;
    }
    const Real hi = Real(dimensions[a] - 1);
    if (step[a] == Real(0))
    {
      if (start[a] < Real(0) || start[a] > hi)
      {
        return false;
      }
      continue;
    }
    Real ta = -start[a] / step[a];
    Real tb = (hi - start[a]) / step[a];
    if (ta > tb)
    {
      std::swap(ta, tb);
    }
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 < t1 && std::isfinite(t0) && std::isfinite(t1);
}

// The scalar along the ray origin + t direction, t in voxel units: the
// `field` argument of the evaluators in RayIntegrators.h (a mixture's
// components' values through ComponentVolumes, Mixture.h).
template <typename Real, typename VolumeT>
struct RayField
{
  const VolumeT& Volume;
  glm::vec<3, Real> Origin;
  glm::vec<3, Real> Direction;

  auto operator()(Real t) const { return this->Volume(this->Origin + t * this->Direction); }
};

} // namespace numerics
} // namespace avos

#endif
