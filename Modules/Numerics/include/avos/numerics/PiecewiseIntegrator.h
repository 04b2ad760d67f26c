// Piecewise adaptive integration: the volume rendering integral along a ray
// through a trilinear volume, integrated piece by piece between the events
// where its integrand can lose smoothness (cell faces and transfer-function
// knot crossings; see Pieces.h), never across one.
//
// Why. The paper's adaptive Simpson rule (IntegrateAdaptive) estimates its
// error from five samples of a step; a step of up to h_max can jump over a
// layer thinner than a voxel (a transfer-function spike, a material
// boundary), all its samples see tau = 0 and the step is accepted with an
// error as large as the layer's whole contribution. Here no step crosses a
// knot, so nothing can hide between samples, and on a piece everything is
// known in closed form but one scalar integral:
//
// On a piece, v in [0, l] from its start, the scalar is s = Start + q(v) with
// q a cubic, tau(v) = a + b q(v) + c q(v)^2 + e q(v)^3 (c = e = 0 but in
// VTK's alpha model, Pieces.h) and C(v) = c0 + c1 q(v).
// - Inner integral (optical depth), exact: the integral of a polynomial,
//     theta(v) = a v + b int_0^v q + c int_0^v q^2 + e int_0^v q^3.
// - Outer integral, by parts (d/dv e^{-theta} = -tau e^{-theta}):
//     int C tau T = C(0) T(0) - C(l) T(l) + c1 T(0) J,
//     J = int_0^l q'(v) e^{-theta(v)} dv,
//   one scalar integral for all three channels, zero when the colour is
//   constant on the piece. Where s is monotone on the piece (q' keeps its
//   sign; pieces with a knot crossing are split at the extrema, the others
//   tested) and since e^{-theta} decreases, J lies between dq e^{-theta(l)}
//   and dq (second mean value theorem): the midpoint of those bounds errs by
//   at most |dq| (1 - e^{-theta(l)}) / 2. Where that is within the piece's share of
//   the tolerance, J costs nothing more; elsewhere J is integrated term by
//   term from the power series of e^{-theta} (SeriesIntegral), on
//   sub-intervals short enough for the series to converge fast, each
//   truncated where a dominating series proves the rest within its share.
//   No error is estimated anywhere: every part of the error is bounded.
//
// Tolerance eps, per channel, split:
// - 0.6 eps for J. A sub-interval [v, v + h] may err by
//     0.6 eps (dT + h / L) / 2 / max |c1|,
//   dT the transmittance it spends and L the ray's visible length: the shares
//   of all sub-intervals add up to at most 0.6 eps (sum dT <= 1, sum h <= L).
// - 0.15 eps for early termination: the ray stops once T max(1, max C) is
//   below it (what the rest could add to any channel).
// - 0.25 eps for VTK's alpha model, whose extinction the transfer function
//   approximates within a relative error r = eps / 8 (Pieces.h); a relative
//   error r in tau changes a channel by at most r / (1 - r) + r / (1 - r)^2
//   (bound |tau' e^{-theta'} - tau e^{-theta}| term by term), about 2 r.
// So the error of every channel of every ray is below eps, up to rounding
// (relative 1e-16 per operation), in both opacity models (in VTK's, where
// alpha stays below 1 - 2.3e-16 or reaches 1: in between tau is only within
// 11 %, see Pieces.h).
//
// Termination. Pieces per ray: see Pieces.h (at most 3 (m + 1) per cell
// crossed). Per piece, a sub-interval is halved only while its depth's
// coefficient magnitude A(h) = sum_j |theta_j| h^j (shifted to its start)
// exceeds 1 or 40 series terms do not settle it, and not below l 2^-40; the
// shifted coefficients are bounded by those of the piece (shift by at most
// l), so A is below any bound for all h below a constant of the piece's data
// (h_A for A <= 1; the 40 terms settle once A is small enough for the tail
// bound to meet the share). Hence at most 2 l / max(h_A', l 2^-40) + 1
// sub-intervals per piece, h_A' the smaller constant, each after at most 40
// halvings and with at most 40 series terms; and a piece stops as soon as what is left of J, at
// most its transmittance times the variation of q over the rest, fits the rest's share (at once
// when the transmittance underflows to 0). Since 2^41 steps would never end in practice, a piece is
// refused (the ray reports an error) beyond 2^16 sub-intervals: only data near 1e100 against knots
// near 1 needs them (found by fuzzing). A sample is one evaluation of the transfer function at an
// interpolated scalar: one per piece (its end); the series needs none.
#ifndef avos_numerics_PiecewiseIntegrator_h
#define avos_numerics_PiecewiseIntegrator_h

#include "avos/numerics/Pieces.h"
#include "avos/numerics/RayIntegrators.h"

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

// The relative error of tau to build the transfer function with for a
// tolerance eps (the alpha model's share, see above).
template <typename Real>
Real PiecewiseRelativeError(Real tolerance)
{
  return tolerance / Real(8);
}

// The smallest and largest tolerance IntegratePiecewise accepts.
template <typename Real>
constexpr Real PiecewiseMinimumTolerance()
{
  return Real(1e-12);
}

// Empty when the piecewise method can honour `tolerance` in `model`, else
// why: within [1e-12, 1], and in VTK's alpha model at least 8e-7, whose
// extinction is approximated within a relative eps / 8 (Pieces.h builds no
// finer than PiecewiseTransferFunction::MinimumRelativeError).
template <typename Real>
std::string ValidatePiecewiseTolerance(Real tolerance, OpacityModel model)
{
  if (!(tolerance >= PiecewiseMinimumTolerance<Real>() && tolerance <= Real(1)))
  {
    return "the piecewise method's tolerance must be in [1e-12, 1]";
  }
  if (model == OpacityModel::Alpha &&
    !(PiecewiseRelativeError(tolerance) >= PiecewiseTransferFunction<Real>::MinimumRelativeError))
  {
    return "in VTK's opacity model the piecewise method's tolerance must be at least 8e-7 (its "
           "extinction -ln(1 - alpha) is approximated within a relative eps / 8 between extra "
           "knots)";
  }
  return std::string();
}

// The tolerance of the exact piecewise reference (extinction model): the
// error of a channel is below 1e-9 (TestPiecewise checks it against closed
// forms).
template <typename Real>
constexpr Real PiecewiseReferenceTolerance()
{
  return Real(1e-10);
}

namespace detail
{
// 1 / k for k = 1 .. 47: divisions by small integers become products (the
// depth polynomial's coefficients, the series' terms).
template <typename Real>
struct Reciprocals
{
  Real R[48];
  constexpr Reciprocals()
    : R()
  {
    for (int k = 1; k < 48; ++k)
    {
      this->R[k] = Real(1) / Real(k);
    }
  }
};

// theta(v) on a piece, the exact integral of tau = a + b q + c q^2 + e q^3
// over [0, v]: a polynomial of degree up to 10 in v (4 when c = e = 0), D[k]
// its coefficient of v^k.
template <typename Real>
struct PieceDepth
{
  static constexpr int MaximumDegree = 10;
  Real D[MaximumDegree + 1];

  PieceDepth(const Cubic<Real>& q, Real a, Real b, Real c, Real e)
  {
    static constexpr Reciprocals<Real> reciprocal{};
    const Real* inverse = reciprocal.R;
    const Real* k = q.K;
    this->D[0] = Real(0);
    this->D[1] = a + b * k[0];
    this->D[2] = b * k[1] * inverse[2];
    this->D[3] = b * k[2] * inverse[3];
    this->D[4] = b * k[3] * inverse[4];
    this->Degree = 4;
    if (c == Real(0) && e == Real(0))
    {
      return;
    }
    // tau's coefficients of v^i beyond b q: c q^2 + e q^3.
    const Real square[7] = { k[0] * k[0], Real(2) * k[0] * k[1],
      Real(2) * k[0] * k[2] + k[1] * k[1], Real(2) * (k[0] * k[3] + k[1] * k[2]),
      Real(2) * k[1] * k[3] + k[2] * k[2], Real(2) * k[2] * k[3], k[3] * k[3] };
    this->Degree = e != Real(0) ? 10 : 7;
    for (int i = 5; i <= this->Degree; ++i)
    {
      this->D[i] = Real(0);
    }
    for (int i = 0; i < 7; ++i)
    {
      this->D[i + 1] += c * square[i] * inverse[i + 1];
    }
    if (e != Real(0))
    {
      for (int i = 0; i < 7; ++i)
      {
        for (int j = 0; j < 4; ++j)
        {
          this->D[i + j + 1] += e * square[i] * k[j] * inverse[i + j + 1];
        }
      }
    }
  }

  Real operator()(Real v) const
  {
    Real r = this->D[this->Degree];
    for (int k = this->Degree - 1; k >= 0; --k)
    {
      r = r * v + this->D[k];
    }
    return std::max(r, Real(0));
  }

  int Degree;
};

// p(v0 + w) in powers of w: Taylor shift in place (repeated synthetic
// division), coefficients c[0..degree].
template <typename Real>
void ShiftPolynomial(Real* c, int degree, Real v0)
{
  if (v0 == Real(0))
  {
    return; // the first sub-interval of every piece
  }
  for (int i = 0; i < degree; ++i)
  {
    for (int j = degree - 1; j >= i; --j)
    {
      c[j] += v0 * c[j + 1];
    }
  }
}

// J = int_0^l q'(v) e^{-theta(v)} dv on sub-intervals [v, v + h] where the
// shifted depth thetas(w) = theta(v + w) - theta(v) has
// A = sum_j |thetas_j| h^j <= 1. There y = e^{-thetas} is the power series
// c_0 = 1, (k + 1) c_k+1 = -sum_j j thetas_j c_k+1-j (from y' = -thetas' y),
// dominated term by term by the series C_k of e^{A(w)} (the same recursion on
// |thetas_j|), whose sum at h is e^A. So truncating y after N terms errs by
// at most e^A - sum_{k <= N} C_k h^k on [0, h], and the integral of q' times
// the truncated series, exact, by h max|q'| times that. Terms are added until
// the sub-interval's share `allowed(E(v), E(v + h), h)` is met; a
// sub-interval where A > 1 is halved first, and one whose 40 terms do not meet
// its share is halved and taken again (a term of order k needs at least k / D
// factors of A(w), D the depth's degree, so after N terms the tail is below
// sum_{m > N / D} A^m / m!: e / 41! for D = 1, but 0.02 for D = 10); then
// they grow back by doubling. Accepted and halved sub-intervals are counted as
// steps in `stats`.
// The most sub-intervals SeriesIntegral takes on a piece before it gives up
// (returns NaN); the bound above allows 2^41 for extreme data.
constexpr long MaximumSubintervals = 1L << 16;

template <typename Real, typename Allowed>
Real SeriesIntegral(const PieceDepth<Real>& depth, const Cubic<Real>& q, Real l, Real El,
  const Allowed& allowed, RayStatistics<Real>& stats)
{
  constexpr int MaximumTerms = 40;
  static constexpr Reciprocals<Real> inverse{};
  Real J = Real(0);
  Real v = Real(0), h = l, Ev = Real(1);
  for (long count = 0; v < l; ++count)
  {
    if (count == MaximumSubintervals)
    {
      // Only data whose cubic's rounding exceeds the transfer function's
      // scale (corner values near 1e100) gets here: reported, not guessed.
      return std::numeric_limits<Real>::quiet_NaN();
    }
    h = std::min(h, l - v);
    Real theta[PieceDepth<Real>::MaximumDegree + 1];
    std::copy(depth.D, depth.D + depth.Degree + 1, theta);
    ShiftPolynomial(theta, depth.Degree, v);
    Real g[3] = { q.K[1], Real(2) * q.K[2], Real(3) * q.K[3] }; // q'
    ShiftPolynomial(g, 2, v);
    // The rest of J, int_v^l q' e^{-theta}, lies within +-Ev V (theta does
    // not decrease; V bounds int |q'|): once that is within the rest's
    // share, the rest is taken as 0. This ends a piece whose transmittance
    // has run out (Ev = 0 from extreme data) at once, where sub-intervals of
    // l 2^-40 would take 2^40 steps.
    const Real rest = l - v;
    const Real variation =
      rest * (std::abs(g[0]) + rest * (std::abs(g[1]) + rest * std::abs(g[2])));
    if (Ev * variation <= allowed(Ev, El, rest))
    {
      stats.Accept(rest);
      break;
    }
    auto magnitude = [&](Real w)
    {
      Real a = Real(0);
      for (int j = depth.Degree; j >= 1; --j)
      {
        a = (a + std::abs(theta[j])) * w;
      }
      return a;
    };
    const Real floor = l * Real(9.094947017729282e-13); // 2^-40
    Real A = magnitude(h);
    while (A > Real(1) && h > floor)
    {
      ++stats.Rejected;
      h = std::max(Real(0.5) * h, floor);
      A = magnitude(h);
    }
    const Real end = l - v <= h ? l : v + h;
    const Real Eh = end == l ? El : std::exp(-depth(end));
    // Only for extreme data (a depth of 1, or a series that 40 terms do not
    // settle, within l 2^-40): the proven midpoint of J's bounds on this
    // sub-interval (see above).
    auto midpoint = [&]()
    {
      J += (q(end) - q(v)) * (Ev + Eh) / Real(2);
      stats.Accept(h);
      v = end;
      Ev = Eh;
    };
    if (!(A <= Real(1)))
    {
      midpoint();
      continue;
    }
    const Real gmax = std::abs(g[0]) + h * (std::abs(g[1]) + h * std::abs(g[2]));
    const Real limit = allowed(Ev, Eh, h);
    const Real whole = std::exp(A); // the dominating series' sum at h
    // j theta_j and its magnitude, the recursion's weights.
    Real weight[PieceDepth<Real>::MaximumDegree + 1],
      magnitudeWeight[PieceDepth<Real>::MaximumDegree + 1];
    for (int j = 1; j <= depth.Degree; ++j)
    {
      weight[j] = Real(j) * theta[j];
      magnitudeWeight[j] = std::abs(weight[j]);
    }
    // c_k, C_k h^k, and the integral of g(w) w^k over [0, h] for each term.
    Real c[MaximumTerms + 1], C[MaximumTerms + 1];
    c[0] = Real(1);
    C[0] = Real(1);
    Real partial = Real(1), sum = Real(0), hk = Real(1); // hk = h^k
    bool settled = false;
    for (int k = 0; k <= MaximumTerms; ++k)
    {
      // int_0^h g(w) w^k dw for the term c_k w^k.
      sum += c[k] * hk * h *
        (g[0] * inverse.R[k + 1] + h * (g[1] * inverse.R[k + 2] + h * g[2] * inverse.R[k + 3]));
      const Real tail = std::max(whole - partial, Real(0));
      settled = Ev * h * gmax * tail <= limit;
      if (settled || k == MaximumTerms)
      {
        break;
      }
      Real next = Real(0), nextMajorant = Real(0);
      for (int j = 1; j <= std::min(depth.Degree, k + 1); ++j)
      {
        next -= weight[j] * c[k + 1 - j];
        nextMajorant += magnitudeWeight[j] * C[k + 1 - j];
      }
      c[k + 1] = next * inverse.R[k + 1];
      C[k + 1] = nextMajorant * inverse.R[k + 1];
      hk *= h;
      partial += C[k + 1] * hk;
    }
    if (!settled)
    {
      if (h > floor)
      {
        ++stats.Rejected;
        h = std::max(Real(0.5) * h, floor);
      }
      else
      {
        midpoint();
      }
      continue;
    }
    J += Ev * sum;
    stats.Accept(h);
    v = end;
    Ev = Eh;
    h *= Real(2);
  }
  return J;
}
} // namespace detail

template <typename Real, typename VolumeT>
RayResult<Real> IntegratePiecewise(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  const PiecewiseTransferFunction<Real>& tf, Real tolerance, bool earlyTermination = true,
  std::vector<StepRecord<Real>>* steps = nullptr)
{
  RayResult<Real> result;
  result.Statistics.Steps = steps;
  // The alpha model's floor was checked when `tf` was built.
  result.Error = ValidatePiecewiseTolerance(tolerance, OpacityModel::Extinction);
  if (!result.Error.empty())
  {
    return result;
  }
  if (tf.GetNumberOfPieces() == 0)
  {
    result.Error = "the piecewise transfer function was not built";
    return result;
  }
  for (int a = 0; a < 3; ++a)
  {
    if (volume.GetDimension(a) < 2)
    {
      result.Error = "the volume needs at least 2 points along each axis";
      return result;
    }
  }
  if (!std::isfinite(origin.x + origin.y + origin.z + direction.x + direction.y + direction.z))
  {
    result.Error = "the ray's origin and direction must be finite";
    return result;
  }
  result.Error = detail::ValidateSegments(segments, count);
  const Real L = detail::TotalLength(segments, count);
  if (!result.Error.empty() || !(L > Real(0)))
  {
    return result;
  }

  RayStatistics<Real>& stats = result.Statistics;
  const Real budget = Real(0.6) * tolerance;
  const Real terminationBound = Real(0.15) * tolerance / std::max(Real(1), tf.GetMaximumColor());
  glm::vec<3, Real> color(Real(0));
  Real T = Real(1);
  bool stopped = false;

  auto integratePiece = [&](const RayPiece<Real>& piece) -> bool
  {
    const auto& p = tf[piece.TF];
    const Cubic<Real>& q = piece.Q;
    const Real l = piece.Length;
    const detail::PieceDepth<Real> depth(q, p.Tau, p.TauSlope, p.TauCurvature, p.TauCubic);
    ++stats.Pieces;
    ++stats.Samples; // the piece's end
    stats.Accept(l);
    const Real thetaL = depth(l);
    const Real EL = std::exp(-thetaL);
    const Real Ta = T, Tb = T * EL;
    color += Ta * (p.Colour + p.ColourSlope * q.K[0]) - Tb * (p.Colour + p.ColourSlope * q(l));
    const Real cs =
      std::max({ std::abs(p.ColourSlope.x), std::abs(p.ColourSlope.y), std::abs(p.ColourSlope.z) });
    if (cs > Real(0) && Ta > Real(0))
    {
      // The error J may have on [v, v + h], spending e^{-theta} from Ev to Eh.
      const Real scale = budget / (Real(2) * cs * Ta);
      auto allowed = [&](Real Ev, Real Eh, Real h) { return scale * (Ta * (Ev - Eh) + h / L); };
      const Real dq = q(l) - q.K[0];
      Real J;
      if (piece.Monotone && std::abs(dq) * (Real(1) - EL) / Real(2) <= allowed(Real(1), EL, l))
      {
        J = dq * (Real(1) + EL) / Real(2);
      }
      else
      {
        J = detail::SeriesIntegral(depth, q, l, EL, allowed, stats);
        if (std::isnan(J))
        {
          result.Error = "a piece needs more than 65536 sub-intervals (data values too large "
                         "for double precision against the transfer function's knots)";
          stopped = true;
          return false;
        }
      }
      color += p.ColourSlope * (Ta * J);
    }
    T = Tb;
    if (stats.Steps)
    {
      stats.Steps->push_back({ piece.Begin, l, Real(1) - T });
    }
    if (earlyTermination && T <= terminationBound)
    {
      stats.Terminated = true;
      stopped = true;
      return false;
    }
    return true;
  };

  for (std::size_t j = 0; j < count && !stopped; ++j)
  {
    PieceWalk(volume, origin, direction, segments[j].Begin, segments[j].End, tf, stats.Cells,
      integratePiece);
  }
  if (!result.Error.empty())
  {
    return result; // a refused piece: no value
  }
  // Inside [0, 1] whatever the rounding: each channel is a sum of
  // non-negative contributions bounded by 1 - T.
  for (int c = 0; c < 3; ++c)
  {
    color[c] = std::min(std::max(color[c], Real(0)), Real(1) - T);
  }
  result.RGBA = glm::vec<4, Real>(color, Real(1) - T);
  detail::RequireFinite(result);
  return result;
}

template <typename Real, typename VolumeT>
RayResult<Real> IntegratePiecewise(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, Real D, const PiecewiseTransferFunction<Real>& tf,
  Real tolerance, bool earlyTermination = true)
{
  if (!(D >= Real(0)) || !std::isfinite(D))
  {
    RayResult<Real> result;
    result.Error = "the ray length must be finite and non-negative";
    return result;
  }
  const Interval<Real> whole{ Real(0), D };
  return IntegratePiecewise(volume, origin, direction, &whole, 1, tf, tolerance, earlyTermination);
}

} // namespace numerics
} // namespace avos

#endif
