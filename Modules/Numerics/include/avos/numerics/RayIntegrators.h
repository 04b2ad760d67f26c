// Evaluators of the volume rendering integral along one ray.
//
//   I     = int_0^D C(s(t)) tau(s(t)) exp(-int_0^t tau(s(t')) dt') dt   (per RGB channel)
//   alpha = 1 - exp(-int_0^D tau(s(t)) dt)
//
// A ray is any callable `Real field(Real t)` giving the scalar s at distance t
// (in voxel units) from the ray's entry, t in [0, D], and a TransferFunction;
// or a mixture's field giving its components' values and a
// MixtureTransferFunction (Mixture.h).
// A field with a member `Shade(t, colour)` (ShadedRayField, Shading.h) lights
// each sample's colour: the emission is then tau C'(x) with C' in [0, 1]; one
// with a member `Modulate(t, tau)` (GradientOpacityField, GradientOpacity.h)
// scales each sample's extinction.
// The colour I is premultiplied by opacity (RGB = I, A = alpha), black
// background.
//
// Evaluators, after L. Q. Campagnolo, W. Celes and L. H. de Figueiredo,
// "Accurate Volume Rendering based on Adaptive Numerical Integration",
// SIBGRAPI 2015 ("the paper"):
// - IntegrateRiemann: the paper's uniform-step baseline, right-hand rule,
//   with T *= (1 - tau h) (RiemannForm::Linear) or T *= exp(-tau h)
//   (RiemannForm::Exponential). First order.
// - IntegrateSimpson: composite Simpson with a fixed step for both the inner
//   and the outer integral. Fourth order.
// - IntegrateAdaptive: the paper's Algorithm 3 on top of its iterative
//   adaptive Simpson rule (Algorithm 2), Strategy::Coupled or ::Decoupled.
// - IntegrateReference: IntegrateAdaptive with a tolerance of 1e-9 and steps
//   down to 1e-7 voxel, error below 1e-6 per channel (proven by the oracles
//   in Numerics/Testing).
//
// Tolerance. Algorithm 2 halves eps with h, i.e. it uses a tolerance per unit
// length; like the authors' code (15 eps h / L on |D - S|), a step of length h
// is accepted when its estimated error E = |D - S| / 15 is at most
// eps_part * h / L, L the ray length, so the estimated errors of all steps
// add up to at most eps_part. The budget eps is split three ways:
// - inner integral (optical depth theta): 0.4 eps. An error d in theta
//   changes every later contribution, and 1 - alpha, by a factor e^{-d}, so by
//   at most T d: the inner estimate is weighted by the transmittance T(t) at
//   the step's start (steps behind opaque matter need no accuracy).
// - outer integral (RGB): 0.4 eps.
// - early ray termination: 0.2 eps. What the rest of a ray can add to any
//   channel is at most T * max C (colour <= max C, int tau e^{-theta} <= T),
//   and alpha moves by at most T; the ray stops once T * max(1, max C) is
//   below that share.
// The guarantee is as good as Simpson's error estimate, which can miss
// features narrower than a step and is capped by h_min (a step of h_min is
// taken even when it fails, as in the paper); Numerics/Testing measures how
// often the bound holds on random rays.
//
// Termination. Every attempt either accepts a step of at least
// min(h_min, remaining length), or halves a step that is above h_min; h never
// exceeds h_max; t + h is exact at the ray's end and h_min is raised to at
// least 8 ulp of D so that t always advances. Hence at most
// MaximumAttempts(D, settings) attempts and 5 samples per attempt, whatever
// the data (NaN scalars are transparent; infinities clamp to the end knots).
// Over segments, the same holds per segment, with D its length.
#ifndef avos_numerics_RayIntegrators_h
#define avos_numerics_RayIntegrators_h

#include "avos/numerics/TransferFunction.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace avos
{
namespace numerics
{

enum class Strategy
{
  Coupled,  // the inner integral's step starts each outer integration
  Decoupled // the outer integral keeps its own step; the inner one only bounds it
};

enum class RiemannForm
{
  Linear,     // T *= 1 - tau h (tau h clamped to 1)
  Exponential // T *= exp(-tau h)
};

template <typename Real>
struct AdaptiveSettings
{
  Real Tolerance = Real(0.01);  // eps, per channel
  Real InitialStep = Real(0.5); // h0, voxel units
  Real MinimumStep = Real(0.1); // h_min
  Real MaximumStep = Real(2.0); // h_max
  Strategy Coupling = Strategy::Coupled;
  bool EarlyTermination = true;
  // The field's range, when known (a volume's data range): transfer-function
  // knots outside it are never crossed, which spares the error estimate's
  // safety factors there (see Bracket::EstimateScale).
  Real FieldMinimum = -std::numeric_limits<Real>::infinity();
  Real FieldMaximum = std::numeric_limits<Real>::infinity();

  // Empty when valid, else the reason.
  std::string Validate() const
  {
    if (!(this->Tolerance > Real(0)) || !std::isfinite(this->Tolerance))
    {
      return "the tolerance must be positive and finite";
    }
    if (!(this->InitialStep > Real(0)) || !std::isfinite(this->InitialStep))
    {
      return "the initial step must be positive and finite";
    }
    if (!(this->MinimumStep > Real(0)) || !(this->MaximumStep >= this->MinimumStep) ||
      !std::isfinite(this->MaximumStep))
    {
      return "the steps must satisfy 0 < minimum step <= maximum step < inf";
    }
    return std::string();
  }
};

// An accepted step of the outer integral, [Start, Start + Length], and the
// opacity 1 - T the integration has reached at its end.
template <typename Real>
struct StepRecord
{
  Real Start;
  Real Length;
  Real Opacity;
};

template <typename Real>
struct RayStatistics
{
  long Samples = 0;  // transfer-function evaluations
  long Accepted = 0; // accepted steps, inner and outer
  long Rejected = 0; // rejected (halved) steps, inner and outer
  long Cells = 0;    // cells entered whose range is visible (IntegratePiecewise)
  long Pieces = 0;   // visible smooth pieces integrated (IntegratePiecewise)
  Real SmallestStep = std::numeric_limits<Real>::infinity();
  Real LargestStep = Real(0);
  bool Terminated = false; // stopped early by the transmittance bound
  // When non-null, receives the accepted outer steps (the paper's Figure 6);
  // the last argument of IntegrateAdaptive and IntegrateRiemann.
  std::vector<StepRecord<Real>>* Steps = nullptr;

  long Attempts() const { return this->Accepted + this->Rejected; }
  void Accept(Real h)
  {
    ++this->Accepted;
    this->SmallestStep = std::min(this->SmallestStep, h);
    this->LargestStep = std::max(this->LargestStep, h);
  }
  // An accepted outer step, ending at the given opacity.
  void Accept(Real t, Real h, Real opacity)
  {
    this->Accept(h);
    if (this->Steps)
    {
      this->Steps->push_back({ t, h, opacity });
    }
  }
};

template <typename Real>
struct RayResult
{
  glm::vec<4, Real> RGBA = glm::vec<4, Real>(Real(0));
  RayStatistics<Real> Statistics;
  std::string Error; // non-empty: invalid input, RGBA is zero
};

// Upper bound on step attempts of IntegrateAdaptive for a ray of length D:
// at most ceil(D / h_min) + 1 accepted steps for each of the inner and the
// outer integral, at most one interval-end step per inner step, and between
// two accepted steps at most ceil(log2(h_max / h_min)) + 1 rejections.
template <typename Real>
long MaximumAttempts(Real D, const AdaptiveSettings<Real>& settings)
{
  const Real hmin =
    std::max(settings.MinimumStep, Real(8) * std::numeric_limits<Real>::epsilon() * D);
  const double steps = std::ceil(double(D) / double(hmin)) + 1.0;
  const double halvings = std::ceil(std::log2(double(settings.MaximumStep) / double(hmin))) + 2.0;
  return static_cast<long>(std::min(3.0 * steps * halvings, 9e18));
}

// The factor by which the adaptive rule's Simpson estimate |D - S| / 15 is
// taken for a step whose scalars stay within [lo, hi] (Bracket::EstimateScale):
// 15 where C or tau jumps inside, 5 where they have a kink, 1 where smooth or
// where the range is empty or NaN.
template <typename Real>
Real SimpsonErrorScale(const TransferFunction<Real>& tf, Real lo, Real hi)
{
  if (!(lo == lo && hi == hi && lo < hi))
  {
    return Real(1);
  }
  return tf.HasJumpIn(lo, hi) ? Real(15) : (tf.HasKnotIn(lo, hi) ? Real(5) : Real(1));
}

namespace detail
{

// A sample: the field's value (a scalar, or the components of a mixture,
// Mixture.h), tau and the colour there.
template <typename Real, typename Value = Real>
struct Sample
{
  Value Scalar;
  Real Tau;
  glm::vec<3, Real> Color;
};

// Fields with a Modulate(t, tau) member scale the extinction
// (GradientOpacity.h).
template <typename Field, typename Real, typename = void>
struct IsModulated : std::false_type
{
};
template <typename Field, typename Real>
struct IsModulated<Field, Real,
  std::void_t<decltype(std::declval<const Field&>().Modulate(Real(0), Real(0)))>>
  : std::true_type
{
};

// Fields with a Shade(t, colour) member light the emission (Shading.h).
template <typename Field, typename Real, typename = void>
struct IsShaded : std::false_type
{
};
template <typename Field, typename Real>
struct IsShaded<Field, Real,
  std::void_t<decltype(std::declval<const Field&>().Shade(
    Real(0), std::declval<const glm::vec<3, Real>&>()))>> : std::true_type
{
};

// The field's value type: Real for a scalar field, a vector for a mixture's.
template <typename Real, typename Field>
using ValueOf = std::decay_t<decltype(std::declval<const Field&>()(Real(0)))>;

// Samples the field through `tf`, a TransferFunction or a
// MixtureTransferFunction (Mixture.h): anything with Classify(value, tau,
// colour) for the field's values.
template <typename Real, typename Field, typename Function>
class Sampler
{
public:
  using Value = ValueOf<Real, Field>;

  Sampler(const Field& field, const Function& tf, RayStatistics<Real>& stats)
    : F(field)
    , TF(tf)
    , Stats(stats)
  {
  }

  Sample<Real, Value> operator()(Real t) const
  {
    ++this->Stats.Samples;
    Sample<Real, Value> sample;
    sample.Scalar = this->F(t);
    this->TF.Classify(sample.Scalar, sample.Tau, sample.Color);
    if constexpr (IsModulated<Field, Real>::value)
    {
      if (sample.Tau > Real(0))
      {
        sample.Tau = this->F.Modulate(t, sample.Tau);
      }
    }
    if constexpr (IsShaded<Field, Real>::value)
    {
      if (sample.Tau > Real(0))
      {
        sample.Color = this->F.Shade(t, sample.Color);
      }
    }
    return sample;
  }

private:
  const Field& F;
  const Function& TF;
  RayStatistics<Real>& Stats;
};

// Componentwise minimum, maximum and absolute value of scalars and of mixtures'
// vectors (std::min's and glm::min's NaN rules are the same: the first
// argument unless the second compares below it).
template <typename Real>
Real Lower(Real a, Real b)
{
  return std::min(a, b);
}
template <typename Real>
Real Upper(Real a, Real b)
{
  return std::max(a, b);
}
template <typename Real>
Real Absolute(Real a)
{
  return std::abs(a);
}
template <int N, typename Real>
glm::vec<N, Real> Lower(const glm::vec<N, Real>& a, const glm::vec<N, Real>& b)
{
  return glm::min(a, b);
}
template <int N, typename Real>
glm::vec<N, Real> Upper(const glm::vec<N, Real>& a, const glm::vec<N, Real>& b)
{
  return glm::max(a, b);
}
template <int N, typename Real>
glm::vec<N, Real> Absolute(const glm::vec<N, Real>& a)
{
  return glm::abs(a);
}

// Five equidistant samples over [u, u + k]: Simpson on the whole step (S) and
// on its two halves (D), for both the inner and the outer integral. Halving
// keeps three samples and takes two new ones.
template <typename Real, typename Value = Real>
struct Bracket
{
  Real U = Real(0);
  Real K = Real(0);
  Sample<Real, Value> S[5];
  Real Scale = Real(0); // EstimateScale's cached value, 0 when unknown

  template <typename SamplerT>
  void Fill(const SamplerT& sample, Real u, Real k)
  {
    this->U = u;
    this->K = k;
    this->Scale = Real(0);
    for (int i = 1; i < 5; ++i)
    {
      this->S[i] = sample(i == 4 ? u + k : u + Real(0.25) * Real(i) * k);
    }
  }

  template <typename SamplerT>
  void Halve(const SamplerT& sample)
  {
    this->K *= Real(0.5);
    this->Scale = Real(0);
    this->S[4] = this->S[2];
    this->S[2] = this->S[1];
    this->S[1] = sample(this->U + Real(0.25) * this->K);
    this->S[3] = sample(this->U + Real(0.75) * this->K);
  }

  // Simpson's estimate |D - S| / 15 assumes a smooth integrand (error
  // O(h^5), so E(D) = E(S) / 16). Where the transfer function jumps inside
  // the step's scalar range the error of D is of the order of |D - S| itself
  // (factor 15); where it has a kink the integrand is only C0, the error is
  // O(h^2) and E(D) = |D - S| / 3 (factor 5). The range is that of the
  // samples, widened by the largest change between neighbours (a non-monotone
  // field can reach past its samples between them) and clipped to the field's
  // known range; a knot at an end of the clipped range is never crossed.
  // Computed once per set of samples; a mixture's components each through
  // their own functions (SimpsonErrorScale).
  template <typename TF>
  Real EstimateScale(const TF& tf, Real fieldMinimum, Real fieldMaximum)
  {
    if (this->Scale > Real(0))
    {
      return this->Scale;
    }
    Value lo = this->S[0].Scalar, hi = lo, spread = Value(Real(0));
    for (int i = 1; i < 5; ++i)
    {
      lo = Lower(lo, this->S[i].Scalar);
      hi = Upper(hi, this->S[i].Scalar);
      spread = Upper(spread, Absolute(this->S[i].Scalar - this->S[i - 1].Scalar));
    }
    lo = Upper(lo - spread, Value(fieldMinimum));
    hi = Lower(hi + spread, Value(fieldMaximum));
    this->Scale = SimpsonErrorScale(tf, lo, hi);
    return this->Scale;
  }

  // The stable rule for a step taken at h_min although its estimate fails:
  // piecewise-constant extinction and colour on the four quarters, each
  // integrated exactly (T *= e^{-tau dt}). Bounded and monotone, unlike a
  // Simpson polynomial across a jump or a huge extinction.
  void Stable(Real& theta, glm::vec<3, Real>& color) const
  {
    const Real dt = Real(0.25) * this->K;
    for (int i = 1; i < 5; ++i)
    {
      const Real tau = Real(0.5) * (this->S[i - 1].Tau + this->S[i].Tau);
      const glm::vec<3, Real> c = Real(0.5) * (this->S[i - 1].Color + this->S[i].Color);
      color += std::exp(-theta) * -std::expm1(-tau * dt) * c;
      theta += tau * dt;
    }
  }

  bool AllTransparent() const
  {
    for (const auto& s : this->S)
    {
      if (s.Tau != Real(0))
      {
        return false;
      }
    }
    return true;
  }

  // Simpson on the whole step (S) and on its two halves (D). Their
  // difference estimates the error of D: E = |D - S| / 15, and
  // D + (D - S) / 15 is the Richardson-corrected value.
  template <typename V>
  struct Pair
  {
    V S;
    V D;
    V Corrected() const { return this->D + (this->D - this->S) / Real(15); }
  };

  // Inner integral: int tau over the step.
  Pair<Real> Inner() const
  {
    const Real k = this->K;
    return { k / Real(6) * (this->S[0].Tau + Real(4) * this->S[2].Tau + this->S[4].Tau),
      k / Real(12) *
        (this->S[0].Tau + Real(4) * this->S[1].Tau + Real(2) * this->S[2].Tau +
          Real(4) * this->S[3].Tau + this->S[4].Tau) };
  }

  // Outer integral: int C tau e^{-theta} over the step with theta(U) = theta0.
  // theta inside the step comes from regular Simpson (its error is already
  // bounded by the inner step): at the half points by Simpson on each half, at
  // the quarter points by integrating the quadratic through a half's samples.
  Pair<glm::vec<3, Real>> Outer(Real theta0) const
  {
    const Real k = this->K;
    Real t[5];
    for (int i = 0; i < 5; ++i)
    {
      t[i] = this->S[i].Tau;
    }
    Real theta[5];
    theta[0] = theta0;
    theta[1] = theta0 + k / Real(48) * (Real(5) * t[0] + Real(8) * t[1] - t[2]);
    theta[2] = theta0 + k / Real(12) * (t[0] + Real(4) * t[1] + t[2]);
    theta[3] = theta[2] + k / Real(48) * (Real(5) * t[2] + Real(8) * t[3] - t[4]);
    theta[4] = theta[2] + k / Real(12) * (t[2] + Real(4) * t[3] + t[4]);
    glm::vec<3, Real> g[5];
    for (int i = 0; i < 5; ++i)
    {
      // Transparent samples (common at the ends of visible segments) add
      // nothing: no exponential for them.
      g[i] = t[i] > Real(0) ? this->S[i].Color * (t[i] * std::exp(-theta[i]))
                            : glm::vec<3, Real>(Real(0));
    }
    return { k / Real(6) * (g[0] + Real(4) * g[2] + g[4]),
      k / Real(12) * (g[0] + Real(4) * g[1] + Real(2) * g[2] + Real(4) * g[3] + g[4]) };
  }
};

template <typename Real>
Real ErrorEstimate(Real s, Real d)
{
  return std::abs(d - s) / Real(15);
}

template <typename Real>
Real ErrorEstimate(const glm::vec<3, Real>& s, const glm::vec<3, Real>& d)
{
  const glm::vec<3, Real> e = glm::abs(d - s) / Real(15);
  return std::max({ e[0], e[1], e[2] });
}

// Algorithm 2's step control: double after two consecutive successes, halve
// on failure, within [h_min, h_max].
template <typename Real>
struct StepControl
{
  Real H;
  Real Min;
  Real Max;
  bool LastSucceeded = true;

  void Succeeded()
  {
    if (this->LastSucceeded)
    {
      this->H = std::min(Real(2) * this->H, this->Max);
    }
    this->LastSucceeded = true;
  }
  void Failed()
  {
    this->H = std::max(Real(0.5) * this->H, this->Min);
    this->LastSucceeded = false;
  }
};

// Algorithm 2's inner loop: halve the step until error(bracket) is at most
// tolerance * K, or K has reached h_min. Returns true when the step is forced
// (taken at h_min although its estimate fails).
template <typename Real, typename Value, typename SamplerT, typename Error>
bool Refine(Bracket<Real, Value>& bracket, const SamplerT& sample, StepControl<Real>& control,
  Real tolerance, RayStatistics<Real>& stats, Error error)
{
  for (;;)
  {
    if (error(bracket) <= tolerance * bracket.K)
    {
      return false;
    }
    if (bracket.K <= control.Min)
    {
      return true;
    }
    ++stats.Rejected;
    control.Failed();
    bracket.Halve(sample);
  }
}

// Empty when the transfer function, the ray length and the step are usable.
template <typename Real, typename TF>
std::string ValidateRay(const TF& tf, Real D, Real h)
{
  std::string error = tf.Validate();
  if (error.empty() && (!(h > Real(0)) || !std::isfinite(h)))
  {
    error = "the step must be positive and finite";
  }
  if (error.empty() && (!(D >= Real(0)) || !std::isfinite(D)))
  {
    error = "the ray length must be finite and non-negative";
  }
  // Sample indices are counted in a long (found by fuzzing: D / h = 1.8e29).
  if (error.empty() && !(double(D) / double(h) <= 1e15))
  {
    error = "the ray needs more than 1e15 samples at this step";
  }
  return error;
}

} // namespace detail

// A part of a ray, [Begin, End] in the ray's parameter (voxel units), where
// the integrand may be non-zero. The segment overloads of the evaluators skip
// everything outside their sorted, disjoint segments (empty-space skipping:
// the caller guarantees tau = 0 there); the plain overloads integrate [0, D].
template <typename Real>
struct Interval
{
  Real Begin;
  Real End;
};

namespace detail
{
// Data or transfer-function values near the limits of Real can overflow an
// integral (inf - inf): such a ray is reported, never returned as NaN.
template <typename Real>
void RequireFinite(RayResult<Real>& result)
{
  if (!std::isfinite(result.RGBA.r + result.RGBA.g + result.RGBA.b + result.RGBA.a))
  {
    result.RGBA = glm::vec<4, Real>(Real(0));
    result.Error = "the integral overflowed (data or transfer-function values too large)";
  }
}

// Empty when the segments are finite, ordered and disjoint, within [0, inf).
template <typename Real>
std::string ValidateSegments(const Interval<Real>* segments, std::size_t count)
{
  Real previous = Real(0);
  for (std::size_t i = 0; i < count; ++i)
  {
    const Interval<Real>& s = segments[i];
    if (!(s.Begin >= previous) || !(s.End >= s.Begin) || !std::isfinite(s.End))
    {
      return "the ray segments must be finite, sorted and disjoint in [0, inf)";
    }
    previous = s.End;
  }
  return std::string();
}

template <typename Real>
Real TotalLength(const Interval<Real>* segments, std::size_t count)
{
  Real length = Real(0);
  for (std::size_t i = 0; i < count; ++i)
  {
    length += segments[i].End - segments[i].Begin;
  }
  return length;
}
} // namespace detail

// Riemann sum with samples at t_i = min(i h, D), i = 1..ceil(D / h). With
// segments, only the samples inside them are taken: since tau = 0 elsewhere,
// the result is exactly that of the full sum. The ray stops once what is left
// can change no channel by more than `terminationBound` (0: never).
template <typename Real, typename Field, typename TF>
RayResult<Real> IntegrateRiemann(const Field& field, const TF& tf, Real D, Real h, RiemannForm form,
  const Interval<Real>* segments, std::size_t count, Real terminationBound = Real(0),
  std::vector<StepRecord<Real>>* steps = nullptr)
{
  RayResult<Real> result;
  result.Statistics.Steps = steps;
  result.Error = detail::ValidateRay(tf, D, h);
  if (result.Error.empty())
  {
    result.Error = detail::ValidateSegments(segments, count);
  }
  if (!result.Error.empty() || D == Real(0))
  {
    return result;
  }
  const detail::Sampler<Real, Field, TF> sample(field, tf, result.Statistics);
  const Real bound = terminationBound / std::max(Real(1), tf.GetMaximumColor());
  glm::vec<3, Real> color(Real(0));
  Real T = Real(1);
  const long n = static_cast<long>(std::ceil(double(D) / double(h)));
  long next = 1; // the first sample index not yet taken
  for (std::size_t j = 0; j < count && next <= n; ++j)
  {
    next = std::max(next, static_cast<long>(std::ceil(double(segments[j].Begin) / double(h))));
    next = std::max(next, 1L);
    for (; next <= n; ++next)
    {
      const Real t1 = next == n ? D : std::min(Real(next) * h, D);
      if (t1 > segments[j].End)
      {
        break;
      }
      const Real t0 = Real(next - 1) * h;
      const Real dt = t1 - t0;
      const auto s = sample(t1);
      const Real a =
        form == RiemannForm::Linear ? std::min(s.Tau * dt, Real(1)) : -std::expm1(-s.Tau * dt);
      color += T * a * s.Color;
      T *= Real(1) - a;
      result.Statistics.Accept(t0, dt, Real(1) - T);
      if (T <= bound)
      {
        result.Statistics.Terminated = next < n;
        next = n + 1;
      }
    }
  }
  result.RGBA = glm::vec<4, Real>(color, Real(1) - T);
  detail::RequireFinite(result);
  return result;
}

template <typename Real, typename Field, typename TF>
RayResult<Real> IntegrateRiemann(const Field& field, const TF& tf, Real D, Real h, RiemannForm form)
{
  const Interval<Real> whole{ Real(0), std::isfinite(D) && D > Real(0) ? D : Real(0) };
  return IntegrateRiemann(field, tf, D, h, form, &whole, 1);
}

template <typename Real, typename Field, typename TF>
RayResult<Real> IntegrateSimpson(const Field& field, const TF& tf, Real D, Real h)
{
  RayResult<Real> result;
  result.Error = detail::ValidateRay(tf, D, h);
  if (!result.Error.empty() || D == Real(0))
  {
    return result;
  }
  const detail::Sampler<Real, Field, TF> sample(field, tf, result.Statistics);
  const long n = static_cast<long>(std::ceil(double(D) / double(h)));
  const Real k = D / Real(n);
  detail::Bracket<Real, detail::ValueOf<Real, Field>> b;
  b.S[0] = sample(Real(0));
  glm::vec<3, Real> color(Real(0));
  Real theta = Real(0);
  for (long i = 0; i < n; ++i)
  {
    b.Fill(sample, Real(i) * k, k);
    // Plain composite Simpson with step k / 2, without Richardson's correction.
    color += b.Outer(theta).D;
    theta += b.Inner().D;
    result.Statistics.Accept(b.U, k, -std::expm1(-theta));
    b.S[0] = b.S[4];
  }
  result.RGBA = glm::vec<4, Real>(color, -std::expm1(-theta));
  return result;
}

// The paper's Algorithm 3: the inner integral finds a step over which the
// optical depth is accurate (Algorithm 2 with the h_min/h_max clamps, returning
// as soon as a step is accepted); the outer integral then covers that
// interval for the RGB channels with its own adaptive steps, started from the
// inner step (Coupled) or from where it left off (Decoupled), using regular
// Simpson for theta inside; the outer integral is skipped where the inner one
// is exactly zero. Samples are shared: a halved step reuses three of its five
// samples, and the coupled outer integral's first try reuses the inner one's.
// With segments, the tolerance per unit length is spread over their total
// length L (so the bound on the whole ray is unchanged) and the step sizes
// carry over from one segment to the next.
template <typename Real, typename Field, typename TF>
RayResult<Real> IntegrateAdaptive(const Field& field, const TF& tf, const Interval<Real>* segments,
  std::size_t count, const AdaptiveSettings<Real>& settings,
  std::vector<StepRecord<Real>>* steps = nullptr)
{
  RayResult<Real> result;
  result.Statistics.Steps = steps;
  result.Error = settings.Validate();
  if (result.Error.empty())
  {
    result.Error = detail::ValidateSegments(segments, count);
  }
  const Real L = detail::TotalLength(segments, count);
  if (result.Error.empty())
  {
    result.Error = detail::ValidateRay(tf, L, settings.MaximumStep);
  }
  if (!result.Error.empty() || L == Real(0))
  {
    return result;
  }
  RayStatistics<Real>& stats = result.Statistics;
  const detail::Sampler<Real, Field, TF> sample(field, tf, stats);
  using Bracket = detail::Bracket<Real, detail::ValueOf<Real, Field>>;

  // h_min of at least 8 ulp of the ray's far end: t + h > t everywhere.
  const Real hmin = std::max(
    settings.MinimumStep, Real(8) * std::numeric_limits<Real>::epsilon() * segments[count - 1].End);
  const Real hmax = std::max(settings.MaximumStep, hmin);
  const Real eps = settings.Tolerance;
  const Real innerTolerance = Real(0.4) * eps / L; // per unit length
  const Real outerTolerance = Real(0.4) * eps / L;
  const Real terminationBudget = Real(0.2) * eps / std::max(Real(1), tf.GetMaximumColor());
  const Real terminationDepth = -std::log(terminationBudget); // T <= budget: theta >= this
  const Real fieldMinimum = settings.FieldMinimum;
  const Real fieldMaximum = settings.FieldMaximum;

  const Real h0 = std::min(std::max(std::min(settings.InitialStep, L), hmin), hmax);
  detail::StepControl<Real> inner{ h0, hmin, hmax };
  detail::StepControl<Real> outer{ h0, hmin, hmax };

  Bracket in;
  Bracket out;
  glm::vec<3, Real> color(Real(0));
  Real theta = Real(0);
  for (std::size_t j = 0; j < count && !stats.Terminated; ++j)
  {
    Real t = segments[j].Begin;
    const Real D = segments[j].End;
    if (t < D)
    {
      in.S[0] = sample(t);
    }
    while (t < D)
    {
      // Inner integral: the first acceptable step from t.
      const Real T = std::exp(-theta);
      const Real remaining = D - t;
      in.Fill(sample, t, std::min(inner.H, remaining));
      typename Bracket::template Pair<Real> innerPair;
      const bool innerForced = detail::Refine(in, sample, inner, innerTolerance, stats,
        [&](Bracket& b)
        {
          innerPair = b.Inner();
          return T * b.EstimateScale(tf, fieldMinimum, fieldMaximum) *
            detail::ErrorEstimate(innerPair.S, innerPair.D);
        });
      const Real h = in.K;
      const Real tEnd = in.K == remaining ? D : t + h;
      stats.Accept(h);
      Real innerValue = std::max(innerPair.Corrected(), Real(0));
      if (innerForced)
      {
        // The stable rule over the whole step, colour included: no outer pass.
        Real thetaEnd = theta;
        in.Stable(thetaEnd, color);
        innerValue = thetaEnd - theta;
      }

      if (innerForced || in.AllTransparent())
      {
        if (stats.Steps)
        {
          // No outer pass: the inner step is the step.
          stats.Steps->push_back({ t, h, -std::expm1(-(theta + innerValue)) });
        }
      }
      else
      {
        // Outer integral over [t, tEnd].
        if (settings.Coupling == Strategy::Coupled)
        {
          outer.H = h;
          outer.LastSucceeded = true;
        }
        Real u = t;
        Real thetaU = theta;
        out.S[0] = in.S[0];
        while (u < tEnd)
        {
          const Real k = std::min(outer.H, tEnd - u);
          if (u == t && k == h)
          {
            out = in; // the inner step's samples, exactly
          }
          else
          {
            out.Fill(sample, u, k);
          }
          typename Bracket::template Pair<glm::vec<3, Real>> outerPair;
          const bool outerForced = detail::Refine(out, sample, outer, outerTolerance, stats,
            [&](Bracket& b)
            {
              outerPair = b.Outer(thetaU);
              return b.EstimateScale(tf, fieldMinimum, fieldMaximum) *
                detail::ErrorEstimate(outerPair.S, outerPair.D);
            });
          if (outerForced)
          {
            out.Stable(thetaU, color);
          }
          else
          {
            color += outerPair.Corrected();
            thetaU += std::max(out.Inner().Corrected(), Real(0));
          }
          const Real uEnd = out.K == tEnd - u ? tEnd : u + out.K;
          stats.Accept(u, out.K, stats.Steps ? -std::expm1(-thetaU) : Real(0));
          outer.Succeeded();
          u = uEnd;
          out.S[0] = out.S[4];
        }
      }

      theta += innerValue;
      t = tEnd;
      in.S[0] = in.S[4];
      inner.Succeeded();

      if (settings.EarlyTermination && (t < D || j + 1 < count) && theta >= terminationDepth)
      {
        stats.Terminated = true;
        break;
      }
    }
  }
  // Each channel is the integral of C tau T with C in [0, 1]: within
  // [0, 1 - T]. Simpson's estimates can overshoot on extreme transfer
  // functions (found by fuzzing: 1.59); clamping only brings a channel
  // closer to its true value.
  const Real alpha = -std::expm1(-theta);
  for (int c = 0; c < 3; ++c)
  {
    color[c] = std::min(std::max(color[c], Real(0)), alpha);
  }
  result.RGBA = glm::vec<4, Real>(color, alpha);
  detail::RequireFinite(result);
  return result;
}

template <typename Real, typename Field, typename TF>
RayResult<Real> IntegrateAdaptive(const Field& field, const TF& tf, Real D,
  const AdaptiveSettings<Real>& settings, std::vector<StepRecord<Real>>* steps = nullptr)
{
  if (!(D >= Real(0)) || !std::isfinite(D))
  {
    RayResult<Real> result;
    result.Error = "the ray length must be finite and non-negative";
    return result;
  }
  const Interval<Real> whole{ Real(0), D };
  return IntegrateAdaptive(field, tf, &whole, 1, settings, steps);
}

// Reference evaluator: IntegrateAdaptive (decoupled) with eps = 1e-9, steps
// between 1e-7 and 0.25 voxel; its early termination changes no channel by
// more than 2e-10. Meant for double; Numerics/Testing shows its error is below
// 1e-6 per channel on the oracles.
template <typename Real>
AdaptiveSettings<Real> ReferenceSettings()
{
  AdaptiveSettings<Real> settings;
  settings.Tolerance = Real(1e-9);
  settings.InitialStep = Real(0.125);
  settings.MinimumStep = Real(1e-7);
  settings.MaximumStep = Real(0.25);
  settings.Coupling = Strategy::Decoupled;
  return settings;
}

template <typename Real, typename Field, typename TF>
RayResult<Real> IntegrateReference(
  const Field& field, const TF& tf, const Interval<Real>* segments, std::size_t count)
{
  return IntegrateAdaptive(field, tf, segments, count, ReferenceSettings<Real>());
}

template <typename Real, typename Field, typename TF>
RayResult<Real> IntegrateReference(const Field& field, const TF& tf, Real D)
{
  return IntegrateAdaptive(field, tf, D, ReferenceSettings<Real>());
}

} // namespace numerics
} // namespace avos

#endif
