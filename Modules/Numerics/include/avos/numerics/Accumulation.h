// The additive and average intensity projections along a ray, with the
// meaning VTK's GPU ray caster gives them, integrated instead of sampled.
//
// VTK sums, over the samples of a ray, alpha'(s) * n(s): alpha' the
// transfer function's opacity corrected for the sample distance h (the
// opacity of a slab of thickness h, 1 - exp(-tau h)), n the scalar normalised
// to the data's range, n = (s - smin) / (smax - smin).
// - Additive: the sum, clamped to [0, 1]. As h -> 0 it tends to
//     A = int tau(s(t)) n(s(t)) dt,
//   independent of h (alpha' = tau h + O(h^2)). AdditiveAlongRay computes A
//   exactly on every piece of the ray where s is a cubic and tau a cubic in
//   s (Pieces.h): the integrand is a polynomial of degree at most 12 in t,
//   which seven-point Gauss-Legendre integrates exactly (up to degree 13).
//   In the extinction model tau is exact; in VTK's alpha model the pieces'
//   tau is within a relative error r of the true one (Pieces.h), so A is
//   within r A.
// - Average: the mean of alpha'(s) n(s) over the samples whose scalar lies
//   in a range [r0, r1], i.e. over the part of the ray where s is in the
//   range: the length-weighted mean
//     M = int_{s in [r0, r1]} alpha_h(s(t)) n(s(t)) dt / |{t : s(t) in [r0, r1]}|,
//   alpha_h = 1 - exp(-tau h) at the mapper's sample distance h (VTK's mean
//   of samples tends to M as they get denser at that h). The ray is cut where
//   s crosses r0, r1 and the transfer function's knots, so the integrand is
//   smooth on each piece; it is integrated by Gauss-Legendre of 4 and 8 nodes,
//   halving a piece while the two differ by more than the piece's share of
//   the tolerance (at most 20 halvings: a piece of the ray below 2^-20 of a
//   cell takes the 8-node value). The ray's length in the range is exact.
#ifndef avos_numerics_Accumulation_h
#define avos_numerics_Accumulation_h

#include "avos/numerics/Pieces.h"
#include "avos/numerics/RayIntegrators.h"

#include <glm/glm.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace avos
{
namespace numerics
{

template <typename Real>
struct Accumulation
{
  Real Value = Real(0);  // A, or M (0 when the ray never meets the range)
  Real Length = Real(0); // the ray's length in the range (average), or 0
  long Cells = 0;        // cells whose cubic was built
  std::string Error;
};

namespace detail
{
// Gauss-Legendre nodes and weights on [-1, 1].
template <typename Real>
struct GaussLegendre
{
  static constexpr Real N4[4] = { Real(-0.8611363115940526), Real(-0.3399810435848563),
    Real(0.3399810435848563), Real(0.8611363115940526) };
  static constexpr Real W4[4] = { Real(0.3478548451374538), Real(0.6521451548625461),
    Real(0.6521451548625461), Real(0.3478548451374538) };
  static constexpr Real N7[7] = { Real(-0.9491079123427585), Real(-0.7415311855993945),
    Real(-0.4058451513773972), Real(0.0), Real(0.4058451513773972), Real(0.7415311855993945),
    Real(0.9491079123427585) };
  static constexpr Real W7[7] = { Real(0.1294849661688697), Real(0.2797053914892766),
    Real(0.3818300505051189), Real(0.4179591836734694), Real(0.3818300505051189),
    Real(0.2797053914892766), Real(0.1294849661688697) };
  static constexpr Real N8[8] = { Real(-0.9602898564975363), Real(-0.7966664774136267),
    Real(-0.5255324099163290), Real(-0.1834346424956498), Real(0.1834346424956498),
    Real(0.5255324099163290), Real(0.7966664774136267), Real(0.9602898564975363) };
  static constexpr Real W8[8] = { Real(0.1012285362903763), Real(0.2223810344533745),
    Real(0.3137066458778873), Real(0.3626837833783620), Real(0.3626837833783620),
    Real(0.3137066458778873), Real(0.2223810344533745), Real(0.1012285362903763) };
};

template <typename Real, int N, typename F>
Real Quadrature(const Real (&nodes)[N], const Real (&weights)[N], Real a, Real b, F&& f)
{
  const Real half = Real(0.5) * (b - a), mid = Real(0.5) * (a + b);
  Real sum = Real(0);
  for (int i = 0; i < N; ++i)
  {
    sum += weights[i] * f(mid + half * nodes[i]);
  }
  return half * sum;
}

// int_a^b f within `budget` (Gauss-Legendre 4 against 8, halving).
template <typename Real, typename F>
Real AdaptiveGauss(Real a, Real b, Real budget, int depth, F&& f)
{
  using G = GaussLegendre<Real>;
  const Real coarse = Quadrature(G::N4, G::W4, a, b, f);
  const Real fine = Quadrature(G::N8, G::W8, a, b, f);
  if (std::abs(fine - coarse) <= budget || depth >= 20)
  {
    return fine;
  }
  const Real m = Real(0.5) * (a + b);
  return AdaptiveGauss(a, m, Real(0.5) * budget, depth + 1, f) +
    AdaptiveGauss(m, b, Real(0.5) * budget, depth + 1, f);
}

template <typename Real>
std::string ValidateAccumulation(
  Real D, const Interval<Real>* segments, std::size_t count, Real smin, Real smax)
{
  if (!(D >= Real(0)) || !std::isfinite(D))
  {
    return "the ray length must be finite and >= 0";
  }
  if (!(smax > smin) || !std::isfinite(smax - smin))
  {
    return "the scalar range must be finite with its maximum above its minimum";
  }
  return ValidateSegments(segments, count);
}
} // namespace detail

// A = int tau n dt over the segments of the ray origin + t direction (grid
// coordinates, t in voxel units), `tf` built from the transfer function
// (PiecewiseTransferFunction::Build), n normalised to [smin, smax].
template <typename Real, typename VolumeT>
Accumulation<Real> AdditiveAlongRay(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  const PiecewiseTransferFunction<Real>& tf, Real smin, Real smax)
{
  Accumulation<Real> result;
  result.Error = detail::ValidateAccumulation(
    count ? segments[count - 1].End : Real(0), segments, count, smin, smax);
  if (!result.Error.empty())
  {
    return result;
  }
  using G = detail::GaussLegendre<Real>;
  const Real scale = Real(1) / (smax - smin);
  for (std::size_t j = 0; j < count; ++j)
  {
    PieceWalk(volume, origin, direction, segments[j].Begin, segments[j].End, tf, result.Cells,
      [&](const RayPiece<Real>& p)
      {
        const auto& piece = tf[p.TF];
        result.Value += detail::Quadrature(G::N7, G::W7, Real(0), p.Length,
          [&](Real v)
          {
            const Real d = p.Q(v);
            const Real tau =
              piece.Tau + d * (piece.TauSlope + d * (piece.TauCurvature + d * piece.TauCubic));
            return tau * (piece.Start + d - smin) * scale;
          });
        return true;
      });
  }
  if (!std::isfinite(result.Value))
  {
    result = Accumulation<Real>();
    result.Error = "the additive projection overflowed";
  }
  return result;
}

// The range [r0, r1] of an average projection, prepared for AverageAlongRay:
// pieces that mark it (a transfer function with opacity 1 on the range, 0
// outside, and knots at r0, r1 and at every knot of `tf`, so that the walk's
// pieces are the parts of a ray in the range, cut at tf's knots), and which of
// those pieces tf leaves transparent (their integrand is 0: only their length
// counts).
template <typename Real>
class AverageRange
{
public:
  // Empty on success, else why. A range of zero width holds no ray.
  std::string Build(const TransferFunction<Real>& tf, Real r0, Real r1)
  {
    this->Empty = true;
    if (!(r0 <= r1) || !std::isfinite(r0) || !std::isfinite(r1))
    {
      return "the average's scalar range must be finite with its minimum at most its maximum";
    }
    if (r0 == r1)
    {
      return std::string();
    }
    TransferFunction<Real> marks;
    marks.AddColorKnot(r0, Real(0), Real(0), Real(0));
    marks.AddOpacityKnot(r0, Real(0));
    marks.AddOpacityKnot(r0, Real(1));
    for (Real k : tf.GetKnotValues())
    {
      if (k > r0 && k < r1)
      {
        marks.AddOpacityKnot(k, Real(1));
      }
    }
    marks.AddOpacityKnot(r1, Real(1));
    marks.AddOpacityKnot(r1, Real(0));
    marks.Finalize();
    // The marks are exact (extinction model): the relative error is unused.
    std::string error = this->Pieces.Build(marks, Real(1e-3));
    if (!error.empty())
    {
      return error;
    }
    const std::size_t n = this->Pieces.GetNumberOfPieces();
    this->Transparent.assign(n, false);
    for (std::size_t i = 0; i < n; ++i)
    {
      const Real lo = this->Pieces[i].Start;
      const Real hi = i + 1 < n ? this->Pieces[i + 1].Start : r1;
      this->Transparent[i] = tf.GetMaximumExtinction(lo, hi) == Real(0);
    }
    this->Empty = false;
    return std::string();
  }

  bool IsEmpty() const { return this->Empty; }
  const PiecewiseTransferFunction<Real>& GetPieces() const { return this->Pieces; }
  bool IsTransparent(std::size_t piece) const { return this->Transparent[piece]; }

private:
  PiecewiseTransferFunction<Real> Pieces;
  std::vector<bool> Transparent;
  bool Empty = true;
};

// M over the segments (`range` built from `tf`), alpha_h from `tf` at the
// sample distance h (voxel units), within `tolerance` (absolute, on M).
template <typename Real, typename VolumeT>
Accumulation<Real> AverageAlongRay(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  const AverageRange<Real>& range, const TransferFunction<Real>& tf, Real h, Real smin, Real smax,
  Real tolerance)
{
  Accumulation<Real> result;
  result.Error = detail::ValidateAccumulation(
    count ? segments[count - 1].End : Real(0), segments, count, smin, smax);
  if (result.Error.empty() && (!(h > Real(0)) || !std::isfinite(h)))
  {
    result.Error = "the sample distance must be positive and finite";
  }
  if (result.Error.empty() && (!(tolerance > Real(0)) || !std::isfinite(tolerance)))
  {
    result.Error = "the tolerance must be positive and finite";
  }
  if (!result.Error.empty() || range.IsEmpty())
  {
    return result;
  }
  const PiecewiseTransferFunction<Real>& pieces = range.GetPieces();
  const Real scale = Real(1) / (smax - smin);
  // The budget per unit length: the pieces' errors add up to at most
  // tolerance times the length in the range, so M is within tolerance.
  Real integral = Real(0);
  for (std::size_t j = 0; j < count; ++j)
  {
    PieceWalk(volume, origin, direction, segments[j].Begin, segments[j].End, pieces, result.Cells,
      [&](const RayPiece<Real>& p)
      {
        result.Length += p.Length;
        if (range.IsTransparent(p.TF))
        {
          return true;
        }
        const Real start = pieces[p.TF].Start;
        integral += detail::AdaptiveGauss(Real(0), p.Length, tolerance * p.Length, 0,
          [&](Real v)
          {
            const Real s = start + p.Q(v);
            Real tau;
            glm::vec<3, Real> color;
            tf.Classify(s, tau, color);
            return -std::expm1(-tau * h) * (s - smin) * scale;
          });
        return true;
      });
  }
  result.Value = result.Length > Real(0) ? integral / result.Length : Real(0);
  if (!std::isfinite(result.Value))
  {
    result = Accumulation<Real>();
    result.Error = "the average projection overflowed";
  }
  return result;
}

} // namespace numerics
} // namespace avos

#endif
