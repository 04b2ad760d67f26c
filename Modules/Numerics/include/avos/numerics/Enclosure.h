// Rigorous enclosures of a function of one variable over an interval:
// interval arithmetic (Bounds) and second-order Taylor jets of intervals
// (Jet), the tools of a certified bound where a closed form does not exist.
//
// A Bounds [Lo, Hi] contains every value the quantity takes. Each
// operation widens its result outward by a few units in the last place, so
// that the rounding of Real (at most half an ulp for + - * / and sqrt, a few
// ulps for the library's pow, log, sin and cos) cannot move a true value out
// of it. Empty results and divisions by an interval holding 0 give the whole
// line (infinite ends): a later bound is then infinite or NaN, and callers
// treat a bound that is not finite as "not proven".
//
// A Jet of f over X holds enclosures of f(X), f'(X) and f''(X) (Smooth), or
// only of f(X) where f may have a kink or a jump in X (Smooth false: Rough).
// Arithmetic follows the product, quotient and chain rules pointwise, so
// every enclosure stays valid over all of X.
#ifndef avos_numerics_Enclosure_h
#define avos_numerics_Enclosure_h

#include <algorithm>
#include <cmath>
#include <limits>

namespace avos
{
namespace numerics
{

template <typename Real>
struct Bounds
{
  Real Lo = Real(0);
  Real Hi = Real(0);

  Bounds() = default;
  Bounds(Real v)
    : Lo(v)
    , Hi(v)
  {
  }
  Bounds(Real lo, Real hi)
    : Lo(lo)
    , Hi(hi)
  {
  }

  Real Width() const { return this->Hi - this->Lo; }
  Real Magnitude() const { return std::max(std::abs(this->Lo), std::abs(this->Hi)); }
  bool Contains(Real v) const { return v >= this->Lo && v <= this->Hi; }

  static Bounds Whole()
  {
    const Real inf = std::numeric_limits<Real>::infinity();
    return Bounds(-inf, inf);
  }

  // [lo, hi] widened by `ulps` units of the larger end's magnitude.
  static Bounds Outward(Real lo, Real hi, int ulps = 2)
  {
    if (!(lo <= hi))
    {
      return Whole();
    }
    const Real e = std::numeric_limits<Real>::epsilon() * ulps;
    const Real tiny = std::numeric_limits<Real>::min();
    return Bounds(lo - e * std::abs(lo) - tiny, hi + e * std::abs(hi) + tiny);
  }
};

template <typename Real>
Bounds<Real> Hull(const Bounds<Real>& a, const Bounds<Real>& b)
{
  return Bounds<Real>(std::min(a.Lo, b.Lo), std::max(a.Hi, b.Hi));
}

template <typename Real>
Bounds<Real> operator+(const Bounds<Real>& a, const Bounds<Real>& b)
{
  return Bounds<Real>::Outward(a.Lo + b.Lo, a.Hi + b.Hi);
}

template <typename Real>
Bounds<Real> operator-(const Bounds<Real>& a)
{
  return Bounds<Real>(-a.Hi, -a.Lo);
}

template <typename Real>
Bounds<Real> operator-(const Bounds<Real>& a, const Bounds<Real>& b)
{
  return Bounds<Real>::Outward(a.Lo - b.Hi, a.Hi - b.Lo);
}

// The hull of the four end products (branch-free, inlined: the enclosures'
// hottest operation). A NaN product (0 times an infinite end) gives the
// whole line.
template <typename Real>
inline Bounds<Real> operator*(const Bounds<Real>& a, const Bounds<Real>& b)
{
  const Real p0 = a.Lo * b.Lo, p1 = a.Lo * b.Hi, p2 = a.Hi * b.Lo, p3 = a.Hi * b.Hi;
  if (std::isnan(p0 + p1 + p2 + p3))
  {
    return Bounds<Real>::Whole();
  }
  return Bounds<Real>::Outward(
    std::min(std::min(p0, p1), std::min(p2, p3)), std::max(std::max(p0, p1), std::max(p2, p3)));
}

template <typename Real>
Bounds<Real> operator/(const Bounds<Real>& a, const Bounds<Real>& b)
{
  if (!(b.Lo > Real(0) || b.Hi < Real(0)))
  {
    return Bounds<Real>::Whole();
  }
  const Real q[4] = { a.Lo / b.Lo, a.Lo / b.Hi, a.Hi / b.Lo, a.Hi / b.Hi };
  return Bounds<Real>::Outward(*std::min_element(q, q + 4), *std::max_element(q, q + 4));
}

// x^2, tighter than x * x when x holds 0.
template <typename Real>
Bounds<Real> Square(const Bounds<Real>& x)
{
  const Real a = x.Lo * x.Lo, b = x.Hi * x.Hi;
  const Real lo = x.Contains(Real(0)) ? Real(0) : std::min(a, b);
  return Bounds<Real>::Outward(lo, std::max(a, b));
}

// x^p for x >= 0 (the part of x below 0 is dropped), any real p: monotone in
// x, increasing for p > 0, decreasing for p < 0.
template <typename Real>
Bounds<Real> Pow(const Bounds<Real>& x, Real p)
{
  const Real lo = std::max(x.Lo, Real(0)), hi = std::max(x.Hi, Real(0));
  if (p == Real(0))
  {
    return Bounds<Real>(Real(1));
  }
  const Real a = std::pow(lo, p), b = std::pow(hi, p);
  return Bounds<Real>::Outward(std::min(a, b), std::max(a, b), 8);
}

// The natural logarithm, for x > 0.
template <typename Real>
Bounds<Real> Log(const Bounds<Real>& x)
{
  if (!(x.Lo > Real(0)))
  {
    return Bounds<Real>::Whole();
  }
  return Bounds<Real>::Outward(std::log(x.Lo), std::log(x.Hi), 8);
}

// cos over x: the ends, and 1 or -1 where x holds a multiple of pi.
template <typename Real>
Bounds<Real> Cos(const Bounds<Real>& x)
{
  const Real pi = Real(3.141592653589793238462643383279502884L);
  if (!(x.Width() < Real(2) * pi))
  {
    return Bounds<Real>(Real(-1), Real(1));
  }
  const Real a = std::cos(x.Lo), b = std::cos(x.Hi);
  Real lo = std::min(a, b), hi = std::max(a, b);
  // The multiples k pi in x (k even: a maximum, odd: a minimum), with the
  // rounding of x / pi taken outward.
  const Real first = std::ceil(x.Lo / pi - Real(1e-12)), last = std::floor(x.Hi / pi + Real(1e-12));
  for (Real k = first; k <= last; k += Real(1))
  {
    if (static_cast<long long>(k) % 2 == 0)
    {
      hi = Real(1);
    }
    else
    {
      lo = Real(-1);
    }
  }
  return Bounds<Real>::Outward(std::max(lo, Real(-1)), std::min(hi, Real(1)), 8);
}

template <typename Real>
Bounds<Real> Sin(const Bounds<Real>& x)
{
  const Real halfPi = Real(1.570796326794896619231321691639751442L);
  // sin x = cos(x - pi/2); the shift's rounding is taken outward.
  return Cos(Bounds<Real>::Outward(x.Lo - halfPi, x.Hi - halfPi));
}

// Intersection of two enclosures of one quantity; where rounding leaves
// them disjoint, the first is kept (both are valid, neither is preferred).
template <typename Real>
Bounds<Real> Intersect(const Bounds<Real>& a, const Bounds<Real>& b)
{
  const Real lo = std::max(a.Lo, b.Lo), hi = std::min(a.Hi, b.Hi);
  return lo <= hi ? Bounds<Real>(lo, hi) : a;
}

template <typename Real>
struct Jet
{
  Bounds<Real> V;  // f(X)
  Bounds<Real> D1; // f'(X), when Smooth
  Bounds<Real> D2; // f''(X), when Smooth
  bool Smooth = true;
  // f(c) and f'(c) at X's centre c, and X's radius r about it, where known
  // (Centred): they give the mean-value forms f(X) in f(c) + f'(c) [-r, r]
  // + f''(X) [0, r^2 / 2] and f'(X) in f'(c) + f''(X) [-r, r], which keep
  // the enclosures of a long chain of operations within O(r) of the
  // range instead of growing with every use of the variable.
  Bounds<Real> F, F1;
  Real Radius = Real(0);
  bool Centred = true;

  Jet() = default;
  // A constant.
  Jet(Real c)
    : V(c)
    , D1(Real(0))
    , D2(Real(0))
    , F(c)
    , F1(Real(0))
  {
  }

  // The variable itself over X.
  static Jet Variable(const Bounds<Real>& x)
  {
    Jet j;
    j.V = x;
    j.D1 = j.F1 = Bounds<Real>(Real(1));
    j.D2 = Bounds<Real>(Real(0));
    const Real c = x.Lo + (x.Hi - x.Lo) / Real(2);
    j.F = Bounds<Real>(c);
    j.Radius = Bounds<Real>::Outward(Real(0), std::max(c - x.Lo, x.Hi - c)).Hi;
    return j;
  }
  // A function known only to stay within v over X.
  static Jet Rough(const Bounds<Real>& v)
  {
    Jet j;
    j.V = v;
    j.D1 = j.D2 = Bounds<Real>::Whole();
    j.Smooth = j.Centred = false;
    return j;
  }

  // Tightens V and D1 by the mean-value forms. x [-r, r] and x [0, r^2 / 2]
  // are taken in closed form (a magnitude times r; the ends' signs), not by
  // the general product: every operation on Jets calls this. Each end is a
  // sum of at most five rounded terms, so widening it by 8 units of the
  // largest magnitude in play covers the rounding.
  Jet& Tighten()
  {
    if (this->Smooth && this->Centred)
    {
      const Real eps = std::numeric_limits<Real>::epsilon();
      const Real tiny = std::numeric_limits<Real>::min();
      const Real r = this->Radius;
      const Real half = r * r * Real(0.5) * (Real(1) + Real(4) * eps); // at least r^2 / 2
      const Real slope = this->F1.Magnitude() * r, bend = this->D2.Magnitude() * r;
      const Real lo = std::min(this->D2.Lo * half, Real(0));
      const Real hi = std::max(this->D2.Hi * half, Real(0));
      const Real e = Real(8) * eps * (this->F.Magnitude() + slope - lo + hi) + tiny;
      this->V =
        Intersect(this->V, Bounds<Real>(this->F.Lo - slope + lo - e, this->F.Hi + slope + hi + e));
      const Real e1 = Real(8) * eps * (this->F1.Magnitude() + bend) + tiny;
      this->D1 =
        Intersect(this->D1, Bounds<Real>(this->F1.Lo - bend - e1, this->F1.Hi + bend + e1));
    }
    return *this;
  }
};

namespace detail
{
// The common part of a binary operation's result.
template <typename Real>
Jet<Real> Combine(const Jet<Real>& a, const Jet<Real>& b)
{
  Jet<Real> j;
  j.Smooth = a.Smooth && b.Smooth;
  j.Centred = j.Smooth && a.Centred && b.Centred;
  j.Radius = std::max(a.Radius, b.Radius);
  return j;
}
} // namespace detail

template <typename Real>
Jet<Real> operator+(const Jet<Real>& a, const Jet<Real>& b)
{
  Jet<Real> j = detail::Combine(a, b);
  j.V = a.V + b.V;
  j.D1 = a.D1 + b.D1;
  j.D2 = a.D2 + b.D2;
  j.F = a.F + b.F;
  j.F1 = a.F1 + b.F1;
  return j.Tighten();
}

template <typename Real>
Jet<Real> operator-(const Jet<Real>& a)
{
  Jet<Real> j = a;
  j.V = -a.V;
  j.D1 = -a.D1;
  j.D2 = -a.D2;
  j.F = -a.F;
  j.F1 = -a.F1;
  return j;
}

template <typename Real>
Jet<Real> operator-(const Jet<Real>& a, const Jet<Real>& b)
{
  return a + (-b);
}

template <typename Real>
Jet<Real> operator*(const Jet<Real>& a, const Jet<Real>& b)
{
  // (ab)' = a'b + ab', (ab)'' = a''b + 2a'b' + ab''.
  const Bounds<Real> two(Real(2));
  Jet<Real> j = detail::Combine(a, b);
  j.V = a.V * b.V;
  j.D1 = a.D1 * b.V + a.V * b.D1;
  j.D2 = a.D2 * b.V + two * a.D1 * b.D1 + a.V * b.D2;
  j.F = a.F * b.F;
  j.F1 = a.F1 * b.F + a.F * b.F1;
  return j.Tighten();
}

template <typename Real>
Jet<Real> operator/(const Jet<Real>& a, const Jet<Real>& b)
{
  // q = a / b: q' = (a' - q b') / b, q'' = (a'' - 2 q' b' - q b'') / b.
  const Bounds<Real> two(Real(2));
  Jet<Real> j = detail::Combine(a, b);
  j.V = a.V / b.V;
  j.D1 = (a.D1 - j.V * b.D1) / b.V;
  j.D2 = (a.D2 - two * j.D1 * b.D1 - j.V * b.D2) / b.V;
  j.F = a.F / b.F;
  j.F1 = (a.F1 - j.F * b.F1) / b.F;
  return j.Tighten();
}

// With a constant on either side: a shift or a scaling of every enclosure,
// which keeps each as tight as it was (no Tighten), at a fifth of the cost of
// the general operations.
template <typename Real>
Jet<Real> operator+(const Jet<Real>& a, Real c)
{
  Jet<Real> j = a;
  j.V = a.V + Bounds<Real>(c);
  j.F = a.F + Bounds<Real>(c);
  return j;
}

template <typename Real>
Jet<Real> operator+(Real c, const Jet<Real>& a)
{
  return a + c;
}

template <typename Real>
Jet<Real> operator-(const Jet<Real>& a, Real c)
{
  return a + (-c);
}

template <typename Real>
Jet<Real> operator-(Real c, const Jet<Real>& a)
{
  return Jet<Real>(c) - a;
}

namespace detail
{
// Every enclosure of `a` through the linear map `f` (a product or quotient
// by a constant other than 0), each end rounded outward.
template <typename Real, typename F>
Jet<Real> Linear(const Jet<Real>& a, F&& f)
{
  auto image = [&f](const Bounds<Real>& b)
  {
    const Real x = f(b.Lo), y = f(b.Hi);
    return Bounds<Real>::Outward(std::min(x, y), std::max(x, y));
  };
  Jet<Real> j = a;
  j.V = image(a.V);
  j.D1 = image(a.D1);
  j.D2 = image(a.D2);
  j.F = image(a.F);
  j.F1 = image(a.F1);
  return j;
}
} // namespace detail

template <typename Real>
Jet<Real> operator*(Real c, const Jet<Real>& a)
{
  if (c == Real(0))
  {
    return Jet<Real>(Real(0)); // 0 f = 0, also where f's enclosures are infinite
  }
  return detail::Linear(a, [c](Real x) { return x * c; });
}

template <typename Real>
Jet<Real> operator*(const Jet<Real>& a, Real c)
{
  return c * a;
}

template <typename Real>
Jet<Real> operator/(const Jet<Real>& a, Real c)
{
  if (c == Real(0))
  {
    return a / Jet<Real>(c); // the whole line, as the general division gives
  }
  return detail::Linear(a, [c](Real x) { return x / c; });
}

// g(a) by the chain rule: (g o a)' = g'(a) a', (g o a)'' = g''(a) a'^2 +
// g'(a) a''. `g(v, value, slope, curvature)` fills enclosures of g, g' and
// g'' over the values v (called for a's values and for its centre value).
template <typename Real, typename G>
Jet<Real> Compose(const Jet<Real>& a, G&& g)
{
  Bounds<Real> g0, g1, g2;
  g(a.V, g0, g1, g2);
  Jet<Real> j = a;
  j.V = g0;
  j.D1 = g1 * a.D1;
  j.D2 = g2 * Square(a.D1) + g1 * a.D2;
  if (j.Centred)
  {
    Bounds<Real> c1, c2;
    g(a.F, j.F, c1, c2);
    j.F1 = c1 * a.F1;
  }
  return j.Tighten();
}

// a^p for a >= 0 over X (p real); where p < 2 and a reaches 0 the second
// derivative is unbounded and the enclosure says so (infinite ends).
template <typename Real>
Jet<Real> Pow(const Jet<Real>& a, Real p)
{
  return Compose(a,
    [p](const Bounds<Real>& v, Bounds<Real>& g0, Bounds<Real>& g1, Bounds<Real>& g2)
    {
      g0 = Pow(v, p);
      g1 = Bounds<Real>(p) * Pow(v, p - Real(1));
      g2 = Bounds<Real>(p * (p - Real(1))) * Pow(v, p - Real(2));
    });
}

template <typename Real>
Jet<Real> Log(const Jet<Real>& a)
{
  return Compose(a,
    [](const Bounds<Real>& v, Bounds<Real>& g0, Bounds<Real>& g1, Bounds<Real>& g2)
    {
      g0 = Log(v);
      g1 = Bounds<Real>(Real(1)) / v;
      g2 = -Square(g1);
    });
}

template <typename Real>
Jet<Real> Cos(const Jet<Real>& a)
{
  return Compose(a,
    [](const Bounds<Real>& v, Bounds<Real>& g0, Bounds<Real>& g1, Bounds<Real>& g2)
    {
      g0 = Cos(v);
      g1 = -Sin(v);
      g2 = -g0;
    });
}

template <typename Real>
Jet<Real> Sin(const Jet<Real>& a)
{
  return Compose(a,
    [](const Bounds<Real>& v, Bounds<Real>& g0, Bounds<Real>& g1, Bounds<Real>& g2)
    {
      g0 = Sin(v);
      g1 = Cos(v);
      g2 = -g0;
    });
}

// A function defined by cases: below(x) where x <= threshold, above(x) where
// x > threshold (as `x > threshold ? above : below`). Where X's values fall
// on both sides (within a relative guard of 1e-12 of the threshold, so that
// the rounding of the caller's own comparison cannot pick a case the
// enclosure did not take), the result is Rough: the hull of both cases, each
// over its part of the values. `below` and `above` take and return Jets.
template <typename Real, typename Below, typename Above>
Jet<Real> Cases(const Jet<Real>& x, Real threshold, Below&& below, Above&& above)
{
  const Real guard = Real(1e-12) * std::max(std::abs(threshold), Real(1e-300));
  if (x.V.Lo > threshold + guard)
  {
    return above(x);
  }
  if (x.V.Hi < threshold - guard)
  {
    return below(x);
  }
  // Each case over its part of the values (its centre unknown there).
  Jet<Real> low = x, high = x;
  low.V.Hi = std::min(x.V.Hi, threshold + guard);
  high.V.Lo = std::max(x.V.Lo, threshold - guard);
  low.Centred = high.Centred = false;
  return Jet<Real>::Rough(Hull(below(low).V, above(high).V));
}

// The same on plain numbers, so that one templated model evaluates both.
template <typename Below, typename Above>
double Cases(double x, double threshold, Below&& below, Above&& above)
{
  return x > threshold ? above(x) : below(x);
}

// The value-only bound of a Jet: the widest of f'' over X times w^2 / 8
// (the chord's error on an interval of width w, Smooth) or the width of
// f(X) (any function whose chord ends lie in f(X)).
template <typename Real>
Real ChordErrorBound(const Jet<Real>& f, Real width)
{
  if (f.Smooth)
  {
    return std::min(f.D2.Magnitude() * width * width / Real(8), f.V.Width());
  }
  return f.V.Width();
}
} // namespace numerics
} // namespace avos

#endif
