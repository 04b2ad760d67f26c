// Piecewise-linear 1D transfer function: colour C(s) and extinction tau(s).
//
// The volume rendering integral (Max 1995, emission-absorption model) needs
// the extinction coefficient tau per unit length. Two ways to give it:
// - Extinction model (the adaptive-integration paper's): the opacity knots
//   ARE tau per voxel unit, interpolated linearly in s.
// - Alpha model (VTK's): the opacity knots are an alpha accumulated over
//   UnitDistance, interpolated linearly in s, and
//   tau(s) = -ln(1 - alpha(s)) / UnitDistance.
//   alpha >= 1 (fully opaque) gives OpaqueExtinction / UnitDistance, a finite
//   tau whose transmittance over one unit distance is below 1e-17, so no
//   inf or NaN ever enters the integrators.
//
// Knots must be sorted by scalar value. Equal consecutive values make a jump
// (the function is right-continuous there): discontinuous transfer functions
// are representable. Outside the knots the end values are held (clamping).
// A NaN scalar is defined to be fully transparent and black.
#ifndef avos_numerics_TransferFunction_h
#define avos_numerics_TransferFunction_h

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace avos
{
namespace numerics
{

enum class OpacityModel
{
  Extinction,
  Alpha
};

// The number of sorted knots at or below s (what std::upper_bound finds, 0
// for a NaN) in constant time and with few mispredicted branches (samples
// come in no order). Up to 16 knots it counts them without a branch; above,
// a uniform grid of about four buckets per knot gives a first guess,
// corrected by a few comparisons so the answer is exact whatever the
// rounding of the bucket.
template <typename Real>
class KnotLocator
{
public:
  // `knots` sorted, finite, at least one.
  void Build(std::vector<Real> knots)
  {
    this->Knots = std::move(knots);
    this->Buckets.clear();
    const std::size_t n = this->Knots.size();
    if (n <= 16)
    {
      return;
    }
    const Real span = this->Knots.back() - this->Knots.front();
    const std::size_t count = std::min<std::size_t>(4 * n, std::size_t(1) << 16);
    this->BucketScale = span > Real(0) ? Real(count) / span : Real(0);
    for (std::size_t b = 0; b < count; ++b)
    {
      const Real edge = this->Knots.front() + span * Real(b) / Real(count);
      this->Buckets.push_back(static_cast<std::size_t>(
        std::upper_bound(this->Knots.begin(), this->Knots.end(), edge) - this->Knots.begin()));
    }
  }

  std::size_t UpperBound(Real s) const
  {
    const std::size_t n = this->Knots.size();
    if (n <= 16)
    {
      std::size_t count = 0;
      for (std::size_t k = 0; k < n; ++k)
      {
        count += this->Knots[k] <= s ? 1 : 0;
      }
      return count;
    }
    if (!(s >= this->Knots.front()))
    {
      return 0;
    }
    if (s >= this->Knots.back())
    {
      return n;
    }
    // A knot span that overflows makes x NaN or infinite (found by fuzzing):
    // any first guess is corrected below.
    const Real x = (s - this->Knots.front()) * this->BucketScale;
    const std::size_t last = this->Buckets.size() - 1;
    std::size_t i =
      this->Buckets[x < Real(last) ? (x >= Real(0) ? static_cast<std::size_t>(x) : 0) : last];
    while (i < n && this->Knots[i] <= s)
    {
      ++i;
    }
    while (i > 0 && this->Knots[i - 1] > s)
    {
      --i;
    }
    return i;
  }

  const std::vector<Real>& GetKnots() const { return this->Knots; }
  void Clear()
  {
    this->Knots.clear();
    this->Buckets.clear();
  }

private:
  std::vector<Real> Knots;
  std::vector<std::size_t> Buckets; // knots at or below each bucket's lower edge
  Real BucketScale = Real(0);       // buckets per unit scalar
};

template <typename Real>
class TransferFunction
{
public:
  using Color = glm::vec<3, Real>;

  // -ln(1e-17) ~ 39.1: transmittance of an "opaque" unit distance.
  static constexpr Real OpaqueExtinction = Real(40);

  void AddColorKnot(Real s, Real r, Real g, Real b)
  {
    this->ColorValues.push_back(s);
    this->Colors.push_back(Color(r, g, b));
    this->Pieces.clear();
  }
  void AddOpacityKnot(Real s, Real value)
  {
    this->OpacityValues.push_back(s);
    this->Opacities.push_back(value);
    this->Pieces.clear();
  }

  void SetOpacityModel(OpacityModel model, Real unitDistance = Real(1))
  {
    this->Model = model;
    this->UnitDistance = unitDistance;
  }

  // Builds the lookup that lets Classify() find tau and C with one search;
  // call it after the last knot (adding a knot drops it). Without it, or
  // when the knots are not valid, Classify() takes two searches.
  void Finalize() { this->BuildPieces(); }

  // tau(s) and C(s) together: what the integrators call per sample.
  void Classify(Real s, Real& tau, Color& color) const
  {
    if (std::isnan(s) || this->Pieces.empty())
    {
      tau = this->GetExtinction(s);
      color = this->GetColor(s);
      return;
    }
    const std::size_t i = this->Locate(s);
    if (i == NoPiece)
    {
      // Below the first knot: the first values (before a jump there).
      tau = this->ToExtinction(this->Opacities.front());
      color = this->Colors.front();
      return;
    }
    const Piece& p = this->Pieces[i];
    // Clamped to the piece: holds the end values above the last knot, for an
    // infinite scalar too.
    const Real d = std::min(std::max(s - p.Start, Real(0)), p.Length);
    tau = this->ToExtinction(p.Opacity + p.OpacitySlope * d);
    color = p.Colour + p.ColourSlope * d;
  }
  OpacityModel GetOpacityModel() const { return this->Model; }
  Real GetUnitDistance() const { return this->UnitDistance; }

  // Between consecutive knots of either function, both are linear: one piece
  // per such interval, starting at its left knot with the right-continuous
  // values there. The last piece (slopes 0) holds the end values. Opacity is
  // the knot's own quantity (tau in the extinction model, alpha in VTK's).
  struct Piece
  {
    Real Start;
    Real Length; // 0 for the last piece
    Real Opacity;
    Real OpacitySlope;
    Color Colour;
    Color ColourSlope;
  };

  // The pieces Finalize() built (empty before it, or for invalid knots), and
  // the values held below the first knot.
  const std::vector<Piece>& GetPieces() const { return this->Pieces; }
  // JumpsBefore()[k]: the jumps among the first k piece starts (k up to the
  // piece count); what HasJumpIn counts. Empty when GetPieces() is.
  const std::vector<std::size_t>& GetJumpsBefore() const { return this->JumpsBefore; }
  Real GetOpacityBelow() const { return this->Opacities.front(); }
  Color GetColorBelow() const { return this->Colors.front(); }

  // Empty string when usable; otherwise what is wrong.
  std::string Validate() const
  {
    if (this->ColorValues.empty() || this->OpacityValues.empty())
    {
      return "the transfer function has no colour or no opacity knots";
    }
    auto sortedFinite = [](const std::vector<Real>& v)
    {
      for (std::size_t i = 0; i < v.size(); ++i)
      {
        if (!std::isfinite(v[i]) || (i > 0 && v[i] < v[i - 1]))
        {
          return false;
        }
      }
      return true;
    };
    if (!sortedFinite(this->ColorValues) || !sortedFinite(this->OpacityValues))
    {
      return "transfer function knot values must be finite and sorted";
    }
    for (const Color& c : this->Colors)
    {
      for (int i = 0; i < 3; ++i)
      {
        if (!(c[i] >= Real(0) && c[i] <= Real(1)))
        {
          return "transfer function colours must be in [0, 1]";
        }
      }
    }
    for (Real a : this->Opacities)
    {
      if (!(a >= Real(0)) || !std::isfinite(a))
      {
        return "transfer function opacities must be finite and non-negative";
      }
    }
    if (this->Model == OpacityModel::Alpha && !(this->UnitDistance > Real(0)))
    {
      return "the opacity unit distance must be positive";
    }
    return std::string();
  }

  Color GetColor(Real s) const
  {
    if (std::isnan(s))
    {
      return Color(Real(0));
    }
    return Interpolate(this->ColorValues, this->Colors, s);
  }

  // The opacity function's own value at s (tau in the extinction model,
  // alpha in VTK's): what the intensity projections show.
  Real GetOpacityValue(Real s) const
  {
    if (std::isnan(s))
    {
      return Real(0);
    }
    return Interpolate(this->OpacityValues, this->Opacities, s);
  }

  Real GetExtinction(Real s) const
  {
    if (std::isnan(s))
    {
      return Real(0);
    }
    return this->ToExtinction(Interpolate(this->OpacityValues, this->Opacities, s));
  }

  Real ToExtinction(Real value) const
  {
    if (this->Model == OpacityModel::Extinction)
    {
      return value;
    }
    if (value >= Real(1))
    {
      return OpaqueExtinction / this->UnitDistance;
    }
    // log(1 - a), not log1p(-a): 1 - a rounds by at most half an ulp of 1,
    // so tau is off by 1.1e-16 / UnitDistance at most, and std::log costs a
    // third less per sample than std::log1p here.
    return std::min(-std::log(Real(1) - value), OpaqueExtinction) / this->UnitDistance;
  }

  // An upper bound of ToExtinction's slope below `value` (it is convex):
  // infinite at an opacity of 1 in the alpha model.
  Real ExtinctionSlope(Real value) const
  {
    if (this->Model == OpacityModel::Extinction)
    {
      return Real(1);
    }
    return value < Real(1) ? Real(1) / ((Real(1) - value) * this->UnitDistance)
                           : std::numeric_limits<Real>::infinity();
  }

  // True when the opacity is 0 everywhere (every opacity knot is).
  bool IsTransparent() const
  {
    return std::all_of(
      this->Opacities.begin(), this->Opacities.end(), [](Real a) { return a == Real(0); });
  }

  // Multiplies the extinction by `weight` > 0 everywhere: the extinction
  // model's knots, or the alpha model's unit distance divided by it (tau =
  // -ln(1 - alpha) / UnitDistance). Finalize again before use.
  void ScaleExtinction(Real weight)
  {
    if (this->Model == OpacityModel::Extinction)
    {
      for (Real& tau : this->Opacities)
      {
        tau *= weight;
      }
    }
    else
    {
      this->UnitDistance /= weight;
    }
    this->Pieces.clear();
  }

  // Largest colour component: bounds what the rest of a ray can add.
  Real GetMaximumColor() const
  {
    Real m = Real(0);
    for (const Color& c : this->Colors)
    {
      m = std::max({ m, c[0], c[1], c[2] });
    }
    return m;
  }

  // The largest tau(s) for s in [lo, hi]: tau is piecewise linear in the
  // opacity knots, and the Alpha model's map is monotone, so the maximum is at
  // an end or at a knot inside. Zero means [lo, hi] is fully transparent:
  // empty-space skipping relies on it.
  Real GetMaximumExtinction(Real lo, Real hi) const
  {
    Real m = std::max(this->GetExtinction(lo), this->GetExtinction(hi));
    auto i = std::lower_bound(this->OpacityValues.begin(), this->OpacityValues.end(), lo);
    for (; i != this->OpacityValues.end() && *i <= hi; ++i)
    {
      const std::size_t k = static_cast<std::size_t>(i - this->OpacityValues.begin());
      m = std::max(m, this->ToExtinction(this->Opacities[k]));
    }
    return m;
  }

  // True when C or tau jumps at a scalar value in (lo, hi): there Simpson's
  // error estimate is unreliable (it assumes a smooth integrand).
  bool HasJumpIn(Real lo, Real hi) const
  {
    if (this->Pieces.empty() || std::isnan(lo) || std::isnan(hi))
    {
      return HasEqualPairIn(this->ColorValues, lo, hi) ||
        HasEqualPairIn(this->OpacityValues, lo, hi);
    }
    // Jumps at the knots with indices in [first above lo, first at or above hi).
    const std::size_t first = this->Locate(lo) + 1; // NoPiece + 1 == 0
    std::size_t end = this->Locate(hi) + 1;
    if (end > 0 && this->Starts.GetKnots()[end - 1] == hi)
    {
      --end;
    }
    return end > first && this->JumpsBefore[end] > this->JumpsBefore[first];
  }

  // True when C or tau has a kink (or a jump) at a scalar value in (lo, hi).
  bool HasKnotIn(Real lo, Real hi) const
  {
    if (this->Pieces.empty() || std::isnan(lo) || std::isnan(hi))
    {
      return HasValueIn(this->ColorValues, lo, hi) || HasValueIn(this->OpacityValues, lo, hi);
    }
    const std::size_t next = this->Locate(lo) + 1; // the first knot above lo
    const std::vector<Real>& starts = this->Starts.GetKnots();
    return next < starts.size() && starts[next] < hi;
  }

  // The same knots and model in another precision, finalized if this one is:
  // what a single-precision integrator (the GLSL version) classifies with.
  template <typename Other>
  TransferFunction<Other> Cast() const
  {
    TransferFunction<Other> out;
    for (std::size_t i = 0; i < this->ColorValues.size(); ++i)
    {
      const Color& c = this->Colors[i];
      out.AddColorKnot(Other(this->ColorValues[i]), Other(c.r), Other(c.g), Other(c.b));
    }
    for (std::size_t i = 0; i < this->OpacityValues.size(); ++i)
    {
      out.AddOpacityKnot(Other(this->OpacityValues[i]), Other(this->Opacities[i]));
    }
    out.SetOpacityModel(this->Model, Other(this->UnitDistance));
    if (!this->Pieces.empty())
    {
      out.Finalize();
    }
    return out;
  }

  // Sorted scalar values where C or tau has a kink or a jump.
  std::vector<Real> GetKnotValues() const
  {
    std::vector<Real> all(this->ColorValues);
    all.insert(all.end(), this->OpacityValues.begin(), this->OpacityValues.end());
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    return all;
  }

private:
  static constexpr std::size_t NoPiece = static_cast<std::size_t>(-1);

  // The index of the last knot (piece start) at or below s, NoPiece below the
  // first one or for a NaN.
  std::size_t Locate(Real s) const
  {
    return this->Starts.UpperBound(s) - 1; // NoPiece when 0
  }

  void BuildPieces()
  {
    this->Pieces.clear();
    this->Starts.Clear();
    this->JumpsBefore.clear();
    auto usable = [](const std::vector<Real>& v)
    {
      for (std::size_t i = 0; i < v.size(); ++i)
      {
        if (!std::isfinite(v[i]) || (i > 0 && v[i] < v[i - 1]))
        {
          return false;
        }
      }
      return !v.empty();
    };
    if (!usable(this->ColorValues) || !usable(this->OpacityValues))
    {
      return; // Validate() reports it; Classify() falls back meanwhile
    }
    std::vector<Real> starts = this->GetKnotValues();
    for (std::size_t i = 0; i < starts.size(); ++i)
    {
      Piece p;
      p.Start = starts[i];
      p.Opacity = Interpolate(this->OpacityValues, this->Opacities, p.Start);
      p.Colour = Interpolate(this->ColorValues, this->Colors, p.Start);
      p.Length = Real(0);
      p.OpacitySlope = Real(0);
      p.ColourSlope = Color(Real(0));
      if (i + 1 < starts.size())
      {
        // Both functions are linear on the piece: the slopes of the knot
        // segments that hold it (not a difference quotient over the piece,
        // which loses all precision on pieces a few ulp long).
        p.Length = starts[i + 1] - starts[i];
        p.OpacitySlope = Slope(this->OpacityValues, this->Opacities, p.Start);
        p.ColourSlope = Slope(this->ColorValues, this->Colors, p.Start);
      }
      this->Pieces.push_back(p);
    }
    // A jump is a knot value given twice in either function.
    this->JumpsBefore.assign(1, 0);
    for (Real v : starts)
    {
      const bool jump = std::count(this->ColorValues.begin(), this->ColorValues.end(), v) > 1 ||
        std::count(this->OpacityValues.begin(), this->OpacityValues.end(), v) > 1;
      this->JumpsBefore.push_back(this->JumpsBefore.back() + (jump ? 1 : 0));
    }
    this->Starts.Build(std::move(starts));
  }

  static bool HasValueIn(const std::vector<Real>& values, Real lo, Real hi)
  {
    auto i = std::upper_bound(values.begin(), values.end(), lo);
    return i != values.end() && *i < hi;
  }

  static bool HasEqualPairIn(const std::vector<Real>& values, Real lo, Real hi)
  {
    auto i = std::upper_bound(values.begin(), values.end(), lo);
    for (; i != values.end() && *i < hi; ++i)
    {
      if (i + 1 != values.end() && *(i + 1) == *i)
      {
        return true;
      }
    }
    return false;
  }

  // The slope of the segment between the knots around s, right-continuous
  // like Interpolate; 0 outside the knots.
  template <typename T>
  static T Slope(const std::vector<Real>& values, const std::vector<T>& data, Real s)
  {
    const auto upper = std::upper_bound(values.begin(), values.end(), s);
    if (upper == values.begin() || upper == values.end())
    {
      return T(Real(0));
    }
    const std::size_t i = static_cast<std::size_t>(upper - values.begin());
    return (data[i] - data[i - 1]) / (values[i] - values[i - 1]);
  }

  template <typename T>
  static T Interpolate(const std::vector<Real>& values, const std::vector<T>& data, Real s)
  {
    if (s < values.front())
    {
      return data.front();
    }
    // First knot strictly above s: right-continuous at jumps.
    const auto upper = std::upper_bound(values.begin(), values.end(), s);
    if (upper == values.end())
    {
      return data.back();
    }
    const std::size_t i = static_cast<std::size_t>(upper - values.begin());
    const Real w = (s - values[i - 1]) / (values[i] - values[i - 1]);
    return data[i - 1] + (data[i] - data[i - 1]) * w;
  }

  std::vector<Real> ColorValues;
  std::vector<Color> Colors;
  std::vector<Real> OpacityValues;
  std::vector<Real> Opacities;
  OpacityModel Model = OpacityModel::Extinction;
  Real UnitDistance = Real(1);
  std::vector<Piece> Pieces;
  KnotLocator<Real> Starts; // the pieces' starts
  // JumpsBefore[k]: jumps among the first k knots.
  std::vector<std::size_t> JumpsBefore;
};

} // namespace numerics
} // namespace avos

#endif
