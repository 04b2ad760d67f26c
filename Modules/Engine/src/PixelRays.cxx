// A frame's pixel rays for every Highway target (foreach_target re-includes
// this file once per target), the dispatching entry points and the scalar
// ray (under HWY_ONCE). RowRays repeats PixelRay's arithmetic operation for
// operation; the CMake file turns off the contraction of multiply-adds here.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/PixelRays.cxx"
#include "hwy/foreach_target.h" // IWYU pragma: keep

#include "hwy/highway.h"

#include "avos/engine/PixelRays.h"
#include "avos/numerics/Volume.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

HWY_BEFORE_NAMESPACE();
namespace avos
{
namespace engine
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;

int RowRaysImpl(const FrameRays& frame, int y, int x0, int x1, int* xs, double* origins,
  double* directions, double* lengths)
{
  const hn::ScalableTag<double> d;
  const hn::Rebind<float, decltype(d)> df;
  using V = hn::Vec<decltype(d)>;
  using M = hn::Mask<decltype(d)>;
  const int lanes = static_cast<int>(hn::Lanes(d));
  constexpr int MaximumLanes = HWY_MAX_BYTES / sizeof(double);
  HWY_ALIGN float depths[MaximumLanes];
  HWY_ALIGN double out[8][MaximumLanes];
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
  const V half = hn::Set(d, 0.5);
  const V ny = hn::Set(d, 2.0 * (y + 0.5) / frame.Height - 1.0);
  const float* row = frame.Depth + static_cast<std::size_t>(y) * frame.Width;
  // Row i of a matrix times (p0, p1, p2, p3), summed left to right.
  auto product = [&](const double* m, int i, V p0, V p1, V p2, V p3) HWY_ATTR
  {
    const V a = hn::Add(hn::Mul(hn::Set(d, m[4 * i]), p0), hn::Mul(hn::Set(d, m[4 * i + 1]), p1));
    const V b = hn::Add(a, hn::Mul(hn::Set(d, m[4 * i + 2]), p2));
    return hn::Add(b, hn::Mul(hn::Set(d, m[4 * i + 3]), p3));
  };
  int count = 0;
  for (int x = x0; x < x1; x += lanes)
  {
    const int used = std::min(lanes, x1 - x);
    for (int k = 0; k < lanes; ++k)
    {
      depths[k] = row[x + std::min(k, used - 1)];
    }
    const V nx = hn::Sub(
      hn::Div(hn::Mul(two, hn::Add(hn::Iota(d, double(x)), half)), hn::Set(d, double(frame.Width))),
      one);
    const V depth = hn::PromoteTo(d, hn::Load(df, depths));
    const V nearZ = hn::Set(d, -1.0), farZ = hn::Sub(hn::Mul(two, depth), one);
    V nearWorld[3], farWorld[3];
    const double* toWorld = frame.NDCToWorld;
    const V nearW = product(toWorld, 3, nx, ny, nearZ, one);
    const V farW = product(toWorld, 3, nx, ny, farZ, one);
    for (int a = 0; a < 3; ++a)
    {
      nearWorld[a] = hn::Div(product(toWorld, a, nx, ny, nearZ, one), nearW);
      farWorld[a] = hn::Div(product(toWorld, a, nx, ny, farZ, one), farW);
    }
    const V dx = hn::Sub(farWorld[0], nearWorld[0]), dy = hn::Sub(farWorld[1], nearWorld[1]);
    const V dz = hn::Sub(farWorld[2], nearWorld[2]);
    const V length =
      hn::Div(hn::Sqrt(hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz))),
        hn::Set(d, frame.Voxel));
    M hit = hn::And(hn::Gt(length, zero), hn::IsFinite(length));
    hit = hn::And(hit, hn::FirstN(d, static_cast<std::size_t>(used)));
    V nearGrid[3], direction[3];
    for (int a = 0; a < 3; ++a)
    {
      const double* toGrid = frame.WorldToGrid;
      nearGrid[a] = product(toGrid, a, nearWorld[0], nearWorld[1], nearWorld[2], one);
      const V farGrid = product(toGrid, a, farWorld[0], farWorld[1], farWorld[2], one);
      direction[a] = hn::Div(hn::Sub(farGrid, nearGrid[a]), length);
    }
    // numerics::ClipToGrid, slab by slab, with std::max and std::min's
    // choices on ties.
    V t0 = zero, t1 = length;
    for (int a = 0; a < 3; ++a)
    {
      const V start = nearGrid[a], step = direction[a];
      const V hi = hn::Set(d, double(frame.Dimensions[a] - 1));
      hit = hn::And(hit, hn::And(hn::IsFinite(start), hn::IsFinite(step)));
      const M flat = hn::Eq(step, zero);
      hit = hn::AndNot(hn::And(flat, hn::Or(hn::Lt(start, zero), hn::Gt(start, hi))), hit);
      V ta = hn::Div(hn::Neg(start), step);
      V tb = hn::Div(hn::Sub(hi, start), step);
      const M swap = hn::Gt(ta, tb);
      const V lo = hn::IfThenElse(swap, tb, ta), up = hn::IfThenElse(swap, ta, tb);
      t0 = hn::IfThenElse(flat, t0, hn::IfThenElse(hn::Lt(t0, lo), lo, t0));
      t1 = hn::IfThenElse(flat, t1, hn::IfThenElse(hn::Lt(up, t1), up, t1));
    }
    hit = hn::And(hit, hn::And(hn::Lt(t0, t1), hn::And(hn::IsFinite(t0), hn::IsFinite(t1))));
    if (hn::AllFalse(d, hit))
    {
      continue;
    }
    for (int a = 0; a < 3; ++a)
    {
      hn::Store(hn::Add(nearGrid[a], hn::Mul(t0, direction[a])), d, out[a]);
      hn::Store(direction[a], d, out[3 + a]);
    }
    hn::Store(hn::Sub(t1, t0), d, out[6]);
    hn::Store(hn::IfThenElseZero(hit, one), d, out[7]);
    for (int k = 0; k < used; ++k)
    {
      if (out[7][k] != 0.0)
      {
        xs[count] = x + k;
        for (int a = 0; a < 3; ++a)
        {
          origins[3 * count + a] = out[a][k];
          directions[3 * count + a] = out[3 + a][k];
        }
        lengths[count++] = out[6][k];
      }
    }
  }
  return count;
}

const char* RowTargetNameImpl()
{
  return hwy::TargetName(HWY_TARGET);
}

} // namespace HWY_NAMESPACE
} // namespace engine
} // namespace avos
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace avos
{
namespace engine
{
HWY_EXPORT(RowRaysImpl);
HWY_EXPORT(RowTargetNameImpl);

namespace
{
// Row i of a matrix times p, summed left to right.
double Product(const double* m, int i, const double p[4])
{
  return m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3] * p[3];
}
} // namespace

bool PixelRay(
  const FrameRays& frame, int x, int y, double origin[3], double direction[3], double& D)
{
  const double nx = 2.0 * (x + 0.5) / frame.Width - 1.0;
  const double ny = 2.0 * (y + 0.5) / frame.Height - 1.0;
  const double depth = frame.Depth[static_cast<std::size_t>(y) * frame.Width + x];
  const double nearNDC[4] = { nx, ny, -1.0, 1.0 }, farNDC[4] = { nx, ny, 2.0 * depth - 1.0, 1.0 };
  const double nearW = Product(frame.NDCToWorld, 3, nearNDC);
  const double farW = Product(frame.NDCToWorld, 3, farNDC);
  double nearWorld[4], farWorld[4];
  for (int a = 0; a < 3; ++a)
  {
    nearWorld[a] = Product(frame.NDCToWorld, a, nearNDC) / nearW;
    farWorld[a] = Product(frame.NDCToWorld, a, farNDC) / farW;
  }
  nearWorld[3] = farWorld[3] = 1.0;
  const double dx = farWorld[0] - nearWorld[0], dy = farWorld[1] - nearWorld[1];
  const double dz = farWorld[2] - nearWorld[2];
  const double length = std::sqrt(dx * dx + dy * dy + dz * dz) / frame.Voxel;
  if (!(length > 0.0) || !std::isfinite(length))
  {
    return false;
  }
  glm::dvec3 nearGrid, step;
  for (int a = 0; a < 3; ++a)
  {
    nearGrid[a] = Product(frame.WorldToGrid, a, nearWorld);
    step[a] = (Product(frame.WorldToGrid, a, farWorld) - nearGrid[a]) / length;
  }
  double t0 = 0.0, t1 = length;
  if (!numerics::ClipToGrid(nearGrid, step, frame.Dimensions, t0, t1))
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    origin[a] = nearGrid[a] + t0 * step[a];
    direction[a] = step[a];
  }
  D = t1 - t0;
  return true;
}

int RowRays(const FrameRays& frame, int y, int x0, int x1, int* xs, double* origins,
  double* directions, double* lengths)
{
  if (x1 <= x0)
  {
    return 0;
  }
  return HWY_DYNAMIC_DISPATCH(RowRaysImpl)(frame, y, x0, x1, xs, origins, directions, lengths);
}

const char* RowRaysTarget()
{
  return HWY_DYNAMIC_DISPATCH(RowTargetNameImpl)();
}

} // namespace engine
} // namespace avos
#endif
