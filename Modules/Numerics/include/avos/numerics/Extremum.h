// Maximum and minimum intensity projection, exactly: the largest (smallest)
// value of the trilinear interpolant along a ray.
//
// Inside a cell the interpolant along the ray is a cubic s(u) (Pieces.h,
// CellCubic), so its extremum over the part of the ray in the cell is at an
// end of that part or where s'(u) = 0, the roots of a quadratic: no sampling,
// nothing between samples to miss (a sampled projection with step h misses a
// peak's top by up to |s''| h^2 / 8). A cell whose corners cannot beat the
// best value so far (the interpolant stays between their minimum and
// maximum) is passed over without its cubic. Cells with a non-finite corner
// are passed over (undefined there, as for the other methods). The value is
// exact up to rounding in Real.
#ifndef avos_numerics_Extremum_h
#define avos_numerics_Extremum_h

#include "avos/numerics/EmptySpace.h"
#include "avos/numerics/Pieces.h"
#include "avos/numerics/RayIntegrators.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace avos
{
namespace numerics
{

template <typename Real>
struct RayExtremum
{
  bool Found = false; // false: no finite cell on the segments
  Real Value = Real(0);
  long Cells = 0; // cells whose cubic was examined
};

// Updates `result` with the maximum (`maximum`) or minimum of the trilinear
// interpolant of `volume` on the ray origin + t direction over the sorted,
// disjoint segments: cells that cannot beat result.Value (when Found) are
// passed over, so parts of a ray may be searched best first.
template <typename Real, typename VolumeT>
void ExtremumAlongRay(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  bool maximum, RayExtremum<Real>& result)
{
  // Compare as a maximum: the minimum is the maximum of -s.
  const Real sign = maximum ? Real(1) : Real(-1);
  Real best = result.Found ? sign * result.Value : -std::numeric_limits<Real>::infinity();
  auto cell = [&](const int index[3], Real t, Real t1) -> bool
  {
    Real c[8];
    volume.GetCorners(index[0], index[1], index[2], c);
    Real top = sign * c[0], bottom = top;
    for (int i = 1; i < 8; ++i)
    {
      top = std::max(top, sign * c[i]);
      bottom = std::min(bottom, sign * c[i]);
    }
    if (!std::isfinite(c[0] + c[1] + c[2] + c[3] + c[4] + c[5] + c[6] + c[7]) || top <= best)
    {
      return true;
    }
    ++result.Cells;
    const Cubic<Real> s = CellCubic(c,
      origin + t * direction - glm::vec<3, Real>(Real(index[0]), Real(index[1]), Real(index[2])),
      direction);
    const Real length = t1 - t;
    // The interpolant never leaves the corners' range: values the cubic's
    // rounding puts beyond it (relative 1e-16 of the corners' magnitude) are
    // clamped back (a NaN from overflowing coefficients to the bottom).
    auto at = [&](Real u) { return std::min(top, std::max(bottom, sign * s(u))); };
    best = std::max({ best, at(Real(0)), at(length) });
    Real roots[2];
    const int r = detail::QuadraticRoots(Real(3) * s.K[3], Real(2) * s.K[2], s.K[1], length, roots);
    for (int i = 0; i < r; ++i)
    {
      best = std::max(best, at(roots[i]));
    }
    result.Found = true;
    return true;
  };
  for (std::size_t j = 0; j < count; ++j)
  {
    CellWalk(volume, origin, direction, segments[j].Begin, segments[j].End, cell);
  }
  if (result.Found)
  {
    result.Value = sign * best;
  }
}

template <typename Real, typename VolumeT>
RayExtremum<Real> ExtremumAlongRay(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  bool maximum)
{
  RayExtremum<Real> result;
  ExtremumAlongRay(volume, origin, direction, segments, count, maximum, result);
  return result;
}

// The same, searching the blocks of `map` the ray crosses best first: each
// block's part of the ray (EmptySpaceMap::Spans, widened by `pad`) in the
// order of the block's range, until a block's range cannot beat the
// extremum found, when neither can the rest. The ray lies in the volume's
// box for t in [0, D], the segments in [0, D]; `spans` is scratch space.
template <typename Real, typename VolumeT>
RayExtremum<Real> ExtremumByBlocks(const VolumeT& volume, const EmptySpaceMap<Real>& map,
  const glm::vec<3, Real>& origin, const glm::vec<3, Real>& direction, Real D, Real pad,
  const Interval<Real>* segments, std::size_t count, bool maximum,
  std::vector<typename EmptySpaceMap<Real>::Span>& spans)
{
  RayExtremum<Real> result;
  map.Spans(origin, direction, D, pad, spans);
  std::sort(spans.begin(), spans.end(),
    [maximum](const auto& a, const auto& b)
    { return maximum ? a.Maximum > b.Maximum : a.Minimum < b.Minimum; });
  for (const auto& span : spans)
  {
    if (result.Found && (maximum ? span.Maximum <= result.Value : span.Minimum >= result.Value))
    {
      break;
    }
    for (std::size_t j = 0; j < count; ++j)
    {
      const Interval<Real> part{ std::max(segments[j].Begin, span.Begin),
        std::min(segments[j].End, span.End) };
      if (part.Begin < part.End)
      {
        ExtremumAlongRay(volume, origin, direction, &part, 1, maximum, result);
      }
    }
  }
  return result;
}

} // namespace numerics
} // namespace avos

#endif
