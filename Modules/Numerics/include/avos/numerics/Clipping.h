// The part of a ray that clipping planes and cropping regions keep, exactly.
//
// A clipping plane keeps the closed half-space its normal points into,
// n . x + d >= 0; along a ray x(t) = o + t u that is a linear inequality in
// t, so the planes together keep one interval, its ends the roots of the
// planes' equations. Cropping (VTK's vtkVolumeMapper semantics) cuts the box
// by two planes per axis into 3 x 3 x 3 regions, region i + 3 j + 9 k (0 below
// the lower plane, 1 between, 2 above the upper one) kept when bit
// i + 3 j + 9 k of the flags is set; along a ray the region changes only where
// the ray crosses one of the six planes, so the kept part is a union of at
// most 7 intervals, each classified at its middle. Everything is in grid
// coordinates (continuous indices; the caller transforms its planes), and
// the ends are computed from the plane equations in Real, with no sampling:
// the integrators then integrate exactly the kept part.
#ifndef avos_numerics_Clipping_h
#define avos_numerics_Clipping_h

#include "avos/numerics/RayIntegrators.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace avos
{
namespace numerics
{

template <typename Real>
class ClipRegion
{
public:
  using Point = glm::vec<3, Real>;

  // Keeps Normal . x + Offset >= 0.
  struct HalfSpace
  {
    Point Normal;
    Real Offset;
  };

  static constexpr int AllRegions = (1 << 27) - 1;

  void Clear()
  {
    this->Planes.clear();
    this->Cropping = false;
  }
  void AddPlane(const Point& normal, Real offset) { this->Planes.push_back({ normal, offset }); }
  // planes: xmin, xmax, ymin, ymax, zmin, zmax; flags: the 27 region bits.
  void SetCropping(const Real planes[6], int flags)
  {
    std::copy(planes, planes + 6, this->CropPlanes);
    this->CropFlags = flags;
    this->Cropping = true;
  }

  const std::vector<HalfSpace>& GetPlanes() const { return this->Planes; }
  bool GetCropping() const { return this->Cropping; }
  const Real* GetCropPlanes() const { return this->CropPlanes; }
  int GetCropFlags() const { return this->CropFlags; }

  // True when nothing is clipped or cropped.
  bool IsEmpty() const { return this->Planes.empty() && !this->Cropping; }

  // Empty when usable, else why.
  std::string Validate() const
  {
    for (const HalfSpace& h : this->Planes)
    {
      const Real n = std::abs(h.Normal.x) + std::abs(h.Normal.y) + std::abs(h.Normal.z);
      if (!(n > Real(0)) || !std::isfinite(n) || !std::isfinite(h.Offset))
      {
        return "a clipping plane needs a finite, non-zero normal and a finite origin";
      }
    }
    if (this->Cropping)
    {
      for (int a = 0; a < 3; ++a)
      {
        const Real lo = this->CropPlanes[2 * a], hi = this->CropPlanes[2 * a + 1];
        if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi))
        {
          return "the cropping region planes must be finite, each minimum at most its maximum";
        }
      }
      if (this->CropFlags < 0 || this->CropFlags > AllRegions)
      {
        return "the cropping region flags must be a 27-bit mask";
      }
    }
    return std::string();
  }

  // The kept part of the ray origin + t direction, t in [0, D]: sorted,
  // disjoint intervals, none empty (`kept` is replaced).
  void Kept(
    const Point& origin, const Point& direction, Real D, std::vector<Interval<Real>>& kept) const
  {
    kept.clear();
    Real t0 = Real(0), t1 = D;
    for (const HalfSpace& h : this->Planes)
    {
      // f(t) = a + b t >= 0.
      const Real a = glm::dot(h.Normal, origin) + h.Offset;
      const Real b = glm::dot(h.Normal, direction);
      if (b > Real(0))
      {
        t0 = std::max(t0, -a / b);
      }
      else if (b < Real(0))
      {
        t1 = std::min(t1, -a / b);
      }
      else if (a < Real(0))
      {
        return; // parallel, on the clipped side
      }
    }
    if (!(t0 < t1))
    {
      return;
    }
    if (!this->Cropping)
    {
      kept.push_back({ t0, t1 });
      return;
    }
    // Where the ray crosses a cropping plane inside (t0, t1), in order.
    Real cuts[8];
    int n = 0;
    cuts[n++] = t0;
    for (int a = 0; a < 3; ++a)
    {
      if (direction[a] == Real(0))
      {
        continue;
      }
      for (int side = 0; side < 2; ++side)
      {
        const Real t = (this->CropPlanes[2 * a + side] - origin[a]) / direction[a];
        if (t > t0 && t < t1)
        {
          cuts[n++] = t;
        }
      }
    }
    // At most six: insertion sort.
    for (int i = 2; i < n; ++i)
    {
      for (int j = i; j > 1 && cuts[j] < cuts[j - 1]; --j)
      {
        std::swap(cuts[j], cuts[j - 1]);
      }
    }
    cuts[n++] = t1;
    for (int i = 0; i + 1 < n; ++i)
    {
      const Real a = cuts[i], b = cuts[i + 1];
      if (!(b > a) || !this->RegionKept(origin + (Real(0.5) * (a + b)) * direction))
      {
        continue;
      }
      if (!kept.empty() && kept.back().End >= a)
      {
        kept.back().End = b; // adjacent kept regions: one interval
      }
      else
      {
        kept.push_back({ a, b });
      }
    }
  }

  // out = the intersection of two sorted, disjoint interval lists (out is
  // neither of them).
  static void Intersect(const std::vector<Interval<Real>>& x, const std::vector<Interval<Real>>& y,
    std::vector<Interval<Real>>& out)
  {
    out.clear();
    std::size_t i = 0, j = 0;
    while (i < x.size() && j < y.size())
    {
      const Real a = std::max(x[i].Begin, y[j].Begin);
      const Real b = std::min(x[i].End, y[j].End);
      if (a < b)
      {
        out.push_back({ a, b });
      }
      (x[i].End < y[j].End ? i : j)++;
    }
  }

  bool operator==(const ClipRegion& other) const
  {
    if (this->Planes.size() != other.Planes.size() || this->Cropping != other.Cropping)
    {
      return false;
    }
    for (std::size_t i = 0; i < this->Planes.size(); ++i)
    {
      if (this->Planes[i].Normal != other.Planes[i].Normal ||
        this->Planes[i].Offset != other.Planes[i].Offset)
      {
        return false;
      }
    }
    return !this->Cropping ||
      (std::equal(this->CropPlanes, this->CropPlanes + 6, other.CropPlanes) &&
        this->CropFlags == other.CropFlags);
  }
  bool operator!=(const ClipRegion& other) const { return !(*this == other); }

private:
  bool RegionKept(const Point& p) const
  {
    int region = 0, weight = 1;
    for (int a = 0; a < 3; ++a, weight *= 3)
    {
      const int index =
        p[a] < this->CropPlanes[2 * a] ? 0 : (p[a] > this->CropPlanes[2 * a + 1] ? 2 : 1);
      region += index * weight;
    }
    return (this->CropFlags >> region) & 1;
  }

  std::vector<HalfSpace> Planes;
  bool Cropping = false;
  Real CropPlanes[6] = { Real(0), Real(0), Real(0), Real(0), Real(0), Real(0) };
  int CropFlags = AllRegions;
};

} // namespace numerics
} // namespace avos

#endif
