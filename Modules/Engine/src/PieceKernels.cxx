// The piecewise method's kernels for every Highway target (foreach_target
// re-includes this file once per target) and the dispatching entry points.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/PieceKernels.cxx"
#include "hwy/foreach_target.h" // IWYU pragma: keep

#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"

#include "avos/engine/PieceKernels.h"

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
constexpr int Degree = Batch::Degree;
constexpr numerics::detail::Reciprocals<double> Inverse{};

// e^x, NaN where x is (Highway's Exp gives 0 there).
template <class D, class V>
HWY_INLINE V ExpKeepingNaN(D d, V x)
{
  return hn::IfThenElse(hn::Eq(x, x), hn::Exp(d, x), x);
}

void DepthsImpl(Batch& b)
{
  const hn::ScalableTag<double> d;
  const int N = static_cast<int>(hn::Lanes(d));
  const double* R = Inverse.R;
  for (int i = 0; i < b.Count; i += N)
  {
    using V = hn::Vec<decltype(d)>;
    const V k[4] = { hn::LoadU(d, b.Q[0] + i), hn::LoadU(d, b.Q[1] + i), hn::LoadU(d, b.Q[2] + i),
      hn::LoadU(d, b.Q[3] + i) };
    const V a = hn::LoadU(d, b.Tau[0] + i), s = hn::LoadU(d, b.Tau[1] + i);
    const V c = hn::LoadU(d, b.Tau[2] + i), e = hn::LoadU(d, b.Tau[3] + i);
    V D[Degree + 1];
    D[0] = hn::Zero(d);
    D[1] = hn::Add(a, hn::Mul(s, k[0]));
    for (int j = 2; j <= 4; ++j)
    {
      D[j] = hn::Mul(hn::Mul(s, k[j - 1]), hn::Set(d, R[j]));
    }
    for (int j = 5; j <= Degree; ++j)
    {
      D[j] = hn::Zero(d);
    }
    // c q^2 + e q^3, as PieceDepth (zero where c = e = 0).
    const V two = hn::Set(d, 2.0);
    const V square[7] = { hn::Mul(k[0], k[0]), hn::Mul(two, hn::Mul(k[0], k[1])),
      hn::Add(hn::Mul(two, hn::Mul(k[0], k[2])), hn::Mul(k[1], k[1])),
      hn::Mul(two, hn::Add(hn::Mul(k[0], k[3]), hn::Mul(k[1], k[2]))),
      hn::Add(hn::Mul(two, hn::Mul(k[1], k[3])), hn::Mul(k[2], k[2])),
      hn::Mul(two, hn::Mul(k[2], k[3])), hn::Mul(k[3], k[3]) };
    for (int j = 0; j < 7; ++j)
    {
      D[j + 1] = hn::Add(D[j + 1], hn::Mul(hn::Mul(c, square[j]), hn::Set(d, R[j + 1])));
      for (int m = 0; m < 4; ++m)
      {
        D[j + m + 1] = hn::Add(
          D[j + m + 1], hn::Mul(hn::Mul(hn::Mul(e, square[j]), k[m]), hn::Set(d, R[j + m + 1])));
      }
    }
    const V l = hn::LoadU(d, b.Length + i);
    V theta = D[Degree];
    for (int j = Degree; j >= 1; --j)
    {
      hn::StoreU(D[j], d, b.Depth[j] + i);
      theta = hn::MulAdd(theta, l, D[j - 1]);
    }
    // max(theta, 0) keeping a NaN, as PieceDepth.
    theta = hn::IfThenElse(hn::Lt(theta, hn::Zero(d)), hn::Zero(d), theta);
    hn::StoreU(ExpKeepingNaN(d, hn::Neg(theta)), d, b.Transmittance + i);
    // numerics::detail::Monotone: s' at both ends and at the vertex of the
    // quadratic s' where it lies inside (none where K[3] = 0: the vertex is
    // then infinite or NaN, never inside).
    const V three = hn::Set(d, 3.0);
    auto derivative = [&](V u)
    { return hn::MulAdd(u, hn::MulAdd(u, hn::Mul(three, k[3]), hn::Mul(two, k[2])), k[1]); };
    const V d1 = derivative(l);
    V lo = hn::Min(k[1], d1), hi = hn::Max(k[1], d1);
    const V vertex = hn::Div(hn::Neg(k[2]), hn::Mul(three, k[3]));
    const auto inside = hn::And(hn::Gt(vertex, hn::Zero(d)), hn::Lt(vertex, l));
    const V dv = derivative(hn::IfThenElseZero(inside, vertex));
    lo = hn::IfThenElse(inside, hn::Min(lo, dv), lo);
    hi = hn::IfThenElse(inside, hn::Max(hi, dv), hi);
    const auto monotone = hn::Or(hn::Ne(hn::LoadU(d, b.Monotone + i), hn::Zero(d)),
      hn::Or(hn::Ge(lo, hn::Zero(d)), hn::Le(hi, hn::Zero(d))));
    hn::StoreU(hn::IfThenElseZero(monotone, hn::Set(d, 1.0)), d, b.Monotone + i);
  }
}

void SeriesImpl(Series& b)
{
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const int N = static_cast<int>(hn::Lanes(d));
  constexpr int Terms = numerics::detail::MaximumTerms;
  const double* R = Inverse.R;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), inverseL = hn::Set(d, b.InverseLength);
  for (int i = 0; i < b.Count; i += N)
  {
    const V l = hn::LoadU(d, b.Length + i), E = hn::LoadU(d, b.Transmittance + i);
    const V g0 = hn::LoadU(d, b.Slope[0] + i), g1 = hn::LoadU(d, b.Slope[1] + i),
            g2 = hn::LoadU(d, b.Slope[2] + i);
    const V limit = hn::Mul(hn::LoadU(d, b.Scale + i),
      hn::MulAdd(hn::LoadU(d, b.Front + i), hn::Sub(one, E), hn::Mul(l, inverseL)));
    // l max|q'|: the rest bound at v = 0 (J within the share as 0), and the
    // tail's factor.
    const V lgmax = hn::Mul(l, hn::MulAdd(l, hn::MulAdd(l, hn::Abs(g2), hn::Abs(g1)), hn::Abs(g0)));
    const auto rest = hn::Le(lgmax, limit);
    V weight[Degree + 1], magnitudeWeight[Degree + 1];
    V A = zero;
    for (int j = Degree; j >= 1; --j)
    {
      const V theta = hn::LoadU(d, b.Depth[j] + i);
      A = hn::Mul(hn::Add(A, hn::Abs(theta)), l);
      weight[j] = hn::Mul(hn::Set(d, double(j)), theta);
      magnitudeWeight[j] = hn::Abs(weight[j]);
    }
    // Lanes still adding terms; a lane with A > 1 (or NaN) is left to
    // SeriesIntegral.
    auto open = hn::AndNot(rest, hn::Le(A, one));
    const V whole = hn::Exp(d, hn::IfThenElseZero(open, A));
    auto settled = rest;
    V c[Terms + 1], C[Terms + 1];
    c[0] = one;
    C[0] = one;
    V partial = one, sum = zero, hk = one;
    for (int k = 0; k <= Terms && !hn::AllFalse(d, open); ++k)
    {
      const V term = hn::Mul(hn::Mul(hn::Mul(c[k], hk), l),
        hn::MulAdd(l,
          hn::MulAdd(l, hn::Mul(g2, hn::Set(d, R[k + 3])), hn::Mul(g1, hn::Set(d, R[k + 2]))),
          hn::Mul(g0, hn::Set(d, R[k + 1]))));
      sum = hn::IfThenElse(open, hn::Add(sum, term), sum);
      const V tail = hn::Max(hn::Sub(whole, partial), zero);
      const auto now = hn::And(open, hn::Le(hn::Mul(lgmax, tail), limit));
      settled = hn::Or(settled, now);
      open = hn::AndNot(now, open);
      if (k == Terms)
      {
        break;
      }
      V next = zero, nextMajorant = zero;
      for (int j = 1; j <= (k + 1 < Degree ? k + 1 : Degree); ++j)
      {
        next = hn::NegMulAdd(weight[j], c[k + 1 - j], next);
        nextMajorant = hn::MulAdd(magnitudeWeight[j], C[k + 1 - j], nextMajorant);
      }
      c[k + 1] = hn::Mul(next, hn::Set(d, R[k + 1]));
      C[k + 1] = hn::Mul(nextMajorant, hn::Set(d, R[k + 1]));
      hk = hn::Mul(hk, l);
      partial = hn::MulAdd(C[k + 1], hk, partial);
    }
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
