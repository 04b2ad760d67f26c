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
// q a cubic, tau(v) = a + b q(v) + c q(v)^2 (c = 0 but in VTK's alpha model,
// Pieces.h) and C(v) = c0 + c1 q(v).
// - Inner integral (optical depth), exact: the integral of a polynomial,
//     theta(v) = a v + b int_0^v q + c int_0^v q^2.
// - Outer integral, by parts (d/dv e^{-theta} = -tau e^{-theta}):
//     int C tau T = C(0) T(0) - C(l) T(l) + c1 T(0) J,
//     J = int_0^l q'(v) e^{-theta(v)} dv,
//   one scalar integral for all three channels, zero when the colour is
//   constant on the piece. Since s is monotone on a piece (q' keeps its
//   sign) and e^{-theta} decreases, J lies between dq e^{-theta(l)} and dq
//   (second mean value theorem): the midpoint of those bounds errs by at most
//   |dq| (1 - e^{-theta(l)}) / 2, a proven bound, not an estimate. Where it
//   is within the piece's share of the tolerance J costs no sample at all;
//   elsewhere adaptive Simpson integrates J (smooth: a quadratic times the
//   exponential of a quartic), each step accepted when either Simpson's
//   estimate |D - S| / 15 or the proven bound on that step is within its
//   share.
//
// Tolerance eps, per channel, split:
// - 0.6 eps for J. A step [v, v + h] may err by
//     0.6 eps (dT + h / L) / 2 / (max |c1| T(0)),
//   dT the transmittance it spends and L the ray's visible length: the shares
//   of all steps add up to at most 0.6 eps (sum dT <= 1, sum h <= L).
// - 0.15 eps for early termination: the ray stops once T max(1, max C) is
//   below it (what the rest could add to any channel).
// - 0.25 eps for VTK's alpha model, whose extinction the transfer function
//   approximates within a relative error r = eps / 8 (Pieces.h); a relative
//   error r in tau changes a channel by at most r / (1 - r) + r / (1 - r)^2
//   (bound |tau' e^{-theta'} - tau e^{-theta}| term by term), about 2 r.
// The only estimate left is Simpson's on a smooth integrand, and only where
// the proven bound fails.
//
// Termination. Pieces per ray: see Pieces.h (at most 3 (m + 1) per cell
// crossed). Per piece, the proven bound of a step of length h is at most
// max|q'| max tau h^2 / 2, within the step's share once
//   h <= h* = 0.6 eps / (L max|c1| max|q'| max tau),
// so halving stops there at the latest (an h_min derived from eps and the
// data, not a setting); with a floor of l 2^-30 against rounding. So a piece
// takes at most 2 l / min(h*, l 2^-30) + 1 accepted steps, each after at most
// log2(l / h*) + 1 halvings, 4 samples for the first try and 2 per halving.
// A sample is one evaluation of the integrand (scalar, transfer function and
// transmittance) at a point inside a piece or at its end.
#ifndef avos_numerics_PiecewiseIntegrator_h
#define avos_numerics_PiecewiseIntegrator_h

#include "avos/numerics/Pieces.h"
#include "avos/numerics/RayIntegrators.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
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

// The tolerance of the exact piecewise reference (extinction model): the
// error of a channel is below 1e-9 (TestPiecewise checks it against closed
// forms).
template <typename Real>
constexpr Real PiecewiseReferenceTolerance()
{
  return Real(1e-10);
}

namespace detail
{
// theta(v) on a piece, the exact integral of tau = a + b q + c q^2 over
// [0, v]: a polynomial of degree 7 in v, D[k] its coefficient of v^k.
template <typename Real>
struct PieceDepth
{
  Real D[8];

  PieceDepth(const Cubic<Real>& q, Real a, Real b, Real c)
  {
    this->D[0] = Real(0);
    this->D[1] = a + b * q.K[0];
    this->D[2] = b * q.K[1] / Real(2);
    this->D[3] = b * q.K[2] / Real(3);
    this->D[4] = b * q.K[3] / Real(4);
    this->Degree = 4;
    if (c != Real(0))
    {
      const Real* k = q.K;
      const Real square[7] = { k[0] * k[0], Real(2) * k[0] * k[1],
        Real(2) * k[0] * k[2] + k[1] * k[1], Real(2) * (k[0] * k[3] + k[1] * k[2]),
        Real(2) * k[1] * k[3] + k[2] * k[2], Real(2) * k[2] * k[3], k[3] * k[3] };
      for (int i = 0; i < 7; ++i)
      {
        this->D[i + 1] = (i < 4 ? this->D[i + 1] : Real(0)) + c * square[i] / Real(i + 1);
      }
      this->Degree = 7;
    }
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
} // namespace detail

template <typename Real, typename VolumeT>
RayResult<Real> IntegratePiecewise(const VolumeT& volume, const glm::vec<3, Real>& origin,
  const glm::vec<3, Real>& direction, const Interval<Real>* segments, std::size_t count,
  const PiecewiseTransferFunction<Real>& tf, Real tolerance, bool earlyTermination = true,
  std::vector<StepRecord<Real>>* steps = nullptr)
{
  RayResult<Real> result;
  result.Statistics.Steps = steps;
  if (!(tolerance >= PiecewiseMinimumTolerance<Real>() && tolerance <= Real(1)))
  {
    result.Error = "the tolerance must be in [1e-12, 1]";
    return result;
  }
  if (tf.GetNumberOfPieces() == 0)
  {
    result.Error = "the piecewise transfer function was not built";
    return result;
  }
  for (int a = 0; a < 3; ++a)
  {
    if (volume.GetDimension(a) < 2)
    {
      result.Error = "the volume needs at least 2 points along each axis";
      return result;
    }
  }
  if (!std::isfinite(origin.x + origin.y + origin.z + direction.x + direction.y + direction.z))
  {
    result.Error = "the ray's origin and direction must be finite";
    return result;
  }
  result.Error = detail::ValidateSegments(segments, count);
  const Real L = detail::TotalLength(segments, count);
  if (!result.Error.empty() || !(L > Real(0)))
  {
    return result;
  }

  RayStatistics<Real>& stats = result.Statistics;
  const Real budget = Real(0.6) * tolerance;
  const Real terminationBound = Real(0.15) * tolerance / std::max(Real(1), tf.GetMaximumColor());
  glm::vec<3, Real> color(Real(0));
  Real T = Real(1);
  bool stopped = false;

  auto integratePiece = [&](const RayPiece<Real>& piece) -> bool
  {
    const auto& p = tf[piece.TF];
    const Cubic<Real>& q = piece.Q;
    const Real l = piece.Length;
    const detail::PieceDepth<Real> depth(q, p.Tau, p.TauSlope, p.TauCurvature);
    ++stats.Pieces;
    ++stats.Samples; // the piece's end
    stats.Accept(l);
    const Real thetaL = depth(l);
    const Real EL = std::exp(-thetaL);
    const Real Ta = T, Tb = T * EL;
    color += Ta * (p.Colour + p.ColourSlope * q.K[0]) - Tb * (p.Colour + p.ColourSlope * q(l));
    const Real cs = std::max({ std::abs(p.ColourSlope.x), std::abs(p.ColourSlope.y),
      std::abs(p.ColourSlope.z) });
    if (cs > Real(0) && Ta > Real(0))
    {
      // The error J may have on [v, v + h], spending e^{-theta} from Ev to Eh.
      const Real scale = budget / (Real(2) * cs * Ta);
      auto allowed = [&](Real Ev, Real Eh, Real h) { return scale * (Ta * (Ev - Eh) + h / L); };
      const Real dq = q(l) - q.K[0];
      Real J;
      if (std::abs(dq) * (Real(1) - EL) / Real(2) <= allowed(Real(1), EL, l))
      {
        J = dq * (Real(1) + EL) / Real(2);
      }
      else
      {
        // Adaptive Simpson on g = q' e^{-theta}; E = e^{-theta} kept beside.
        struct Point
        {
          Real G, E;
        };
        auto at = [&](Real v)
        {
          ++stats.Samples;
          const Real E = std::exp(-depth(v));
          return Point{ q.Derivative(v) * E, E };
        };
        const Real floor = l * Real(9.3e-10); // 2^-30
        J = Real(0);
        Real v = Real(0), h = l;
        bool lastSucceeded = true;
        Point P[5];
        P[0] = Point{ q.K[1], Real(1) };
        while (v < l)
        {
          h = std::min(h, l - v);
          for (int i = 1; i < 5; ++i)
          {
            P[i] = at(i == 4 ? v + h : v + Real(0.25) * Real(i) * h);
          }
          for (;;)
          {
            const Real S = h / Real(6) * (P[0].G + Real(4) * P[2].G + P[4].G);
            const Real D =
              h / Real(12) * (P[0].G + Real(4) * P[1].G + Real(2) * P[2].G + Real(4) * P[3].G + P[4].G);
            const Real limit = allowed(P[0].E, P[4].E, h);
            const Real qv = q(v), qh = q(v + h);
            // Simpson's estimate is trusted only where the step resolves
            // the transmittance (it falls by at most a factor e): there the
            // smooth integrand is in the estimate's asymptotic regime. A step
            // over a steep drop (extinction 50 per voxel) can see an
            // unresolved boundary layer whose error the estimate misses.
            if (P[4].E >= P[0].E * Real(0.36787944117144233) &&
              std::abs(D - S) / Real(15) <= limit)
            {
              J += D + (D - S) / Real(15);
              break;
            }
            if (std::abs(qh - qv) * (P[0].E - P[4].E) / Real(2) <= limit || h <= floor)
            {
              J += (qh - qv) * (P[0].E + P[4].E) / Real(2);
              break;
            }
            ++stats.Rejected;
            lastSucceeded = false;
            h *= Real(0.5);
            P[4] = P[2];
            P[2] = P[1];
            P[1] = at(v + Real(0.25) * h);
            P[3] = at(v + Real(0.75) * h);
          }
          stats.Accept(h);
          v = l - v <= h ? l : v + h;
          P[0] = P[4];
          if (lastSucceeded)
          {
            h *= Real(2);
          }
          lastSucceeded = true;
        }
      }
      color += p.ColourSlope * (Ta * J);
    }
    T = Tb;
    if (stats.Steps)
    {
      stats.Steps->push_back({ piece.Begin, l, Real(1) - T });
    }
    if (earlyTermination && T <= terminationBound)
    {
      stats.Terminated = true;
      stopped = true;
      return false;
    }
    return true;
  };

  for (std::size_t j = 0; j < count && !stopped; ++j)
  {
    PieceWalk(volume, origin, direction, segments[j].Begin, segments[j].End, tf, stats.Cells,
      integratePiece);
  }
  // Inside [0, 1] whatever the rounding: each channel is a sum of
  // non-negative contributions bounded by 1 - T.
  for (int c = 0; c < 3; ++c)
  {
    color[c] = std::min(std::max(color[c], Real(0)), Real(1) - T);
  }
  result.RGBA = glm::vec<4, Real>(color, Real(1) - T);
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
