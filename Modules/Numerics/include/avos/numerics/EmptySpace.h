// Empty-space skipping for rays through a TrilinearVolume.
//
// The volume's cells are grouped into blocks of BlockSize^3 cells; each block
// keeps the minimum and maximum of its grid points (faces included, so
// neighbouring blocks overlap by one point). The trilinear interpolant inside
// a block stays within that range, so a block whose range the transfer
// function maps to tau = 0 contributes nothing to any ray, exactly. Ranges
// depend on the data only and are rebuilt when it changes; the visibility of
// the blocks depends on the transfer function too and costs one pass over the
// blocks to renew.
//
// Segments() walks a ray through the blocks (Amanatides and Woo's traversal,
// one block per iteration, so at most Bx + By + Bz iterations) and returns the
// parts of [0, D] that cross visible blocks, widened by `pad` against rounding
// and merged: the segments the evaluators in RayIntegrators.h integrate.
// Spans() returns every block's part of the ray with the block's range: the
// intensity projections visit the blocks that can hold the extremum first.
#ifndef avos_numerics_EmptySpace_h
#define avos_numerics_EmptySpace_h

#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/TransferFunction.h"

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
class EmptySpaceMap
{
public:
  // Cells per block edge. 4 (as VTK's fixed-point mapper's regions) against
  // 8: on Bonsai 800x600 the Riemann sum takes 38 % fewer samples and 10 %
  // less time, the coupled rule 9 % less, the piecewise method 2-3 % less
  // (one run, side by side), for 17 bytes of ranges and visibility per 64
  // cells (27 % of an 8-bit volume's size).
  static constexpr int BlockSize = 4;

  // Dimensions of the volume in grid points, at least 2 on every axis.
  void SetDimensions(const int dimensions[3])
  {
    std::size_t count = 1;
    for (int a = 0; a < 3; ++a)
    {
      this->Dimensions[a] = dimensions[a];
      this->Blocks[a] = (dimensions[a] - 2) / BlockSize + 1;
      count *= static_cast<std::size_t>(this->Blocks[a]);
    }
    this->Minimum.assign(count, Real(0));
    this->Maximum.assign(count, Real(0));
    this->Visible.assign(count, 0);
  }

  int GetNumberOfBlocks(int axis) const { return this->Blocks[axis]; }
  std::size_t GetNumberOfBlocks() const { return this->Visible.size(); }

  // Fills the ranges of the blocks in z-layers [zBegin, zEnd) (layers are
  // independent: callers may fill them in parallel). Returns the number of
  // NaN grid points met.
  template <typename Storage>
  std::size_t ComputeRanges(const Storage* data, int zBegin, int zEnd)
  {
    std::size_t nans = 0;
    const std::ptrdiff_t sy = this->Dimensions[0];
    const std::ptrdiff_t sz = sy * this->Dimensions[1];
    for (int bz = zBegin; bz < zEnd; ++bz)
    {
      for (int by = 0; by < this->Blocks[1]; ++by)
      {
        for (int bx = 0; bx < this->Blocks[0]; ++bx)
        {
          Real lo = std::numeric_limits<Real>::infinity();
          Real hi = -lo;
          const int b[3] = { bx, by, bz };
          int first[3], last[3];
          for (int a = 0; a < 3; ++a)
          {
            first[a] = b[a] * BlockSize;
            last[a] = std::min(first[a] + BlockSize, this->Dimensions[a] - 1);
          }
          for (int k = first[2]; k <= last[2]; ++k)
          {
            for (int j = first[1]; j <= last[1]; ++j)
            {
              const Storage* row = data + k * sz + j * sy;
              for (int i = first[0]; i <= last[0]; ++i)
              {
                const Real v = Real(row[i]);
                if (v != v)
                {
                  ++nans;
                  continue;
                }
                lo = std::min(lo, v);
                hi = std::max(hi, v);
              }
            }
          }
          const std::size_t index = this->Index(bx, by, bz);
          this->Minimum[index] = lo;
          this->Maximum[index] = hi;
        }
      }
    }
    return nans;
  }

  // Marks the blocks where the transfer function can be non-transparent.
  // Returns the number of visible blocks.
  std::size_t Classify(const TransferFunction<Real>& tf)
  {
    std::size_t visible = 0;
    for (std::size_t i = 0; i < this->Visible.size(); ++i)
    {
      // A block of NaN only (lo > hi) is transparent: NaN maps to tau = 0.
      const bool v = this->Minimum[i] <= this->Maximum[i] &&
        tf.GetMaximumExtinction(this->Minimum[i], this->Maximum[i]) > Real(0);
      this->Visible[i] = v ? 1 : 0;
      visible += v ? 1 : 0;
    }
    return visible;
  }

  bool IsVisible(int bx, int by, int bz) const
  {
    return this->Visible[this->Index(bx, by, bz)] != 0;
  }

  // The parts of the ray origin + t direction, t in [0, D], that cross visible
  // blocks. The ray is expected inside the volume's box for t in [0, D].
  void Segments(const glm::vec<3, Real>& origin, const glm::vec<3, Real>& direction, Real D,
    Real pad, std::vector<Interval<Real>>& segments) const
  {
    segments.clear();
    this->WalkBlocks(origin, direction, D,
      [&](std::size_t block, Real t, Real exit)
      {
        if (!this->Visible[block])
        {
          return;
        }
        const Real begin = std::max(t - pad, Real(0));
        const Real end = std::min(exit + pad, D);
        if (!segments.empty() && begin <= segments.back().End)
        {
          segments.back().End = std::max(segments.back().End, end);
        }
        else
        {
          segments.push_back({ begin, end });
        }
      });
  }

  // A block's part of a ray and the block's value range.
  struct Span
  {
    Real Begin, End;
    Real Minimum, Maximum;
  };

  // The parts of the ray in each block it crosses, in order, widened by pad,
  // with the blocks' ranges (blocks of NaN only left out): what the
  // intensity projections search, best block first.
  void Spans(const glm::vec<3, Real>& origin, const glm::vec<3, Real>& direction, Real D, Real pad,
    std::vector<Span>& spans) const
  {
    spans.clear();
    this->WalkBlocks(origin, direction, D,
      [&](std::size_t block, Real t, Real exit)
      {
        if (this->Minimum[block] <= this->Maximum[block])
        {
          spans.push_back({ std::max(t - pad, Real(0)), std::min(exit + pad, D),
            this->Minimum[block], this->Maximum[block] });
        }
      });
  }

private:
  // visit(block index, t, exit) for each block the ray crosses over [0, D]
  // (Amanatides and Woo's traversal over blocks: at most Bx + By + Bz).
  template <typename Visit>
  void WalkBlocks(const glm::vec<3, Real>& origin, const glm::vec<3, Real>& direction, Real D,
    Visit&& visit) const
  {
    if (!(D > Real(0)))
    {
      return;
    }
    const Real inf = std::numeric_limits<Real>::infinity();
    int b[3], step[3];
    Real next[3], delta[3];
    for (int a = 0; a < 3; ++a)
    {
      const Real p = origin[a] / Real(BlockSize);
      b[a] = std::min(std::max(static_cast<int>(std::floor(p)), 0), this->Blocks[a] - 1);
      const Real d = direction[a];
      step[a] = d > Real(0) ? 1 : (d < Real(0) ? -1 : 0);
      delta[a] = step[a] != 0 ? Real(BlockSize) / std::abs(d) : inf;
      next[a] = step[a] > 0 ? (Real((b[a] + 1) * BlockSize) - origin[a]) / d
        : step[a] < 0       ? (Real(b[a] * BlockSize) - origin[a]) / d
                            : inf;
    }
    Real t = Real(0);
    while (t < D)
    {
      const int axis =
        next[0] <= next[1] ? (next[0] <= next[2] ? 0 : 2) : (next[1] <= next[2] ? 1 : 2);
      const Real exit = std::min(next[axis], D);
      if (exit >= t)
      {
        visit(this->Index(b[0], b[1], b[2]), t, exit);
      }
      b[axis] += step[axis];
      if (step[axis] == 0 || b[axis] < 0 || b[axis] >= this->Blocks[axis])
      {
        break;
      }
      t = std::max(t, exit);
      next[axis] += delta[axis];
    }
  }

  std::size_t Index(int bx, int by, int bz) const
  {
    return static_cast<std::size_t>(bx) +
      static_cast<std::size_t>(this->Blocks[0]) *
      (static_cast<std::size_t>(by) + static_cast<std::size_t>(this->Blocks[1]) * bz);
  }

  int Dimensions[3] = { 0, 0, 0 };
  int Blocks[3] = { 0, 0, 0 };
  std::vector<Real> Minimum;
  std::vector<Real> Maximum;
  std::vector<unsigned char> Visible;
};

} // namespace numerics
} // namespace avos

#endif
