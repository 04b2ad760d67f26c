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
// (`slack`, its rounding). A sub-interval whose bound does not fit is halved.
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
 * through (a, value(a)) and them is within `tolerance` of value(x) on
 * [a, b], wherever value(x) is within `slack` of the model, except on
 * sub-intervals [l, r] where `exempt(l, r)` is true (where the caller has
 * no use for the function: they take one chord). `enclose(X)` returns
 * std::array<Jet<Real>, Channels>, `value(x)` std::array<Real, Channels>.
 * Returns false, with `knots` as it was, when the bound cannot be certified
 * within `maxKnots` knots or the model disagrees with the reference.
 */
template <typename Real, int Channels, typename Enclose, typename Value, typename Exempt>
bool Linearize(Real a, Real b, Real tolerance, Real slack, Enclose&& enclose, Value&& value,
  std::vector<LinearKnot<Real, Channels>>& knots, std::size_t maxKnots, Exempt&& exempt)
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
  const Real budget = tolerance - Real(2) * slack;
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
    if (bound <= budget) // false for a NaN bound
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
template <typename Real, int Channels, typename Enclose, typename Value>
bool Linearize(Real a, Real b, Real tolerance, Real slack, Enclose&& enclose, Value&& value,
  std::vector<LinearKnot<Real, Channels>>& knots, std::size_t maxKnots)
{
  return Linearize(
    a, b, tolerance, slack, enclose, value, knots, maxKnots, [](Real, Real) { return false; });
}
} // namespace numerics
} // namespace avos

#endif
