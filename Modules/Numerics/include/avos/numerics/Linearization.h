// Certified linearization: knots for a function that is not piecewise
// linear, placed so that the linear interpolant between them stays within a
// tolerance of the function everywhere, a proven bound rather than a
// sampled one.
//
// The function comes twice: `value(x)`, the reference the knots take (for
// example VTK's own evaluation), and `enclose(X)`, a model of it as Jets
// (Enclosure.h) over an interval X. On [l, r] the chord between the
// reference's values differs from the function by at most ChordErrorBound
// (w^2 / 8 max |f''| where the model is smooth, the width of f(X) where it
// has cases), plus twice the reference's own distance from the model
// (`slack`, its rounding). A sub-interval whose bound does not fit its
// tolerance (one for all, or one that depends on the function's values
// there, as an opacity's does: ExtinctionChordTolerance) is halved.
// A reference value outside the model's enclosure proves the model wrong:
// the linearization then fails rather than certify a bound it does not have.
//
// Termination: every accepted sub-interval adds a knot, every rejected one
// is halved, and the linearization stops with a failure at `maxKnots` knots
// or at a sub-interval too narrow to halve, so it makes at most
// 2 maxKnots + 1 enclosures. A smooth function is accepted once
// w <= sqrt(8 tolerance / max |f''|); near a case change, once the width of
// f(X) fits, which shrinks with w for a function that is continuous there.
#ifndef avos_numerics_Linearization_h
#define avos_numerics_Linearization_h

#include "avos/numerics/Enclosure.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <vector>

namespace avos
{
namespace numerics
{

template <typename Real, int Channels>
struct LinearKnot
{
  Real X;
  std::array<Real, Channels> Value;
};

/**
 * Appends knots on (a, b] (the last at b) such that the linear interpolant
 * through (a, value(a)) and them is within `tolerance(f)` of value(x) on
 * each sub-interval [l, r] between knots, f = enclose([l, r]) (a tolerance
 * that depends on the function's values there, as an extinction's does),
 * wherever value(x) is within `slack` of the model, except on sub-intervals
 * where `exempt(l, r)` is true (where the caller has no use for the
 * function: they take one chord). `enclose(X)` returns
 * std::array<Jet<Real>, Channels>, `value(x)` std::array<Real, Channels>.
 * Returns false, with `knots` as it was, when the bound cannot be certified
 * within `maxKnots` knots or the model disagrees with the reference.
 */
template <typename Real, int Channels, typename Tolerance, typename Enclose, typename Value,
  typename Exempt>
bool LinearizeWithin(Real a, Real b, Tolerance&& tolerance, Real slack, Enclose&& enclose,
  Value&& value, std::vector<LinearKnot<Real, Channels>>& knots, std::size_t maxKnots,
  Exempt&& exempt)
{
  if (!(b > a))
  {
    return true;
  }
  const std::size_t start = knots.size();
  auto fail = [&]()
  {
    knots.resize(start);
    return false;
  };
  std::array<Real, Channels> left = value(a);
  struct Segment
  {
    Real L, R;
  };
  std::vector<Segment> pending{ { a, b } };
  while (!pending.empty())
  {
    const Segment s = pending.back();
    pending.pop_back();
    if (exempt(s.L, s.R))
    {
      if (knots.size() - start >= maxKnots)
      {
        return fail();
      }
      left = value(s.R);
      knots.push_back({ s.R, left });
      continue;
    }
    const std::array<Jet<Real>, Channels> f = enclose(Bounds<Real>(s.L, s.R));
    Real bound = Real(0);
    for (const Jet<Real>& c : f)
    {
      bound = std::max(bound, ChordErrorBound(c, s.R - s.L));
    }
    if (bound + Real(2) * slack <= tolerance(f)) // false for a NaN bound
    {
      const std::array<Real, Channels> right = value(s.R);
      for (int c = 0; c < Channels; ++c)
      {
        const Bounds<Real>& v = f[c].V;
        if (!(left[c] >= v.Lo - slack && left[c] <= v.Hi + slack && right[c] >= v.Lo - slack &&
              right[c] <= v.Hi + slack))
        {
          return fail();
        }
      }
      if (knots.size() - start >= maxKnots)
      {
        return fail();
      }
      knots.push_back({ s.R, right });
      left = right;
      continue;
    }
    const Real m = s.L + (s.R - s.L) / Real(2);
    if (!(m > s.L && m < s.R))
    {
      return fail();
    }
    pending.push_back({ m, s.R });
    pending.push_back({ s.L, m });
  }
  return true;
}

/** LinearizeWithin one tolerance everywhere. */
template <typename Real, int Channels, typename Enclose, typename Value, typename Exempt>
bool Linearize(Real a, Real b, Real tolerance, Real slack, Enclose&& enclose, Value&& value,
  std::vector<LinearKnot<Real, Channels>>& knots, std::size_t maxKnots, Exempt&& exempt)
{
  return LinearizeWithin(
    a, b, [tolerance](const std::array<Jet<Real>, Channels>&) { return tolerance; }, slack, enclose,
    value, knots, maxKnots, exempt);
}
template <typename Real, int Channels, typename Enclose, typename Value>
bool Linearize(Real a, Real b, Real tolerance, Real slack, Enclose&& enclose, Value&& value,
  std::vector<LinearKnot<Real, Channels>>& knots, std::size_t maxKnots)
{
  return Linearize(
    a, b, tolerance, slack, enclose, value, knots, maxKnots, [](Real, Real) { return false; });
}

/**
 * What an error in the extinction does to a pixel, and the chord error
 * that keeps it within a budget: the certified linearization of an opacity
 * function that VTK does not interpolate linearly.
 *
 * If a converted extinction tau~ differs from the exact tau by
 *   |tau~ - tau| <= Relative min(tau, tau~) + Absolute
 * on a ray of length at most L whose colours are at most G, every channel
 * of the composited pixel moves by at most 2 G (Relative + Absolute L).
 * Proof: along tau_l = tau + l (tau~ - tau), l in [0, 1] (so tau_l >=
 * min(tau, tau~) and |tau~ - tau| <= Relative tau_l + Absolute), the pixel
 * I(l) = int c tau_l T_l dt has dI/dl = int c (tau~ - tau) T_l dt -
 * int c tau_l T_l (int_0^t (tau~ - tau)) dt. The first term is at most
 * G (Relative int tau_l T_l + Absolute int T_l) <= G (Relative + Absolute L);
 * the second at most G (Relative int tau_l T_l Theta_l + Absolute L
 * int tau_l T_l) <= G (Relative + Absolute L), Theta_l the optical depth,
 * because int tau T Theta dt = int Theta e^-Theta dTheta <= 1. The ray's
 * opacity 1 - T moves by at most Relative + Absolute L. Near an opacity of
 * 0 the absolute part holds (a relative one cannot: VTK's Hermite curves
 * leave a node of value 0 as x^p); near an opacity of 1 the relative part
 * does (the extinction grows without bound there).
 */
template <typename Real>
struct ExtinctionBudget
{
  Real Relative = Real(0);
  Real Absolute = Real(0);

  /** Half of `pixel` to each part, for rays up to `length` and colours up to `gain`. */
  static ExtinctionBudget Within(Real pixel, Real length, Real gain)
  {
    const Real share = pixel / (Real(4) * gain);
    return { share, share / length };
  }
};

/**
 * The chord error allowed on a sub-interval of an opacity function whose
 * values there lie in `values` (to `slack`), for the extinction
 * `extinction(v)`, non-decreasing and convex, whose slope is at most
 * `slope(v)` below v (infinite where unbounded): two values a, b in
 * [lo, hi] give extinctions at most min(|a - b| slope(hi), extinction(hi) -
 * extinction(lo)) apart, which must be at most Relative extinction(lo) +
 * Absolute. Infinite when any chord holds; 0 when none can. The extinctions
 * are computed in Real: their rounding (a few ulps of 40 / UnitDistance at
 * most) is far below any Absolute a class asks for.
 */
template <typename Real, typename Extinction, typename Slope>
Real ExtinctionChordTolerance(const Bounds<Real>& values, Real slack,
  const ExtinctionBudget<Real>& budget, Extinction&& extinction, Slope&& slope)
{
  const Real lo = std::max(values.Lo - slack, Real(0)), hi = values.Hi + slack;
  const Real allowed = budget.Relative * extinction(lo) + budget.Absolute;
  if (extinction(hi) - extinction(lo) <= allowed)
  {
    return std::numeric_limits<Real>::infinity();
  }
  const Real s = slope(hi);
  return s < std::numeric_limits<Real>::infinity() ? allowed / s : Real(0);
}
} // namespace numerics
} // namespace avos

#endif
