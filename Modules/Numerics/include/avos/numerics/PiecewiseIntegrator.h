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
// halvings and with at most 40 series terms; and a piece stops as soon as
// what is left of J, at most its transmittance times the variation of q over
// the rest, fits the rest's share (at once when the transmittance underflows
// to 0). Since 2^41 steps would never end in practice, a piece is refused
// (the ray reports an error) beyond 2^16 sub-intervals: only data near 1e100
// against knots near 1 needs them (found by fuzzing). A sample is one
// evaluation of the transfer function at an interpolated scalar: one per
// piece (its end); the series needs none.
//
// Batches. The walk takes the ray's cells in batches (CellBatch: corners,
// range, cubic) and hands its pieces over in batches of PieceBatch::Capacity
// (8), each stage run by a kernel a batch at a time (ScalarPieceKernels here;
// the engine's vectorised one takes a cell or a piece per SIMD lane), in
// order, so the result is the same as piece by piece; only the walk may run
// up to 7 cells and 7 pieces past the point where early termination stops
// the ray (never integrated; batches shrink as the ray nears it).
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
// why: within [1e-12, 1], and in VTK's alpha model at least 8e-12, whose
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
    return "in VTK's opacity model the piecewise method's tolerance must be at least 8e-12 (its "
           "extinction -ln(1 - alpha) is approximated within a relative eps / 8 between extra "
           "knots)";
  }
  return std::string();
}

// The tolerance of the exact piecewise reference (both opacity models): the
// error of a channel is below 1e-9 (TestPiecewise checks it against closed
// forms).
template <typename Real>
constexpr Real PiecewiseReferenceTolerance()
{
  return Real(1e-10);
}

namespace detail
{
// T, in a context that template argument deduction skips: a parameter of
// this type takes nullptr (or anything convertible) whatever T is deduced
// from the others.
template <typename T>
struct NotDeducedType
{
  using Type = T;
};
template <typename T>
using NotDeduced = typename NotDeducedType<T>::Type;

// 1 / k for k = 1 .. 63: divisions by small integers become products (the
// depth polynomial's coefficients, the series' terms).
template <typename Real>
struct Reciprocals
{
  Real R[64];
  constexpr Reciprocals()
    : R()
  {
    for (int k = 1; k < 64; ++k)
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

  // theta = 0 (a sum of depths starts there, Add).
  PieceDepth()
    : D()
    , Degree(0)
  {
  }

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

  // theta += weight other: the depth of a sum of extinctions (Mixture.h).
  void Add(const PieceDepth& other, Real weight)
  {
    for (int k = this->Degree + 1; k <= other.Degree; ++k)
    {
      this->D[k] = Real(0);
    }
    for (int k = 0; k <= other.Degree; ++k)
    {
      this->D[k] += weight * other.D[k];
    }
    this->Degree = std::max(this->Degree, other.Degree);
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

// A = sum_j |theta_j| h^j, the dominating series' exponent at h.
template <typename Real>
Real Magnitude(const Real* theta, int degree, Real h)
{
  Real a = Real(0);
  for (int j = degree; j >= 1; --j)
  {
    a = (a + std::abs(theta[j])) * h;
  }
  return a;
}

// The most terms of the series on one sub-interval.
constexpr int MaximumTerms = 40;

// sum_j |c_j| h^j over the M coefficients c: a bound of |c(w)| on [0, h].
template <typename Real, int M>
Real MagnitudeAt(const Real (&c)[M], Real h)
{
  Real m = std::abs(c[M - 1]);
  for (int j = M - 2; j >= 0; --j)
  {
    m = std::abs(c[j]) + h * m;
  }
  return m;
}

// One sub-interval of SeriesIntegrals, [v, v + h] with v = 0 after the shift:
// theta[1..degree] the shifted depth (A = Magnitude(theta, degree, h) <= 1),
// g[i][0..M-1] the shifted coefficients of N polynomials g_i of degree below
// M (M <= 16). Adds terms of int_0^h g_i e^{-theta} until
// Ev h max|g_i| (e^A - sum_{k <= N} C_k h^k) is within limit[i] for every i,
// at most MaximumTerms + 1 of them; sum[i] is the truncated integral. False
// when they do not settle it.
template <typename Real, int N, int M>
bool SubintervalSeries(const Real* theta, int degree, const Real (&g)[N][M], Real h, Real A,
  Real Ev, const Real (&limit)[N], Real (&sum)[N])
{
  static_assert(M >= 1 && M <= 16, "the reciprocals cover terms of degree up to 63");
  static constexpr Reciprocals<Real> inverse{};
  Real gmax[N];
  for (int i = 0; i < N; ++i)
  {
    gmax[i] = MagnitudeAt(g[i], h);
    sum[i] = Real(0);
  }
  const Real whole = std::exp(A); // the dominating series' sum at h
  // j theta_j and its magnitude, the recursion's weights.
  Real weight[PieceDepth<Real>::MaximumDegree + 1],
    magnitudeWeight[PieceDepth<Real>::MaximumDegree + 1];
  for (int j = 1; j <= degree; ++j)
  {
    weight[j] = Real(j) * theta[j];
    magnitudeWeight[j] = std::abs(weight[j]);
  }
  // c_k, C_k h^k, and the integral of g(w) w^k over [0, h] for each term.
  Real c[MaximumTerms + 1], C[MaximumTerms + 1];
  c[0] = Real(1);
  C[0] = Real(1);
  Real partial = Real(1), hk = Real(1); // hk = h^k
  for (int k = 0; k <= MaximumTerms; ++k)
  {
    // int_0^h g(w) w^k dw for the term c_k w^k.
    const Real term = c[k] * hk * h;
    bool settled = true;
    const Real tail = std::max(whole - partial, Real(0));
    for (int i = 0; i < N; ++i)
    {
      // int_0^h g_i(w) w^k dw / h^(k + 1) = sum_j g_ij h^j / (k + j + 1).
      Real moment = g[i][M - 1] * inverse.R[k + M];
      for (int j = M - 2; j >= 0; --j)
      {
        moment = g[i][j] * inverse.R[k + j + 1] + h * moment;
      }
      sum[i] += term * moment;
      settled = settled && Ev * h * gmax[i] * tail <= limit[i];
    }
    if (settled)
    {
      return true;
    }
    if (k == MaximumTerms)
    {
      break;
    }
    Real next = Real(0), nextMajorant = Real(0);
    for (int j = 1; j <= std::min(degree, k + 1); ++j)
    {
      next -= weight[j] * c[k + 1 - j];
      nextMajorant += magnitudeWeight[j] * C[k + 1 - j];
    }
    c[k + 1] = next * inverse.R[k + 1];
    C[k + 1] = nextMajorant * inverse.R[k + 1];
    hk *= h;
    partial += C[k + 1] * hk;
  }
  return false;
}

// One quadratic.
template <typename Real>
bool SubintervalSeries(
  const Real* theta, int degree, const Real g[3], Real h, Real A, Real Ev, Real limit, Real& sum)
{
  const Real gs[1][3] = { { g[0], g[1], g[2] } };
  const Real limits[1] = { limit };
  Real sums[1];
  const bool settled = SubintervalSeries(theta, degree, gs, h, A, Ev, limits, sums);
  sum = sums[0];
  return settled;
}

// The integrals int_0^l g_i(v) e^{-theta(v)} dv of N polynomials g_i of
// degree below M (coefficients g[i][0..M-1]), each keeping its sign on
// [0, l] (the colour integral J's q' on a monotone piece, a mixture's
// emissions: Mixture.h), on sub-intervals [v, v + h] where the shifted depth
// thetas(w) = theta(v + w) - theta(v) has A = sum_j |thetas_j| h^j <= 1.
// There y = e^{-thetas} is the power series c_0 = 1,
// (k + 1) c_k+1 = -sum_j j thetas_j c_k+1-j (from y' = -thetas' y),
// dominated term by term by the series C_k of e^{A(w)} (the same recursion on
// |thetas_j|), whose sum at h is e^A. So truncating y after N terms errs by
// at most e^A - sum_{k <= N} C_k h^k on [0, h], and the integral of g_i times
// the truncated series, exact, by h max|g_i| times that. Terms are added until
// the sub-interval's share `allowed(E(v), E(v + h), h)` is met for every i; a
// sub-interval where A > 1 is halved first, and one whose 40 terms do not
// meet its share is halved and taken again (a term of order k needs at least
// k / D factors of A(w), D the depth's degree, so after N terms the tail is
// below sum_{m > N / D} A^m / m!: e / 41! for D = 1, but 0.02 for D = 10);
// then they grow back by doubling. Accepted and halved sub-intervals are
// counted as steps in `stats`. False when refused (beyond
// MaximumSubintervals), `out` undefined.
// The most sub-intervals SeriesIntegrals takes on a piece before it gives up;
// the bound above allows 2^41 for extreme data.
constexpr long MaximumSubintervals = 1L << 16;

template <typename Real, int N, int M, typename Allowed>
bool SeriesIntegrals(const PieceDepth<Real>& depth, const Real (&g)[N][M], Real l, Real El,
  const Allowed& allowed, RayStatistics<Real>& stats, Real (&out)[N])
{
  static constexpr Reciprocals<Real> inverse{};
  std::fill(out, out + N, Real(0));
  Real v = Real(0), h = l, Ev = Real(1);
  for (long count = 0; v < l; ++count)
  {
    if (count == MaximumSubintervals)
    {
      // Only data whose cubic's rounding exceeds the transfer function's
      // scale (corner values near 1e100) gets here: reported, not guessed.
      return false;
    }
    h = std::min(h, l - v);
    Real theta[PieceDepth<Real>::MaximumDegree + 1];
    std::copy(depth.D, depth.D + depth.Degree + 1, theta);
    ShiftPolynomial(theta, depth.Degree, v);
    Real gs[N][M];
    for (int i = 0; i < N; ++i)
    {
      std::copy(g[i], g[i] + M, gs[i]);
      ShiftPolynomial(gs[i], M - 1, v);
    }
    // The rest of each integral, int_v^l g_i e^{-theta}, lies within
    // +-Ev V_i (theta does not decrease; V_i bounds int |g_i|): once that is
    // within the rest's share, the rest is taken as 0. This ends a piece
    // whose transmittance has run out (Ev = 0 from extreme data) at once,
    // where sub-intervals of l 2^-40 would take 2^40 steps.
    const Real rest = l - v;
    Real variation = Real(0);
    for (int i = 0; i < N; ++i)
    {
      variation = std::max(variation, rest * MagnitudeAt(gs[i], rest));
    }
    if (Ev * variation <= allowed(Ev, El, rest))
    {
      stats.Accept(rest);
      break;
    }
    const Real floor = l * Real(9.094947017729282e-13); // 2^-40
    Real A = Magnitude(theta, depth.Degree, h);
    while (A > Real(1) && h > floor)
    {
      ++stats.Rejected;
      h = std::max(Real(0.5) * h, floor);
      A = Magnitude(theta, depth.Degree, h);
    }
    const Real end = l - v <= h ? l : v + h;
    const Real Eh = end == l ? El : std::exp(-depth(end));
    // Only for extreme data (a depth of 1, or a series that 40 terms do not
    // settle, within l 2^-40): each g_i keeps its sign, so its integral lies
    // between Eh and Ev times int g_i; their midpoint, proven within half the
    // difference (and the second mean value theorem).
    auto midpoint = [&]()
    {
      for (int i = 0; i < N; ++i)
      {
        Real integral = gs[i][M - 1] * inverse.R[M];
        for (int j = M - 2; j >= 0; --j)
        {
          integral = gs[i][j] * inverse.R[j + 1] + h * integral;
        }
        out[i] += h * integral * (Ev + Eh) / Real(2);
      }
      stats.Accept(h);
      v = end;
      Ev = Eh;
    };
    if (!(A <= Real(1)))
    {
      midpoint();
      continue;
    }
    Real limits[N], sums[N];
    std::fill(limits, limits + N, allowed(Ev, Eh, h));
    if (!SubintervalSeries(theta, depth.Degree, gs, h, A, Ev, limits, sums))
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
    for (int i = 0; i < N; ++i)
    {
      out[i] += Ev * sums[i];
    }
    stats.Accept(h);
    v = end;
    Ev = Eh;
    h *= Real(2);
  }
  return true;
}

// J = int_0^l q'(v) e^{-theta(v)} dv on a piece where q is monotone
// (SeriesIntegrals); NaN when refused.
template <typename Real, typename Allowed>
Real SeriesIntegral(const PieceDepth<Real>& depth, const Cubic<Real>& q, Real l, Real El,
  const Allowed& allowed, RayStatistics<Real>& stats)
{
  const Real g[1][3] = { { q.K[1], Real(2) * q.K[2], Real(3) * q.K[3] } };
  Real J[1];
  return SeriesIntegrals(depth, g, l, El, allowed, stats, J)
    ? J[0]
    : std::numeric_limits<Real>::quiet_NaN();
}

// Empty when the ray origin + t direction over `segments` can be
// integrated, else why; L its visible length (nothing to integrate unless
// positive).
template <typename Real>
std::string ValidatePiecewiseRay(const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count, Real& L)
{
  L = Real(0);
  if (!std::isfinite(origin.x + origin.y + origin.z + direction.x + direction.y + direction.z))
  {
    return "the ray's origin and direction must be finite";
  }
  L = TotalLength(segments, count);
  return ValidateSegments(segments, count);
}

// Empty when IntegratePiecewise can integrate the ray, else why; L as
// ValidatePiecewiseRay's.
template <typename Real, typename VolumeT>
std::string ValidatePiecewise(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  const PiecewiseTransferFunction<Real>& tf, Real tolerance, Real& L)
{
  L = Real(0);
  // The alpha model's floor was checked when `tf` was built.
  std::string error = ValidatePiecewiseTolerance(tolerance, OpacityModel::Extinction);
  if (!error.empty())
  {
    return error;
  }
  if (tf.GetNumberOfPieces() == 0)
  {
    return "the piecewise transfer function was not built";
  }
  for (int a = 0; a < 3; ++a)
  {
    if (volume.GetDimension(a) < 2)
    {
      return "the volume needs at least 2 points along each axis";
    }
  }
  return ValidatePiecewiseRay(origin, direction, segments, count, L);
}

// Why a ray's piece was refused: SubintervalsJ gave NaN.
constexpr const char* RefusedPieceError =
  "a piece needs more than 65536 sub-intervals (data values too large for double precision "
  "against the transfer function's knots)";

// J on the piece [0, l] (q, depth theta, e^{-theta(l)} = E) that its first
// sub-interval did not settle: SeriesIntegral's sub-intervals, [v, v + h]
// allowed scale (front (Ev - Eh) + h inverseL) (see above); NaN when
// refused.
template <typename Real>
Real SubintervalsJ(const Cubic<Real>& q, const PieceDepth<Real>& depth, Real l, Real E, Real scale,
  Real front, Real inverseL, RayStatistics<Real>& stats)
{
  auto allowed = [&](Real Ev, Real Eh, Real h)
  { return scale * (front * (Ev - Eh) + h * inverseL); };
  return SeriesIntegral(depth, q, l, E, allowed, stats);
}

// The same in transfer-function piece p (its depth).
template <typename Real>
Real SubintervalsJ(const Cubic<Real>& q, const typename PiecewiseTransferFunction<Real>::Piece& p,
  Real l, Real E, Real scale, Real front, Real inverseL, RayStatistics<Real>& stats)
{
  return SubintervalsJ(q, PieceDepth<Real>(q, p.Tau, p.TauSlope, p.TauCurvature, p.TauCubic), l, E,
    scale, front, inverseL, stats);
}

// A ray's RGBA from its colour and transmittance T: each channel inside [0,
// 1 - T] whatever the rounding (a sum of non-negative contributions bounded
// by 1 - T); none when not finite (RequireFinite).
template <typename Real>
void PiecewiseRGBA(glm::vec<3, Real> color, Real T, RayResult<Real>& result)
{
  for (int c = 0; c < 3; ++c)
  {
    color[c] = std::min(std::max(color[c], Real(0)), Real(1) - T);
  }
  result.RGBA = glm::vec<4, Real>(color, Real(1) - T);
  RequireFinite(result);
}
} // namespace detail

// The pieces of one ray, integrated a batch at a time: structures of arrays,
// lane i for the batch's i-th piece, so that a vectorised kernel
// (avos/engine/PieceKernels.h) takes a vector of pieces at once. The pieces
// of a ray are independent but for the transmittance in front of each (which
// scales J's share of the tolerance and decides early termination), so
// IntegratePiecewise runs two stages on a batch, Depths then Series, and
// composites between them, in order:
// - Depths, per piece: theta's coefficients (PieceDepth), e^{-theta(l)}, and
//   whether s is monotone where the walk did not know it (detail::Monotone);
// - Series, per piece whose J the midpoint bound does not settle: J on the
//   whole piece as the first sub-interval of SeriesIntegral does it (the rest
//   bound, then the series if A <= 1); a piece that this does not settle
//   (Settled 0) goes to SeriesIntegral whole.
// ScalarPieceKernels is the reference; a vectorised one computes the same
// formulas in another order (fused multiply-adds, a vector exponential of
// 1 ulp) and may differ from it by that rounding: relative 1e-13 in the
// depth and transmittance, and in J unless a rounding tips a decision (one
// series term more or less), where J stays within that piece's share of
// the tolerance either way.
template <typename Real>
struct PieceBatch
{
  // A multiple of the widest vector of Real of any target (8 doubles).
  static constexpr int Capacity = 8;
  static constexpr int Degree = detail::PieceDepth<Real>::MaximumDegree;
  int Count = 0;
  // In: q's coefficients, the length, tau's coefficients a, b, c, e.
  alignas(64) Real Q[4][Capacity];
  alignas(64) Real Length[Capacity];
  alignas(64) Real Tau[4][Capacity];
  // Out: theta's coefficients of v^1 .. v^Degree (Depth[0] unused) and
  // e^{-theta(l)}.
  alignas(64) Real Depth[Degree + 1][Capacity];
  alignas(64) Real Transmittance[Capacity];
  // In: 1 where s is known to be monotone on the piece, else 0; out: 1 where
  // it is (RayPiece::Monotone).
  alignas(64) Real Monotone[Capacity];

  // The piece in lane i.
  Cubic<Real> CubicAt(int i) const
  {
    return { { this->Q[0][i], this->Q[1][i], this->Q[2][i], this->Q[3][i] } };
  }

  // Lanes Count .. Capacity - 1 zeroed: transparent pieces of length 0, so
  // that kernels may take whole vectors.
  void Pad()
  {
    for (int i = this->Count; i < Capacity; ++i)
    {
      for (int k = 0; k < 4; ++k)
      {
        this->Q[k][i] = this->Tau[k][i] = Real(0);
      }
      this->Length[i] = Real(0);
      this->Monotone[i] = Real(1);
    }
  }
};

template <typename Real>
struct SeriesBatch
{
  static constexpr int Capacity = PieceBatch<Real>::Capacity;
  static constexpr int Degree = PieceBatch<Real>::Degree;
  int Count = 0;
  // In: theta's coefficients (Depth[0] unused), q' (K[1], 2 K[2], 3 K[3]),
  // the length l, e^{-theta(l)}, and the share of the tolerance J may take
  // on [0, h], allowed(1, E, h) = Scale (Front (1 - E) + h InverseLength),
  // InverseLength 1 / the ray's visible length.
  alignas(64) Real Depth[Degree + 1][Capacity];
  alignas(64) Real Slope[3][Capacity];
  alignas(64) Real Length[Capacity];
  alignas(64) Real Transmittance[Capacity];
  alignas(64) Real Scale[Capacity];
  alignas(64) Real Front[Capacity];
  Real InverseLength = Real(0);
  // Out: J, and 1 where it is settled (else 0, J undefined).
  alignas(64) Real J[Capacity];
  alignas(64) Real Settled[Capacity];

  // As PieceBatch::Pad: a piece of length 0 with no share, settled at once.
  void Pad()
  {
    for (int i = this->Count; i < Capacity; ++i)
    {
      for (int k = 1; k <= Degree; ++k)
      {
        this->Depth[k][i] = Real(0);
      }
      for (int k = 0; k < 3; ++k)
      {
        this->Slope[k][i] = Real(0);
      }
      this->Length[i] = this->Scale[i] = this->Front[i] = Real(0);
      this->Transmittance[i] = Real(1);
    }
  }
};

// The piecewise method's stages a piece (a cell) at a time: the reference
// the engine's kernels are tested against.
template <typename Real>
struct ScalarPieceKernels : ScalarCellKernels<Real>
{
  void Depths(PieceBatch<Real>& b) const
  {
    for (int i = 0; i < b.Count; ++i)
    {
      const Cubic<Real> q = b.CubicAt(i);
      const detail::PieceDepth<Real> depth(q, b.Tau[0][i], b.Tau[1][i], b.Tau[2][i], b.Tau[3][i]);
      for (int k = 1; k <= PieceBatch<Real>::Degree; ++k)
      {
        b.Depth[k][i] = k <= depth.Degree ? depth.D[k] : Real(0);
      }
      b.Transmittance[i] = std::exp(-depth(b.Length[i]));
      if (b.Monotone[i] == Real(0) && detail::Monotone(q, b.Length[i]))
      {
        b.Monotone[i] = Real(1);
      }
    }
  }

  void Series(SeriesBatch<Real>& b) const
  {
    for (int i = 0; i < b.Count; ++i)
    {
      const Real l = b.Length[i], E = b.Transmittance[i];
      Real theta[SeriesBatch<Real>::Degree + 1];
      theta[0] = Real(0);
      int degree = 1; // trailing zero coefficients add exact zeros: left out
      for (int k = 1; k <= SeriesBatch<Real>::Degree; ++k)
      {
        theta[k] = b.Depth[k][i];
        degree = theta[k] != Real(0) ? k : degree;
      }
      const Real g[3] = { b.Slope[0][i], b.Slope[1][i], b.Slope[2][i] };
      const Real limit = b.Scale[i] * (b.Front[i] * (Real(1) - E) + l * b.InverseLength);
      const Real variation = l * (std::abs(g[0]) + l * (std::abs(g[1]) + l * std::abs(g[2])));
      Real J = Real(0);
      bool settled = variation <= limit; // SeriesIntegral's rest bound, v = 0
      if (!settled)
      {
        const Real A = detail::Magnitude(theta, degree, l);
        settled =
          A <= Real(1) && detail::SubintervalSeries(theta, degree, g, l, A, Real(1), limit, J);
      }
      b.J[i] = J;
      b.Settled[i] = settled ? Real(1) : Real(0);
    }
  }
};

// `kernels` integrates the pieces' batches (PieceBatch): ScalarPieceKernels,
// or a vectorised one of the engine.
template <typename Real, typename VolumeT, typename Kernels = ScalarPieceKernels<Real>>
RayResult<Real> IntegratePiecewise(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  const PiecewiseTransferFunction<Real>& tf, Real tolerance, bool earlyTermination = true,
  std::vector<StepRecord<detail::NotDeduced<Real>>>* steps = nullptr,
  const Kernels& kernels = Kernels())
{
  RayResult<Real> result;
  result.Statistics.Steps = steps;
  Real L;
  result.Error =
    detail::ValidatePiecewise(volume, origin, direction, segments, count, tf, tolerance, L);
  if (!result.Error.empty() || !(L > Real(0)))
  {
    return result;
  }

  RayStatistics<Real>& stats = result.Statistics;
  const Real budget = Real(0.6) * tolerance;
  const Real terminationBound = Real(0.15) * tolerance / std::max(Real(1), tf.GetMaximumColor());
  const Real inverseL = Real(1) / L;
  glm::vec<3, Real> color(Real(0));
  Real T = Real(1);
  bool stopped = false;

  constexpr int Capacity = PieceBatch<Real>::Capacity;
  PieceBatch<Real> batch;
  SeriesBatch<Real> series;
  series.InverseLength = inverseL;
  // Per piece of the batch, beside its lanes: where it starts on the ray,
  // its transfer-function piece and the transmittance in front of it.
  Real begin[Capacity], front[Capacity];
  std::size_t piece[Capacity];
  int limit = Capacity;      // of the batch being gathered
  int seriesPiece[Capacity]; // the batch's lane of each series lane

  // Integrates the batch's pieces front to back; false once the ray stops.
  auto flush = [&]() -> bool
  {
    batch.Pad();
    kernels.Depths(batch);
    series.Count = 0;
    for (int i = 0; i < batch.Count && !stopped; ++i)
    {
      const auto& p = tf[piece[i]];
      const Real l = batch.Length[i];
      const Real qa = batch.Q[0][i], ql = batch.CubicAt(i)(l);
      ++stats.Pieces;
      ++stats.Samples; // the piece's end
      stats.Accept(l);
      const Real EL = batch.Transmittance[i];
      const Real Ta = T, Tb = T * EL;
      front[i] = Ta;
      color += Ta * (p.Colour + p.ColourSlope * qa) - Tb * (p.Colour + p.ColourSlope * ql);
      const Real cs = p.ColourSlopeMaximum;
      if (cs > Real(0) && Ta > Real(0))
      {
        // The error J may have on [v, v + h], spending e^{-theta} from Ev to
        // Eh, is budget (Ta (Ev - Eh) + h / L) / (2 cs Ta); the midpoint of
        // J's bounds errs by |dq| (1 - EL) / 2 on the whole piece.
        const Real dq = ql - qa;
        if (batch.Monotone[i] != Real(0) &&
          cs * Ta * std::abs(dq) * (Real(1) - EL) <= budget * (Ta * (Real(1) - EL) + l * inverseL))
        {
          color += p.ColourSlope * (Ta * (dq * (Real(1) + EL) / Real(2)));
        }
        else
        {
          const int j = series.Count++;
          seriesPiece[j] = i;
          for (int k = 1; k <= PieceBatch<Real>::Degree; ++k)
          {
            series.Depth[k][j] = batch.Depth[k][i];
          }
          series.Slope[0][j] = batch.Q[1][i];
          series.Slope[1][j] = Real(2) * batch.Q[2][i];
          series.Slope[2][j] = Real(3) * batch.Q[3][i];
          series.Length[j] = l;
          series.Transmittance[j] = EL;
          series.Scale[j] = budget / (Real(2) * cs * Ta);
          series.Front[j] = Ta;
        }
      }
      T = Tb;
      if (stats.Steps)
      {
        stats.Steps->push_back({ begin[i], l, Real(1) - T });
      }
      if (earlyTermination && T <= terminationBound)
      {
        stats.Terminated = true;
        stopped = true;
      }
    }
    if (series.Count > 0)
    {
      series.Pad();
      kernels.Series(series);
    }
    for (int j = 0; j < series.Count; ++j)
    {
      const int i = seriesPiece[j];
      const auto& p = tf[piece[i]];
      const Real Ta = front[i], scale = series.Scale[j], l = batch.Length[i];
      Real J = series.J[j];
      if (series.Settled[j] != Real(0))
      {
        stats.Accept(l);
      }
      else
      {
        // Not settled on the whole piece: sub-intervals.
        J = detail::SubintervalsJ(
          batch.CubicAt(i), p, l, series.Transmittance[j], scale, Ta, inverseL, stats);
        if (std::isnan(J))
        {
          result.Error = detail::RefusedPieceError;
          stopped = true;
          break;
        }
      }
      color += p.ColourSlope * (Ta * J);
    }
    batch.Count = 0;
    // The next batch holds no more pieces than the ray may need to reach
    // early termination at the mean depth of its pieces so far, so that the
    // walk seldom runs past it (the batch's size changes nothing else).
    if (earlyTermination && T < Real(1) && T > terminationBound)
    {
      const Real expected = std::log(T / terminationBound) * Real(stats.Pieces) / -std::log(T);
      limit = expected < Real(Capacity) ? static_cast<int>(expected) + 1 : Capacity;
    }
    return !stopped;
  };
  auto gather = [&](const RayPiece<Real>& rp) -> bool
  {
    const int i = batch.Count++;
    begin[i] = rp.Begin;
    piece[i] = rp.TF;
    batch.Monotone[i] = rp.Monotone ? Real(1) : Real(0);
    const auto& p = tf[rp.TF];
    for (int k = 0; k < 4; ++k)
    {
      batch.Q[k][i] = rp.Q.K[k];
    }
    batch.Length[i] = rp.Length;
    batch.Tau[0][i] = p.Tau;
    batch.Tau[1][i] = p.TauSlope;
    batch.Tau[2][i] = p.TauCurvature;
    batch.Tau[3][i] = p.TauCubic;
    return batch.Count < limit || flush();
  };

  for (std::size_t j = 0; j < count && !stopped; ++j)
  {
    // The cells' stage takes no more cells at a time than the pieces'.
    PieceWalk(volume, origin, direction, segments[j].Begin, segments[j].End, tf, stats.Cells,
      gather, kernels, &limit);
  }
  if (!stopped && batch.Count > 0)
  {
    flush();
  }
  if (!result.Error.empty())
  {
    return result; // a refused piece: no value
  }
  detail::PiecewiseRGBA(color, T, result);
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
