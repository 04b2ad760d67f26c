// Taylor models (Makino and Berz): a function f of one variable over the
// interval X = [c - r, c + r], enclosed as a polynomial P of degree N in
// y = v - c and a remainder bound R:
//
//   |f(c + y) - P(y)| <= R   for every |y| <= r.
//
// Sums, products and smooth functions of Taylor models are Taylor models of
// the results, their remainders shrinking as r^(N+1) where the functions are
// smooth: the enclosure of a long chain of operations (the lit colour of
// Shading.h) stays within O(r^(N+1)) of the function instead of the O(r) of
// interval arithmetic, which overestimates every repeated use of v (the
// dependency problem). Where a function has a kink inside X (|x|, a clamp),
// the model keeps its polynomial and takes the kink's excess into R, so R
// shrinks as the kink's reach into X.
//
// Rounding: every coefficient is computed in Real with rounding to nearest.
// Each operation adds to R a bound of what rounding can move its
// coefficients by, over |y| <= r: a sum of coefficients errs by at most u
// times its magnitude, a product's coefficient, a sum of at most N + 1
// products, by (N + 2) u times the sum of their magnitudes, so the terms below
// take 2 eps (= 4 u) and 2 (N + 2) eps of the magnitudes in play. The bounds
// themselves (sums of non-negative terms) are rounded up by the factor Up.
// Non-finite coefficients or remainders make R infinite: nothing is known,
// and callers treat an infinite R as "not proven".
#ifndef avos_numerics_TaylorModel_h
#define avos_numerics_TaylorModel_h

#include "avos/numerics/Enclosure.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace avos
{
namespace numerics
{

template <typename Real, int N>
struct TaylorModel
{
  static_assert(N >= 0 && N <= 8, "a degree from 0 to 8");
  static constexpr int Degree = N;

  Real A[N + 1] = {}; // the coefficients of y^k
  Real R = Real(0);   // the remainder bound
  Real Radius = Real(0);

  TaylorModel() = default;
  // A constant (any radius: its polynomial has no y).
  TaylorModel(Real c) { this->A[0] = c; }

  // The factor that rounds a computed sum of non-negative terms up.
  static Real Up() { return Real(1) + Real(8 * (N + 4)) * std::numeric_limits<Real>::epsilon(); }

  // The constant model of a value known only to lie in b: its midpoint,
  // within half its width (infinite where b is not finite).
  static TaylorModel Enclosing(const Bounds<Real>& b, Real radius)
  {
    TaylorModel m;
    m.Radius = radius;
    if (!(std::isfinite(b.Lo) && std::isfinite(b.Hi) && b.Lo <= b.Hi))
    {
      m.R = std::numeric_limits<Real>::infinity();
      return m;
    }
    m.A[0] = b.Lo + (b.Hi - b.Lo) / Real(2);
    m.R = std::max(m.A[0] - b.Lo, b.Hi - m.A[0]) * Up() + std::numeric_limits<Real>::min();
    return m;
  }

  // The polynomial sum_k p[k] v^k (D + 1 exact coefficients) about the
  // centre c, over the radius r: its coefficients in y = v - c by Taylor
  // shifts (D (D + 1) / 2 rounded multiply-adds, each coefficient off by at
  // most 2 D u of the terms |p_j| C(j, k) |c|^(j - k) it sums: in all at most
  // 2 D u sum_j |p_j| (|c| + r)^j over |y| <= r), the terms above degree N
  // moved into R.
  template <int M>
  static TaylorModel Polynomial(const Real (&p)[M], Real c, Real r)
  {
    constexpr int D = M - 1;
    Real b[D + 1];
    std::copy(p, p + D + 1, b);
    for (int i = 0; i < D; ++i)
    {
      for (int k = D - 1; k >= i; --k)
      {
        b[k] += c * b[k + 1];
      }
    }
    TaylorModel m;
    m.Radius = r;
    Real spread = Real(0), reach = Real(0);
    for (int k = D; k >= 0; --k)
    {
      spread = spread * (std::abs(c) + r) + std::abs(p[k]);
      reach = k > N ? (reach + std::abs(b[k])) * r : reach;
      if (k <= N)
      {
        m.A[k] = b[k];
      }
    }
    for (int k = 0; k < N && D > N; ++k)
    {
      reach *= r; // sum_{k > N} |b_k| r^k
    }
    m.R = (Real(4 * D + 2) * std::numeric_limits<Real>::epsilon() * spread + reach) * Up();
    return m.Checked();
  }

  // P(y) = sum_k A_k y^k.
  Real Evaluate(Real y) const
  {
    Real value = this->A[N];
    for (int k = N - 1; k >= 0; --k)
    {
      value = value * y + this->A[k];
    }
    return value;
  }

  // sum_k |A_k| r^k: at least |P(y)| for |y| <= r.
  Real Magnitude() const
  {
    Real m = std::abs(this->A[N]);
    for (int k = N - 1; k >= 0; --k)
    {
      m = m * this->Radius + std::abs(this->A[k]);
    }
    return m * Up();
  }

  // A bound of |f - A_0| over X.
  Real Spread() const
  {
    Real m = Real(0);
    for (int k = N; k >= 1; --k)
    {
      m = (m + std::abs(this->A[k])) * this->Radius;
    }
    return (m + this->R) * Up();
  }

  // An enclosure of f(X).
  Bounds<Real> Range() const
  {
    const Real s = this->Spread();
    return Bounds<Real>::Outward(this->A[0] - s, this->A[0] + s);
  }

  // A tighter enclosure of f(X), for the kinks: the exact range of the
  // polynomial's terms up to degree 2 (their values at the ends and at the
  // vertex), the higher terms by their magnitudes, R, and the rounding of
  // these evaluations (a few ulps of the magnitude). Where a kink lies at
  // X's end, the range then reaches past it by O(r^3) instead of O(r^2).
  Bounds<Real> TightRange() const
  {
    const Real r = this->Radius;
    auto quadratic = [this](Real y) {
      return this->A[0] + y * (N >= 1 ? this->A[1] + y * (N >= 2 ? this->A[2] : Real(0)) : Real(0));
    };
    const Real left = quadratic(-r), right = quadratic(r);
    Real lo = std::min(left, right), hi = std::max(left, right);
    if (N >= 2 && this->A[2] != Real(0))
    {
      const Real vertex = -this->A[1] / (Real(2) * this->A[2]);
      if (std::abs(vertex) < r)
      {
        lo = std::min(lo, quadratic(vertex));
        hi = std::max(hi, quadratic(vertex));
      }
    }
    Real higher = Real(0);
    for (int k = N; k >= 3; --k)
    {
      higher = (higher + std::abs(this->A[k])) * r;
    }
    for (int k = 0; k < 2 && N >= 3; ++k)
    {
      higher *= r;
    }
    const Real e =
      (higher + this->R + Real(8) * std::numeric_limits<Real>::epsilon() * this->Magnitude()) *
      Up();
    const Bounds<Real> tight = Bounds<Real>::Outward(lo - e, hi + e);
    return Intersect(tight, this->Range());
  }

  bool Finite() const { return std::isfinite(this->R); }

  // R infinite where R is not finite: enough after an operation whose R
  // sums a magnitude of every coefficient it changed (NaN or infinite with
  // any of them).
  TaylorModel& Settled()
  {
    if (!(this->R <= std::numeric_limits<Real>::max()))
    {
      this->R = std::numeric_limits<Real>::infinity();
    }
    return *this;
  }

  // R infinite where a coefficient or R is not finite.
  TaylorModel& Checked()
  {
    Real sum = this->R * Real(0); // NaN where a term is not finite
    for (int k = 0; k <= N; ++k)
    {
      sum += this->A[k] * Real(0);
    }
    if (!(sum == Real(0)) || !(this->R >= Real(0)))
    {
      this->R = std::numeric_limits<Real>::infinity();
    }
    return *this;
  }
};

template <typename Real, int N>
TaylorModel<Real, N> operator-(const TaylorModel<Real, N>& a)
{
  TaylorModel<Real, N> m = a;
  for (Real& x : m.A)
  {
    x = -x;
  }
  return m;
}

template <typename Real, int N>
TaylorModel<Real, N> operator+(const TaylorModel<Real, N>& a, const TaylorModel<Real, N>& b)
{
  TaylorModel<Real, N> m;
  m.Radius = std::max(a.Radius, b.Radius);
  for (int k = 0; k <= N; ++k)
  {
    m.A[k] = a.A[k] + b.A[k];
  }
  m.R = (a.R + b.R + Real(2) * std::numeric_limits<Real>::epsilon() * m.Magnitude()) *
    TaylorModel<Real, N>::Up();
  return m.Settled();
}

template <typename Real, int N>
TaylorModel<Real, N> operator-(const TaylorModel<Real, N>& a, const TaylorModel<Real, N>& b)
{
  return a + (-b);
}

template <typename Real, int N>
TaylorModel<Real, N> operator+(const TaylorModel<Real, N>& a, Real c)
{
  TaylorModel<Real, N> m = a;
  m.A[0] += c;
  m.R = (a.R + Real(2) * std::numeric_limits<Real>::epsilon() * std::abs(m.A[0])) *
    TaylorModel<Real, N>::Up();
  return m.Settled();
}

template <typename Real, int N>
TaylorModel<Real, N> operator+(Real c, const TaylorModel<Real, N>& a)
{
  return a + c;
}

template <typename Real, int N>
TaylorModel<Real, N> operator-(const TaylorModel<Real, N>& a, Real c)
{
  return a + (-c);
}

template <typename Real, int N>
TaylorModel<Real, N> operator-(Real c, const TaylorModel<Real, N>& a)
{
  return (-a) + c;
}

template <typename Real, int N>
TaylorModel<Real, N> operator*(Real c, const TaylorModel<Real, N>& a)
{
  if (c == Real(0))
  {
    return TaylorModel<Real, N>(Real(0)); // 0 f = 0, also where f is unknown
  }
  TaylorModel<Real, N> m;
  m.Radius = a.Radius;
  for (int k = 0; k <= N; ++k)
  {
    m.A[k] = c * a.A[k];
  }
  m.R = (std::abs(c) * a.R + Real(2) * std::numeric_limits<Real>::epsilon() * m.Magnitude()) *
    TaylorModel<Real, N>::Up();
  return m.Settled();
}

template <typename Real, int N>
TaylorModel<Real, N> operator*(const TaylorModel<Real, N>& a, Real c)
{
  return c * a;
}

// (P_a + e_a)(P_b + e_b) = P_a P_b + P_a e_b + P_b e_a + e_a e_b: the product
// polynomial's terms above degree N, |P_a| e_b + |P_b| e_a + e_a e_b and the
// rounding of the coefficients (each a sum of at most N + 1 products) go
// into R.
template <typename Real, int N>
TaylorModel<Real, N> operator*(const TaylorModel<Real, N>& a, const TaylorModel<Real, N>& b)
{
  TaylorModel<Real, N> m;
  const Real r = std::max(a.Radius, b.Radius);
  m.Radius = r;
  // The kept coefficients, the dropped ones' sum_k |p_(N+1+k)| r^k, and both
  // factors' magnitudes, in one pass over the powers of r.
  Real truncated = Real(0), ma = Real(0), mb = Real(0), power = Real(1);
  for (int k = 0; k <= N; ++k)
  {
    Real kept = Real(0), dropped = Real(0);
    for (int i = 0; i <= k; ++i)
    {
      kept += a.A[i] * b.A[k - i];
    }
    for (int i = k + 1; i <= N; ++i)
    {
      dropped += a.A[i] * b.A[N + 1 + k - i];
    }
    m.A[k] = kept;
    truncated += std::abs(dropped) * power;
    ma += std::abs(a.A[k]) * power;
    mb += std::abs(b.A[k]) * power;
    power *= r;
  }
  truncated *= power; // power = r^(N+1)
  const Real rounding = Real(2 * (N + 2)) * std::numeric_limits<Real>::epsilon() * ma * mb;
  m.R = (truncated + ma * b.R + mb * a.R + a.R * b.R + rounding) * TaylorModel<Real, N>::Up();
  return m.Checked();
}

namespace detail
{
// f(a) from f's Taylor coefficients c_k = f^(k)(a_0) / k! at a's constant
// term a_0 (c[0..N], each within a relative `coefficientError`) and a bound
// `tail` of |f^(N+1)| / (N + 1)! over a's range: f(a) = sum_k c_k d^k + the
// Lagrange remainder, d = a - a_0, |d| <= U = a.Spread(), so the remainder
// is at most tail U^(N+1). Horner's rule on Taylor models.
template <typename Real, int N>
TaylorModel<Real, N> ComposeTaylor(
  const TaylorModel<Real, N>& a, const Real (&c)[N + 1], Real coefficientError, Real tail)
{
  TaylorModel<Real, N> d = a;
  d.A[0] = Real(0);
  const Real U = a.Spread();
  TaylorModel<Real, N> m(c[N]);
  m.Radius = a.Radius;
  for (int k = N - 1; k >= 0; --k)
  {
    m = m * d + c[k];
  }
  Real error = std::abs(c[0]), power = Real(1); // sum_k |c_k| U^k; U^N
  for (int k = 1; k <= N; ++k)
  {
    power *= U;
    error += std::abs(c[k]) * power;
  }
  m.R = (m.R + coefficientError * error + tail * power * U) * TaylorModel<Real, N>::Up();
  return m.Checked();
}

// x^p for x > 0: by squaring (and a square root) where p is a whole or half
// number up to 32 in magnitude (the specular powers and the normalisation's
// -1/2, several times cheaper than std::pow), within (|p| + 8) u <= 40 u (a
// squaring doubles its input's relative error), std::pow (within a few
// ulps) otherwise.
template <typename Real>
Real PowerOf(Real x, Real p)
{
  const Real twice = Real(2) * p;
  if (!(std::abs(p) <= Real(32)) || twice != std::floor(twice))
  {
    return std::pow(x, p);
  }
  unsigned n = static_cast<unsigned>(std::abs(p)); // the whole part of |p|
  Real result = twice == Real(2) * std::floor(p) ? Real(1) : std::sqrt(x);
  for (Real base = x; n > 0; n >>= 1, base *= base)
  {
    result = n & 1u ? result * base : result;
  }
  return p < Real(0) ? Real(1) / result : result;
}
} // namespace detail

// a^p for a > 0 over X, any real p. Taylor's expansion about a_0 with
// C(p, k) a_0^(p - k) and the remainder |C(p, N + 1)| max x^(p - N - 1) over
// a's range; where that range reaches 0, or where the expansion's remainder
// is not small (1e-3 of the value) and the range's power is narrower, the
// constant model of the range's power (p > 0; for p < 0 nothing is known).
template <typename Real, int N>
TaylorModel<Real, N> Pow(const TaylorModel<Real, N>& a, Real p)
{
  if (p == Real(0))
  {
    return TaylorModel<Real, N>(Real(1));
  }
  const Bounds<Real> x = a.Range();
  auto hull = [&]()
  {
    return TaylorModel<Real, N>::Enclosing(
      p > Real(0) || x.Lo > Real(0) ? Pow(x, p) : Bounds<Real>::Whole(), a.Radius);
  };
  if (!(x.Lo > Real(0)) || !a.Finite())
  {
    return hull();
  }
  const Real a0 = a.A[0];
  Real c[N + 1];
  c[0] = detail::PowerOf(a0, p);
  Real binomial = Real(1); // C(p, k)
  for (int k = 0; k < N; ++k)
  {
    c[k + 1] = c[k] * (p - Real(k)) / (Real(k + 1) * a0);
    binomial *= (p - Real(k)) / Real(k + 1);
  }
  binomial *= (p - Real(N)) / Real(N + 1);
  const Real e = p - Real(N + 1);
  const Real extreme = detail::PowerOf(e < Real(0) ? x.Lo : x.Hi, e);
  const Real eps = std::numeric_limits<Real>::epsilon();
  const Real tail = std::abs(binomial) * extreme * (Real(1) + Real(64) * eps);
  const TaylorModel<Real, N> m = detail::ComposeTaylor(a, c, Real(8 * (N + 4)) * eps, tail);
  if (m.R <= Real(1e-3) * std::abs(c[0]))
  {
    return m;
  }
  const TaylorModel<Real, N> h = hull();
  return m.R <= h.R ? m : h;
}

// x^n for a whole n >= 1 by squaring: valid whatever the signs of x.
template <typename Real, int N>
TaylorModel<Real, N> WholePower(TaylorModel<Real, N> x, unsigned n)
{
  TaylorModel<Real, N> result(Real(1));
  result.Radius = x.Radius;
  bool first = true;
  for (; n > 0; n >>= 1)
  {
    if (n & 1u)
    {
      result = first ? x : result * x;
      first = false;
    }
    if (n > 1)
    {
      x = x * x;
    }
  }
  return result;
}

// The hull of a's range clamped to [lo, hi], or, where a's constant term is
// inside, a itself plus what the clamp can move it by over a's range
// (clamp(x) - x lies in [-(x_max - hi)+, (lo - x_min)+]): an enclosure of
// clamp(f), whichever is narrower. It also tightens a model of a quantity
// known to lie in [lo, hi] (a cosine).
template <typename Real, int N>
TaylorModel<Real, N> Clamp(const TaylorModel<Real, N>& a, Real lo, Real hi)
{
  const Bounds<Real> plain = a.Range(); // enough, and cheaper, where it is inside
  if (a.Finite() && plain.Lo >= lo && plain.Hi <= hi)
  {
    return a;
  }
  const Bounds<Real> x = a.TightRange();
  if (!a.Finite() || !(x.Lo <= x.Hi))
  {
    return TaylorModel<Real, N>::Enclosing(Bounds<Real>(lo, hi), a.Radius);
  }
  if (x.Lo >= lo && x.Hi <= hi)
  {
    return a;
  }
  if (x.Hi <= lo || x.Lo >= hi)
  {
    return TaylorModel<Real, N>(x.Hi <= lo ? lo : hi);
  }
  const TaylorModel<Real, N> hull =
    TaylorModel<Real, N>::Enclosing(Bounds<Real>(std::max(x.Lo, lo), std::min(x.Hi, hi)), a.Radius);
  if (!(a.A[0] >= lo && a.A[0] <= hi))
  {
    return hull;
  }
  const Real up = std::max(lo - x.Lo, Real(0)), down = std::max(x.Hi - hi, Real(0));
  TaylorModel<Real, N> m = a;
  m.A[0] += (up - down) / Real(2);
  m.R = (a.R + (up + down) / Real(2) +
          Real(2) * std::numeric_limits<Real>::epsilon() * std::abs(m.A[0])) *
    TaylorModel<Real, N>::Up();
  return m.R <= hull.R ? m : hull;
}

namespace detail
{
// |a| (twoSided) or max(0, a): a or -a, whichever the constant term's sign
// picks, plus what the kink can add over a's range (|x| - x lies in
// [0, 2 (-x_min)+], max(0, x) - x in [0, (-x_min)+]), or the hull of the
// range, whichever is narrower.
template <typename Real, int N>
TaylorModel<Real, N> Kink(const TaylorModel<Real, N>& a, bool twoSided)
{
  const Bounds<Real> plain = a.Range(); // enough, and cheaper, away from the kink
  if (a.Finite() && plain.Lo >= Real(0))
  {
    return a;
  }
  const Bounds<Real> x = a.TightRange();
  if (!a.Finite() || !(x.Lo <= x.Hi))
  {
    return TaylorModel<Real, N>::Enclosing(Bounds<Real>::Whole(), a.Radius);
  }
  if (x.Lo >= Real(0))
  {
    return a;
  }
  if (x.Hi <= Real(0))
  {
    return twoSided ? -a : TaylorModel<Real, N>(Real(0));
  }
  const TaylorModel<Real, N> hull = TaylorModel<Real, N>::Enclosing(
    Bounds<Real>(Real(0), twoSided ? x.Magnitude() : x.Hi), a.Radius);
  if (!twoSided && a.A[0] < Real(0))
  {
    return hull;
  }
  // The side the constant term is on, and how far the range reaches past 0.
  const bool positive = a.A[0] >= Real(0);
  const Real excess = positive ? -x.Lo : x.Hi;
  TaylorModel<Real, N> m = positive ? a : -a;
  const Real shift = twoSided ? excess : excess / Real(2);
  m.A[0] += shift;
  m.R = (a.R + shift + Real(2) * std::numeric_limits<Real>::epsilon() * std::abs(m.A[0])) *
    TaylorModel<Real, N>::Up();
  return m.R <= hull.R ? m : hull;
}
} // namespace detail

template <typename Real, int N>
TaylorModel<Real, N> Abs(const TaylorModel<Real, N>& a)
{
  return detail::Kink(a, true);
}

template <typename Real, int N>
TaylorModel<Real, N> PositivePart(const TaylorModel<Real, N>& a)
{
  return detail::Kink(a, false);
}

// A function by cases, as Cases on Jets (Enclosure.h): the case the range
// lies in, or, where it holds the threshold, the constant model of the hull
// of both cases, each over its part of the range.
template <typename Real, int N, typename Below, typename Above>
TaylorModel<Real, N> Cases(
  const TaylorModel<Real, N>& x, Real threshold, Below&& below, Above&& above)
{
  const Real guard = Real(1e-12) * std::max(std::abs(threshold), Real(1e-300));
  const Bounds<Real> v = x.Range();
  if (v.Lo > threshold + guard)
  {
    return above(x);
  }
  if (v.Hi < threshold - guard)
  {
    return below(x);
  }
  using Model = TaylorModel<Real, N>;
  const Model low =
    Model::Enclosing(Bounds<Real>(v.Lo, std::min(v.Hi, threshold + guard)), x.Radius);
  const Model high =
    Model::Enclosing(Bounds<Real>(std::max(v.Lo, threshold - guard), v.Hi), x.Radius);
  return Model::Enclosing(Hull(below(low).Range(), above(high).Range()), x.Radius);
}

// The constant model of the hull of two models' ranges: either may hold.
template <typename Real, int N>
TaylorModel<Real, N> Hull(const TaylorModel<Real, N>& a, const TaylorModel<Real, N>& b)
{
  return TaylorModel<Real, N>::Enclosing(Hull(a.Range(), b.Range()), std::max(a.Radius, b.Radius));
}

} // namespace numerics
} // namespace avos

#endif
