// Shading in the piecewise method: the lit emission of Shading.h integrated
// piece by piece (PiecewiseIntegrator.h) with a proven error.
//
// On a piece, v in [0, l] from its start, the depth theta(v) and the
// transmittance T = Ta e^{-theta} are exact as without shading; the emission
// is tau(v) L(v), L the lit colour (LitColour): the colour C(s(v)) lit by the
// exact gradient of the trilinear interpolant, whose world-space components
// along the ray are quadratics in v. L has no closed-form integral against
// tau T, so it is enclosed. On a sub-interval X = [v0, v1] of the piece, one
// evaluation of LitColourOf on Jets (Enclosure.h; the piece's cubic and
// gradient components enter as PolynomialJets of their coefficients)
// encloses, per channel, L(X), and where L is smooth on X also L(c) and
// L'(c) at X's centre c and L''(X).
// Two approximations of L on X with proven errors:
// - the constant P = mid L(X): |L - P| <= delta0 = width L(X) / 2;
// - the quadratic P(v) = f + f1 (v - c) + f2 (v - c)^2 / 2, f, f1, f2 the
//   midpoints of the enclosures of L(c), L'(c), L''(X): by Taylor's theorem
//   |L - P| <= delta2 = w L(c) / 2 + w L'(c) r / 2 + w L''(X) r^2 / 4, r the
//   radius of X (w the enclosure's width; delta2 shrinks as r^3).
// The weight tau T is positive and its integral over X is the transmittance
// dT spent there, exactly, so |int_X (L - P) tau T| <= delta dT. The rest is
// by parts (d/dv T = -tau T):
//   int_X P tau T = P(v0) T(v0) - P(v1) T(v1) + int_X P' T,
// the last term 0 for the constant; for the quadratic (P' linear) T(v0) times
// int_0^h P'(v0 + u) e^{-(theta(v0 + u) - theta(v0))} du, which the series of
// PiecewiseIntegrator.h gives with a proven truncation error, the three
// channels at once, or, where P' keeps its sign, the midpoint of its bounds
// dP e^{-dtheta} and dP, within |dP| dT / 2 (second mean value theorem).
//
// Tolerance eps, per channel:
// - 0.55 eps for the lit colour: sub-interval X may err by its share,
//   0.275 eps (dT + h / L) (h its length, L the ray's visible length), half
//   for delta dT and half for the P' term; the shares of all sub-intervals
//   add up to at most 0.55 eps (sum dT <= 1, sum h <= L).
// - 0.05 eps for sub-intervals that reach the floor l 2^-40 without fitting
//   their share (a kink of L, or a gradient vanishing at a point, inside):
//   they take the constant, whose delta0 <= 1/2 (L is clamped to [0, 1]),
//   and what they exceed their share by is summed; past 0.05 eps the ray
//   reports an error instead of a colour outside the tolerance.
// - 0.15 eps for early termination: the ray stops once T is below it (the
//   lit colour is at most 1).
// - 0.25 eps for VTK's alpha model, as without shading.
// So every channel of every ray is within eps, up to rounding.
//
// Termination. A sub-interval is accepted (v advances by its length h, at
// least the floor but at the piece's end; h then grows by the factor
// NextLengthFactor predicts, within [1, 4], or doubles after a floor
// sub-interval) or shrunk by at least half, at most 41 times in a row before
// h reaches the floor, where it is accepted. So a piece takes at most 42
// (2^40 + 1) evaluations. Since that would never end
// in practice, a piece is refused beyond MaximumSubintervals evaluations
// (the ray reports an error). A smooth L needs few: delta2 shrinks as h^3.
// A kink of L (n.l or n.h changing sign, the clamp switching) makes its
// sub-interval Rough, whose delta0 shrinks as h: about log2(L' / eps)
// halvings around each kink. A spot's cone edge is a jump of L: its
// sub-interval halves until its dT fits, at most to the floor (41 halvings).
//
// A sample is one evaluation of the lit colour's enclosure.
#ifndef avos_numerics_PiecewiseShading_h
#define avos_numerics_PiecewiseShading_h

#include "avos/numerics/Enclosure.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Shading.h"

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
// The world-space gradient of the trilinear interpolant along the piece `rp`
// of the ray origin + t direction (grid coordinates): G[a][k] the
// coefficient of v^k of component a, v from the piece's start.
template <typename Real, typename VolumeT>
void PieceGradient(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const RayPiece<Real>& rp,
  const glm::mat<3, 3, Real>& normalMatrix, Real G[3][3])
{
  // The piece lies in one cell: the one holding its middle.
  const glm::vec<3, Real> middle = origin + (rp.Begin + rp.Length / Real(2)) * direction;
  int index[3];
  Real fraction;
  for (int a = 0; a < 3; ++a)
  {
    LocateCell(middle[a], volume.GetDimension(a), index[a], fraction);
  }
  Real c[8];
  volume.GetCorners(index[0], index[1], index[2], c);
  const TrilinearForm<Real> f(c);
  const glm::vec<3, Real> e = origin + rp.Begin * direction -
    glm::vec<3, Real>(Real(index[0]), Real(index[1]), Real(index[2]));
  const glm::vec<3, Real> grid[3] = { f.Gradient(e), f.GradientSlope(e, direction),
    f.GradientCurvature(direction) };
  for (int k = 0; k < 3; ++k)
  {
    const glm::vec<3, Real> world = normalMatrix * grid[k];
    for (int a = 0; a < 3; ++a)
    {
      G[a][k] = world[a];
    }
  }
}

// The polynomial sum_k p[k] v^k (its coefficients enclosed) as a Jet over
// the sub-interval of centre c and radius r: its coefficients about c, b_k
// (Taylor shift in interval arithmetic), give F = b0, F1 = b1 and the ranges
// of the value, first and second derivatives as sums of b_k y^k over y in
// [-r, r]. Far cheaper than Horner's rule on Jets (a product of Jets per
// degree), and tighter.
template <typename Real, int N>
Jet<Real> PolynomialJet(const Bounds<Real> (&p)[N], Real c, Real r)
{
  static_assert(N >= 1 && N <= 5, "degree at most 4");
  Bounds<Real> b[N];
  std::copy(p, p + N, b);
  const Bounds<Real> centre(c);
  for (int i = 0; i < N - 1; ++i)
  {
    for (int k = N - 2; k >= i; --k)
    {
      b[k] = b[k] + centre * b[k + 1];
    }
  }
  // y^k over [-r, r]: [-r^k, r^k] for odd k, [0, r^k] for even k.
  Bounds<Real> Y[N];
  Real power = Real(1);
  for (int k = 0; k < N; ++k)
  {
    Y[k] = k == 0 ? Bounds<Real>(Real(1))
      : k % 2     ? Bounds<Real>::Outward(-power, power)
                  : Bounds<Real>::Outward(Real(0), power);
    power *= r;
  }
  Jet<Real> j;
  j.F = b[0];
  j.F1 = N > 1 ? b[1] : Bounds<Real>(Real(0));
  j.V = b[0];
  j.D1 = j.F1;
  j.D2 = Bounds<Real>(Real(0));
  for (int k = 1; k < N; ++k)
  {
    j.V = j.V + b[k] * Y[k];
    if (k >= 2)
    {
      j.D1 = j.D1 + Bounds<Real>(Real(k)) * b[k] * Y[k - 1];
      j.D2 = j.D2 + Bounds<Real>(Real(k * (k - 1))) * b[k] * Y[k - 2];
    }
  }
  j.Radius = r;
  return j;
}

// A piece's gradient as LitColourOf reads it (Shading.h), from its
// world-space components' quadratics G[a][k] v^k over the sub-interval of
// centre c and radius r: each component a PolynomialJet, the squared length
// and the dot products with constant directions built from them (not from
// the quartic's own coefficients, whose cancellation where the gradient
// nearly vanishes would cost the enclosure its relative precision there).
// `Zero` where the cell's corners are equal (no normal anywhere).
template <typename Real>
struct GradientPolynomials
{
  Jet<Real> G[3];
  bool Zero;

  GradientPolynomials(const Real (*g)[3], Real c, Real r, bool zero)
    : Zero(zero)
  {
    for (int a = 0; a < 3 && !zero; ++a)
    {
      const Bounds<Real> q[3] = { g[a][0], g[a][1], g[a][2] };
      this->G[a] = PolynomialJet(q, c, r);
    }
  }

  Jet<Real> Squared() const
  {
    return this->G[0] * this->G[0] + this->G[1] * this->G[1] + this->G[2] * this->G[2];
  }
  Jet<Real> Dot(const glm::vec<3, Real>& w) const
  {
    return this->G[0] * w.x + this->G[1] * w.y + this->G[2] * w.z;
  }
  void Components(Jet<Real> g[3]) const { std::copy(this->G, this->G + 3, g); }
  Sign SignOf(const Jet<Real>& squared) const
  {
    if (this->Zero || squared.V.Hi <= Real(0))
    {
      return Sign::Zero;
    }
    return squared.V.Lo > Real(0) && std::isfinite(squared.V.Hi) ? Sign::Positive : Sign::Either;
  }
};

// The floor of a piece's sub-intervals, relative to its length: 2^-40.
constexpr double ShadedFloor = 9.094947017729282e-13;

// The lit colour's approximation on one sub-interval of centre c, per
// channel: the constant Constant, or (Quadratic) F + F1 (v - c) + F2 (v - c)^2
// / 2, within Delta of L.
template <typename Real>
struct LitApproximation
{
  bool Quadratic[3];
  Real Constant[3];
  Real F[3], F1[3], F2[3];
  Real Delta[3];
};

// The factor of the next sub-interval's length after one whose
// approximation erred by `excess` times its half share: the error times dT
// shrinks as the length's fourth power for the quadratic (delta2 ~ r^3, dT ~
// r) against a share ~ r, so the cube root of 0.8 / excess aims just below
// the share (fewer, longer sub-intervals for a few more rejections,
// measured); at most `most`, at least 1/8 (a kink makes the error shrink
// only as r).
template <typename Real>
Real NextLengthFactor(Real excess, Real most)
{
  const Real f = excess > Real(0) && std::isfinite(excess) ? std::cbrt(Real(0.8) / excess) : most;
  return std::min(most, std::max(Real(0.125), f));
}

// Fills `a` from the Jets of the lit colour over a sub-interval of radius r:
// per channel the constant unless its error times dT exceeds `limit` and the
// quadratic's is smaller. True when every channel's delta dT is within
// `limit`.
template <typename Real>
bool Approximate(const Jet<Real> lit[3], Real r, Real dT, Real limit, LitApproximation<Real>& a)
{
  bool fits = true;
  for (int k = 0; k < 3; ++k)
  {
    const Jet<Real>& L = lit[k];
    const Real delta0 = L.V.Width() / Real(2);
    Real delta2 = std::numeric_limits<Real>::infinity();
    if (L.Smooth && L.Centred)
    {
      delta2 = L.F.Width() / Real(2) + L.F1.Width() / Real(2) * r + L.D2.Width() / Real(4) * r * r;
      delta2 = std::isfinite(delta2) ? delta2 : std::numeric_limits<Real>::infinity();
    }
    a.Quadratic[k] = !(delta0 * dT <= limit) && delta2 < delta0;
    if (a.Quadratic[k])
    {
      a.F[k] = L.F.Lo + L.F.Width() / Real(2);
      a.F1[k] = L.F1.Lo + L.F1.Width() / Real(2);
      a.F2[k] = L.D2.Lo + L.D2.Width() / Real(2);
      a.Delta[k] = delta2;
    }
    else
    {
      a.Constant[k] = L.V.Lo + L.V.Width() / Real(2);
      a.Delta[k] = delta0;
    }
    fits = fits && a.Delta[k] * dT <= limit;
  }
  return fits;
}

// int_0^l L tau T over a piece (q, transfer-function piece p, depth theta,
// e^{-theta(l)} = El, transmittance Ta in front, world gradient G, world
// position `start` at v = 0), added to `color`; see above. `scale` turns
// (dT + h / L) into a share, `inverseL` is 1 / L; what floor sub-intervals
// exceed their share by is added to `overdraft`. False when the piece is
// refused (MaximumSubintervals).
template <typename Real>
bool ShadedPiece(const Cubic<Real>& q, const typename PiecewiseTransferFunction<Real>::Piece& p,
  const PieceDepth<Real>& depth, Real l, Real El, Real Ta, const Real G[3][3],
  const glm::vec<3, Real>& start, const RayShading<Real>& shading, Real scale, Real inverseL,
  glm::vec<3, Real>& color, Real& overdraft, RayStatistics<Real>& stats)
{
  using JetR = Jet<Real>;
  const bool positional = shading.Model->HasPositionalLights();
  bool zero = true; // no normal anywhere on the piece
  for (int a = 0; a < 3; ++a)
  {
    zero = zero && G[a][0] == Real(0) && G[a][1] == Real(0) && G[a][2] == Real(0);
  }
  const Real floor = l * Real(ShadedFloor);
  Real v = Real(0), h = l, Ev = Real(1);
  for (long count = 0; v < l && Ev > Real(0); ++count)
  {
    if (count == MaximumSubintervals)
    {
      return false;
    }
    h = std::min(h, l - v);
    const Real end = l - v <= h ? l : v + h;
    const Real width = end - v;
    const Real Eh = end == l ? El : std::exp(-depth(end));
    const Real dT = Ta * (Ev - Eh);
    const Real share = scale * (dT + width * inverseL);
    const bool atFloor = h <= floor; // not width: v + h - v may round above it

    const JetR u = JetR::Variable(Bounds<Real>(v, end));
    const Real c = u.F.Lo;
    const Bounds<Real> cubic[4] = { q.K[0], q.K[1], q.K[2], q.K[3] };
    const JetR s = PolynomialJet(cubic, c, u.Radius);
    JetR colour[3], lit[3];
    for (int k = 0; k < 3; ++k)
    {
      colour[k] = p.Colour[k] + p.ColourSlope[k] * s;
    }
    const GradientPolynomials<Real> gradient(G, c, u.Radius, zero);
    JetR position[3];
    if (positional)
    {
      for (int k = 0; k < 3; ++k)
      {
        position[k] = start[k] + u * shading.WorldDirection[k];
      }
    }
    LitColourOf(*shading.Model, colour, gradient, shading.ToViewer, position, lit);
    ++stats.Samples;

    LitApproximation<Real> a;
    bool fits = Approximate(lit, u.Radius, dT, share / Real(2), a);
    // How far the approximation's error is from its half share: the next
    // length follows from it (below).
    Real ratio = Real(0);
    for (int k = 0; k < 3; ++k)
    {
      ratio = std::max(ratio, a.Delta[k] * dT / (share / Real(2)));
    }
    // The P' terms: T(v0) int P' e^{-dtheta}, per channel (0 for a constant).
    Real Pv[3], Pe[3], terms[3] = { Real(0), Real(0), Real(0) };
    Real g[3][3], limits[3];
    bool series = false;
    for (int k = 0; k < 3 && fits; ++k)
    {
      g[k][0] = g[k][1] = g[k][2] = Real(0);
      limits[k] = share / Real(2);
      if (!a.Quadratic[k])
      {
        Pv[k] = Pe[k] = a.Constant[k];
        continue;
      }
      const Real x0 = v - c, x1 = end - c;
      Pv[k] = a.F[k] + x0 * (a.F1[k] + x0 * a.F2[k] / Real(2));
      Pe[k] = a.F[k] + x1 * (a.F1[k] + x1 * a.F2[k] / Real(2));
      const Real s0 = a.F1[k] + a.F2[k] * x0, s1 = a.F1[k] + a.F2[k] * x1;
      const Real dP = Pe[k] - Pv[k];
      if (s0 * s1 >= Real(0) && std::abs(dP) * dT <= share)
      {
        terms[k] = Ta * dP * (Ev + Eh) / Real(2);
        continue;
      }
      g[k][0] = s0;
      g[k][1] = a.F2[k];
      series = true;
    }
    if (fits && series)
    {
      Real theta[PieceDepth<Real>::MaximumDegree + 1];
      std::copy(depth.D, depth.D + depth.Degree + 1, theta);
      ShiftPolynomial(theta, depth.Degree, v);
      const Real A = Magnitude(theta, depth.Degree, width);
      Real sums[3];
      fits =
        A <= Real(1) && SubintervalSeries(theta, depth.Degree, g, width, A, Ta * Ev, limits, sums);
      for (int k = 0; k < 3 && fits; ++k)
      {
        if (g[k][0] != Real(0) || g[k][1] != Real(0))
        {
          terms[k] = Ta * Ev * sums[k];
        }
      }
    }
    if (!fits && !atFloor)
    {
      ++stats.Rejected;
      h = std::max(h * NextLengthFactor(ratio, Real(0.5)), floor);
      continue;
    }
    if (!fits)
    {
      // At the floor: the constants (lit[k].V within [0, 1]), their excess
      // over the share counted.
      Real excess = Real(0);
      for (int k = 0; k < 3; ++k)
      {
        const Real delta0 = lit[k].V.Width() / Real(2);
        Pv[k] = Pe[k] = lit[k].V.Lo + delta0;
        terms[k] = Real(0);
        excess = std::max(excess, delta0 * dT - share);
      }
      overdraft += excess;
    }
    for (int k = 0; k < 3; ++k)
    {
      color[k] += Ta * (Pv[k] * Ev - Pe[k] * Eh) + terms[k];
    }
    stats.Accept(width);
    v = end;
    Ev = Eh;
    // A fit predicts its successor's length; a floor sub-interval that did
    // not fit (a kink) says nothing of the next one: h doubles.
    h *= fits ? std::max(Real(1), NextLengthFactor(ratio, Real(4))) : Real(2);
  }
  return true;
}
} // namespace detail

// The piecewise method (IntegratePiecewise) with the emission lit by
// `shading` (Shading.h), within `tolerance` per channel; see above. The
// volume must be trilinear (TrilinearVolume: a gradient per cell).
template <typename Real, typename VolumeT>
RayResult<Real> IntegratePiecewiseShaded(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  const PiecewiseTransferFunction<Real>& tf, Real tolerance, const RayShading<Real>& shading,
  bool earlyTermination = true, std::vector<StepRecord<detail::NotDeduced<Real>>>* steps = nullptr)
{
  RayResult<Real> result;
  result.Statistics.Steps = steps;
  Real L;
  result.Error =
    detail::ValidatePiecewise(volume, origin, direction, segments, count, tf, tolerance, L);
  if (result.Error.empty())
  {
    result.Error = shading.Model ? shading.Model->Validate() : "no shading model";
  }
  if (!result.Error.empty() || !(L > Real(0)))
  {
    return result;
  }
  RayStatistics<Real>& stats = result.Statistics;
  const Real scale = Real(0.275) * tolerance, reserve = Real(0.05) * tolerance;
  const Real terminationBound = Real(0.15) * tolerance;
  const Real inverseL = Real(1) / L;
  glm::vec<3, Real> color(Real(0));
  Real T = Real(1), overdraft = Real(0);
  bool stopped = false;
  auto visit = [&](const RayPiece<Real>& rp) -> bool
  {
    const auto& p = tf[rp.TF];
    ++stats.Pieces;
    const detail::PieceDepth<Real> depth(rp.Q, p.Tau, p.TauSlope, p.TauCurvature, p.TauCubic);
    const Real El = std::exp(-depth(rp.Length));
    if (T * (Real(1) - El) > Real(0))
    {
      Real G[3][3];
      detail::PieceGradient(volume, origin, direction, rp, shading.NormalMatrix, G);
      const glm::vec<3, Real> start = shading.WorldOrigin + rp.Begin * shading.WorldDirection;
      if (!detail::ShadedPiece(rp.Q, p, depth, rp.Length, El, T, G, start, shading, scale, inverseL,
            color, overdraft, stats))
      {
        result.Error = "a piece needs more than 65536 enclosures of the lit colour (its kinks "
                       "or a nearly vanishing gradient too close together)";
      }
      else if (overdraft > reserve)
      {
        result.Error = "the lit colour has kinks or vanishing gradients closer together than "
                       "double precision separates (sub-intervals of 2^-40 of a piece exceed the "
                       "tolerance's reserve)";
      }
    }
    T *= El;
    if (stats.Steps)
    {
      stats.Steps->push_back({ rp.Begin, rp.Length, Real(1) - T });
    }
    if (!result.Error.empty() || (earlyTermination && T <= terminationBound))
    {
      stats.Terminated = result.Error.empty();
      stopped = true;
    }
    return !stopped;
  };
  for (std::size_t j = 0; j < count && !stopped; ++j)
  {
    PieceWalk(
      volume, origin, direction, segments[j].Begin, segments[j].End, tf, stats.Cells, visit);
  }
  if (!result.Error.empty())
  {
    return result;
  }
  detail::PiecewiseRGBA(color, T, result);
  return result;
}

} // namespace numerics
} // namespace avos

#endif
