// Gradient opacity in the piecewise method: the extinction tau(s) G(|g|)
// (GradientOpacity.h), g the world-space gradient of the trilinear
// interpolant, integrated piece by piece (PiecewiseIntegrator.h) with a
// proven error, shaded (PiecewiseShading.h) or not.
//
// On a piece, v in [0, l] from its start, g's components are quadratics in
// v, so |g| is the square root of a quartic and G(|g|) a piecewise-linear
// function of it: the extinction kappa(v) = tau(v) G(|g(v)|) is no longer a
// polynomial and the depth no longer exact. Two cases:
// - G constant over an enclosure of |g| on the piece (a flat stretch of G,
//   where most of a medical preset's pieces lie): kappa = gamma tau, and the
//   piece is integrated as without gradient opacity, with tau scaled by
//   gamma: exactly unshaded (the closed-form depth, J by its midpoint bound or
//   its series), with the enclosures of PiecewiseShading.h shaded. A piece
//   where G is 0 is empty.
// - Elsewhere the piece is cut into sub-intervals X = [v0, v0 + h], centre c
//   (PiecewiseShading.h's SubintervalPiece, shaded ending them at n.l's
//   kinks too), on which a Taylor model (TaylorModel.h) of the extinction, polynomial K
//   and remainder R_K, |kappa - K| <= R_K, is built from the piece's cubic,
//   the gradient's quadratics, a model of |g| (the square root of their
//   squared length, the hull where it reaches 0) and G on the linear stretch
//   holding |g|'s enclosure (the hull of G's values where it spans a knot),
//   and a model of the emission E (the colour C(s), or the lit colour),
//   polynomial P and remainder R_E. With the approximate depth
//   Theta(u) = int_0^u K (exact, a polynomial), the sub-interval's
//   contribution T0 int_0^h P K e^{-Theta} is, by parts,
//     T0 (P(0) - P(h) e^{-Theta(h)}) + T0 int_0^h P' e^{-Theta},
//   the last term by the series of PiecewiseIntegrator.h (the three channels
//   at once) or, where P' keeps its sign and K >= 0, the midpoint of its
//   bounds; and the transmittance after X is T1 = T0 e^{-Theta(h)}.
//
// The error. Let theta be the true depth over X: |theta - Theta| <= d =
// R_K u (+ rounding) at u. The true contribution T0 int E kappa e^{-theta}
// differs from T0 int P K e^{-Theta} by at most
//   T0 [R_E (1 - e^{-Theta(h) - d}) + max|P| h (R_K + max|K| e^d (e^d - 1))]
// (|E - P| <= R_E against the weight kappa e^{-theta}, whose integral is at
// most 1 - e^{-Theta(h) - d}; then |kappa e^{-theta} - K e^{-Theta}| <= R_K +
// |K| e^{-Theta} |e^{Theta - theta} - 1|, and e^{-Theta} <= e^d). The true
// transmittance after X differs from T1 by at most T1 (e^d - 1). Write V_j in
// [0, 1] for what the rest of the ray from X_j on gives a channel (colour or
// alpha) per unit transmittance in front, V_j = A_j + t_j V_j+1 with t_j
// X_j's transmittance: the computed V differs from the true one by at most
//   sum_j T_j-1 |A'_j - A_j| + T_j |t'_j - t_j| / t'_j
// (unrolling |V'_j - V_j| <= |A'_j - A_j| + |t'_j - t_j| V_j+1 + t'_j |V'_j+1 -
// V_j+1|, V_j+1 <= 1, with the computed transmittances T' in front): each
// sub-interval's error, weighted by the computed transmittance, adds up, with
// no product of errors. The alpha channel's A_j = 1 - t_j counts |t'_j - t_j|
// once more: 2 T1 (e^d - 1) per sub-interval in all.
//
// Tolerance eps, per channel, as with shading: 0.55 eps for the
// sub-intervals (each its share 0.275 eps (dT + h / L), half for the model
// errors above, half for the P' term; an exact piece's J takes its share),
// 0.05 eps the reserve for excesses at the floor (PiecewiseShading.h), 0.15
// eps for early termination (the ray stops once T is below it; colours are at
// most 1), 0.25 eps for VTK's alpha model. So every channel of every ray is
// within eps, up to rounding (the models take their own into R_K and R_E,
// and d bounds the rounding of Theta's shift and evaluation too).
//
// Termination: as PiecewiseShading.h's sub-intervals (accepted, or shrunk by
// at least half down to the floor l 2^-40 where they are accepted, at most
// MaximumSubintervals per piece, then the ray reports an error). A kink of
// G(|g|) (|g| crossing a knot of G, or vanishing) shrinks R_K only as the
// sub-interval's length: about log2(G' / eps) halvings around each.
#ifndef avos_numerics_PiecewiseGradientOpacity_h
#define avos_numerics_PiecewiseGradientOpacity_h

#include "avos/numerics/GradientOpacity.h"
#include "avos/numerics/PiecewiseShading.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace avos
{
namespace numerics
{

namespace detail
{
// G clamped to [0, 1], as GradientOpacity::Factor applies it.
template <typename Real>
Real ClampedFactor(Real value)
{
  return std::min(std::max(value, Real(0)), Real(1));
}

// The range of clamp(G(m), 0, 1) over m in [lo, hi] (0 <= lo <= hi): G is
// piecewise linear, so its values at lo, hi and both sides of every knot
// between them.
template <typename Real>
Bounds<Real> GradientFactorRange(const TransferFunction<Real>& f, Real lo, Real hi)
{
  const Real a = ClampedFactor(f.GetOpacityValue(lo)), b = ClampedFactor(f.GetOpacityValue(hi));
  Bounds<Real> range(std::min(a, b), std::max(a, b));
  const auto& pieces = f.GetPieces();
  for (std::size_t i = 0; i < pieces.size(); ++i)
  {
    if (pieces[i].Start > lo && pieces[i].Start <= hi)
    {
      const Real left = i == 0
        ? f.GetOpacityBelow()
        : pieces[i - 1].Opacity + pieces[i - 1].OpacitySlope * pieces[i - 1].Length;
      for (const Real value : { ClampedFactor(left), ClampedFactor(pieces[i].Opacity) })
      {
        range.Lo = std::min(range.Lo, value);
        range.Hi = std::max(range.Hi, value);
      }
    }
  }
  return range;
}

// A model of clamp(G(m), 0, 1) from a model m of |g| over X: G's linear
// stretch where m's enclosure lies inside one (clamped as a model), else the
// hull of G's values over the enclosure.
template <typename Real, int N>
TaylorModel<Real, N> GradientFactor(const TransferFunction<Real>& f, const TaylorModel<Real, N>& m)
{
  using Model = TaylorModel<Real, N>;
  const Bounds<Real> x = m.Range();
  const Real lo = std::max(x.Lo, Real(0)), hi = x.Hi;
  if (!m.Finite() || !(hi >= lo))
  {
    return Model::Enclosing(Bounds<Real>(Real(0), Real(1)), m.Radius);
  }
  const auto& pieces = f.GetPieces();
  // The last piece starting at or below lo (none: below the first knot).
  const auto after = std::upper_bound(pieces.begin(), pieces.end(), lo,
    [](Real value, const typename TransferFunction<Real>::Piece& p) { return value < p.Start; });
  const Real end = after == pieces.end() ? std::numeric_limits<Real>::infinity() : after->Start;
  if (hi < end)
  {
    if (after == pieces.begin())
    {
      Model constant(ClampedFactor(f.GetOpacityBelow()));
      constant.Radius = m.Radius;
      return constant;
    }
    const auto& p = *(after - 1);
    return Clamp((m - p.Start) * p.OpacitySlope + p.Opacity, Real(0), Real(1));
  }
  return Model::Enclosing(GradientFactorRange(f, lo, hi), m.Radius);
}

// A model of |g| over X from the gradient's models (0 where it vanishes on
// the whole cell).
template <typename Real, int N>
TaylorModel<Real, N> GradientMagnitude(const GradientPolynomials<Real, N>& gradient, Real r)
{
  if (gradient.Zero)
  {
    TaylorModel<Real, N> zero(Real(0));
    zero.Radius = r;
    return zero;
  }
  return Pow(gradient.Squared(), Real(0.5));
}

// The extinction tau(q) G(|g|) over the sub-interval of centre c and radius
// r of a piece (cubic q, transfer-function piece p, world gradient Gw of
// G's normal matrix).
template <int N, typename Real>
TaylorModel<Real, N> ExtinctionModel(const Cubic<Real>& q,
  const typename PiecewiseTransferFunction<Real>::Piece& p, const Real Gw[3][3], bool zero,
  const TransferFunction<Real>& f, Real c, Real r)
{
  using Model = TaylorModel<Real, N>;
  const Real cubic[4] = { q.K[0], q.K[1], q.K[2], q.K[3] };
  const Model s = Model::Polynomial(cubic, c, r);
  const Model tau = p.TauCurvature == Real(0) && p.TauCubic == Real(0)
    ? p.TauSlope * s + p.Tau
    : ((p.TauCubic * s + p.TauCurvature) * s + p.TauSlope) * s + p.Tau;
  const GradientPolynomials<Real, N> gradient(Gw, c, r, zero);
  return tau * GradientFactor(f, GradientMagnitude(gradient, r));
}

// The range of clamp(G(|g|)) over a whole piece of length l (the models of
// degree N over it).
template <int N, typename Real>
Bounds<Real> PieceFactorRange(const Real Gw[3][3], Real l, const TransferFunction<Real>& f)
{
  const Real c = l / Real(2);
  const Real r = c * (Real(1) + Real(4) * std::numeric_limits<Real>::epsilon()) +
    std::numeric_limits<Real>::min();
  const GradientPolynomials<Real, N> gradient(Gw, c, r, ZeroGradient(Gw));
  const TaylorModel<Real, N> m = GradientMagnitude(gradient, r);
  const Bounds<Real> x = m.Range();
  if (!m.Finite() || !(x.Hi >= std::max(x.Lo, Real(0))))
  {
    return Bounds<Real>(Real(0), Real(1));
  }
  return GradientFactorRange(f, std::max(x.Lo, Real(0)), x.Hi);
}

// The unshaded piece (q, transfer-function piece p, depth theta, e^{-theta(l)}
// = El, transmittance Ta in front, monotone s where `monotone`) integrated
// as IntegratePiecewise does: C(0) Ta - C(l) Ta El + c1 Ta J, J by its
// midpoint bound or its series within the share budget.Scale (Ta (1 - El) +
// l / L). False when the series refuses the piece.
template <typename Real>
bool ExactPiece(const Cubic<Real>& q, const typename PiecewiseTransferFunction<Real>::Piece& p,
  const PieceDepth<Real>& depth, Real l, Real El, Real Ta, bool monotone,
  const ShadedBudget<Real>& budget, glm::vec<3, Real>& color, RayStatistics<Real>& stats)
{
  const Real qa = q.K[0], ql = q(l);
  color += Ta * (p.Colour + p.ColourSlope * qa) - Ta * El * (p.Colour + p.ColourSlope * ql);
  ++stats.Samples;
  stats.Accept(l);
  const Real cs = p.ColourSlopeMaximum;
  if (!(cs > Real(0) && Ta > Real(0)))
  {
    return true;
  }
  const Real dq = ql - qa;
  if ((monotone || Monotone(q, l)) &&
    cs * Ta * std::abs(dq) * (Real(1) - El) / Real(2) <=
      budget.Scale * (Ta * (Real(1) - El) + l * budget.InverseL))
  {
    color += p.ColourSlope * (Ta * dq * (Real(1) + El) / Real(2));
    return true;
  }
  const Real J =
    SubintervalsJ(q, depth, l, El, budget.Scale / (cs * Ta), Ta, budget.InverseL, stats);
  color += p.ColourSlope * (Ta * J);
  return !std::isnan(J);
}

// The depth of a piece whose extinction is not a polynomial, for
// SubintervalPiece (PiecewiseShading.h): on each sub-interval the model K of
// kappa that `kappa(c, r)` gives, Theta its exact integral, D = R_K h plus
// the rounding of Theta's shift (each coefficient within 2 N u of the terms
// it sums, |v - c| <= r and u <= 2 r) and evaluation (16 (N + 4) ulps of its
// magnitude).
template <int N, typename Real, typename Extinction>
struct ModelDepth
{
  const Extinction& Kappa;

  void operator()(Real v, Real end, Real c, Real r, Real Ev, SubintervalDepth<Real>& s,
    RayStatistics<Real>& stats) const
  {
    static constexpr Reciprocals<Real> inverse{};
    const Real eps = std::numeric_limits<Real>::epsilon();
    const TaylorModel<Real, N> K = this->Kappa(c, r);
    ++stats.Samples;
    // Theta(u) = int_0^u K(v - c + w) dw, u from the sub-interval's start.
    s.Degree = N + 1;
    s.Theta[0] = Real(0);
    std::copy(K.A, K.A + N + 1, s.Theta + 1);
    ShiftPolynomial(s.Theta + 1, N, v - c);
    Real Theta = Real(0);
    const Real width = end - v;
    for (int j = N + 1; j >= 1; --j)
    {
      s.Theta[j] *= inverse.R[j];
      Theta = (Theta + s.Theta[j]) * width;
    }
    Real reach = Real(0);
    for (int j = N; j >= 0; --j)
    {
      reach = reach * Real(3) * r + std::abs(K.A[j]);
    }
    s.D = (K.R * width + Real(4 * N + 2) * eps * width * reach +
            Real(16 * (N + 4)) * eps * Magnitude(s.Theta, N + 1, width)) *
      TaylorModel<Real, N>::Up();
    s.Eh = Ev * std::exp(-Theta);
    s.R = K.R;
    s.Magnitude = K.Magnitude();
    s.Decreasing = K.Range().Lo >= Real(0);
    s.Ready = true;
  }
  void Shift(Real, SubintervalDepth<Real>&) const {}
};

// One piece of IntegratePiecewiseGradientOpacity with models of degree N:
// false when refused (`error` says why).
template <int N, typename Real, typename VolumeT>
bool GradientOpacityPiece(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const RayPiece<Real>& rp,
  const typename PiecewiseTransferFunction<Real>::Piece& p, const GradientOpacity<Real>& opacity,
  const RayShading<Real>* shading, const ShadedBudget<Real>& budget, glm::vec<3, Real>& color,
  Real& T, Real& overdraft, Real& length, RayStatistics<Real>& stats, std::string& error)
{
  const Real l = rp.Length;
  Real Gw[3][3];
  PieceGradient(volume, origin, direction, rp, opacity.NormalMatrix, Gw);
  const bool zero = ZeroGradient(Gw);
  // The shading's gradient: the same unless its normal matrix differs (the
  // classes give both the inverse transpose of one grid-to-world map).
  Real Gs[3][3];
  if (shading && shading->NormalMatrix != opacity.NormalMatrix)
  {
    PieceGradient(volume, origin, direction, rp, shading->NormalMatrix, Gs);
  }
  else if (shading)
  {
    std::copy(&Gw[0][0], &Gw[0][0] + 9, &Gs[0][0]);
  }
  const glm::vec<3, Real> start =
    shading ? shading->WorldOrigin + rp.Begin * shading->WorldDirection : glm::vec<3, Real>(0);
  const Bounds<Real> factor = PieceFactorRange<N>(Gw, l, *opacity.Function);
  if (factor.Hi <= Real(0))
  {
    ++stats.Samples;
    stats.Accept(l);
    return true; // empty
  }
  if (factor.Lo == factor.Hi)
  {
    const Real gamma = factor.Lo;
    const PieceDepth<Real> depth(
      rp.Q, gamma * p.Tau, gamma * p.TauSlope, gamma * p.TauCurvature, gamma * p.TauCubic);
    const Real El = std::exp(-depth(l));
    bool integrated = true;
    if (T * (Real(1) - El) > Real(0))
    {
      integrated = shading
        ? ShadedPiece<N>(
            rp.Q, p, depth, l, El, T, Gs, start, *shading, budget, color, overdraft, length, stats)
        : ExactPiece(rp.Q, p, depth, l, El, T, rp.Monotone, budget, color, stats);
    }
    T *= El;
    if (!integrated)
    {
      error = shading ? RefusedSubintervalsError : RefusedPieceError;
    }
    return integrated;
  }
  auto extinction = [&](Real c, Real r)
  { return ExtinctionModel<N>(rp.Q, p, Gw, zero, *opacity.Function, c, r); };
  const ModelDepth<N, Real, decltype(extinction)> depth{ extinction };
  Real E = Real(1);
  bool integrated;
  KinkCuts<Real> cuts;
  if (shading)
  {
    const bool shadeZero = ZeroGradient(Gs);
    if (!shadeZero)
    {
      cuts.Find(Gs, l, *shading->Model, shading->ToViewer, N);
    }
    auto lit = [&](Real c, Real r, TaylorModel<Real, N> models[3])
    { LitModels<N>(rp.Q, p, Gs, shadeZero, start, *shading, c, r, models); };
    integrated =
      SubintervalPiece<N>(l, T, depth, lit, cuts, budget, color, E, overdraft, length, stats);
  }
  else
  {
    auto plain = [&](Real c, Real r, TaylorModel<Real, N> models[3])
    {
      const Real cubic[4] = { rp.Q.K[0], rp.Q.K[1], rp.Q.K[2], rp.Q.K[3] };
      const TaylorModel<Real, N> s = TaylorModel<Real, N>::Polynomial(cubic, c, r);
      for (int k = 0; k < 3; ++k)
      {
        models[k] = p.ColourSlope[k] * s + p.Colour[k];
      }
    };
    integrated =
      SubintervalPiece<N>(l, T, depth, plain, cuts, budget, color, E, overdraft, length, stats);
  }
  T *= E;
  if (!integrated)
  {
    error = RefusedSubintervalsError;
  }
  return integrated;
}
} // namespace detail

// The piecewise method (IntegratePiecewise) with the extinction scaled by
// gradient opacity, G(|grad s|) in scalar units per world unit
// (GradientOpacity.h), and the emission lit by `shading` where given, within
// `tolerance` per channel; see above. The volume must be trilinear.
template <typename Real, typename VolumeT>
RayResult<Real> IntegratePiecewiseGradientOpacity(const VolumeT& volume,
  const glm::vec<3, Real>& origin, const glm::vec<3, Real>& direction,
  const Interval<Real>* segments, std::size_t count, const PiecewiseTransferFunction<Real>& tf,
  Real tolerance, const GradientOpacity<Real>& opacity,
  const RayShading<detail::NotDeduced<Real>>* shading = nullptr, bool earlyTermination = true,
  std::vector<StepRecord<detail::NotDeduced<Real>>>* steps = nullptr)
{
  RayResult<Real> result;
  result.Statistics.Steps = steps;
  Real L;
  result.Error =
    detail::ValidatePiecewise(volume, origin, direction, segments, count, tf, tolerance, L);
  if (result.Error.empty())
  {
    result.Error = opacity.Validate();
  }
  if (result.Error.empty() && shading)
  {
    result.Error = shading->Model ? shading->Model->Validate() : "no shading model";
  }
  if (!result.Error.empty() || !(L > Real(0)))
  {
    return result;
  }
  auto piece = [&](auto degree, const RayPiece<Real>& rp, const detail::ShadedBudget<Real>& budget,
                 glm::vec<3, Real>& color, Real& T, Real& overdraft, Real& length,
                 RayStatistics<Real>& stats, std::string& error)
  {
    return detail::GradientOpacityPiece<decltype(degree)::value>(volume, origin, direction, rp,
      tf[rp.TF], opacity, shading, budget, color, T, overdraft, length, stats, error);
  };
  detail::SubintervalRay(
    volume, origin, direction, segments, count, tf, tolerance, L, earlyTermination, piece, result);
  return result;
}

} // namespace numerics
} // namespace avos

#endif
