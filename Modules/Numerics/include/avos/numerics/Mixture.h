// Volumes of several components (VTK's independent and dependent components)
// as one emission-absorption medium, integrated by every method.
//
// The medium. Each component's scalar s_k is read from its own interleaved
// array in place (ComponentVolumes) and interpolated as a single component
// would be. With independent components each is a medium of its own with
// its own transfer function (tau_k, C_k) and weight w_k >= 0, and the
// volume is their mixture:
//   tau = sum_k w_k tau_k(s_k),   emission = sum_k w_k tau_k(s_k) C_k(s_k),
// so a ray sees the sum of the components' extinctions and of their
// emissions (densities add), its colour at a point the components' colours
// weighted by their shares of the extinction. Dependent components are one
// medium: with two, the colour function of s_0 and the opacity function of
// s_1 (ColourOpacity); with four, the colour (s_0, s_1, s_2) times a scale
// (1 / 255 for unsigned char) and the opacity function of s_3 (RGBOpacity).
// How this relates to VTK's mappers (which combine per sample) is stated in
// vtkAdaptiveVolumeMapper.h.
//
// The piecewise method (IntegratePiecewiseMixture). Inside a cell each
// component's scalar is a cubic along the ray (Pieces.h), each transfer
// function linear between its knots, so cutting the ray at every used
// component's knot crossings (sought on the monotone stretches between its
// cubic's extrema) and at the extrema of every cubic a colour is linear in
// leaves pieces on which the extinction is a polynomial of degree at most 3
// (9 in VTK's alpha model: Pieces.h's cubic in s), each emission one of
// degree at most 6 (12), and each colour's cubic monotone. Then on a piece
// [0, l] (transmittance Ta in front, theta the exact depth, PieceDepth
// summed over the terms):
// - one visible term (the others transparent there, every dependent
//   mixture): the emission is tau C with theta' = tau (the weight cancels),
//   so by parts int tau C e^{-theta} = C(0) - C(l) e^{-theta(l)} +
//   sum_c b_c J_c with J_c = int x_c' e^{-theta}, x_c the cubic the colour
//   channel c is linear in (slope b_c): IntegratePiecewise's closed form
//   and proven remainder, with up to three sources;
// - several visible terms: int E_c e^{-theta} for the emission polynomials
//   E_c >= 0, E = e^{-theta(l)}: the midpoint of [E, 1] int E_c, within
//   (1 - E) int E_c / 2, or the mean colour int E_c / theta(l) times 1 - E,
//   within (1 - E) / 2 times a bound of how far the terms' colours and
//   their shares of the extinction vary over the piece
//   (MixturePiece::Emissions), or else the power series of e^{-theta} on
//   sub-intervals with a proven tail (SeriesIntegrals).
// A mixture in which one component alone shows (the others of weight 0 or
// transparent everywhere) is that component's medium, its weight in its
// extinction: its rays are IntegratePiecewise's on that component.
// The tolerance eps is split as IntegratePiecewise's: 0.6 eps for these
// remainders (a sub-interval's share (Ta dT + h / L) / 2 of it, summing to
// at most 0.6 eps over the ray), 0.15 eps for early termination, 0.25 eps for
// VTK's alpha model (each term's extinction within a relative eps / 8, hence
// their sum and every emission too). A component with a NaN corner gives
// nothing in that cell (its term is left out; a dependent mixture's cell is
// then empty); the sampled methods agree, NaN samples being transparent.
//
// Termination: a ray crosses at most nx + ny + nz cells; each cell's cuts
// are extrema (2 per cubic) and knot crossings (at most 3 (m_k + 1) per
// function, PieceWalk's bound), each found in at most 128 iterations; each
// piece's remainder takes at most MaximumSubintervals sub-intervals of at
// most 41 series terms (SeriesIntegrals), or the ray reports an error.
#ifndef avos_numerics_Mixture_h
#define avos_numerics_Mixture_h

#include "avos/numerics/Accumulation.h" // GaussLegendre
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/TransferFunction.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace avos
{
namespace numerics
{

constexpr int MaximumComponents = 4;

// How the components make the medium (see above).
enum class ComponentMix
{
  Independent,   // 1 to 4 components, each its own transfer function and weight
  ColourOpacity, // 2 components: the colour of s_0, the opacity of s_1
  RGBOpacity     // 4 components: the colour (s_0, s_1, s_2) scale, the opacity of s_3
};

// The components' transfer functions and how they mix, for the sampled
// methods (IntegrateRiemann, IntegrateAdaptive, IntegrateReference): what
// they take in place of a TransferFunction for fields of a mixture's values
// (RayField over ComponentVolumes). The functions are the caller's, alive
// while this is used.
template <typename Real>
class MixtureTransferFunction
{
public:
  using Color = glm::vec<3, Real>;
  using Values = glm::vec<MaximumComponents, Real>;

  // `count` components, component k through functions[k] with weight
  // weights[k].
  void SetIndependent(
    int count, const TransferFunction<Real>* const functions[], const Real weights[])
  {
    this->Mix = ComponentMix::Independent;
    this->Count = count;
    this->SingleComponent = -1;
    int shown = 0;
    bool valid = true; // (else Validate says why)
    for (int k = 0; k < MaximumComponents; ++k)
    {
      const bool used = k < count;
      this->Functions[k] = used ? functions[k] : nullptr;
      this->Weights[k] = used ? weights[k] : Real(0);
      const Real w = this->Weights[k];
      valid = valid && (!used || (functions[k] && w >= Real(0) && std::isfinite(w)));
      if (valid && used && w > Real(0) && !functions[k]->IsTransparent())
      {
        this->SingleComponent = shown++ == 0 ? k : -1;
      }
    }
    this->SingleComponent = valid ? this->SingleComponent : -1;
    if (this->SingleComponent >= 0 && this->Weights[this->SingleComponent] != Real(1))
    {
      this->Scaled = *this->Functions[this->SingleComponent];
      this->Scaled.ScaleExtinction(this->Weights[this->SingleComponent]);
      this->Scaled.Finalize();
    }
  }

  // The medium when one component alone shows (independent components, the
  // others of weight 0 or transparent everywhere): that component's
  // function, its weight in its extinction (TransferFunction::
  // ScaleExtinction); null otherwise. Its rays are a single component's.
  const TransferFunction<Real>* GetSingle() const
  {
    if (this->SingleComponent < 0)
    {
      return nullptr;
    }
    return this->Weights[this->SingleComponent] == Real(1) ? this->Functions[this->SingleComponent]
                                                           : &this->Scaled;
  }
  // The component GetSingle's medium reads (-1: none).
  int GetSingleComponent() const { return this->SingleComponent; }

  // Two components: the colour of `tf` at s_0, its opacity at s_1.
  void SetColourOpacity(const TransferFunction<Real>& tf) { this->SetDependent(2, tf, Real(0)); }

  // Four components: the colour (s_0, s_1, s_2) scale, which the caller keeps
  // within [0, 1] (unsigned char data, scale 1 / 255); the opacity of `tf`
  // at s_3.
  void SetRGBOpacity(const TransferFunction<Real>& tf, Real scale)
  {
    this->SetDependent(4, tf, scale);
  }

  ComponentMix GetMix() const { return this->Mix; }
  int GetNumberOfComponents() const { return this->Count; }
  Real GetWeight(int k) const { return this->Weights[k]; }
  Real GetScale() const { return this->Scale; }
  // Component k's function (independent), or the one function (dependent,
  // any k).
  const TransferFunction<Real>& GetFunction(int k) const
  {
    return this->Mix == ComponentMix::Independent ? *this->Functions[k] : *this->Functions[0];
  }

  // Empty when usable; otherwise what is wrong.
  std::string Validate() const
  {
    const int wanted = this->Mix == ComponentMix::Independent
      ? this->Count
      : (this->Mix == ComponentMix::ColourOpacity ? 2 : 4);
    if (this->Count < 1 || this->Count > MaximumComponents || this->Count != wanted)
    {
      return "a mixture takes 1 to 4 independent components, 2 (colour and opacity) or 4 (RGB "
             "and opacity) dependent ones";
    }
    const int functions = this->Mix == ComponentMix::Independent ? this->Count : 1;
    for (int k = 0; k < functions; ++k)
    {
      if (!this->Functions[k])
      {
        return "a component has no transfer function";
      }
      if (!(this->Weights[k] >= Real(0)) || !std::isfinite(this->Weights[k]))
      {
        return "component weights must be finite and non-negative";
      }
      const std::string error = this->Functions[k]->Validate();
      if (!error.empty())
      {
        return error;
      }
    }
    if (this->Mix == ComponentMix::RGBOpacity && !(this->Scale > Real(0) && this->Scale <= Real(1)))
    {
      return "the colour scale of RGB components must be in (0, 1]";
    }
    return std::string();
  }

  // tau and the colour of the medium at the components' values s (the
  // emission is tau colour).
  void Classify(const Values& s, Real& tau, Color& colour) const
  {
    tau = Real(0);
    colour = Color(Real(0));
    if (this->Mix == ComponentMix::Independent)
    {
      Color emission(Real(0));
      for (int k = 0; k < this->Count; ++k)
      {
        if (this->Weights[k] > Real(0))
        {
          Real t;
          Color c;
          this->Functions[k]->Classify(s[k], t, c);
          tau += this->Weights[k] * t;
          emission += (this->Weights[k] * t) * c;
        }
      }
      if (tau > Real(0))
      {
        colour = emission / tau;
      }
      return;
    }
    const TransferFunction<Real>& tf = *this->Functions[0];
    if (this->Mix == ComponentMix::ColourOpacity)
    {
      if (!std::isnan(s[0]))
      {
        tau = tf.GetExtinction(s[1]);
        colour = tf.GetColor(s[0]);
      }
      return;
    }
    const Color rgb = Color(s[0], s[1], s[2]) * this->Scale;
    if (!std::isnan(rgb[0] + rgb[1] + rgb[2]))
    {
      tau = tf.GetExtinction(s[3]);
      colour = rgb;
    }
  }

  // Whether the medium can show anywhere each component k stays within
  // [lo[k], hi[k]] (a block's ranges: EmptySpaceMap::ClassifyBlocks): some
  // term's extinction is not 0 there. An empty range (lo > hi: NaN only)
  // shows nothing.
  bool IsVisible(const Real* lo, const Real* hi) const
  {
    auto shows = [&](const TransferFunction<Real>& tf, int k)
    { return lo[k] <= hi[k] && tf.GetMaximumExtinction(lo[k], hi[k]) > Real(0); };
    switch (this->Mix)
    {
      case ComponentMix::Independent:
        for (int k = 0; k < this->Count; ++k)
        {
          if (this->Weights[k] > Real(0) && shows(*this->Functions[k], k))
          {
            return true;
          }
        }
        return false;
      case ComponentMix::ColourOpacity:
        return shows(*this->Functions[0], 1);
      default:
        return shows(*this->Functions[0], 3);
    }
  }

  // Largest colour component: bounds what the rest of a ray can add.
  Real GetMaximumColor() const
  {
    if (this->Mix == ComponentMix::RGBOpacity)
    {
      return Real(1);
    }
    Real m = Real(0);
    const int functions = this->Mix == ComponentMix::Independent ? this->Count : 1;
    for (int k = 0; k < functions; ++k)
    {
      if (this->Weights[k] > Real(0))
      {
        m = std::max(m, this->Functions[k]->GetMaximumColor());
      }
    }
    return m;
  }

private:
  void SetDependent(int count, const TransferFunction<Real>& tf, Real scale)
  {
    this->SingleComponent = -1;
    this->Mix = count == 2 ? ComponentMix::ColourOpacity : ComponentMix::RGBOpacity;
    this->Count = count;
    this->Functions = { { &tf, nullptr, nullptr, nullptr } };
    this->Weights = { { Real(1), Real(0), Real(0), Real(0) } };
    this->Scale = scale;
  }

  ComponentMix Mix = ComponentMix::Independent;
  int Count = 0;
  std::array<const TransferFunction<Real>*, MaximumComponents> Functions{};
  std::array<Real, MaximumComponents> Weights{};
  Real Scale = Real(0);
  int SingleComponent = -1;
  TransferFunction<Real> Scaled; // GetSingle's where the weight is not 1
};

// The adaptive rule's error scale (SimpsonErrorScale) of a mixture: the
// largest over the components it reads, each through its function.
template <typename Real>
Real SimpsonErrorScale(const MixtureTransferFunction<Real>& mixture,
  const glm::vec<MaximumComponents, Real>& lo, const glm::vec<MaximumComponents, Real>& hi)
{
  Real scale = Real(1);
  for (int k = 0; k < mixture.GetNumberOfComponents(); ++k)
  {
    const bool read = mixture.GetMix() != ComponentMix::Independent || mixture.GetWeight(k) > 0;
    const bool rgb = mixture.GetMix() == ComponentMix::RGBOpacity && k < 3;
    if (read && !rgb)
    {
      scale = std::max(scale, SimpsonErrorScale(mixture.GetFunction(k), lo[k], hi[k]));
    }
  }
  return scale;
}

// A volume of several components, each a VolumeT (Volume.h) reading its
// own values of interleaved tuples in place; its value at a point is the
// components' values (0 beyond its count), what RayField gives the sampled
// methods with a MixtureTransferFunction.
template <typename Real, typename VolumeT>
class ComponentVolumes
{
public:
  using Point = glm::vec<3, Real>;
  using Values = glm::vec<MaximumComponents, Real>;

  // component(k) makes component k's volume, k < count (1 to 4).
  template <typename Make>
  ComponentVolumes(int count, Make&& component)
  {
    this->Volumes.reserve(static_cast<std::size_t>(count));
    for (int k = 0; k < count; ++k)
    {
      this->Volumes.push_back(component(k));
    }
  }

  int GetNumberOfComponents() const { return static_cast<int>(this->Volumes.size()); }
  const VolumeT& operator[](int k) const { return this->Volumes[static_cast<std::size_t>(k)]; }

  Values operator()(const Point& p) const
  {
    Values v(Real(0));
    for (std::size_t k = 0; k < this->Volumes.size(); ++k)
    {
      v[static_cast<int>(k)] = this->Volumes[k](p);
    }
    return v;
  }

  Point ToWalk(const Point& p) const { return this->Volumes.front().ToWalk(p); }
  int GetDimension(int axis) const { return this->Volumes.front().GetDimension(axis); }

private:
  std::vector<VolumeT> Volumes;
};

// A MixtureTransferFunction in pieces (Pieces.h) for the piecewise method:
// each of its functions built once.
template <typename Real>
class PiecewiseMixture
{
public:
  // A term of the medium: the extinction Weight tau(s_Opacity) of the
  // function's pieces, its colour from the same pieces at s_Colour, or
  // (Direct) the channels s_0, s_1, s_2 times Scale.
  struct Term
  {
    int Opacity = 0;
    int Colour = 0;
    bool Direct = false;
    Real Weight = Real(1);
    const PiecewiseTransferFunction<Real>* Pieces = nullptr;
  };

  // Builds the pieces of each function of `mixture` (valid) with the alpha
  // model's `relativeError` (PiecewiseTransferFunction::Build). Empty on
  // success, else why.
  std::string Build(const MixtureTransferFunction<Real>& mixture, Real relativeError)
  {
    this->Terms.clear();
    this->HasSingle = false;
    this->Read = 0;
    std::string error = mixture.Validate();
    const ComponentMix mix = mixture.GetMix();
    const int functions = mix == ComponentMix::Independent ? mixture.GetNumberOfComponents() : 1;
    for (int k = 0; k < functions && error.empty(); ++k)
    {
      error = this->Functions[k].Build(mixture.GetFunction(k), relativeError);
    }
    if (!error.empty())
    {
      return error;
    }
    this->Scale = mixture.GetScale();
    this->MaximumColor = mixture.GetMaximumColor();
    this->Count = mixture.GetNumberOfComponents();
    if (mix == ComponentMix::Independent)
    {
      // A component of weight 0, or whose function is transparent
      // everywhere, shows nothing: no term, its values never read.
      for (int k = 0; k < functions; ++k)
      {
        const PiecewiseTransferFunction<Real>& f = this->Functions[k];
        if (mixture.GetWeight(k) > Real(0) && f.NextVisible(0) < f.GetNumberOfPieces())
        {
          this->Terms.push_back({ k, k, false, mixture.GetWeight(k), &f });
        }
      }
    }
    else if (mix == ComponentMix::ColourOpacity)
    {
      this->Terms.push_back({ 1, 0, false, Real(1), &this->Functions[0] });
    }
    else
    {
      this->Terms.push_back({ 3, 0, true, Real(1), &this->Functions[0] });
    }
    for (const Term& t : this->Terms)
    {
      this->Read |= (1u << t.Opacity) | (t.Direct ? 7u : (1u << t.Colour));
    }
    // One term of one component: a single component's medium, its weight
    // in its extinction.
    this->HasSingle = this->Terms.size() == 1 && mix == ComponentMix::Independent;
    if (this->HasSingle)
    {
      this->Single = *this->Terms[0].Pieces;
      this->Single.ScaleExtinction(this->Terms[0].Weight);
    }
    return std::string();
  }

  // The medium when one component alone shows (an independent mixture of
  // one term, the others of weight 0 or transparent): that component's
  // pieces with the extinction times its weight, integrated as one
  // component's (IntegratePiecewise, same bound); null otherwise.
  const PiecewiseTransferFunction<Real>* GetSingle() const
  {
    return this->HasSingle ? &this->Single : nullptr;
  }
  // The component GetSingle's medium reads.
  int GetSingleComponent() const { return this->HasSingle ? this->Terms[0].Opacity : -1; }

  const std::vector<Term>& GetTerms() const { return this->Terms; }
  // Whether component k is read by a term.
  bool Reads(int k) const { return (this->Read >> k) & 1u; }
  int GetNumberOfComponents() const { return this->Count; }
  Real GetScale() const { return this->Scale; }
  Real GetMaximumColor() const { return this->MaximumColor; }

private:
  std::array<PiecewiseTransferFunction<Real>, MaximumComponents> Functions;
  std::vector<Term> Terms;
  PiecewiseTransferFunction<Real> Single;
  bool HasSingle = false;
  unsigned Read = 0;
  int Count = 0;
  Real Scale = Real(0);
  Real MaximumColor = Real(0);
};

namespace detail
{
// A term's colour on a piece: channel c is A[c] + B[c] x_c(v), x_c a cubic
// in v from the piece's start, X[c] (Sources 3), or X[0] for all three
// (Sources 1: a colour function of one scalar).
template <typename Real>
struct PieceColour
{
  glm::vec<3, Real> A, B;
  Cubic<Real> X[3];
  int Sources;

  const Cubic<Real>& Of(int c) const { return this->X[this->Sources == 1 ? 0 : c]; }
  // x_c at v, each channel.
  glm::vec<3, Real> At(Real v) const
  {
    return this->Sources == 1 ? glm::vec<3, Real>(this->X[0](v))
                              : glm::vec<3, Real>(this->X[0](v), this->X[1](v), this->X[2](v));
  }
};

// A visible term on a piece: its weight, its extinction's piece and the
// cubic d(v) = s(v) - Start it takes, its colour.
template <typename Real>
struct PieceTerm
{
  Real Weight;
  const typename PiecewiseTransferFunction<Real>::Piece* Extinction;
  Cubic<Real> D;
  PieceColour<Real> Colour;
};

// Polynomials in v as coefficient arrays of fixed capacity.
template <typename Real, int M>
struct Polynomial
{
  Real C[M] = {};
};

// tau(d(v)) = a + d (b + d (c + d e)) as a polynomial of degree up to 9
// (Horner's rule on polynomials, from the highest non-zero coefficient).
template <typename Real>
Polynomial<Real, 10> ExtinctionPolynomial(
  const typename PiecewiseTransferFunction<Real>::Piece& p, const Cubic<Real>& d)
{
  const Real coefficient[4] = { p.Tau, p.TauSlope, p.TauCurvature, p.TauCubic };
  int top = 3;
  while (top > 0 && coefficient[top] == Real(0))
  {
    --top;
  }
  Polynomial<Real, 10> tau;
  tau.C[0] = coefficient[top];
  for (int j = top - 1, degree = 0; j >= 0; --j, degree += 3)
  {
    // tau = tau d + coefficient[j]: degree + 3.
    Real next[10] = {};
    for (int i = 0; i <= degree; ++i)
    {
      for (int k = 0; k < 4; ++k)
      {
        next[i + k] += tau.C[i] * d.K[k];
      }
    }
    next[0] += coefficient[j];
    std::copy(next, next + 10, tau.C);
  }
  return tau;
}

// The range [lo, hi] of the cubic q over [0, length]: its values at the
// bounds of its monotone stretches (StretchBounds), up to rounding.
template <typename Real>
void CubicRange(const Cubic<Real>& q, Real length, Real& lo, Real& hi)
{
  Real bounds[4];
  const int n = StretchBounds(q, length, bounds);
  lo = hi = q(bounds[0]);
  for (int i = 1; i < n; ++i)
  {
    lo = std::min(lo, q(bounds[i]));
    hi = std::max(hi, q(bounds[i]));
  }
}

// The range of a term's w tau(d(v)) over [0, l]: tau's cubic in d over d's
// range.
template <typename Real>
void ExtinctionRange(const PieceTerm<Real>& term, Real l, Real& lo, Real& hi)
{
  // d is monotone where the term's colour is of its own scalar (a cubic cut
  // at its extrema: d's up to a constant).
  const Cubic<Real>& x = term.Colour.X[0];
  const Cubic<Real>& d = term.D;
  Real dlo = std::min(d(Real(0)), d(l)), dhi = std::max(d(Real(0)), d(l));
  if (term.Colour.Sources != 1 || x.K[1] != d.K[1] || x.K[2] != d.K[2] || x.K[3] != d.K[3])
  {
    CubicRange(d, l, dlo, dhi);
  }
  const auto& e = *term.Extinction;
  const Cubic<Real> tau{ { e.Tau, e.TauSlope, e.TauCurvature, e.TauCubic } };
  if (e.TauCurvature == Real(0) && e.TauCubic == Real(0))
  {
    lo = std::min(tau(dlo), tau(dhi));
    hi = std::max(tau(dlo), tau(dhi));
  }
  else
  {
    CubicRange(tau.Shifted(dlo), dhi - dlo, lo, hi);
  }
  lo = term.Weight * std::max(lo, Real(0));
  hi = term.Weight * std::max(hi, Real(0));
}

// The integral of a colour remainder (by parts, one visible term) or of the
// emissions (several) over one piece, within the piece's share of the
// tolerance; Ta the transmittance in front. Its transmittance E =
// e^{-theta(l)}: of one term from theta's polynomial, of several from the
// terms' depths theta_t(l) = int_0^l w_t tau_t by 7-point Gauss-Legendre
// (exact for their degree, at most 9), which the emissions' integrals reuse.
template <typename Real>
class MixturePiece
{
public:
  MixturePiece(const PieceTerm<Real>* terms, int count, Real length, Real front, Real budget,
    Real inverseL, RayStatistics<Real>& stats)
    : Terms(terms)
    , Count(count)
    , L(length)
    , Ta(front)
    , Budget(budget)
    , InverseL(inverseL)
    , Stats(stats)
  {
    if (count == 1)
    {
      this->E = std::exp(-this->Depth()(length));
      return;
    }
    using G = GaussLegendre<Real>;
    const Real half = Real(0.5) * length;
    for (int i = 0; i < 7; ++i)
    {
      this->Nodes[i] = half + half * G::N7[i];
    }
    for (int t = 0; t < count; ++t)
    {
      const auto& e = *terms[t].Extinction;
      Real& sum = this->TauSum[t];
      sum = Real(0);
      for (int i = 0; i < 7; ++i)
      {
        const Real d = terms[t].D(this->Nodes[i]);
        const Real tau = e.Tau + d * (e.TauSlope + d * (e.TauCurvature + d * e.TauCubic));
        this->WeightedTau[t][i] = G::W7[i] * terms[t].Weight * tau;
        sum += this->WeightedTau[t][i];
      }
      this->Theta[t] = std::max(sum * half, Real(0));
      this->TotalTheta += this->Theta[t];
    }
    this->E = std::exp(-this->TotalTheta);
  }

  // e^{-theta(l)}.
  Real Transmittance() const { return this->E; }

  // Adds the piece's colour; false when a remainder is refused.
  bool Integrate(glm::vec<3, Real>& colour) const
  {
    return this->Count == 1 ? this->ByParts(colour) : this->Emissions(colour);
  }

private:
  bool ByParts(glm::vec<3, Real>& colour) const
  {
    const PieceColour<Real>& pc = this->Terms[0].Colour;
    const glm::vec<3, Real> x0 = pc.At(Real(0)), dx = pc.At(this->L) - x0;
    colour += this->Ta * (pc.A + pc.B * x0) - (this->Ta * this->E) * (pc.A + pc.B * (x0 + dx));
    const glm::vec<3, Real> change = glm::abs(pc.B * dx), slope = glm::abs(pc.B);
    const Real cs = std::max({ slope.x, slope.y, slope.z });
    if (cs == Real(0) || this->Ta == Real(0))
    {
      return true;
    }
    if (std::max({ change.x, change.y, change.z }) * this->Ta * (Real(1) - this->E) <=
      this->Share())
    {
      // Each x_c is monotone: J_c within [dx_c E, dx_c], their midpoint.
      colour += pc.B * dx * (this->Ta * (Real(1) + this->E) / Real(2));
      return true;
    }
    // J of each distinct cubic.
    const Real scale = this->Budget / (Real(2) * cs * this->Ta);
    auto slopes = [&pc](int c, Real* g)
    {
      const Cubic<Real>& x = pc.X[c];
      g[0] = x.K[1];
      g[1] = Real(2) * x.K[2];
      g[2] = Real(3) * x.K[3];
    };
    if (pc.Sources == 1)
    {
      Real g[1][3], J[1];
      slopes(0, g[0]);
      if (!this->Series(g, scale, J))
      {
        return false;
      }
      colour += pc.B * (this->Ta * J[0]);
      return true;
    }
    Real g[3][3], J[3];
    for (int c = 0; c < 3; ++c)
    {
      slopes(c, g[c]);
    }
    if (!this->Series(g, scale, J))
    {
      return false;
    }
    colour += pc.B * glm::vec<3, Real>(J[0], J[1], J[2]) * this->Ta;
    return true;
  }

  // int E_c e^{-theta}, E_c = sum_t w_t tau_t C_tc >= 0 and theta' = tau =
  // sum_t w_t tau_t: for any constant m_c, with r_c = E_c - m_c tau,
  //   int E_c e^{-theta} = m_c (1 - E) + (1 + E) / 2 (W_c - m_c theta(l))
  //     + int r_c (e^{-theta} - (1 + E) / 2),
  // W_c = int E_c, and since e^{-theta} lies in [E, 1] the last term is at
  // most (1 - E) / 2 int |r_c|. m_c = 0 is the midpoint of [E, 1] times W_c,
  // int |r_c| = W_c; m_c = W_c / theta(l), the mean colour, has
  // int |r_c| <= SpreadAround(m) (the terms' colours around it), or, split
  // term by term, <= SplitSpread. The smaller bound, where it fits the share;
  // else the power series of e^{-theta}.
  bool Emissions(glm::vec<3, Real>& colour) const
  {
    if (this->Ta == Real(0))
    {
      return true;
    }
    glm::vec<3, Real> wholes[MaximumComponents];
    const glm::vec<3, Real> whole = this->EmissionIntegrals(wholes);
    const Real theta = this->TotalTheta;
    const glm::vec<3, Real> m = theta > Real(0) ? whole / theta : glm::vec<3, Real>(Real(0));
    const glm::vec<3, Real> midpoint = glm::abs(whole);
    glm::vec<3, Real> around = this->SpreadAround(m);
    if (theta > Real(0) && !this->Fits(glm::min(midpoint, around)))
    {
      around = glm::min(around, this->SplitSpread(wholes, theta, midpoint, around));
    }
    glm::vec<3, Real> mean(Real(0)), bound = midpoint;
    for (int c = 0; c < 3; ++c)
    {
      if (theta > Real(0) && around[c] < midpoint[c])
      {
        mean[c] = m[c];
        bound[c] = around[c];
      }
    }
    if (this->Fits(bound))
    {
      colour += this->Ta *
        (mean * (Real(1) - this->E) + (whole - mean * theta) * ((Real(1) + this->E) / Real(2)));
      return true;
    }
    // Degree 6 where every extinction is linear in its scalar (the
    // extinction model), 12 otherwise.
    for (int t = 0; t < this->Count; ++t)
    {
      const auto& e = *this->Terms[t].Extinction;
      if (e.TauCurvature != Real(0) || e.TauCubic != Real(0))
      {
        return this->SeriesOf<13>(colour);
      }
    }
    return this->SeriesOf<7>(colour);
  }

  // Whether (1 - E) / 2 `bound` (of int |r_c|, each channel) fits half the
  // share.
  bool Fits(const glm::vec<3, Real>& bound) const
  {
    const Real worst = std::max({ bound.x, bound.y, bound.z });
    return worst * this->Ta * (Real(1) - this->E) <= this->Share();
  }

  // max |C_c - m_c| over the piece for a colour monotone on it (extremes at
  // the ends).
  glm::vec<3, Real> ColourSpread(const PieceColour<Real>& pc, const glm::vec<3, Real>& m) const
  {
    const glm::vec<3, Real> c0 = pc.A + pc.B * pc.At(Real(0));
    const glm::vec<3, Real> cl = pc.A + pc.B * pc.At(this->L);
    return glm::max(glm::abs(c0 - m), glm::abs(cl - m));
  }

  // int |r_c| <= sum_t int w_t tau_t |C_tc - m_c| <= sum_t theta_t max |C_tc - m_c|.
  glm::vec<3, Real> SpreadAround(const glm::vec<3, Real>& m) const
  {
    glm::vec<3, Real> spread(Real(0));
    for (int t = 0; t < this->Count; ++t)
    {
      spread += this->Theta[t] * this->ColourSpread(this->Terms[t].Colour, m);
    }
    return spread;
  }

  // int |r_c| for the mean m_c term by term: with each term's mean colour
  // m_tc = W_tc / theta_t and its share of the extinction rho_t = w_t tau_t /
  // tau (mean rho_t = theta_t / theta over the piece), K_t = int w_t tau_t
  // e^{-theta} = rho_t (1 - E) + Q_t, the Q_t summing to 0, so
  //   int E_c e^{-theta} - m_c (1 - E) = sum_t (m_tc - mu) Q_t
  //     + sum_t int w_t tau_t (C_tc - m_tc) e^{-theta}
  // for any mu; each sum of the right vanishes without e^{-theta}, so (as
  // above) |Q_t| <= (1 - E) / 2 theta (rho_t's range over the piece) and the
  // last term is within (1 - E) / 2 theta_t max |C_tc - m_tc|. rho_t's range
  // comes from the ranges of the terms' extinctions (ExtinctionRange); mu is
  // the m_uc that gives the least.
  // Where even the colours' own spreads (the first sum) leave the bound
  // above the share, the ranges are not sought: `fallback` is returned.
  glm::vec<3, Real> SplitSpread(const glm::vec<3, Real>* wholes, Real theta,
    const glm::vec<3, Real>& midpoint, const glm::vec<3, Real>& fallback) const
  {
    glm::vec<3, Real> own(Real(0)), means[MaximumComponents];
    for (int t = 0; t < this->Count; ++t)
    {
      means[t] = this->Theta[t] > Real(0) ? wholes[t] / this->Theta[t] : glm::vec<3, Real>(Real(0));
      own += this->Theta[t] * this->ColourSpread(this->Terms[t].Colour, means[t]);
    }
    if (!this->Fits(glm::min(midpoint, own)))
    {
      return fallback;
    }
    Real lo[MaximumComponents], hi[MaximumComponents], shares[MaximumComponents];
    for (int t = 0; t < this->Count; ++t)
    {
      ExtinctionRange(this->Terms[t], this->L, lo[t], hi[t]);
    }
    for (int t = 0; t < this->Count; ++t)
    {
      Real otherLo = Real(0), otherHi = Real(0);
      for (int u = 0; u < this->Count; ++u)
      {
        otherLo += u == t ? Real(0) : lo[u];
        otherHi += u == t ? Real(0) : hi[u];
      }
      // rho_t = A / (A + B) rises with A and falls with B.
      const Real least = lo[t] + otherHi > Real(0) ? lo[t] / (lo[t] + otherHi) : Real(0);
      const Real most = hi[t] + otherLo > Real(0) ? hi[t] / (hi[t] + otherLo) : Real(1);
      shares[t] = std::max(most - least, Real(0));
    }
    glm::vec<3, Real> between(std::numeric_limits<Real>::infinity());
    for (int u = 0; u < this->Count; ++u)
    {
      glm::vec<3, Real> sum(Real(0));
      for (int t = 0; t < this->Count; ++t)
      {
        sum += glm::abs(means[t] - means[u]) * shares[t];
      }
      between = glm::min(between, sum);
    }
    return own + theta * between;
  }

  // W_c = int_0^l E_c, E_c(v) = sum_t w_t tau_t(v) (a_tc + b_tc x_tc(v)), by
  // 7-point Gauss-Legendre, exact for E_c's degree (at most 12), and each
  // term's W_tc in `wholes`: a term's sum of weighted extinctions and, of one
  // colour scalar, its moment serve every channel.
  glm::vec<3, Real> EmissionIntegrals(glm::vec<3, Real>* wholes) const
  {
    const Real half = Real(0.5) * this->L;
    glm::vec<3, Real> whole(Real(0));
    for (int t = 0; t < this->Count; ++t)
    {
      const Real* wtau = this->WeightedTau[t];
      const PieceColour<Real>& pc = this->Terms[t].Colour;
      Real moment[3];
      for (int c = 0; c < pc.Sources; ++c)
      {
        const Cubic<Real>& x = pc.X[c];
        moment[c] = Real(0);
        for (int i = 0; i < 7; ++i)
        {
          moment[c] += wtau[i] * x(this->Nodes[i]);
        }
      }
      for (int c = 0; c < 3; ++c)
      {
        wholes[t][c] =
          half * (pc.A[c] * this->TauSum[t] + pc.B[c] * moment[pc.Sources == 1 ? 0 : c]);
      }
      whole += wholes[t];
    }
    return whole;
  }

  // The emissions as polynomials of M coefficients, integrated against
  // e^{-theta} by SeriesIntegrals.
  template <int M>
  bool SeriesOf(glm::vec<3, Real>& colour) const
  {
    // E_c(v) = sum_t w_t tau_t(v) (a_tc + b_tc x_tc(v)).
    Real emission[3][M] = {};
    for (int t = 0; t < this->Count; ++t)
    {
      const PieceTerm<Real>& term = this->Terms[t];
      const Polynomial<Real, 10> tau = ExtinctionPolynomial(*term.Extinction, term.D);
      const PieceColour<Real>& pc = term.Colour;
      for (int c = 0; c < 3; ++c)
      {
        const Cubic<Real>& x = pc.Of(c);
        const Real C[4] = { pc.A[c] + pc.B[c] * x.K[0], pc.B[c] * x.K[1], pc.B[c] * x.K[2],
          pc.B[c] * x.K[3] };
        for (int i = 0; i + 3 < M; ++i)
        {
          const Real wt = term.Weight * tau.C[i];
          for (int k = 0; k < 4; ++k)
          {
            emission[c][i + k] += wt * C[k];
          }
        }
      }
    }
    Real I[3];
    if (!this->Series(emission, this->Budget / (Real(2) * this->Ta), I))
    {
      return false;
    }
    for (int c = 0; c < 3; ++c)
    {
      colour[c] += this->Ta * I[c];
    }
    return true;
  }

  // What the piece's remainder may err by, times 2: budget (Ta (1 - E) + l / L).
  Real Share() const
  {
    return this->Budget * (this->Ta * (Real(1) - this->E) + this->L * this->InverseL);
  }

  // SeriesIntegrals on the piece, sub-interval [v, v + h] allowed
  // scale (Ta (Ev - Eh) + h / L).
  template <int N, int M>
  bool Series(const Real (&g)[N][M], Real scale, Real (&out)[N]) const
  {
    const Real front = this->Ta, inverseL = this->InverseL;
    auto allowed = [&](Real Ev, Real Eh, Real h)
    { return scale * (front * (Ev - Eh) + h * inverseL); };
    return SeriesIntegrals(this->Depth(), g, this->L, this->E, allowed, this->Stats, out);
  }

  // theta's polynomial, built where the series needs it.
  const PieceDepth<Real>& Depth() const
  {
    if (!this->HasDepth)
    {
      this->Summed = TermDepth(this->Terms[0]);
      for (int t = 1; t < this->Count; ++t)
      {
        this->Summed.Add(TermDepth(this->Terms[t]), Real(1));
      }
      this->HasDepth = true;
    }
    return this->Summed;
  }

  static PieceDepth<Real> TermDepth(const PieceTerm<Real>& term)
  {
    const auto& e = *term.Extinction;
    const Real w = term.Weight;
    return PieceDepth<Real>(term.D, w * e.Tau, w * e.TauSlope, w * e.TauCurvature, w * e.TauCubic);
  }

  const PieceTerm<Real>* Terms;
  int Count;
  Real L, Ta, Budget, InverseL;
  Real E = Real(1);
  RayStatistics<Real>& Stats;
  // Several terms: 7-point Gauss-Legendre's nodes on [0, l], each term's w
  // tau times the node's weight there and their sum, its depth theta_t(l)
  // (that sum times l / 2, at least 0), and the terms' total theta(l).
  Real Nodes[7];
  Real WeightedTau[MaximumComponents][7];
  Real TauSum[MaximumComponents];
  Real Theta[MaximumComponents];
  Real TotalTheta = Real(0);
  mutable PieceDepth<Real> Summed;
  mutable bool HasDepth = false;
};
} // namespace detail

namespace detail
{
// One ray of IntegratePiecewiseMixture, a cell at a time: the cell's
// components (corners, ranges, cubics), its cuts, its pieces composited
// front to back.
template <typename Real, typename VolumeT>
class MixtureRay
{
public:
  using Term = typename PiecewiseMixture<Real>::Term;

  MixtureRay(const ComponentVolumes<Real, VolumeT>& volumes, const glm::vec<3, Real>& origin,
    const glm::vec<3, Real>& direction, const PiecewiseMixture<Real>& mixture, Real tolerance,
    Real L, bool earlyTermination, RayResult<Real>& result)
    : Volumes(volumes)
    , Origin(origin)
    , Direction(direction)
    , Mixture(mixture)
    , Budget(Real(0.6) * tolerance)
    , TerminationBound(earlyTermination
          ? Real(0.15) * tolerance / std::max(Real(1), mixture.GetMaximumColor())
          : Real(-1))
    , InverseL(Real(1) / L)
    , Result(result)
  {
  }

  // The cells of [tBegin, tEnd]; false once the ray stopped (early
  // termination, or an error in Result).
  bool Segment(Real tBegin, Real tEnd)
  {
    return CellWalk(this->Volumes, this->Origin, this->Direction, tBegin, tEnd,
      [this](const int* cell, Real t0, Real t1) { return this->Cell(cell, t0, t1); });
  }

  void Finish() { PiecewiseRGBA(this->Colour, this->T, this->Result); }

private:
  bool Cell(const int* cell, Real t0, Real t1)
  {
    const int components = this->Volumes.GetNumberOfComponents();
    unsigned finite = 0;
    for (int k = 0; k < components; ++k)
    {
      if (!this->Mixture.Reads(k))
      {
        continue;
      }
      Real* c = this->Corners[k];
      this->Volumes[k].GetCorners(cell[0], cell[1], cell[2], c);
      Real lo = c[0], hi = c[0];
      for (int i = 1; i < 8; ++i)
      {
        lo = std::min(lo, c[i]);
        hi = std::max(hi, c[i]);
      }
      this->Lo[k] = lo;
      this->Hi[k] = hi;
      // Finite only when every corner is (a NaN escapes min and max).
      const bool ok = std::isfinite(c[0] + c[1] + c[2] + c[3] + c[4] + c[5] + c[6] + c[7]);
      finite |= ok ? (1u << k) : 0u;
    }
    // The terms that can show in the cell: their components finite, their
    // extinction not zero over the corners' range.
    int count = 0;
    unsigned used = 0;
    for (const Term& t : this->Mixture.GetTerms())
    {
      const unsigned needs = (1u << t.Opacity) | (t.Direct ? 7u : (1u << t.Colour));
      if ((finite & needs) != needs)
      {
        continue;
      }
      const auto range = t.Pieces->ClassifyRange(this->Lo[t.Opacity], this->Hi[t.Opacity]);
      if (range.Visible)
      {
        this->Visible[count] = &t;
        this->Range[count] = range;
        this->ColourRange[count] = t.Direct || t.Colour == t.Opacity
          ? range
          : t.Pieces->ClassifyRange(this->Lo[t.Colour], this->Hi[t.Colour]);
        ++count;
        used |= needs;
      }
    }
    if (count == 0)
    {
      return true;
    }
    ++this->Result.Statistics.Cells;
    const glm::vec<3, Real> entry = this->Origin + t0 * this->Direction -
      glm::vec<3, Real>(Real(cell[0]), Real(cell[1]), Real(cell[2]));
    const Real length = t1 - t0;
    for (int k = 0; k < components; ++k)
    {
      if ((used >> k) & 1u)
      {
        this->S[k] = CellCubic(this->Corners[k], entry, this->Direction);
      }
    }
    // Cuts: the crossings sought, each on a monotone stretch (cut at the
    // cubic's extrema), and the extrema of every colour cubic (the
    // remainder's bounds take it monotone).
    this->Cuts.assign({ Real(0), length });
    unsigned stretched = 0, monotone = 0;
    for (int i = 0; i < count; ++i)
    {
      const Term& t = *this->Visible[i];
      if (this->Range[i].Crossings)
      {
        this->Crossings(this->S[t.Opacity], *t.Pieces, length, true);
        stretched |= 1u << t.Opacity;
      }
      if (!t.Direct && t.Colour != t.Opacity && this->ColourRange[i].Crossings)
      {
        this->Crossings(this->S[t.Colour], *t.Pieces, length, false);
        stretched |= 1u << t.Colour;
      }
      monotone |= t.Direct ? 7u : (1u << t.Colour);
    }
    for (int k = 0; k < components; ++k)
    {
      if (((monotone & ~stretched) >> k) & 1u)
      {
        Real extrema[2];
        const int n = Extrema(this->S[k], length, extrema);
        this->Cuts.insert(this->Cuts.end(), extrema, extrema + n);
      }
    }
    if (this->Cuts.size() > 2)
    {
      std::sort(this->Cuts.begin(), this->Cuts.end());
    }
    for (std::size_t i = 0; i + 1 < this->Cuts.size(); ++i)
    {
      const Real u = this->Cuts[i], next = this->Cuts[i + 1];
      if (next > u && !this->Piece(t0, u, next, count))
      {
        return false;
      }
    }
    return true;
  }

  // The extrema of the cubic s inside [0, length], and the crossings of the
  // knots of `pieces` by s on each monotone stretch between them, into
  // Cuts; `visibleOnly`: only those that
  // bound a visible piece of it (a knot between two transparent pieces
  // bounds nothing its term shows), else all (a colour's).
  void Crossings(const Cubic<Real>& s, const PiecewiseTransferFunction<Real>& pieces, Real length,
    bool visibleOnly)
  {
    const std::vector<Real>& knots = pieces.GetKnots();
    Real bounds[4];
    const int count = StretchBounds(s, length, bounds);
    this->Cuts.insert(this->Cuts.end(), bounds + 1, bounds + count - 1);
    for (int b = 0; b + 1 < count; ++b)
    {
      const Stretch<Real> st(s, bounds[b], bounds[b + 1], pieces);
      for (std::size_t j = visibleOnly ? st.Useful(pieces, 0) : 0; j < st.Inside;
           j = visibleOnly ? st.Useful(pieces, j + 1) : j + 1)
      {
        this->Cuts.push_back(Crossing(s, st.Value(knots, j), st.A, st.B));
      }
    }
  }

  // The piece [u, next] of the cell entered at t0 with the first `count`
  // Visible terms; false once the ray stops.
  bool Piece(Real t0, Real u, Real next, int count)
  {
    const Real middle = Real(0.5) * (u + next), l = next - u;
    PieceTerm<Real> terms[MaximumComponents];
    int n = 0;
    for (int i = 0; i < count; ++i)
    {
      const Term& t = *this->Visible[i];
      const PiecewiseTransferFunction<Real>& pieces = *t.Pieces;
      // In a cell without crossings, the corners' lowest value's piece.
      const std::size_t first = this->Range[i].First;
      const std::size_t p =
        this->Range[i].Crossings ? pieces.LocateNear(this->S[t.Opacity](middle), first) : first;
      if (!pieces.IsVisible(p))
      {
        continue;
      }
      PieceTerm<Real>& term = terms[n++];
      term.Weight = t.Weight;
      term.Extinction = &pieces[p];
      term.D = this->S[t.Opacity].Shifted(u);
      term.D.K[0] -= pieces[p].Start;
      PieceColour<Real>& pc = term.Colour;
      if (t.Direct)
      {
        pc.A = glm::vec<3, Real>(Real(0));
        pc.B = glm::vec<3, Real>(this->Mixture.GetScale());
        pc.Sources = 3;
        for (int c = 0; c < 3; ++c)
        {
          pc.X[c] = this->S[c].Shifted(u);
        }
        continue;
      }
      const std::size_t firstColour = this->ColourRange[i].First;
      const std::size_t q = t.Colour == t.Opacity ? p
        : this->ColourRange[i].Crossings ? pieces.LocateNear(this->S[t.Colour](middle), firstColour)
                                         : firstColour;
      const auto& colour = pieces[q];
      pc.A = colour.Colour;
      pc.B = colour.ColourSlope;
      pc.Sources = 1;
      pc.X[0] = this->S[t.Colour].Shifted(u);
      pc.X[0].K[0] -= colour.Start;
    }
    if (n == 0)
    {
      return true;
    }
    RayStatistics<Real>& stats = this->Result.Statistics;
    ++stats.Pieces;
    ++stats.Samples;
    stats.Accept(l);
    const MixturePiece<Real> piece(terms, n, l, this->T, this->Budget, this->InverseL, stats);
    const Real E = piece.Transmittance();
    if (!piece.Integrate(this->Colour))
    {
      this->Result.Error = RefusedPieceError;
      return false;
    }
    this->T *= E;
    if (stats.Steps)
    {
      stats.Steps->push_back({ t0 + u, l, Real(1) - this->T });
    }
    if (this->T <= this->TerminationBound)
    {
      stats.Terminated = true;
      return false;
    }
    return true;
  }

  const ComponentVolumes<Real, VolumeT>& Volumes;
  const glm::vec<3, Real> Origin, Direction;
  const PiecewiseMixture<Real>& Mixture;
  const Real Budget, TerminationBound, InverseL;
  RayResult<Real>& Result;
  glm::vec<3, Real> Colour{ Real(0) };
  Real T = Real(1);
  // The cell's.
  Real Corners[MaximumComponents][8];
  Real Lo[MaximumComponents], Hi[MaximumComponents];
  Cubic<Real> S[MaximumComponents];
  // The terms that show in the cell, with the classes of their opacity's
  // and their colour's ranges.
  const Term* Visible[MaximumComponents];
  typename PiecewiseTransferFunction<Real>::RangeClass Range[MaximumComponents],
    ColourRange[MaximumComponents];
  std::vector<Real> Cuts;
};
} // namespace detail

// The piecewise method through a mixture (see above): the ray origin +
// t direction (the components' walk coordinates) over `segments`, within
// `tolerance` per channel. `steps`, when given, receives the pieces.
template <typename Real, typename VolumeT>
RayResult<Real> IntegratePiecewiseMixture(const ComponentVolumes<Real, VolumeT>& volumes,
  const glm::vec<3, Real>& origin, const glm::vec<3, Real>& direction,
  const Interval<Real>* segments, std::size_t count, const PiecewiseMixture<Real>& mixture,
  Real tolerance, bool earlyTermination = true,
  std::vector<StepRecord<detail::NotDeduced<Real>>>* steps = nullptr)
{
  RayResult<Real> result;
  result.Statistics.Steps = steps;
  Real L = Real(0);
  result.Error = ValidatePiecewiseTolerance(tolerance, OpacityModel::Extinction);
  if (result.Error.empty() && mixture.GetNumberOfComponents() != volumes.GetNumberOfComponents())
  {
    result.Error = "the mixture was not built for these components";
  }
  for (int a = 0; a < 3 && result.Error.empty(); ++a)
  {
    if (volumes.GetDimension(a) < 2)
    {
      result.Error = "the volume needs at least 2 points along each axis";
    }
  }
  if (result.Error.empty())
  {
    result.Error = detail::ValidatePiecewiseRay(origin, direction, segments, count, L);
  }
  if (!result.Error.empty() || !(L > Real(0)))
  {
    return result;
  }
  if (const PiecewiseTransferFunction<Real>* single = mixture.GetSingle())
  {
    return IntegratePiecewise(volumes[mixture.GetSingleComponent()], origin, direction, segments,
      count, *single, tolerance, earlyTermination, steps);
  }
  detail::MixtureRay<Real, VolumeT> ray(
    volumes, origin, direction, mixture, tolerance, L, earlyTermination, result);
  bool going = true;
  for (std::size_t j = 0; j < count && going; ++j)
  {
    going = ray.Segment(segments[j].Begin, segments[j].End);
  }
  if (result.Error.empty())
  {
    ray.Finish();
  }
  return result;
}

} // namespace numerics
} // namespace avos

#endif
