// The piecewise method's kernels for every Highway target (foreach_target
// re-includes this file once per target) and the dispatching entry points.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/PieceKernels.cxx"
#include "hwy/foreach_target.h" // IWYU pragma: keep

#include "hwy/highway.h"

#include "avos/engine/PieceKernels.h"
#include "src/PieceLanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace avos
{
namespace engine
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;

using Batch = numerics::PieceBatch<double>;
using Series = numerics::SeriesBatch<double>;

void DepthsImpl(Batch& b)
{
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const int N = static_cast<int>(hn::Lanes(d));
  for (int i = 0; i < b.Count; i += N)
  {
    const V k[4] = { hn::LoadU(d, b.Q[0] + i), hn::LoadU(d, b.Q[1] + i), hn::LoadU(d, b.Q[2] + i),
      hn::LoadU(d, b.Q[3] + i) };
    const V l = hn::LoadU(d, b.Length + i);
    V depth[PieceDegree + 1];
    const V E = DepthLanes(d, k, hn::LoadU(d, b.Tau[0] + i), hn::LoadU(d, b.Tau[1] + i),
      hn::LoadU(d, b.Tau[2] + i), hn::LoadU(d, b.Tau[3] + i), l, depth);
    for (int j = 1; j <= PieceDegree; ++j)
    {
      hn::StoreU(depth[j], d, b.Depth[j] + i);
    }
    hn::StoreU(E, d, b.Transmittance + i);
    const auto monotone =
      hn::Or(hn::Ne(hn::LoadU(d, b.Monotone + i), hn::Zero(d)), MonotoneLanes(d, k, l));
    hn::StoreU(hn::IfThenElseZero(monotone, hn::Set(d, 1.0)), d, b.Monotone + i);
  }
}

void SeriesImpl(Series& b)
{
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const int N = static_cast<int>(hn::Lanes(d));
  const V one = hn::Set(d, 1.0), inverseL = hn::Set(d, b.InverseLength);
  for (int i = 0; i < b.Count; i += N)
  {
    const V l = hn::LoadU(d, b.Length + i), E = hn::LoadU(d, b.Transmittance + i);
    const V limit = hn::Mul(hn::LoadU(d, b.Scale + i),
      hn::MulAdd(hn::LoadU(d, b.Front + i), hn::Sub(one, E), hn::Mul(l, inverseL)));
    V theta[PieceDegree + 1];
    for (int j = 1; j <= PieceDegree; ++j)
    {
      theta[j] = hn::LoadU(d, b.Depth[j] + i);
    }
    V sum;
    const auto settled = SeriesLanes(d, theta, hn::LoadU(d, b.Slope[0] + i),
      hn::LoadU(d, b.Slope[1] + i), hn::LoadU(d, b.Slope[2] + i), l, limit, sum);
    hn::StoreU(sum, d, b.J + i);
    hn::StoreU(hn::IfThenElseZero(settled, one), d, b.Settled + i);
  }
}

const char* PieceTargetNameImpl()
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
HWY_EXPORT(DepthsImpl);
HWY_EXPORT(SeriesImpl);
HWY_EXPORT(PieceTargetNameImpl);

void PieceKernels::Depths(numerics::PieceBatch<double>& batch) const
{
  HWY_DYNAMIC_DISPATCH(DepthsImpl)(batch);
}

void PieceKernels::Series(numerics::SeriesBatch<double>& batch) const
{
  HWY_DYNAMIC_DISPATCH(SeriesImpl)(batch);
}

const char* PieceKernelsTarget()
{
  return HWY_DYNAMIC_DISPATCH(PieceTargetNameImpl)();
}
} // namespace engine
} // namespace avos
#endif
