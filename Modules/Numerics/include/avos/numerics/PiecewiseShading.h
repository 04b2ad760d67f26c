// Shading in the piecewise method: the lit emission of Shading.h integrated
// piece by piece (PiecewiseIntegrator.h) with a proven error.
//
// On a piece, v in [0, l] from its start, the depth theta(v) and the
// transmittance T = Ta e^{-theta} are exact as without shading; the emission
// is tau(v) L(v), L the lit colour (LitColour): the colour C(s(v)) lit by the
// exact gradient of the trilinear interpolant, whose world-space components
// along the ray are quadratics in v. L has no closed-form integral against
// tau T, so it is enclosed. On a sub-interval X = [v0, v1] of centre c, one
// evaluation of LitColourOf on Taylor models of degree N (TaylorModel.h; the
// piece's cubic, the gradient's quadratics and, for positional lights, the
// world position enter as models of their coefficients) gives per channel a
// polynomial P of degree N in y = v - c and a remainder R with |L - P| <= R
// on X: R shrinks as r^(N+1) (r the radius of X) where L is smooth, and as
// the kink's reach into X where n.l or n.h changes sign or the clamp
// switches.
// The weight tau T is positive and its integral over X is the transmittance
// dT spent there, exactly, so |int_X (L - P) tau T| <= R dT. The rest is by
// parts (d/dv T = -tau T):
//   int_X P tau T = P(v0) T(v0) - P(v1) T(v1) + int_X P' T,
// the last term T(v0) int_0^h P'(v0 + u) e^{-(theta(v0 + u) - theta(v0))} du,
// which the series of PiecewiseIntegrator.h gives with a proven truncation
// error, the three channels at once, or, where P' keeps its sign, the
// midpoint of its bounds dP e^{-dtheta} and dP, within |dP| dT / 2 (second
// mean value theorem).
//
// Tolerance eps, per channel:
// - 0.55 eps for the lit colour: sub-interval X may err by its share,
//   0.275 eps (dT + h / L) (h its length, L the ray's visible length), half
//   for R dT and half for the P' term; the shares of all sub-intervals add
//   up to at most 0.55 eps (sum dT <= 1, sum h <= L).
// - 0.05 eps, the reserve, for the excesses over the shares, summed: of
//   sub-intervals that reach the floor l 2^-40 without fitting their share
//   (a jump of L, or a gradient vanishing at a point, inside), which take
//   the constant, the middle of L's enclosure within [0, 1], within at most
//   1/2; and of any sub-interval whose excess is below 2^-20 of what is left
//   of the reserve (near a vanishing gradient, where rounding bounds R from
//   below and no length fits its share, R dT is tiny), which keeps its
//   model. Past 0.05 eps the ray reports an error instead of a colour
//   outside the tolerance.
// - 0.15 eps for early termination: the ray stops once T is below it (the
//   lit colour is at most 1).
// - 0.25 eps for VTK's alpha model, as without shading.
// So every channel of every ray is within eps, up to rounding (the models
// take their own rounding into R).
//
// Termination. A sub-interval is accepted (v advances by its length h, at
// least the floor but at the piece's end or a kink's cut; h then grows by
// the factor NextLengthFactor predicts, within [1, 4], or doubles after a
// sub-interval that did not fit its share or was dim) or shrunk by at least
// half, at most 41 times in a row before h reaches the floor, where it is
// accepted. So a piece takes at most 42
// (2^40 + 1) evaluations. Since that would never end in practice, a piece is
// refused beyond MaximumSubintervals evaluations (the ray reports an error).
// A smooth L needs few: R dT shrinks as h^(N+2) against a share ~ h. A kink
// of L shrinks R only as h: about log2(L' / eps) halvings around each kink.
// A spot's cone edge is a jump of L: its sub-interval halves until its dT
// fits, at most to the floor (41 halvings).
//
// A sample is one evaluation of the lit colour's models.
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
#include <type_traits>
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

// Whether all of a piece's gradient coefficients are 0 (the cell's corners
// are equal: no normal anywhere on the piece).
template <typename Real>
bool ZeroGradient(const Real G[3][3])
{
  bool zero = true;
  for (int a = 0; a < 3; ++a)
  {
    zero = zero && G[a][0] == Real(0) && G[a][1] == Real(0) && G[a][2] == Real(0);
  }
  return zero;
}

// The degree N of the lit colour's Taylor models, by tolerance: a
// sub-interval's error shrinks as its length to the power N + 1, each
// enclosure costs about (N + 1)^2. Measured on random shaded rays through the
// Bonsai: at eps 1e-3 degree 3 is the fastest (1.3x degree 5), at 1e-9
// degree 5 (1.5x degree 3).
template <typename Real>
constexpr int ShadedDegree(Real tolerance)
{
  return tolerance >= Real(1e-5) ? 3 : 5;
}

// A piece's gradient as LitColourOf reads it (Shading.h), from its
// world-space components' quadratics G[a][k] v^k over the sub-interval of
// centre c and radius r: each component a Taylor model, the squared length
// and the dot products with constant directions built from them (not from
// the quartic's own coefficients, whose cancellation where the gradient
// nearly vanishes would cost the enclosure its relative precision there).
// `Zero` where the cell's corners are equal (no normal anywhere).
template <typename Real, int N>
struct GradientPolynomials
{
  using Model = TaylorModel<Real, N>;
  Model G[3];
  bool Zero;

  GradientPolynomials(const Real (*g)[3], Real c, Real r, bool zero)
    : Zero(zero)
  {
    for (int a = 0; a < 3 && !zero; ++a)
    {
      this->G[a] = Model::Polynomial(g[a], c, r);
    }
  }

  Model Squared() const
  {
    return this->G[0] * this->G[0] + this->G[1] * this->G[1] + this->G[2] * this->G[2];
  }
  Model Dot(const glm::vec<3, Real>& w) const
  {
    return this->G[0] * w.x + this->G[1] * w.y + this->G[2] * w.z;
  }
  void Components(Model g[3]) const { std::copy(this->G, this->G + 3, g); }
  Sign SignOf(const Model& squared) const
  {
    const Bounds<Real> range = squared.Range();
    if (this->Zero || range.Hi <= Real(0))
    {
      return Sign::Zero;
    }
    return range.Lo > Real(0) && std::isfinite(range.Hi) ? Sign::Positive : Sign::Either;
  }
};

// The floor of a piece's sub-intervals, relative to its length: 2^-40.
constexpr double ShadedFloor = 9.094947017729282e-13;

// The factor of the next sub-interval's length after one whose
// approximation of degree N erred by `excess` times its half share: the
// error times dT shrinks as the length's (N + 2)th power against a share ~
// the length, so the (N + 1)th root of 0.8 / excess aims just below the
// share; at most `most`, at least 1/8 (a kink makes the error shrink only as
// the length).
template <int N, typename Real>
Real NextLengthFactor(Real excess, Real most)
{
  const Real f = excess > Real(0) && std::isfinite(excess)
    ? std::pow(Real(0.8) / excess, Real(1) / Real(N + 1))
    : most;
  return std::min(most, std::max(Real(0.125), f));
}

// The lit colour's model on the sub-interval [v, end] of the piece (cubic
// q, transfer-function piece p, world gradient G, `zero` where it vanishes
// everywhere, world position `start` at v = 0), about the centre c.
template <int N, typename Real>
void LitModels(const Cubic<Real>& q, const typename PiecewiseTransferFunction<Real>::Piece& p,
  const Real G[3][3], bool zero, const glm::vec<3, Real>& start, const RayShading<Real>& shading,
  Real c, Real r, TaylorModel<Real, N> lit[3])
{
  using Model = TaylorModel<Real, N>;
  const Real cubic[4] = { q.K[0], q.K[1], q.K[2], q.K[3] };
  const Model s = Model::Polynomial(cubic, c, r);
  Model colour[3];
  for (int k = 0; k < 3; ++k)
  {
    colour[k] = p.ColourSlope[k] * s + p.Colour[k];
  }
  const GradientPolynomials<Real, N> gradient(G, c, r, zero);
  Model position[3];
  if (shading.Model->HasPositionalLights())
  {
    for (int k = 0; k < 3; ++k)
    {
      // start + (c + y) direction: a line, its constant term's rounding in R.
      const Real line[2] = { start[k], shading.WorldDirection[k] };
      position[k] = Model::Polynomial(line, c, r);
    }
  }
  LitColourOf(*shading.Model, colour, gradient, shading.ToViewer, position, lit);
}

// Where n.l changes sign on a piece, for each directional light, and n.h
// where the specular power is below N + 1 (|x|^p is smooth enough for the
// models beyond): the roots in (0, l) of the quadratics g.l and g.h (g the
// piece's world gradient G[a][k] v^k), sorted. Sub-intervals end there, so
// that each kink of |n.l| or max(0, n.l) lies at a sub-interval's end, where
// the models take only its rounding's reach (a kink inside one shrinks its
// remainder only as its length). The cuts only shorten sub-intervals: at most
// Capacity of them (lights beyond are left to the subdivision).
template <typename Real>
struct KinkCuts
{
  static constexpr int Capacity = 32;
  Real At[Capacity];
  int Count = 0;

  void Find(const Real G[3][3], Real l, const ShadingModel<Real>& model,
    const glm::vec<3, Real>& toViewer, int degree)
  {
    for (const Light<Real>& light : model.Lights)
    {
      if (light.Positional)
      {
        continue;
      }
      this->Add(G, l, light.Direction);
      const glm::vec<3, Real> half = light.Direction + toViewer;
      if (model.Specular > Real(0) && model.SpecularPower < Real(degree + 1) &&
        glm::length(half) > Real(0))
      {
        this->Add(G, l, glm::normalize(half));
      }
    }
    std::sort(this->At, this->At + this->Count);
  }

private:
  void Add(const Real G[3][3], Real l, const glm::vec<3, Real>& w)
  {
    Real q[3];
    for (int k = 0; k < 3; ++k)
    {
      q[k] = G[0][k] * w.x + G[1][k] * w.y + G[2][k] * w.z;
    }
    Real roots[2];
    const int n = QuadraticRoots(q[2], q[1], q[0], l, roots);
    for (int i = 0; i < n && this->Count < Capacity; ++i)
    {
      this->At[this->Count++] = roots[i];
    }
  }
};

// A ray's error budget for its sub-intervals: a sub-interval of length h
// spending dT may err by Scale (dT + h / L) (its share; InverseL = 1 / L);
// the excesses beyond shares, counted in the ray's overdraft, by Reserve in
// all.
template <typename Real>
struct ShadedBudget
{
  Real Scale;
  Real InverseL;
  Real Reserve;
};

// Why SubintervalPiece refused a piece.
constexpr const char* RefusedSubintervalsError =
  "a piece needs more than 65536 sub-intervals of its models (kinks of the lit colour or the "
  "extinction, or a nearly vanishing gradient, too close together)";

// What a sub-interval [v, v + h] of a piece knows of the depth, from a
// depth policy (ExactDepth below; ModelDepth in PiecewiseGradientOpacity.h):
// Theta(u), u in [0, h], the depth integrated (Theta[0] = 0, up to Degree;
// filled once Ready), Eh = e^{-Theta(h)} times Ev (the transmittance within
// the piece at the end), D a bound of |theta - Theta| over it (theta the
// true depth), R and Magnitude the remainder and magnitude of the
// extinction model Theta integrates (0 where exact), Decreasing where that
// model is non-negative (e^{-Theta} decreases: the midpoint holds).
template <typename Real>
struct SubintervalDepth
{
  Real Theta[PieceDepth<Real>::MaximumDegree + 1];
  int Degree = 0;
  bool Ready = false;
  Real Eh = Real(1);
  Real D = Real(0);
  Real R = Real(0);
  Real Magnitude = Real(0);
  bool Decreasing = true;
};

// The exact depth of a piece (PieceDepth, e^{-theta(l)} = El): D = R = 0,
// Theta shifted from the piece's depth only where the series needs it.
template <typename Real>
struct ExactDepth
{
  const PieceDepth<Real>& Depth;
  Real L, El;

  void operator()(
    Real, Real end, Real, Real, Real, SubintervalDepth<Real>& s, RayStatistics<Real>&) const
  {
    s.Eh = end == this->L ? this->El : std::exp(-this->Depth(end));
    s.Degree = this->Depth.Degree;
    s.Ready = false;
  }
  void Shift(Real v, SubintervalDepth<Real>& s) const
  {
    std::copy(this->Depth.D, this->Depth.D + this->Depth.Degree + 1, s.Theta);
    ShiftPolynomial(s.Theta, this->Depth.Degree, v);
    s.Ready = true;
  }
};

// int_0^l E kappa T over a piece of length l, Ta the transmittance in front:
// the emission E by Taylor models of degree N, `emission(c, r, models)` over
// the sub-interval of centre c and radius r, the depth by `depth` (a policy
// as ExactDepth: `depth(v, end, c, r, Ev, s, stats)` fills s, `Shift(v, s)`
// its Theta where not Ready). Sub-intervals end at the kinks' `cuts`. Adds
// the contributions to `color`, leaves the piece's e^{-Theta} over its
// sub-intervals in E, adds what sub-intervals exceed their shares by
// (`budget`) to `overdraft`. `length` holds the sub-interval length
// predicted by the piece before (infinite on a ray's first): the piece
// starts there, and leaves its own prediction. False when the piece is
// refused (MaximumSubintervals).
//
// Per sub-interval (see above and PiecewiseGradientOpacity.h), with
// T0 = Ta Ev, T1 = Ta Eh, g = e^D - 1: channel k errs by at most
//   R_k spent + max|P_k| T0 h (R + Magnitude (1 + g) g) + 2 T1 g
// (spent = T0 (1 - e^{-Theta(h) - D}), at least the true dT), which must
// fit half its share, the P' term the other half.
template <int N, typename Real, typename Depth, typename Emission>
bool SubintervalPiece(Real l, Real Ta, const Depth& depth, const Emission& emission,
  const KinkCuts<Real>& cuts, const ShadedBudget<Real>& budget, glm::vec<3, Real>& color, Real& E,
  Real& overdraft, Real& length, RayStatistics<Real>& stats)
{
  using Model = TaylorModel<Real, N>;
  const Real eps = std::numeric_limits<Real>::epsilon();
  const Real floor = l * Real(ShadedFloor);
  Real v = Real(0), h = std::max(std::min(l, length), floor), Ev = Real(1);
  SubintervalDepth<Real> s;
  for (long count = 0, next = 0; v < l && Ev > Real(0); ++count)
  {
    if (count == MaximumSubintervals)
    {
      return false;
    }
    // Sub-intervals end at the kinks' cuts too.
    for (; next < cuts.Count && cuts.At[next] <= v; ++next)
    {
    }
    const Real stop = next < cuts.Count ? cuts.At[next] : l;
    const Real tried = std::min(h, stop - v);
    const Real end = stop - v <= tried ? stop : v + tried;
    const Real width = end - v;
    const bool atFloor = tried <= floor; // not width: v + h - v may round above it
    // The centre and a radius that reaches both ends despite rounding.
    const Real c = v + width / Real(2);
    const Real r =
      std::max(c - v, end - c) * (Real(1) + Real(4) * eps) + std::numeric_limits<Real>::min();

    depth(v, end, c, r, Ev, s, stats);
    const Real Eh = s.Eh;
    const Real growth = std::expm1(s.D);
    const Real T0 = Ta * Ev, T1 = Ta * Eh;
    const Real dT = std::max(Ta * (Ev - Eh), Real(0));
    const Real spent = dT - T1 * std::expm1(-s.D);
    const Real share = budget.Scale * (dT + width * budget.InverseL);
    const Real attenuation = T0 * width * (s.R + s.Magnitude * (Real(1) + growth) * growth);
    const Real transmitted = Real(2) * T1 * growth;

    Model models[3];
    const bool dim = spent <= share;
    if (dim)
    {
      // So little light is spent here that E's bounds [0, 1] suffice: the
      // constant 1/2, within 1/2, errs by spent / 2, half the share at most.
      for (Model& model : models)
      {
        model = Model(Real(0.5));
        model.R = Real(0.5);
        model.Radius = r;
      }
    }
    else
    {
      emission(c, r, models);
      ++stats.Samples;
    }

    // The worst channel's error against its half share predicts the next
    // length (below).
    Real ratio = Real(0), excess = Real(0);
    bool known = std::isfinite(growth) && std::isfinite(attenuation);
    for (int k = 0; k < 3; ++k)
    {
      const Real error = models[k].R * spent + models[k].Magnitude() * attenuation + transmitted;
      known = known && std::isfinite(error);
      ratio = std::max(ratio, error / (share / Real(2)));
      excess = std::max(excess, error - share / Real(2));
    }
    // An excess below 2^-20 of what is left of the reserve is taken from it
    // (counted), however long the sub-interval: each takes at most 2^-20 of
    // the rest, so the reserve never runs out this way. Near a vanishing
    // gradient rounding bounds R from below (1e-10 there on the Bonsai)
    // while the share shrinks with dT: no length fits, but R dT is tiny.
    const bool tiny = excess <= (budget.Reserve - overdraft) * Real(0x1p-20);
    bool fits = known && (excess <= Real(0) || tiny);
    // By parts: P(v) T(v) - P(end) T(end) + T(v) int P' e^{-Theta}, per
    // channel; the last term by the monotone midpoint where P' keeps its
    // sign and e^{-Theta} decreases, or by the series.
    Real Pv[3], Pe[3], terms[3] = { Real(0), Real(0), Real(0) };
    Real g[3][N], limits[3];
    bool series = false;
    for (int k = 0; k < 3 && fits; ++k)
    {
      const Real(&a)[N + 1] = models[k].A;
      Pv[k] = models[k].Evaluate(v - c);
      Pe[k] = models[k].Evaluate(end - c);
      limits[k] = share / Real(2);
      // P' over the sub-interval: a[1] within sum_j j |a_j| r^(j-1).
      Real bend = Real(0);
      for (int j = N; j >= 2; --j)
      {
        bend = (bend + Real(j) * std::abs(a[j])) * r;
        g[k][j - 1] = Real(j) * a[j];
      }
      g[k][0] = a[1];
      const Real dP = Pe[k] - Pv[k];
      if (s.Decreasing && std::abs(a[1]) > bend * (Real(1) + Real(16) * eps) &&
        std::abs(dP) * dT <= share)
      {
        terms[k] = Ta * dP * (Ev + Eh) / Real(2);
        std::fill(g[k], g[k] + N, Real(0));
        continue;
      }
      // P'(y) with y = (v - c) + u, u from the sub-interval's start.
      ShiftPolynomial(g[k], N - 1, v - c);
      series = series || std::any_of(g[k], g[k] + N, [](Real x) { return x != Real(0); });
    }
    if (fits && series)
    {
      if (!s.Ready)
      {
        depth.Shift(v, s);
      }
      const Real A = Magnitude(s.Theta, s.Degree, width);
      Real sums[3];
      fits = A <= Real(1) && SubintervalSeries(s.Theta, s.Degree, g, width, A, T0, limits, sums);
      for (int k = 0; k < 3 && fits; ++k)
      {
        if (std::any_of(g[k], g[k] + N, [](Real x) { return x != Real(0); }))
        {
          terms[k] = T0 * sums[k];
        }
      }
    }
    if (!fits && !atFloor)
    {
      ++stats.Rejected;
      h = std::max(tried * NextLengthFactor<N>(ratio, Real(0.5)), floor);
      continue;
    }
    if (!fits)
    {
      // At the floor: the constants, the middles of the models' ranges
      // within [0, 1] (where E lies), whose P' term is 0; their excess over
      // the whole share counted.
      excess = Real(0);
      for (int k = 0; k < 3; ++k)
      {
        const Bounds<Real> range = models[k].Range();
        const Real lo =
          std::isnan(range.Lo) ? Real(0) : std::min(std::max(range.Lo, Real(0)), Real(1));
        const Real hi =
          std::isnan(range.Hi) ? Real(1) : std::min(std::max(range.Hi, Real(0)), Real(1));
        const Real delta0 = (hi - lo) / Real(2);
        Pv[k] = Pe[k] = lo + delta0;
        terms[k] = Real(0);
        excess = std::max(excess, delta0 * spent + hi * attenuation + transmitted - share);
      }
    }
    overdraft += std::max(excess, Real(0));
    for (int k = 0; k < 3; ++k)
    {
      color[k] += Ta * (Pv[k] * Ev - Pe[k] * Eh) + terms[k];
    }
    stats.Accept(width);
    v = end;
    Ev = Eh;
    // A fit predicts its successor's length (a piece's last, cut short by
    // its end, does not shorten it); a floor sub-interval that did not fit
    // (a kink) says nothing of the next one, nor does a dim one or one
    // that took from the reserve (their error and share grow alike): h
    // doubles.
    h = fits && !dim && excess <= Real(0)
      ? std::max(h, tried * std::max(Real(1), NextLengthFactor<N>(ratio, Real(4))))
      : std::max(fits ? h : Real(0), Real(2) * tried);
  }
  E = Ev;
  length = h;
  return true;
}

// int_0^l L tau T over a piece (q, transfer-function piece p, depth theta,
// e^{-theta(l)} = El, transmittance Ta in front, world gradient G, world
// position `start` at v = 0), added to `color`: SubintervalPiece with the
// exact depth and the lit colour's models, cut at the kinks of n.l.
template <int N, typename Real>
bool ShadedPiece(const Cubic<Real>& q, const typename PiecewiseTransferFunction<Real>::Piece& p,
  const PieceDepth<Real>& depth, Real l, Real El, Real Ta, const Real G[3][3],
  const glm::vec<3, Real>& start, const RayShading<Real>& shading, const ShadedBudget<Real>& budget,
  glm::vec<3, Real>& color, Real& overdraft, Real& length, RayStatistics<Real>& stats)
{
  const bool zero = ZeroGradient(G);
  KinkCuts<Real> cuts;
  if (!zero)
  {
    cuts.Find(G, l, *shading.Model, shading.ToViewer, N);
  }
  auto lit = [&](Real c, Real r, TaylorModel<Real, N> models[3])
  { LitModels<N>(q, p, G, zero, start, shading, c, r, models); };
  Real E;
  return SubintervalPiece<N>(
    l, Ta, ExactDepth<Real>{ depth, l, El }, lit, cuts, budget, color, E, overdraft, length, stats);
}

// The ray of the methods whose pieces take sub-intervals under a
// ShadedBudget (IntegratePiecewiseShaded, IntegratePiecewiseGradientOpacity,
// validated, L > 0): the budget split above, the walk, the reserve's check,
// early termination and the steps. `piece(rp, budget, color, T, overdraft,
// length, stats, error)` integrates the piece `rp` into `color` and `T`, its
// models of degree N; false, with `error`, when it refuses the piece.
template <typename Real, typename VolumeT, typename Piece>
void SubintervalRay(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  const PiecewiseTransferFunction<Real>& tf, Real tolerance, Real L, bool earlyTermination,
  const Piece& piece, RayResult<Real>& result)
{
  RayStatistics<Real>& stats = result.Statistics;
  const Real reserve = Real(0.05) * tolerance;
  const Real terminationBound = Real(0.15) * tolerance;
  const ShadedBudget<Real> budget{ Real(0.275) * tolerance, Real(1) / L, reserve };
  const bool high = ShadedDegree(tolerance) == 5;
  glm::vec<3, Real> color(Real(0));
  Real T = Real(1), overdraft = Real(0), length = std::numeric_limits<Real>::infinity();
  bool stopped = false;
  auto visit = [&](const RayPiece<Real>& rp) -> bool
  {
    ++stats.Pieces;
    const bool integrated = high ? piece(std::integral_constant<int, 5>(), rp, budget, color, T,
                                     overdraft, length, stats, result.Error)
                                 : piece(std::integral_constant<int, 3>(), rp, budget, color, T,
                                     overdraft, length, stats, result.Error);
    if (integrated && overdraft > reserve)
    {
      result.Error = "the integrand has kinks closer together than double precision separates "
                     "(sub-intervals of 2^-40 of a piece exceed the tolerance's reserve)";
    }
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
  if (result.Error.empty())
  {
    PiecewiseRGBA(color, T, result);
  }
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
  auto piece = [&](auto degree, const RayPiece<Real>& rp, const detail::ShadedBudget<Real>& budget,
                 glm::vec<3, Real>& color, Real& T, Real& overdraft, Real& length,
                 RayStatistics<Real>& stats, std::string& error)
  {
    const auto& p = tf[rp.TF];
    const detail::PieceDepth<Real> depth(rp.Q, p.Tau, p.TauSlope, p.TauCurvature, p.TauCubic);
    const Real El = std::exp(-depth(rp.Length));
    bool integrated = true;
    if (T * (Real(1) - El) > Real(0))
    {
      Real G[3][3];
      detail::PieceGradient(volume, origin, direction, rp, shading.NormalMatrix, G);
      const glm::vec<3, Real> start = shading.WorldOrigin + rp.Begin * shading.WorldDirection;
      integrated = detail::ShadedPiece<decltype(degree)::value>(rp.Q, p, depth, rp.Length, El, T, G,
        start, shading, budget, color, overdraft, length, stats);
      if (!integrated)
      {
        error = detail::RefusedSubintervalsError;
      }
    }
    T *= El;
    return integrated;
  };
  detail::SubintervalRay(
    volume, origin, direction, segments, count, tf, tolerance, L, earlyTermination, piece, result);
  return result;
}

} // namespace numerics
} // namespace avos

#endif
