// A ray through a trilinear volume, cut into pieces on which the integrand of
// the volume rendering integral is smooth (analytic).
//
// Inside one cell the trilinear interpolant restricted to the ray is a cubic
// polynomial s(t); the transfer function is linear in s between two knots. So
// the integrand can lose smoothness only where the ray crosses a cell face or
// where s(t) crosses a knot value. PieceWalk cuts the ray at exactly those
// events (the cells by Amanatides and Woo's traversal, the crossings from the
// cubic: its extrema bracket monotone stretches, a safeguarded Newton step
// finds each knot inside a stretch), as exact and pre-integrated volume
// rendering do, and hands each piece with its cubic and its transfer-function
// piece to the caller (see PiecewiseIntegrator.h). A cell whose corner range
// holds no knot is one piece: no root is sought there, and a cell whose
// range the transfer function makes transparent costs its corners only.
//
// PiecewiseTransferFunction gives C linear and tau at most a cubic in s on
// each piece (so the optical depth along a piece stays the integral of a
// polynomial). In the extinction model the knots are tau already: linear. In
// VTK's alpha model tau = -ln(1 - alpha) / d is not a polynomial in s; each
// linear alpha segment is cut at extra knots so that the polynomial
// interpolating tau on each cut (a quadratic, or a cubic where that allows a
// cut more than 4 / 3 as long) is within a relative error r of the true tau
// everywhere. A relative error r in tau changes every channel of a ray by at
// most 2 r (1 + O(r)) (see PiecewiseIntegrator.h), whatever the ray. Alpha
// values of 1 and above are opaque (tau = 40 / d, as in TransferFunction);
// the extra knots stop where tau reaches 36 / d (1 - alpha below 2.3e-16),
// and the chord from there up to the opaque value is within 11 %.
//
// Bounds (termination). A ray segment of the volume's box crosses at most
// nx + ny + nz cells; a cell's cubic has at most 3 monotone stretches, and a
// stretch crosses each knot at most once, so a cell holds at most
// 3 (m + 1) pieces for m knots. Each knot crossing takes at most 128
// iterations of bisection-safeguarded Newton.
#ifndef avos_numerics_Pieces_h
#define avos_numerics_Pieces_h

#include "avos/numerics/TransferFunction.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

// The cut's helpers are called once per sub-piece in the walk's innermost
// loop, where GCC would leave them out of line (7 to 9 % of a piecewise
// frame on Foot and Bonsai, measured).
#if defined(__GNUC__)
#define AVOS_NUMERICS_INLINE inline __attribute__((always_inline))
#else
#define AVOS_NUMERICS_INLINE inline
#endif

namespace avos
{
namespace numerics
{

template <typename Real>
class PiecewiseTransferFunction
{
public:
  using Color = glm::vec<3, Real>;

  // tau(s) = Tau + TauSlope d + TauCurvature d^2 + TauCubic d^3,
  // C(s) = Colour + ColourSlope d, d = s - Start.
  struct Piece
  {
    Real Start;
    Real Tau;
    Real TauSlope;
    Real TauCurvature;
    Real TauCubic;
    Color Colour;
    Color ColourSlope;
    Real ColourSlopeMaximum; // max |ColourSlope| over the channels
  };

  // The most knots the alpha model's conversion may add: beyond, the
  // requested relative error is refused.
  static constexpr std::size_t MaximumKnots = std::size_t(1) << 20;
  // The finest relative error of the alpha model's extinction it builds
  // (far above double's rounding of tau; 997 pieces for an alpha ramp from
  // 0 to 0.99, where 1e-7 takes 64).
  static constexpr Real MinimumRelativeError = Real(1e-12);
  // -ln(1 - alpha) from which the alpha model's extra knots stop and the
  // rest, up to the opaque value, is one chord.
  static constexpr Real FlatDepth = Real(36);

  // Prepares `tf` (valid and finalised) for integration. `relativeError` is
  // the largest relative error of tau allowed in the alpha model (unused in
  // the extinction model, where tau is exact). Empty on success, else why.
  std::string Build(const TransferFunction<Real>& tf, Real relativeError)
  {
    this->Locator.Clear();
    this->Pieces.clear();
    this->VisibleBefore.clear();
    this->NextVisiblePiece.clear();
    this->PreviousVisiblePiece.clear();
    std::vector<Real> knots;
    std::string error = tf.Validate();
    if (!error.empty())
    {
      return error;
    }
    const auto& pieces = tf.GetPieces();
    if (pieces.empty())
    {
      return "the transfer function was not finalised";
    }
    const bool alpha = tf.GetOpacityModel() == OpacityModel::Alpha;
    if (alpha && !(relativeError >= MinimumRelativeError && relativeError < Real(1)))
    {
      return "the relative error of the alpha model's extinction must be in [1e-7, 1)";
    }
    // Below the first knot: the first values, constant.
    this->Pieces.push_back({ pieces.front().Start, tf.ToExtinction(tf.GetOpacityBelow()), Real(0),
      Real(0), Real(0), tf.GetColorBelow(), Color(Real(0)), Real(0) });
    for (const auto& p : pieces)
    {
      const Real a0 = p.Opacity;
      const Real a1 = p.Length > Real(0) ? p.OpacitySlope : Real(0);
      if (!alpha || a1 == Real(0))
      {
        this->Add(knots, p.Start, { tf.ToExtinction(a0), alpha ? Real(0) : a1, Real(0), Real(0) },
          p.Colour, p.ColourSlope);
        continue;
      }
      // The alpha model on a sloped segment: extra knots, in alpha from the
      // low end to the high end, then laid out in s.
      const Real aEnd = a0 + a1 * p.Length;
      std::vector<AlphaCut> cuts = AlphaCuts(std::min(a0, aEnd), std::max(a0, aEnd), relativeError);
      if (knots.size() + cuts.size() > MaximumKnots)
      {
        return "the alpha model needs too many knots for that tolerance";
      }
      if (a1 < Real(0))
      {
        std::reverse(cuts.begin(), cuts.end());
      }
      const Real flat = FlatDepth / tf.GetUnitDistance();
      for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
      {
        // In alpha, u = alpha - x over the cut [x, y] (w = y - x < 0 where
        // alpha falls along s): tau = fx + A u + B u^2 + C u^3 through
        // u = 0, w / 3, 2 w / 3 and w (Newton's forward differences, step
        // h = w / 3), or fx + A u + B u^2 through 0, w / 2 and w; the chord
        // where tau nears the opaque clamp. In s, u = a1 (s - start). A cut's
        // flag is at its lower end in alpha.
        const Real x = cuts[k].At, y = cuts[k + 1].At, w = y - x;
        const bool cubic = a1 > Real(0) ? cuts[k].Cubic : cuts[k + 1].Cubic;
        const Real s = k == 0 ? p.Start : p.Start + (x - a0) / a1;
        const Real fx = tf.ToExtinction(x), fy = tf.ToExtinction(y);
        Real A = (fy - fx) / w, B = Real(0), C = Real(0);
        if (fx < flat && fy < flat && std::max(x, y) < Real(1))
        {
          if (cubic)
          {
            const Real h = w / Real(3);
            const Real f1 = tf.ToExtinction(x + h), f2 = tf.ToExtinction(x + Real(2) * h);
            const Real d1 = f1 - fx, d2 = f2 - Real(2) * f1 + fx;
            const Real d3 = fy - Real(3) * f2 + Real(3) * f1 - fx;
            A = (d1 - d2 / Real(2) + d3 / Real(3)) / h;
            B = (d2 - d3) / (Real(2) * h * h);
            C = d3 / (Real(6) * h * h * h);
          }
          else
          {
            const Real fm = tf.ToExtinction(x + Real(0.5) * w);
            B = Real(2) * (fx - Real(2) * fm + fy) / (w * w);
            A = (fy - fx) / w - B * w;
          }
        }
        this->Add(knots, s, { fx, A * a1, B * a1 * a1, C * a1 * a1 * a1 },
          p.Colour + p.ColourSlope * (s - p.Start), p.ColourSlope);
      }
    }
    // Prefix counts of visible pieces: a piece is visible unless tau is zero
    // at both of its ends (tau is linear on it, or in the alpha model a
    // cubic within a relative error r < 1 of -ln(1 - alpha) / d, so zero at
    // both ends only where alpha is).
    this->VisibleBefore.assign(1, 0u);
    for (std::size_t i = 0; i < this->Pieces.size(); ++i)
    {
      const Piece& p = this->Pieces[i];
      Real end = p.Tau;
      if (i + 1 < this->Pieces.size() && i > 0)
      {
        const Real d = knots[i] - p.Start;
        end = p.Tau + d * (p.TauSlope + d * (p.TauCurvature + d * p.TauCubic));
      }
      const bool visible = p.Tau > Real(0) || end > Real(0);
      this->VisibleBefore.push_back(this->VisibleBefore.back() + (visible ? 1u : 0u));
    }
    const std::size_t n = this->Pieces.size();
    this->NextVisiblePiece.assign(n + 1, n);
    this->PreviousVisiblePiece.assign(n, 0);
    for (std::size_t i = n; i-- > 0;)
    {
      this->NextVisiblePiece[i] = this->IsVisible(i) ? i : this->NextVisiblePiece[i + 1];
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      this->PreviousVisiblePiece[i] =
        this->IsVisible(i) ? i + 1 : (i > 0 ? this->PreviousVisiblePiece[i - 1] : 0);
    }
    this->MaximumColor = tf.GetMaximumColor();
    this->Locator.Build(std::move(knots));
    this->BuildUnitCounts();
    return std::string();
  }

  // The piece holding s: 0 below the first knot, i for s in
  // [Knots[i - 1], Knots[i]) (right-continuous at jumps), the last one above
  // the last knot: std::upper_bound's answer (KnotLocator). NaN: 0 (callers
  // never classify a NaN; see PieceWalk).
  std::size_t Locate(Real s) const { return this->Locator.UpperBound(s); }

  // Locate(s) from a guess of it: two comparisons when the guess is right
  // (a sub-piece between two known knots), the search otherwise.
  std::size_t LocateNear(Real s, std::size_t guess) const
  {
    const std::vector<Real>& knots = this->GetKnots();
    if (guess <= knots.size() && (guess == 0 || knots[guess - 1] <= s) &&
      (guess == knots.size() || s < knots[guess]))
    {
      return guess;
    }
    return this->Locate(s);
  }

  // The number of knots strictly below s (std::lower_bound's answer).
  std::size_t CountBelow(Real s) const
  {
    const std::vector<Real>& knots = this->Locator.GetKnots();
    std::size_t i = this->Locate(s);
    while (i > 0 && knots[i - 1] == s)
    {
      --i;
    }
    return i;
  }

  // Multiplies the extinction by `weight` > 0 (a mixture's only term, at
  // one rounding per coefficient); which pieces are visible is unchanged.
  void ScaleExtinction(Real weight)
  {
    for (Piece& p : this->Pieces)
    {
      p.Tau *= weight;
      p.TauSlope *= weight;
      p.TauCurvature *= weight;
      p.TauCubic *= weight;
    }
  }

  const Piece& operator[](std::size_t i) const { return this->Pieces[i]; }
  std::size_t GetNumberOfPieces() const { return this->Pieces.size(); }
  const std::vector<Real>& GetKnots() const { return this->Locator.GetKnots(); }
  Real GetMaximumColor() const { return this->MaximumColor; }

  bool IsVisible(std::size_t i) const
  {
    return this->VisibleBefore[i + 1] > this->VisibleBefore[i];
  }

  // The first visible piece from piece i on, i <= GetNumberOfPieces()
  // (GetNumberOfPieces() when none), and one more than the last visible
  // piece up to piece i, i < GetNumberOfPieces() (0 when none).
  std::size_t NextVisible(std::size_t i) const { return this->NextVisiblePiece[i]; }
  std::size_t PreviousVisibleEnd(std::size_t i) const { return this->PreviousVisiblePiece[i]; }

  // What a cell whose scalar stays within [lo, hi] (its corners' range, lo
  // <= hi, both finite) holds.
  struct RangeClass
  {
    std::size_t First; // the piece of lo: the cell's only one without crossings
    bool Crossings;    // a knot lies strictly inside (lo, hi)
    bool Visible;      // tau > 0 somewhere in [lo, hi]
  };

  // The answer Locate and CountBelow give, from two table reads
  // when lo and hi are integers within the knots' span (8- and 16-bit data:
  // every cell's corners), else from the knot search.
  RangeClass ClassifyRange(Real lo, Real hi) const
  {
    RangeClass c;
    std::size_t l, h, last;
    if (this->UnitIndex(lo, l) && this->UnitIndex(hi, h))
    {
      c.First = this->UnitUpper[l];
      c.Crossings = this->UnitBelow[h] > c.First;
      last = c.Crossings ? this->UnitUpper[h] : c.First;
    }
    else
    {
      const std::vector<Real>& knots = this->GetKnots();
      c.First = this->Locate(lo);
      c.Crossings = c.First < knots.size() && knots[c.First] < hi;
      last = c.Crossings ? this->Locate(hi) : c.First;
    }
    // The pieces of lo to hi: visible when any of them is.
    c.Visible = this->VisibleBefore[last + 1] > this->VisibleBefore[c.First];
    return c;
  }

  // What ClassifyRange reads, for kernels that classify integer ranges in
  // lanes: Locate(Base + i) = Upper[i] and CountBelow(Base + i) = Below[i]
  // for i < Count (Count 0: no tables; below Base both are 0, from
  // Base + Count on both are Knots), VisibleBefore[i] the visible pieces
  // among the first i (Knots + 2 entries).
  struct UnitTables
  {
    Real Base;
    std::uint32_t Count;
    std::uint32_t Knots;
    const std::uint32_t* Upper;
    const std::uint32_t* Below;
    const std::uint32_t* VisibleBefore;
  };
  UnitTables GetUnitTables() const
  {
    return { this->UnitBase, static_cast<std::uint32_t>(this->UnitUpper.size()),
      static_cast<std::uint32_t>(this->GetKnots().size()), this->UnitUpper.data(),
      this->UnitBelow.data(), this->VisibleBefore.data() };
  }

private:
  // tau: the extinction's coefficients of 1, d, d^2, d^3.
  void Add(std::vector<Real>& knots, Real s, const std::array<Real, 4>& tau, const Color& colour,
    const Color& colourSlope)
  {
    const Piece piece{ s, tau[0], tau[1], tau[2], tau[3], colour, colourSlope,
      std::max({ std::abs(colourSlope.x), std::abs(colourSlope.y), std::abs(colourSlope.z) }) };
    if (!knots.empty() && s <= knots.back())
    {
      // A cut rounded onto its neighbour: the later piece starts there and
      // replaces the empty one.
      this->Pieces.back() = piece;
      return;
    }
    knots.push_back(s);
    this->Pieces.push_back(piece);
  }

  // A cut of an alpha segment: where it starts (in alpha), and whether tau
  // is a cubic on the interval from there to the next cut (else a
  // quadratic).
  struct AlphaCut
  {
    Real At;
    bool Cubic;
  };

  // Alpha values lo = x_0 < x_1 < ... < x_n = hi such that on each [x_k,
  // x_k+1] the polynomial interpolating f(a) = -ln(1 - a) is within a
  // relative error r of f: the quadratic through x, the middle m and y, or
  // the cubic through x, x + w / 3, x + 2 w / 3 and y (w = y - x). For z in
  // [x, y], f(z) >= f(x) + f'(x)(z - x) >= max(f(x), (z - x) / (1 - x)) and
  // f's derivatives increase (f''' = 2 / (1 - a)^3, f'''' = 6 / (1 - a)^4):
  // - quadratic: |p(z) - f(z)| <= f'''(y) / 6 |z - x| |z - m| |z - y|
  //     <= f'''(y) min((z - x) w^2 / 2, w^3 / (12 sqrt 3)) / 6, so the
  //   relative error is at most min(w^2 (1 - x) / (6 (1 - y)^3),
  //   w^3 / (36 sqrt 3 (1 - y)^3 f(x)));
  // - cubic: with omega(z) = (z - x)(z - x - w / 3)(z - x - 2 w / 3)(z - y),
  //   |p(z) - f(z)| <= f''''(y) / 24 |omega(z)| and |omega(z)| <=
  //   min((z - x) 2 w^3 / 9, w^4 / 81) (the largest |(z - x - w / 3)
  //   (z - x - 2 w / 3)(z - y)| is at z = x; the largest |omega| where
  //   (z - x - w / 2)^2 = 5 w^2 / 36), so the relative error is at most
  //   min(w^3 (1 - x) / (18 (1 - y)^4), w^4 / (324 (1 - y)^4 f(x))).
  // Both bounds grow with w. Each cut takes the longest interval either
  // allows (within 2^-30 of its width: halving from hi until the bound holds,
  // then bisecting between that width and twice it; fixed numbers of steps),
  // the quadratic's unless the cubic's is more than 4 / 3 as long: a cubic
  // makes the piece's depth a polynomial of degree 10 instead of 7 in the
  // ray parameter, dearer to integrate (PiecewiseIntegrator.h), which only
  // fewer pieces repay.
  static std::vector<AlphaCut> AlphaCuts(Real lo, Real hi, Real r)
  {
    std::vector<AlphaCut> cuts{ { lo, false } };
    const Real opaque = Real(1);
    Real x = lo;
    while (x < hi && cuts.size() < MaximumKnots)
    {
      const Real fx = x < opaque ? -std::log(Real(1) - x) : Real(40);
      if (x >= opaque || fx >= FlatDepth)
      {
        break;
      }
      auto quadratic = [&](Real w)
      {
        const Real y = x + w;
        const Real q = (Real(1) - y) * (Real(1) - y) * (Real(1) - y);
        const Real nearX = w * w * (Real(1) - x) / (Real(6) * q);
        const Real overall = fx > Real(0) ? w * w * w / (Real(62.353829072479584) * q * fx) : nearX;
        return q > Real(0) && std::min(nearX, overall) <= r;
      };
      auto cubic = [&](Real w)
      {
        const Real y = x + w;
        const Real q = (Real(1) - y) * (Real(1) - y) * (Real(1) - y) * (Real(1) - y);
        const Real nearX = w * w * w * (Real(1) - x) / (Real(18) * q);
        const Real overall = fx > Real(0) ? w * w * w * w / (Real(324) * q * fx) : nearX;
        return q > Real(0) && std::min(nearX, overall) <= r;
      };
      auto longest = [&](const auto& holds)
      {
        Real w = std::min(hi, opaque) - x;
        int halvings = 0;
        for (; halvings < 200 && !holds(w); ++halvings)
        {
          w *= Real(0.5);
        }
        if (halvings > 0 && holds(w))
        {
          Real fails = Real(2) * w; // the longest width lies in [w, fails)
          for (int k = 0; k < 30; ++k)
          {
            const Real middle = Real(0.5) * (w + fails);
            (holds(middle) ? w : fails) = middle;
          }
        }
        return w;
      };
      const Real byQuadratic = longest(quadratic), byCubic = longest(cubic);
      const bool useCubic = byCubic > Real(4) / Real(3) * byQuadratic;
      const Real y = x + (useCubic ? byCubic : byQuadratic);
      if (!(y > x))
      {
        break; // below the resolution of Real: the rest is one chord
      }
      cuts.back().Cubic = useCubic;
      x = y;
      cuts.push_back({ x, false });
    }
    // Opacities above 1 are opaque: a cut at 1 leaves the rest constant,
    // where the last chord's would be up to 10 % below the opaque value.
    if (cuts.back().At < opaque && hi > opaque)
    {
      cuts.push_back({ opaque, false });
    }
    if (cuts.back().At < hi)
    {
      cuts.push_back({ hi, false });
    }
    return cuts;
  }

  // Tables of Locate and CountBelow at the integers UnitBase + i covering the
  // knots, where that span is at most 2^16 units and every such integer is
  // exact in Real; empty otherwise.
  void BuildUnitCounts()
  {
    this->UnitUpper.clear();
    this->UnitBelow.clear();
    const std::vector<Real>& knots = this->GetKnots();
    const Real base = std::floor(knots.front()), top = std::ceil(knots.back());
    const Real exact = Real(1) / std::numeric_limits<Real>::epsilon(); // 2^52 for double
    if (!(top - base <= Real(65536) && std::abs(base) + Real(65537) < exact))
    {
      return;
    }
    this->UnitBase = base;
    for (Real u = base; u <= top; u += Real(1))
    {
      this->UnitUpper.push_back(static_cast<std::uint32_t>(this->Locate(u)));
      this->UnitBelow.push_back(static_cast<std::uint32_t>(this->CountBelow(u)));
    }
  }

  // True with i = s - UnitBase when s is an integer the tables hold.
  bool UnitIndex(Real s, std::size_t& i) const
  {
    const Real x = s - this->UnitBase;
    if (!(x >= Real(0) && x < Real(this->UnitUpper.size())))
    {
      return false;
    }
    i = static_cast<std::size_t>(x);
    return Real(i) == x;
  }

  KnotLocator<Real> Locator; // the knots between the pieces
  std::vector<Piece> Pieces;
  std::vector<std::uint32_t> VisibleBefore; // pieces < 2^32 (MaximumKnots)
  std::vector<std::size_t> NextVisiblePiece, PreviousVisiblePiece;
  Real UnitBase = Real(0);
  std::vector<std::uint32_t> UnitUpper, UnitBelow;
  Real MaximumColor = Real(0);
};

// s(u) = K[0] + K[1] u + K[2] u^2 + K[3] u^3.
template <typename Real>
struct Cubic
{
  Real K[4];

  Real operator()(Real u) const
  {
    return this->K[0] + u * (this->K[1] + u * (this->K[2] + u * this->K[3]));
  }
  Real Derivative(Real u) const
  {
    return this->K[1] + u * (Real(2) * this->K[2] + u * Real(3) * this->K[3]);
  }
  // The same polynomial in v = u - u0.
  Cubic Shifted(Real u0) const
  {
    Cubic c;
    c.K[0] = (*this)(u0);
    c.K[1] = this->Derivative(u0);
    c.K[2] = this->K[2] + Real(3) * this->K[3] * u0;
    c.K[3] = this->K[3];
    return c;
  }
};

// One smooth piece of a ray: t in [Begin, Begin + Length], where the scalar is
// Start + Q(t - Begin) and the transfer function is its piece TF (Q includes
// the offset: Q(v) = s(Begin + v) - Start).
template <typename Real>
struct RayPiece
{
  Real Begin;
  Real Length;
  Cubic<Real> Q;
  std::size_t TF;
  // True: s is monotone on the piece (a stretch between the cell's extrema).
  // False: not tested (a cell without knot crossings, whole: whoever needs
  // to know tests it, as IntegratePiecewise does a batch of pieces at once).
  bool Monotone;
};

namespace detail
{
// The root of the monotone cubic s - value on [lo, hi], whose ends bracket
// it: Newton's step where it stays inside the bracket, bisection otherwise.
template <typename Real>
Real Crossing(const Cubic<Real>& s, Real value, Real lo, Real hi)
{
  const Real sign = s(hi) >= s(lo) ? Real(1) : Real(-1);
  const Real slo = s(lo), shi = s(hi);
  Real u = shi != slo ? lo + (hi - lo) * ((value - slo) / (shi - slo)) : Real(0.5) * (lo + hi);
  u = std::min(std::max(u, lo), hi);
  for (int i = 0; i < 128 && lo < hi; ++i)
  {
    const Real f = sign * (s(u) - value);
    if (f == Real(0))
    {
      return u;
    }
    (f < Real(0) ? lo : hi) = u;
    const Real d = sign * s.Derivative(u);
    const Real newton = d > Real(0) ? u - f / d : std::numeric_limits<Real>::quiet_NaN();
    const Real next = newton > lo && newton < hi ? newton : Real(0.5) * (lo + hi);
    if (next == u || hi - lo <= Real(4) * std::numeric_limits<Real>::epsilon() * std::abs(hi))
    {
      return next;
    }
    u = next;
  }
  return u;
}

// True when s' keeps its sign on [0, end]: at both ends and at the vertex of
// the quadratic s' when it lies inside.
template <typename Real>
bool Monotone(const Cubic<Real>& s, Real end)
{
  const Real d0 = s.Derivative(Real(0)), d1 = s.Derivative(end);
  Real lo = std::min(d0, d1), hi = std::max(d0, d1);
  if (s.K[3] != Real(0))
  {
    const Real vertex = -s.K[2] / (Real(3) * s.K[3]);
    if (vertex > Real(0) && vertex < end)
    {
      const Real dv = s.Derivative(vertex);
      lo = std::min(lo, dv);
      hi = std::max(hi, dv);
    }
  }
  return lo >= Real(0) || hi <= Real(0);
}

// Roots of a u^2 + b u + c in (0, end), ascending; at most 2.
template <typename Real>
int QuadraticRoots(Real a, Real b, Real c, Real end, Real roots[2])
{
  int n = 0;
  Real r[2];
  const Real scale = std::max({ std::abs(a) * end * end, std::abs(b) * end, std::abs(c) });
  if (scale == Real(0))
  {
    return 0;
  }
  if (std::abs(a) * end * end <= Real(1e-12) * scale)
  {
    if (b != Real(0))
    {
      r[n++] = -c / b;
    }
  }
  else
  {
    const Real disc = b * b - Real(4) * a * c;
    if (disc >= Real(0))
    {
      // Stable: no cancellation between b and the root of disc.
      const Real q = Real(-0.5) * (b + std::copysign(std::sqrt(disc), b));
      if (q != Real(0))
      {
        r[n++] = q / a;
        r[n++] = c / q;
      }
      else
      {
        r[n++] = Real(0);
      }
    }
  }
  int count = 0;
  for (int i = 0; i < n; ++i)
  {
    if (r[i] > Real(0) && r[i] < end)
    {
      roots[count++] = r[i];
    }
  }
  if (count == 2 && roots[0] > roots[1])
  {
    std::swap(roots[0], roots[1]);
  }
  return count;
}

// The extrema of s inside (0, length), ascending: the roots of s'. None
// when |K1| is more than twice the bound 2 |K2| l + 3 |K3| l^2 on the rest
// of s' = K1 + 2 K2 u + 3 K3 u^2 over [0, l] (the factor covers the
// rounding of this test): s' keeps K1's sign there, and the roots' square
// root and divisions are spared (66 to 94 % of the cells with a knot
// crossing on Foot, Bonsai and Engine at eps 0.001).
template <typename Real>
int Extrema(const Cubic<Real>& s, Real length, Real extrema[2])
{
  const Real rest =
    Real(2) * std::abs(s.K[2]) * length + Real(3) * std::abs(s.K[3]) * length * length;
  if (std::abs(s.K[1]) > Real(2) * rest)
  {
    return 0;
  }
  return QuadraticRoots(Real(3) * s.K[3], Real(2) * s.K[2], s.K[1], length, extrema);
}

// A monotone stretch [A, B] of a cell's cubic s (between its extrema) and
// the knots strictly inside its range (slo, shi), in the order the ray meets
// them: sub-piece j (0 .. Inside) lies in the transfer-function piece
// PieceAt(j), and ends at the crossing of knot Value(j) (j < Inside) or at B.
template <typename Real>
struct Stretch
{
  Real A = Real(0), B = Real(0);
  bool Rising = true;
  std::size_t K0 = 0, K1 = 0, Inside = 0;

  Stretch() = default;
  AVOS_NUMERICS_INLINE Stretch(
    const Cubic<Real>& s, Real a, Real b, const PiecewiseTransferFunction<Real>& tf)
    : A(a)
    , B(b)
  {
    const Real sa = s(a), sb = s(b);
    this->Rising = sb >= sa;
    this->K0 = tf.Locate(std::min(sa, sb));
    this->K1 = tf.CountBelow(std::max(sa, sb));
    this->Inside = this->K1 > this->K0 ? this->K1 - this->K0 : 0;
  }

  std::size_t PieceAt(std::size_t j) const { return this->Rising ? this->K0 + j : this->K1 - j; }

  // Sub-piece j from u (where the one before ended), up to `root` (the
  // crossing of Value(j), read only when j < Inside) or B: where it ends
  // (the next starts there), and whether it is integrated, then in which
  // transfer-function piece (`piece`).
  AVOS_NUMERICS_INLINE bool SubPiece(const PiecewiseTransferFunction<Real>& tf,
    const Cubic<Real>& s, std::size_t j, Real u, Real root, Real& end, std::size_t& piece) const
  {
    const bool visible = this->Inside == 0 || tf.IsVisible(this->PieceAt(j));
    // Rounding may put a root before the one of the knot before.
    end = j < this->Inside ? std::min(std::max(root, u), this->B) : this->B;
    if (!visible || !(end > u))
    {
      return false;
    }
    // The transfer-function piece from the scalar in the middle: robust
    // where a crossing rounds onto a knot.
    piece = tf.LocateNear(s(Real(0.5) * (u + end)), this->PieceAt(j));
    return tf.IsVisible(piece);
  }

  Real Value(const std::vector<Real>& knots, std::size_t j) const
  {
    return knots[this->Rising ? this->K0 + j : this->K1 - 1 - j];
  }

  // A knot between two transparent sub-pieces bounds nothing that is
  // integrated: its crossing is not sought (on Foot's transfer function,
  // two thirds of all crossings). The sub-pieces that matter are the
  // visible ones and those ending at a sought crossing (whose next is
  // visible); Useful(j) is the first of them from j on (Inside + 1 when
  // none), found through the transfer function's next or previous visible
  // piece, so that a transparent run is passed over at once. With no knot
  // inside, the stretch is one sub-piece, always taken.
  AVOS_NUMERICS_INLINE std::size_t Useful(
    const PiecewiseTransferFunction<Real>& tf, std::size_t j) const
  {
    if (this->Inside == 0)
    {
      return j;
    }
    if (j > this->Inside)
    {
      return this->Inside + 1;
    }
    if (this->Rising)
    {
      // Pieces K0 + j, ascending.
      const std::size_t p = tf.NextVisible(this->K0 + j);
      if (p > this->K1)
      {
        return this->Inside + 1;
      }
      return p - this->K0 > j ? p - this->K0 - 1 : j;
    }
    // Pieces K1 - j, descending.
    const std::size_t end = tf.PreviousVisibleEnd(this->K1 - j);
    if (end <= this->K0)
    {
      return this->Inside + 1;
    }
    const std::size_t p = end - 1;
    return this->K1 - p > j ? this->K1 - p - 1 : j;
  }
};

// The bounds of a cell's monotone stretches over [0, length]: 0, the
// extrema of s inside (Extrema), length; how many (2 to 4).
template <typename Real>
AVOS_NUMERICS_INLINE int StretchBounds(const Cubic<Real>& s, Real length, Real bounds[4])
{
  Real extrema[2];
  const int r = Extrema(s, length, extrema);
  bounds[0] = Real(0);
  for (int i = 0; i < r; ++i)
  {
    bounds[i + 1] = extrema[i];
  }
  bounds[r + 1] = length;
  return r + 2;
}
} // namespace detail

// The cells the ray origin + t direction (grid coordinates, t in the
// caller's units) crosses over [tBegin, tEnd], inside the box of a volume of
// `dimensions` points (at least 2 on every axis), in order (Amanatides and
// Woo's traversal), a cell at a time: Next gives the next cell with a part
// [t0, t1] (t1 > t0) of the ray inside it, false once none is left. At most
// nx + ny + nz + 3 steps; none for a non-finite ray.
template <typename Real>
class CellWalker
{
public:
  CellWalker() = default;
  CellWalker(const int dimensions[3], const glm::vec<3, Real>& origin,
    const glm::vec<3, Real>& direction, Real tBegin, Real tEnd)
  {
    const glm::vec<3, Real> p = origin + tBegin * direction;
    // A non-finite ray (or span) visits nothing: its cell would be undefined.
    if (!(tBegin < tEnd) || !std::isfinite(tEnd - tBegin) ||
      !std::isfinite(p.x + p.y + p.z + direction.x + direction.y + direction.z))
    {
      return;
    }
    for (int a = 0; a < 3; ++a)
    {
      this->N[a] = dimensions[a] - 1; // cells along the axis
      const Real x = std::min(std::max(p[a], Real(0)), Real(this->N[a]));
      this->Index[a] = std::min(static_cast<int>(x), this->N[a] - 1);
      if (direction[a] > Real(0))
      {
        this->Step[a] = 1;
        this->TMax[a] = (Real(this->Index[a] + 1) - origin[a]) / direction[a];
        this->TDelta[a] = Real(1) / direction[a];
      }
      else if (direction[a] < Real(0))
      {
        this->Step[a] = -1;
        this->TMax[a] = (Real(this->Index[a]) - origin[a]) / direction[a];
        this->TDelta[a] = -Real(1) / direction[a];
      }
      else
      {
        this->Step[a] = 0;
        this->TMax[a] = std::numeric_limits<Real>::infinity();
        this->TDelta[a] = this->TMax[a];
      }
    }
    this->T = tBegin;
    this->TEnd = tEnd;
    this->Left = this->N[0] + this->N[1] + this->N[2] + 3;
  }

  // The step as written in the traversal's definition: Fill's oracle
  // (Piecewise.CellWalkerFillEqualsNext). Not built on Fill: for a cell at a
  // time (the maximum-intensity walk) that measured no faster.
  AVOS_NUMERICS_INLINE bool Next(int cell[3], Real& t0, Real& t1)
  {
    Real* tMax = this->TMax;
    while (this->Left > 0 && this->T < this->TEnd)
    {
      --this->Left;
      const int axis =
        tMax[0] <= tMax[1] ? (tMax[0] <= tMax[2] ? 0 : 2) : (tMax[1] <= tMax[2] ? 1 : 2);
      const Real end = std::min(tMax[axis], this->TEnd);
      const bool inside = end > this->T;
      if (inside)
      {
        std::copy(this->Index, this->Index + 3, cell);
        t0 = this->T;
        t1 = end;
      }
      this->T = std::max(this->T, end);
      this->Index[axis] += this->Step[axis];
      if (this->Index[axis] < 0 || this->Index[axis] >= this->N[axis])
      {
        this->Left = 0;
      }
      else
      {
        tMax[axis] += this->TDelta[axis];
      }
      if (inside)
      {
        return true;
      }
    }
    return false;
  }

  // Next's cells appended to `batch` (its Index, Begin, End: a CellBatch)
  // until it holds `limit` (at most its capacity); how many were appended
  // (0: none is left).
  template <typename Batch>
  AVOS_NUMERICS_INLINE int Fill(Batch& batch, int limit)
  {
    // Next's steps without branches on the axis (the ray's axis order looks
    // random to a branch predictor): the state in locals (registers), the
    // axis as three flags, the cell written at every step and kept when it
    // has a part of the ray.
    int i0 = this->Index[0], i1 = this->Index[1], i2 = this->Index[2];
    Real m0 = this->TMax[0], m1 = this->TMax[1], m2 = this->TMax[2];
    const Real d0 = this->TDelta[0], d1 = this->TDelta[1], d2 = this->TDelta[2];
    const int s0 = this->Step[0], s1 = this->Step[1], s2 = this->Step[2];
    const unsigned n0 = static_cast<unsigned>(this->N[0]), n1 = static_cast<unsigned>(this->N[1]),
                   n2 = static_cast<unsigned>(this->N[2]);
    const Real tEnd = this->TEnd;
    Real t = this->T;
    int left = this->Left;
    int c = batch.Count;
    const int before = c;
    while (c < limit && left > 0 && t < tEnd)
    {
      --left;
      // Next's choice: the first axis whose boundary is nearest.
      const bool x = (m0 <= m1) & (m0 <= m2);
      const bool y = !x & (m1 <= m2);
      const bool z = !x & !y;
      const Real end = std::min(x ? m0 : (y ? m1 : m2), tEnd);
      batch.Index[0][c] = i0;
      batch.Index[1][c] = i1;
      batch.Index[2][c] = i2;
      batch.Begin[c] = t;
      batch.End[c] = end;
      c += end > t ? 1 : 0;
      t = std::max(t, end);
      i0 += x ? s0 : 0;
      i1 += y ? s1 : 0;
      i2 += z ? s2 : 0;
      m0 = x ? m0 + d0 : m0;
      m1 = y ? m1 + d1 : m1;
      m2 = z ? m2 + d2 : m2;
      // Only the stepped axis can leave the box (the others were inside).
      if ((static_cast<unsigned>(i0) >= n0) | (static_cast<unsigned>(i1) >= n1) |
        (static_cast<unsigned>(i2) >= n2))
      {
        left = 0;
      }
    }
    batch.Count = c;
    this->Index[0] = i0;
    this->Index[1] = i1;
    this->Index[2] = i2;
    this->TMax[0] = m0;
    this->TMax[1] = m1;
    this->TMax[2] = m2;
    this->T = t;
    this->Left = left;
    return c - before;
  }

private:
  int N[3] = { 0, 0, 0 }, Index[3] = { 0, 0, 0 }, Step[3] = { 0, 0, 0 };
  Real TMax[3] = { Real(0), Real(0), Real(0) }, TDelta[3] = { Real(0), Real(0), Real(0) };
  Real T = Real(0), TEnd = Real(0);
  int Left = 0; // steps left
};

// CellWalker's cells, visit(const int cell[3], t0, t1) for each; visit
// returns false to stop. Returns false when stopped.
template <typename Real, typename VolumeT, typename Visit>
bool CellWalk(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, Real tBegin, Real tEnd, Visit&& visit)
{
  const int dimensions[3] = { volume.GetDimension(0), volume.GetDimension(1),
    volume.GetDimension(2) };
  CellWalker<Real> walker(dimensions, origin, direction, tBegin, tEnd);
  int cell[3] = { 0, 0, 0 };
  Real t0 = Real(0), t1 = Real(0);
  while (walker.Next(cell, t0, t1))
  {
    if (!visit(static_cast<const int*>(cell), t0, t1))
    {
      return false;
    }
  }
  return true;
}

// A cell's trilinear interpolant in the form
// f = A + Bx + Cy + Dz + Exy + Fxz + Gyz + Hxyz (cell frame [0, 1]^3), from
// its corners c (x fastest).
template <typename Real>
struct TrilinearForm
{
  Real A, B, C, D, E, F, G, H;

  explicit TrilinearForm(const Real c[8])
    : A(c[0])
    , B(c[1] - c[0])
    , C(c[2] - c[0])
    , D(c[4] - c[0])
    , E(c[3] - c[2] - c[1] + c[0])
    , F(c[5] - c[4] - c[1] + c[0])
    , G(c[6] - c[4] - c[2] + c[0])
    , H(c[7] - c[6] - c[5] - c[3] + c[4] + c[2] + c[1] - c[0])
  {
  }

  // The gradient at p, and along the line p + u d its coefficients of u and
  // u^2 (each component is a quadratic in u).
  glm::vec<3, Real> Gradient(const glm::vec<3, Real>& p) const
  {
    return { this->B + this->E * p.y + this->F * p.z + this->H * p.y * p.z,
      this->C + this->E * p.x + this->G * p.z + this->H * p.x * p.z,
      this->D + this->F * p.x + this->G * p.y + this->H * p.x * p.y };
  }
  glm::vec<3, Real> GradientSlope(const glm::vec<3, Real>& p, const glm::vec<3, Real>& d) const
  {
    return { this->E * d.y + this->F * d.z + this->H * (p.y * d.z + p.z * d.y),
      this->E * d.x + this->G * d.z + this->H * (p.x * d.z + p.z * d.x),
      this->F * d.x + this->G * d.y + this->H * (p.x * d.y + p.y * d.x) };
  }
  glm::vec<3, Real> GradientCurvature(const glm::vec<3, Real>& d) const
  {
    return { this->H * d.y * d.z, this->H * d.x * d.z, this->H * d.x * d.y };
  }
};

// The trilinear interpolant of a cell's corners c (x fastest) along the ray
// from e (the entry point, in the cell's frame [0, 1]^3) in direction d: a
// cubic in the distance u from e (TrilinearForm).
template <typename Real>
Cubic<Real> CellCubic(const Real c[8], const glm::vec<3, Real>& e, const glm::vec<3, Real>& d)
{
  const TrilinearForm<Real> f(c);
  const Real A = f.A, B = f.B, C = f.C, D = f.D, E = f.E, F = f.F, G = f.G, H = f.H;
  const Real x = e.x, y = e.y, z = e.z;
  const glm::vec<3, Real> gradient = f.Gradient(e);
  Cubic<Real> s;
  s.K[0] = A + B * x + C * y + D * z + E * x * y + F * x * z + G * y * z + H * x * y * z;
  s.K[1] = d.x * gradient.x + d.y * gradient.y + d.z * gradient.z;
  s.K[2] = d.x * d.y * (E + H * z) + d.x * d.z * (F + H * y) + d.y * d.z * (G + H * x);
  s.K[3] = H * d.x * d.y * d.z;
  return s;
}

// Consecutive cells of one ray (CellWalk), in lanes: what PieceWalk needs of
// each before cutting it into pieces.
template <typename Real>
struct CellBatch
{
  // A multiple of the widest vector of Real of any target (8 doubles).
  static constexpr int Capacity = 8;
  int Count = 0;
  // In: the cell (i, j, k) and the part [Begin, End] of the ray inside it.
  alignas(64) std::int32_t Index[3][Capacity];
  alignas(64) Real Begin[Capacity];
  alignas(64) Real End[Capacity];
  // Out: whether the cell holds anything visible (ClassifyRange of its
  // corners' range; 0 where a corner is not finite), and where it does, the
  // piece of the corners' lowest value, whether a knot lies strictly inside
  // their range, and the cubic s(u), u = t - Begin (CellCubic).
  alignas(64) std::int32_t Visible[Capacity];
  alignas(64) std::int32_t First[Capacity];
  alignas(64) std::int32_t Crossings[Capacity];
  alignas(64) Real K[4][Capacity];

  // The cubic of the cell in lane i.
  Cubic<Real> CubicAt(int i) const
  {
    return { { this->K[0][i], this->K[1][i], this->K[2][i], this->K[3][i] } };
  }
};

// Knot crossings of one cell's cubic S, in lanes: Root[i] is
// detail::Crossing(S, Value[i], Lo[i], Hi[i]), the root of S - Value[i] on
// the monotone stretch [Lo[i], Hi[i]] that brackets it.
template <typename Real>
struct CrossingBatch
{
  static constexpr int Capacity = CellBatch<Real>::Capacity;
  int Count = 0;
  Cubic<Real> S;
  alignas(64) Real Value[Capacity];
  alignas(64) Real Lo[Capacity];
  alignas(64) Real Hi[Capacity];
  alignas(64) Real Root[Capacity];
};

// The cells' stage of PieceWalk and its knot crossings, a cell (a crossing)
// at a time: the reference the engine's kernels are tested against.
template <typename Real>
struct ScalarCellKernels
{
  void Crossings(CrossingBatch<Real>& b) const
  {
    for (int i = 0; i < b.Count; ++i)
    {
      b.Root[i] = detail::Crossing(b.S, b.Value[i], b.Lo[i], b.Hi[i]);
    }
  }

  template <typename VolumeT>
  void Cells(const VolumeT& volume, const PiecewiseTransferFunction<Real>& tf,
    const glm::vec<3, Real>& origin, const glm::vec<3, Real>& direction, CellBatch<Real>& b) const
  {
    for (int i = 0; i < b.Count; ++i)
    {
      const int index[3] = { b.Index[0][i], b.Index[1][i], b.Index[2][i] };
      Real c[8];
      volume.GetCorners(index[0], index[1], index[2], c);
      Real lo = c[0], hi = c[0];
      for (int k = 1; k < 8; ++k)
      {
        lo = std::min(lo, c[k]);
        hi = std::max(hi, c[k]);
      }
      // The sum is finite only when every corner is (a NaN escapes
      // min/max): the interpolant is undefined elsewhere, transparent as a
      // NaN sample is.
      b.Visible[i] = 0;
      if (!std::isfinite(c[0] + c[1] + c[2] + c[3] + c[4] + c[5] + c[6] + c[7]))
      {
        continue;
      }
      // Inside the cell the scalar stays in [lo, hi]. With no knot strictly
      // inside, the whole cell lies in one transfer-function piece (a corner
      // value on a knot is met at isolated points only): no crossing to
      // find, and nothing to do at all when that piece is transparent.
      const auto range = tf.ClassifyRange(lo, hi);
      if (!range.Visible)
      {
        continue;
      }
      b.Visible[i] = 1;
      b.First[i] = static_cast<std::int32_t>(range.First);
      b.Crossings[i] = range.Crossings ? 1 : 0;
      const Cubic<Real> s = CellCubic(c,
        origin + b.Begin[i] * direction -
          glm::vec<3, Real>(Real(index[0]), Real(index[1]), Real(index[2])),
        direction);
      for (int k = 0; k < 4; ++k)
      {
        b.K[k][i] = s.K[k];
      }
    }
  }
};

// Walks the ray origin + t direction over [tBegin, tEnd] (CellWalk) and calls
// visit(const RayPiece&) for every smooth piece whose transfer-function piece
// is visible, front to back; visit returns false to stop the walk. Cells
// whose corners the transfer function maps to tau = 0 are passed over
// without cutting them (the lanes of `kernels` may have built their cubic),
// and so are cells with a non-finite corner. The cells go through
// kernels.Cells (ScalarCellKernels, or a vectorised one of the engine) in
// batches of at most *cellLimit (when given; CellBatch::Capacity otherwise):
// a stopped walk has done that stage for at most that many cells too many.
// A cell's knot crossings, two or more, go through kernels.Crossings.
// `cells` counts the visible cells. Returns false when stopped.
template <typename Real, typename VolumeT, typename Visit,
  typename Kernels = ScalarCellKernels<Real>>
bool PieceWalk(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, Real tBegin, Real tEnd,
  const PiecewiseTransferFunction<Real>& tf, long& cells, Visit&& visit,
  const Kernels& kernels = Kernels(), const int* cellLimit = nullptr)
{
  const std::vector<Real>& knots = tf.GetKnots();
  // The cell of lane i, once kernels.Cells found it visible.
  auto cut = [&](const CellBatch<Real>& batch, int lane) -> bool
  {
    const std::size_t first = static_cast<std::size_t>(batch.First[lane]);
    const bool crossings = batch.Crossings[lane] != 0;
    ++cells;
    // The cubic in u = t - t (cell entry).
    const Real t = batch.Begin[lane];
    const Cubic<Real> s = batch.CubicAt(lane);
    const Real length = batch.End[lane] - t;
    // The piece [u, next] of the cell, q = s shifted to u.
    auto emit = [&](Real u, Real next, const Cubic<Real>& q, std::size_t piece, bool monotone)
    {
      RayPiece<Real> rp;
      rp.Begin = t + u;
      rp.Length = next - u;
      rp.Q = q;
      rp.Q.K[0] -= tf[piece].Start;
      rp.TF = piece;
      rp.Monotone = monotone;
      return visit(rp);
    };
    if (!crossings)
    {
      // One piece for the cell; whether s is monotone on it only matters
      // to the integrator's cheapest bound, which tests it (not split).
      return emit(Real(0), length, s, first, false);
    }
    // Monotone stretches: split at the extrema inside the cell.
    Real bounds[4];
    const int count = detail::StretchBounds(s, length, bounds);
    detail::Stretch<Real> stretches[3];
    for (int b = 0; b + 1 < count; ++b)
    {
      stretches[b] = detail::Stretch<Real>(s, bounds[b], bounds[b + 1], tf);
    }
    // The crossings sought, each bracketed by its whole stretch (so that
    // they are independent), through kernels.Crossings a batch at a time:
    // the first MaximumSolved of the cell; any beyond are found below.
    constexpr int MaximumSolved = 4 * CrossingBatch<Real>::Capacity;
    Real solved[MaximumSolved];
    int solvedCount = 0;
    CrossingBatch<Real> crossing;
    crossing.S = s;
    auto solve = [&]()
    {
      if (crossing.Count == 1)
      {
        // One crossing: no lanes to fill (the same root, to the bit).
        crossing.Root[0] = detail::Crossing(s, crossing.Value[0], crossing.Lo[0], crossing.Hi[0]);
      }
      else
      {
        kernels.Crossings(crossing);
      }
      std::copy(crossing.Root, crossing.Root + crossing.Count, solved + solvedCount);
      solvedCount += crossing.Count;
      crossing.Count = 0;
    };
    for (int b = 0; b + 1 < count && solvedCount < MaximumSolved; ++b)
    {
      const detail::Stretch<Real>& st = stretches[b];
      for (std::size_t j = st.Useful(tf, 0); j < st.Inside && solvedCount < MaximumSolved;
           j = st.Useful(tf, j + 1))
      {
        const int at = crossing.Count++;
        crossing.Value[at] = st.Value(knots, j);
        crossing.Lo[at] = st.A;
        crossing.Hi[at] = st.B;
        if (crossing.Count == CrossingBatch<Real>::Capacity)
        {
          solve();
        }
      }
    }
    if (crossing.Count > 0)
    {
      solve();
    }
    int taken = 0;
    for (int b = 0; b + 1 < count; ++b)
    {
      const detail::Stretch<Real>& st = stretches[b];
      Real u = st.A; // the start of sub-piece j, or a point before it when skipped
      for (std::size_t j = st.Useful(tf, 0); j <= st.Inside; j = st.Useful(tf, j + 1))
      {
        Real root = st.B, next;
        if (j < st.Inside)
        {
          root = taken < solvedCount ? solved[taken]
                                     : detail::Crossing(s, st.Value(knots, j), st.A, st.B);
          ++taken;
        }
        std::size_t piece;
        if (st.SubPiece(tf, s, j, u, root, next, piece) &&
          !emit(u, next, s.Shifted(u), piece, true))
        {
          return false;
        }
        u = std::max(u, next);
      }
    }
    return true;
  };
  CellBatch<Real> batch;
  // Cuts the batch's visible cells in order; false once visit stops.
  auto flush = [&]() -> bool
  {
    kernels.Cells(volume, tf, origin, direction, batch);
    const int count = batch.Count;
    batch.Count = 0;
    for (int i = 0; i < count; ++i)
    {
      if (batch.Visible[i] != 0 && !cut(batch, i))
      {
        return false;
      }
    }
    return true;
  };
  const int dimensions[3] = { volume.GetDimension(0), volume.GetDimension(1),
    volume.GetDimension(2) };
  CellWalker<Real> walker(dimensions, origin, direction, tBegin, tEnd);
  for (;;)
  {
    // The limit may change while a batch is integrated (flush).
    const int limit = cellLimit ? std::min(std::max(*cellLimit, 1), CellBatch<Real>::Capacity)
                                : CellBatch<Real>::Capacity;
    walker.Fill(batch, limit);
    if (batch.Count == 0)
    {
      return true;
    }
    if (!flush())
    {
      return false;
    }
  }
}

} // namespace numerics
} // namespace avos

#endif
