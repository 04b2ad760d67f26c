// Per-target helpers of the piecewise method's piece stages, shared by the
// batch kernels (PieceKernels.cxx) and the ray-per-lane integrator
// (PiecewiseRays.cxx), a piece per lane in double: the depth polynomial and
// transmittance (numerics::detail::PieceDepth), the monotonicity test
// (numerics::detail::Monotone) and the first sub-interval of
// numerics::detail::SeriesIntegral. Highway's per-target include guard: the
// file is re-included once per target by foreach_target.
#if defined(AVOS_ENGINE_PIECE_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef AVOS_ENGINE_PIECE_LANES_INL_H_
#undef AVOS_ENGINE_PIECE_LANES_INL_H_
#else
#define AVOS_ENGINE_PIECE_LANES_INL_H_
#endif

#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"

#include "avos/numerics/PiecewiseIntegrator.h"

HWY_BEFORE_NAMESPACE();
namespace avos
{
namespace engine
{
namespace HWY_NAMESPACE
{
namespace hn = hwy::HWY_NAMESPACE;

constexpr int PieceDegree = numerics::detail::PieceDepth<double>::MaximumDegree;

// e^x, NaN where x is (Highway's Exp gives 0 there).
template <class D, class V>
HWY_INLINE V ExpKeepingNaN(D d, V x)
{
  return hn::IfThenElse(hn::Eq(x, x), hn::Exp(d, x), x);
}

// theta's coefficients D[0..10] (PieceDepth at degree 10; those a lane does
// not have come out 0) of q = k[0..3] and tau = a + b q + c q^2 + e q^3, and
// e^{-theta(l)}.
template <class D>
HWY_INLINE hn::Vec<D> DepthLanes(D d, const hn::Vec<D> k[4], hn::Vec<D> a, hn::Vec<D> b,
  hn::Vec<D> c, hn::Vec<D> e, hn::Vec<D> l, hn::Vec<D> depth[PieceDegree + 1])
{
  using V = hn::Vec<D>;
  static constexpr numerics::detail::Reciprocals<double> Inverse{};
  const double* R = Inverse.R;
  depth[0] = hn::Zero(d);
  depth[1] = hn::Add(a, hn::Mul(b, k[0]));
  for (int j = 2; j <= 4; ++j)
  {
    depth[j] = hn::Mul(hn::Mul(b, k[j - 1]), hn::Set(d, R[j]));
  }
  for (int j = 5; j <= PieceDegree; ++j)
  {
    depth[j] = hn::Zero(d);
  }
  // c q^2 + e q^3, as PieceDepth: none where c = e = 0 in every lane (the
  // extinction model's pieces, linear in s), as PieceDepth leaves them out.
  if (hn::AllTrue(d, hn::And(hn::Eq(c, hn::Zero(d)), hn::Eq(e, hn::Zero(d)))))
  {
    V theta = depth[4];
    for (int j = 4; j >= 1; --j)
    {
      theta = hn::MulAdd(theta, l, depth[j - 1]);
    }
    theta = hn::IfThenElse(hn::Lt(theta, hn::Zero(d)), hn::Zero(d), theta);
    return ExpKeepingNaN(d, hn::Neg(theta));
  }
  const V two = hn::Set(d, 2.0);
  const V square[7] = { hn::Mul(k[0], k[0]), hn::Mul(two, hn::Mul(k[0], k[1])),
    hn::Add(hn::Mul(two, hn::Mul(k[0], k[2])), hn::Mul(k[1], k[1])),
    hn::Mul(two, hn::Add(hn::Mul(k[0], k[3]), hn::Mul(k[1], k[2]))),
    hn::Add(hn::Mul(two, hn::Mul(k[1], k[3])), hn::Mul(k[2], k[2])),
    hn::Mul(two, hn::Mul(k[2], k[3])), hn::Mul(k[3], k[3]) };
  // Degree 7 where no lane's extinction is cubic (the e terms left out).
  const bool cubic = !hn::AllTrue(d, hn::Eq(e, hn::Zero(d)));
  for (int j = 0; j < 7; ++j)
  {
    depth[j + 1] = hn::Add(depth[j + 1], hn::Mul(hn::Mul(c, square[j]), hn::Set(d, R[j + 1])));
    for (int m = 0; cubic && m < 4; ++m)
    {
      depth[j + m + 1] = hn::Add(
        depth[j + m + 1], hn::Mul(hn::Mul(hn::Mul(e, square[j]), k[m]), hn::Set(d, R[j + m + 1])));
    }
  }
  const int degree = cubic ? PieceDegree : 7;
  V theta = depth[degree];
  for (int j = degree; j >= 1; --j)
  {
    theta = hn::MulAdd(theta, l, depth[j - 1]);
  }
  // max(theta, 0) keeping a NaN, as PieceDepth.
  theta = hn::IfThenElse(hn::Lt(theta, hn::Zero(d)), hn::Zero(d), theta);
  return ExpKeepingNaN(d, hn::Neg(theta));
}

// numerics::detail::Monotone: s' at both ends and at the vertex of the
// quadratic s' where it lies inside (none where k[3] = 0: the vertex is then
// infinite or NaN, never inside).
template <class D>
HWY_INLINE hn::Mask<D> MonotoneLanes(D d, const hn::Vec<D> k[4], hn::Vec<D> l)
{
  using V = hn::Vec<D>;
  const V two = hn::Set(d, 2.0), three = hn::Set(d, 3.0);
  auto derivative = [&](V u)
  { return hn::MulAdd(u, hn::MulAdd(u, hn::Mul(three, k[3]), hn::Mul(two, k[2])), k[1]); };
  const V d1 = derivative(l);
  V lo = hn::Min(k[1], d1), hi = hn::Max(k[1], d1);
  const V vertex = hn::Div(hn::Neg(k[2]), hn::Mul(three, k[3]));
  const auto inside = hn::And(hn::Gt(vertex, hn::Zero(d)), hn::Lt(vertex, l));
  const V dv = derivative(hn::IfThenElseZero(inside, vertex));
  lo = hn::IfThenElse(inside, hn::Min(lo, dv), lo);
  hi = hn::IfThenElse(inside, hn::Max(hi, dv), hi);
  return hn::Or(hn::Ge(lo, hn::Zero(d)), hn::Le(hi, hn::Zero(d)));
}

// SeriesIntegral's first sub-interval on each lane's piece [0, l]: depth
// coefficients theta[1..10], q' = g0 + g1 v + g2 v^2, the share `limit`.
// Returns the lanes it settles (the rest bound, or the series' terms added
// until all lanes settle, at most MaximumTerms + 1 of them), their J in
// `sum` (a settled lane's sum is kept as it was when it settled).
template <class D>
HWY_INLINE hn::Mask<D> SeriesLanes(D d, const hn::Vec<D> theta[PieceDegree + 1], hn::Vec<D> g0,
  hn::Vec<D> g1, hn::Vec<D> g2, hn::Vec<D> l, hn::Vec<D> limit, hn::Vec<D>& sum)
{
  using V = hn::Vec<D>;
  constexpr int Terms = numerics::detail::MaximumTerms;
  static constexpr numerics::detail::Reciprocals<double> Inverse{};
  const double* R = Inverse.R;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  // l max|q'|: the rest bound at v = 0 (J within the share as 0), and the
  // tail's factor.
  const V lgmax = hn::Mul(l, hn::MulAdd(l, hn::MulAdd(l, hn::Abs(g2), hn::Abs(g1)), hn::Abs(g0)));
  const auto rest = hn::Le(lgmax, limit);
  V weight[PieceDegree + 1], magnitudeWeight[PieceDegree + 1];
  V A = zero;
  for (int j = PieceDegree; j >= 1; --j)
  {
    A = hn::Mul(hn::Add(A, hn::Abs(theta[j])), l);
    weight[j] = hn::Mul(hn::Set(d, double(j)), theta[j]);
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
  V partial = one, hk = one;
  sum = zero;
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
    for (int j = 1; j <= (k + 1 < PieceDegree ? k + 1 : PieceDegree); ++j)
    {
      next = hn::NegMulAdd(weight[j], c[k + 1 - j], next);
      nextMajorant = hn::MulAdd(magnitudeWeight[j], C[k + 1 - j], nextMajorant);
    }
    c[k + 1] = hn::Mul(next, hn::Set(d, R[k + 1]));
    C[k + 1] = hn::Mul(nextMajorant, hn::Set(d, R[k + 1]));
    hk = hn::Mul(hk, l);
    partial = hn::MulAdd(C[k + 1], hk, partial);
  }
  return settled;
}

} // namespace HWY_NAMESPACE
} // namespace engine
} // namespace avos
HWY_AFTER_NAMESPACE();

#endif
