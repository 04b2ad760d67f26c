// Gradient shading of the emission, as VTK's volume mappers light a sample
// (Blinn-Phong with the property's ambient, diffuse, specular and specular
// power, the renderer's lights):
//
//   C'(x) = clamp(C(s) (ka + kd sum_l A_l D_l f(n.l)) + ks sum_l A_l S_l f(n.h_l)^p, 0, 1)
//
// per RGB channel, n the unit gradient of the scalar field at x (world
// space), l the unit direction from x towards light l, h_l = normalize(l +
// v), v the unit direction towards the viewer, D_l and S_l the light's
// diffuse and specular colours times its intensity, f(c) = |c| with two-sided
// lighting (VTK's default), max(0, c) otherwise. A directional light has one
// l everywhere and A_l = 1. A positional light at P (vtkLight's
// PositionalOn) has l = (P - x) / d, d = |P - x|, and the attenuation A_l =
// 1 / (a0 + a1 d + a2 d^2) of its attenuation values; a spot (its cone angle
// below 90 degrees, as vtkLight documents: 90 or more is a positional light
// without a cone) multiplies A_l by (-l.a)^e inside its cone (-l.a >= cos of
// the cone angle, a the unit axis from P towards the light's focal point, e
// its exponent) and by 0 outside, as VTK's GPU mapper does. Where the
// gradient vanishes there is no normal: the sample is lit by the ambient
// term only. The emission in the volume rendering integral becomes tau(s)
// C'(x): the optical depth is unchanged.
//
// The gradient is that of the trilinear interpolant, exact (a polynomial in
// the cell; TrilinearVolume::Gradient), not central differences of the grid
// values, and not quantised as VTK's fixed-point mapper's encoded normals.
// The clamp keeps every channel of a ray in [0, 1] and keeps the integrators'
// early-termination bound (which assumes a colour of at most max(1, max C))
// valid. The shaded integrand is smooth except where the gradient vanishes,
// changes cell, a spot's cone is crossed, or a max(0, .) or the clamp
// switches: the adaptive rules control its error as they do the unshaded
// one's (by Simpson's estimate), the piecewise method proves it
// (PiecewiseShading.h, with LitColour on Taylor models).
#ifndef avos_numerics_Shading_h
#define avos_numerics_Shading_h

#include "avos/numerics/TaylorModel.h"
#include "avos/numerics/Volume.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace avos
{
namespace numerics
{

// A light in world space, as vtkLight describes it.
template <typename Real>
struct Light
{
  using Vector = glm::vec<3, Real>;
  Vector Direction; // directional: unit, from the scene towards the light
  Vector Diffuse;   // colour times intensity
  Vector Specular;  // colour times intensity
  bool Positional = false;
  // Positional: the light's position, its attenuation values (a0, a1, a2),
  // and, for a spot (ConeAngle < 90 degrees), the unit axis from the
  // position towards the focal point and the exponent.
  Vector Position{ Real(0) };
  Vector Attenuation{ Real(1), Real(0), Real(0) };
  Real ConeAngle = Real(180);
  Real Exponent = Real(1);
  Vector Axis{ Real(0), Real(0), Real(-1) };

  bool IsSpot() const { return this->Positional && this->ConeAngle < Real(90); }

  // The largest attenuation A_l anywhere: 1, or 1 / a0 (the spot's factor
  // is at most 1).
  Real MaximumAttenuation() const
  {
    return this->Positional ? Real(1) / this->Attenuation[0] : Real(1);
  }
};

template <typename Real>
struct ShadingModel
{
  using Vector = glm::vec<3, Real>;

  Real Ambient = Real(0.1);
  Real Diffuse = Real(0.7);
  Real Specular = Real(0.2);
  Real SpecularPower = Real(10);
  bool TwoSided = true;
  std::vector<Light<Real>> Lights;

  // Empty, or why the model cannot be used.
  std::string Validate() const
  {
    for (Real k : { this->Ambient, this->Diffuse, this->Specular, this->SpecularPower })
    {
      if (!(k >= Real(0)) || !std::isfinite(k))
      {
        return "the shading coefficients and the specular power must be finite and >= 0";
      }
    }
    for (const Light<Real>& light : this->Lights)
    {
      if (light.Positional)
      {
        const std::string invalid = ValidatePositional(light);
        if (!invalid.empty())
        {
          return invalid;
        }
      }
      else if (!(std::abs(glm::length(light.Direction) - Real(1)) < Real(1e-6)))
      {
        return "a light's direction must be a unit vector";
      }
      for (int c = 0; c < 3; ++c)
      {
        if (!(light.Diffuse[c] >= Real(0)) || !(light.Specular[c] >= Real(0)) ||
          !std::isfinite(light.Diffuse[c]) || !std::isfinite(light.Specular[c]))
        {
          return "a light's colours must be finite and >= 0";
        }
      }
    }
    return std::string();
  }

  bool HasPositionalLights() const
  {
    return std::any_of(this->Lights.begin(), this->Lights.end(),
      [](const Light<Real>& light) { return light.Positional; });
  }

  // The most a channel of the lit colour changes per unit change of the
  // sample's colour: ka + kd max_c sum_l max A_l D_l,c (the clamp does not
  // enlarge it), so a colour within delta of the transfer function's is lit
  // within ColourGain() delta.
  Real ColourGain() const
  {
    Real gain = Real(0);
    for (int c = 0; c < 3; ++c)
    {
      Real sum = Real(0);
      for (const Light<Real>& light : this->Lights)
      {
        sum += light.MaximumAttenuation() * light.Diffuse[c];
      }
      gain = std::max(gain, sum);
    }
    return this->Ambient + this->Diffuse * gain;
  }

  // The lit colour of a sample at world position `position` of colour
  // `color` whose world-space gradient is `gradient`, seen from the unit
  // direction `toViewer`.
  Vector Shade(const Vector& color, const Vector& gradient, const Vector& toViewer,
    const Vector& position) const
  {
    const Real c[3] = { color.r, color.g, color.b };
    const Real g[3] = { gradient.x, gradient.y, gradient.z };
    const Real x[3] = { position.x, position.y, position.z };
    Real lit[3];
    LitColour(*this, c, g, toViewer, x, lit);
    return Vector(lit[0], lit[1], lit[2]);
  }

private:
  static std::string ValidatePositional(const Light<Real>& light)
  {
    const Vector& a = light.Attenuation;
    if (!(a[0] > Real(0)) || !(a[1] >= Real(0)) || !(a[2] >= Real(0)) || !std::isfinite(a[0]) ||
      !std::isfinite(a[1]) || !std::isfinite(a[2]))
    {
      return "a positional light's attenuation values must be finite and >= 0, the constant one "
             "> 0 (1 / (a0 + a1 d + a2 d^2) is unbounded at the light otherwise)";
    }
    if (!std::isfinite(light.Position.x) || !std::isfinite(light.Position.y) ||
      !std::isfinite(light.Position.z))
    {
      return "a positional light's position must be finite";
    }
    if (light.IsSpot() &&
      (!(light.ConeAngle > Real(0)) || !(light.Exponent >= Real(0)) ||
        !std::isfinite(light.Exponent) ||
        !(std::abs(glm::length(light.Axis) - Real(1)) < Real(1e-6))))
    {
      return "a spot light needs a cone angle in (0, 90) degrees, a finite exponent >= 0 and a "
             "unit axis (its position and focal point must differ)";
    }
    return std::string();
  }
};

namespace detail
{
// The model's operations on plain numbers and on Taylor models
// (TaylorModel.h), so that one LitColour gives a sample's colour and its
// enclosure over an interval. A model crossing a kink (|x| or max(0, x) at 0,
// the clamp at 0 or 1) keeps its polynomial and takes the kink's excess into
// its remainder.
enum class Sign
{
  Zero,
  Positive,
  Either // a model whose values hold 0 and positive ones
};

// Whether the gradient g, of squared length `squared`, vanishes.
template <typename Real>
Sign GradientSign(const Real*, Real squared)
{
  return squared > Real(0) && std::isfinite(squared) ? Sign::Positive : Sign::Zero;
}

// A model's range is rounded outward, so a gradient whose components are the
// constant 0 (a cell of equal corners) is tested on them.
template <typename Real, int N>
Sign GradientSign(const TaylorModel<Real, N>* g, const TaylorModel<Real, N>& squared)
{
  const Bounds<Real> range = squared.Range();
  if (range.Lo > Real(0) && std::isfinite(range.Hi))
  {
    return Sign::Positive;
  }
  bool zero = true;
  for (int k = 0; k < 3; ++k)
  {
    zero = zero && g[k].R == Real(0) &&
      std::all_of(g[k].A, g[k].A + N + 1, [](Real a) { return a == Real(0); });
  }
  return zero || range.Hi <= Real(0) ? Sign::Zero : Sign::Either;
}

template <typename Real>
Real InverseSqrt(Real x)
{
  return Real(1) / std::sqrt(x);
}

template <typename Real, int N>
TaylorModel<Real, N> InverseSqrt(const TaylorModel<Real, N>& x)
{
  return Pow(x, Real(-0.5));
}

// A cosine: n.l or n.h, in [-1, 1] whatever its enclosure says (a model over
// a stretch where the gradient nearly vanishes may be far wider, or unknown).
template <typename Real>
Real Cosine(Real x)
{
  return x;
}

template <typename Real, int N>
TaylorModel<Real, N> Cosine(const TaylorModel<Real, N>& x)
{
  return Clamp(x, Real(-1), Real(1));
}

// |x| (two-sided lighting) or max(0, x).
template <typename Real>
Real Facing(Real x, bool twoSided)
{
  return twoSided ? std::abs(x) : std::max(x, Real(0));
}

template <typename Real, int N>
TaylorModel<Real, N> Facing(const TaylorModel<Real, N>& x, bool twoSided)
{
  return twoSided ? Abs(x) : PositivePart(x);
}

// x^p for x >= 0, 0 at x = 0 (as VTK's mappers skip a facing term of 0).
template <typename Real>
Real FacingPower(Real x, Real p)
{
  return x > Real(0) ? std::pow(x, p) : Real(0);
}

// The same but at the single point x = 0 when p = 0 (1 there): no integral
// sees a point. A whole power whose base's range reaches 0 (a highlight's
// n.h near a kink) by squaring, which needs no expansion point.
template <typename Real, int N>
TaylorModel<Real, N> FacingPower(const TaylorModel<Real, N>& x, Real p)
{
  if (p >= Real(1) && p <= Real(4096) && p == std::floor(p) && !(x.Range().Lo > Real(0)))
  {
    return WholePower(x, static_cast<unsigned>(p));
  }
  return Pow(x, p);
}

template <typename Real>
Real Clamp01(Real x)
{
  return std::min(std::max(x, Real(0)), Real(1));
}

template <typename Real, int N>
TaylorModel<Real, N> Clamp01(const TaylorModel<Real, N>& x)
{
  return Clamp(x, Real(0), Real(1));
}

template <typename Real>
Real Reciprocal(Real x)
{
  return Real(1) / x;
}

template <typename Real, int N>
TaylorModel<Real, N> Reciprocal(const TaylorModel<Real, N>& x)
{
  return Pow(x, Real(-1));
}

// Whether a squared length vanishes, so that a sample has no direction to
// normalise (at a light's position, or where l = -v). A model's enclosure
// takes such points in (its remainder becomes infinite and the clamp or
// Cosine bounds it): never for models.
template <typename Real>
bool Vanishes(Real squared)
{
  return !(squared > Real(0));
}

template <typename Real, int N>
bool Vanishes(const TaylorModel<Real, N>&)
{
  return false;
}

template <typename Real>
Real Either(Real a, Real)
{
  return a;
}

// The hull of two cases, where either may hold.
template <typename Real, int N>
TaylorModel<Real, N> Either(const TaylorModel<Real, N>& a, const TaylorModel<Real, N>& b)
{
  return Hull(a, b);
}

// x times the constant w, x itself where w is 1 (a model's product adds its
// rounding to the remainder).
template <typename T, typename Real>
T Scaled(const T& x, Real w)
{
  return w == Real(1) ? x : x * w;
}
} // namespace detail

namespace detail
{
// The unit direction l from the sample x (world) towards a positional light,
// and the light's attenuation there (times the spot's factor); both 0 at the
// light's position, where l is undefined (no integral sees a point).
template <typename Real, typename T>
void TowardsLight(const Light<Real>& light, const T x[3], T l[3], T& attenuation)
{
  const T L[3] = { light.Position.x - x[0], light.Position.y - x[1], light.Position.z - x[2] };
  const T squared = L[0] * L[0] + L[1] * L[1] + L[2] * L[2];
  if (Vanishes(squared))
  {
    l[0] = l[1] = l[2] = attenuation = T(Real(0));
    return;
  }
  const T inverse = InverseSqrt(squared);
  for (int k = 0; k < 3; ++k)
  {
    l[k] = L[k] * inverse;
  }
  const Real* a = &light.Attenuation[0];
  attenuation = Reciprocal(a[0] + a[1] * (squared * inverse) + a[2] * squared);
  if (light.IsSpot())
  {
    const T cone = -(l[0] * light.Axis.x + l[1] * light.Axis.y + l[2] * light.Axis.z);
    const Real exponent = light.Exponent;
    attenuation = attenuation *
      Cases(
        cone, std::cos(light.ConeAngle * Real(3.14159265358979323846) / Real(180)),
        [](const T&) { return T(Real(0)); },
        [exponent](const T& c) { return FacingPower(c, exponent); });
  }
}

// f(n.h), h = half / |half| (0 where half vanishes: l = -v).
template <typename Real, typename T>
T HalfwayFacing(const T n[3], const T half[3], bool twoSided)
{
  const T squared = half[0] * half[0] + half[1] * half[1] + half[2] * half[2];
  if (Vanishes(squared))
  {
    return T(Real(0));
  }
  return Facing(
    Cosine((n[0] * half[0] + n[1] * half[1] + n[2] * half[2]) * InverseSqrt(squared)), twoSided);
}
} // namespace detail

namespace detail
{
// A gradient given by its components, as LitColour reads a gradient: its
// squared length, its dot product with a constant direction, its components
// (for positional lights), and whether it vanishes.
template <typename Real, typename T>
struct GradientComponents
{
  const T* G;

  T Squared() const
  {
    return this->G[0] * this->G[0] + this->G[1] * this->G[1] + this->G[2] * this->G[2];
  }
  T Dot(const glm::vec<3, Real>& w) const
  {
    return this->G[0] * w.x + this->G[1] * w.y + this->G[2] * w.z;
  }
  void Components(T g[3]) const { std::copy(this->G, this->G + 3, g); }
  Sign SignOf(const T& squared) const { return GradientSign(this->G, squared); }
};
} // namespace detail

// The lit colour of ShadingModel::Shade, channel by channel, on plain numbers
// (T = Real) or on Taylor models (an enclosure of the lit colour over an
// interval of the ray, each input a model in the same variable): `colour` the sample's
// colour, `gradient` its world-space gradient as detail::GradientComponents
// reads one (PiecewiseShading.h gives one from its polynomials), `toViewer`
// the unit direction towards the viewer, `position` the sample's world
// position (read only when a light is positional: may be null otherwise).
// n.l is (g.l) / |g|: one product per light and term.
template <typename Real, typename T, typename Gradient>
void LitColourOf(const ShadingModel<Real>& model, const T colour[3], const Gradient& gradient,
  const glm::vec<3, Real>& toViewer, const T* position, T lit[3])
{
  const T squared = gradient.Squared();
  const detail::Sign sign = gradient.SignOf(squared);
  if (sign == detail::Sign::Zero)
  {
    for (int c = 0; c < 3; ++c)
    {
      lit[c] = detail::Clamp01(model.Ambient * colour[c]);
    }
    return;
  }
  const T inverse = detail::InverseSqrt(squared);
  // The lights' diffuse and specular sums per channel: one for every channel
  // where each light is grey (VTK's are white unless coloured), as a model
  // costs an operation per channel and term.
  const bool grey = std::all_of(model.Lights.begin(), model.Lights.end(),
    [](const Light<Real>& light)
    {
      const glm::vec<3, Real>& d = light.Diffuse;
      const glm::vec<3, Real>& s = light.Specular;
      return d.x == d.y && d.y == d.z && s.x == s.y && s.y == s.z;
    });
  const int channels = grey ? 1 : 3;
  T diffuse[3] = { T(Real(0)), T(Real(0)), T(Real(0)) };
  T specular[3] = { T(Real(0)), T(Real(0)), T(Real(0)) };
  bool first = true;
  for (const Light<Real>& light : model.Lights)
  {
    T diffuseTerm, specularTerm;
    if (light.Positional)
    {
      T g[3], l[3], attenuation;
      gradient.Components(g);
      const T n[3] = { g[0] * inverse, g[1] * inverse, g[2] * inverse };
      detail::TowardsLight(light, position, l, attenuation);
      const T nl =
        detail::Facing(detail::Cosine(n[0] * l[0] + n[1] * l[1] + n[2] * l[2]), model.TwoSided);
      const T half[3] = { l[0] + toViewer.x, l[1] + toViewer.y, l[2] + toViewer.z };
      const T highlight = detail::FacingPower(
        detail::HalfwayFacing<Real>(n, half, model.TwoSided), model.SpecularPower);
      diffuseTerm = attenuation * nl;
      specularTerm = attenuation * highlight;
    }
    else
    {
      const glm::vec<3, Real>& l = light.Direction;
      diffuseTerm = detail::Facing(detail::Cosine(gradient.Dot(l) * inverse), model.TwoSided);
      const glm::vec<3, Real> half = l + toViewer;
      const Real halfLength = glm::length(half);
      const T nh = halfLength > Real(0)
        ? detail::Facing(detail::Cosine(gradient.Dot(half / halfLength) * inverse), model.TwoSided)
        : T(Real(0));
      specularTerm = detail::FacingPower(nh, model.SpecularPower);
    }
    for (int c = 0; c < channels; ++c)
    {
      const T d = detail::Scaled(diffuseTerm, light.Diffuse[c]);
      const T s = detail::Scaled(specularTerm, light.Specular[c]);
      diffuse[c] = first ? d : diffuse[c] + d;
      specular[c] = first ? s : specular[c] + s;
    }
    first = false;
  }
  // C (ka + kd D) + ks S, channel by channel.
  T factor[3], shine[3];
  for (int c = 0; c < channels; ++c)
  {
    factor[c] = model.Diffuse * diffuse[c] + model.Ambient;
    shine[c] = model.Specular * specular[c];
  }
  for (int c = 0; c < 3; ++c)
  {
    const int k = grey ? 0 : c;
    T value = colour[c] * factor[k] + shine[k];
    if (sign == detail::Sign::Either)
    {
      value = detail::Either(value, model.Ambient * colour[c]);
    }
    lit[c] = detail::Clamp01(value);
  }
}

// LitColourOf with the gradient's components.
template <typename Real, typename T>
void LitColour(const ShadingModel<Real>& model, const T colour[3], const T gradient[3],
  const glm::vec<3, Real>& toViewer, const T* position, T lit[3])
{
  LitColourOf(
    model, colour, detail::GradientComponents<Real, T>{ gradient }, toViewer, position, lit);
}

// The shading of one ray: the model, the normal matrix that maps a gradient
// in the volume's grid coordinates to world space, the unit direction
// towards the viewer (constant along the ray), and the ray in world space
// (the sample at t is at WorldOrigin + t WorldDirection; positional lights
// read it).
template <typename Real>
struct RayShading
{
  const ShadingModel<Real>* Model = nullptr;
  glm::mat<3, 3, Real> NormalMatrix{ Real(1) };
  glm::vec<3, Real> ToViewer{ Real(0), Real(0), Real(1) };
  glm::vec<3, Real> WorldOrigin{ Real(0) };
  glm::vec<3, Real> WorldDirection{ Real(0) };
};

// A ray through a trilinear volume whose emission is shaded: the `field`
// argument of IntegrateRiemann / IntegrateAdaptive (RayIntegrators.h), which
// call Shade() on every sample's colour, lit by the ray's `Shading`.
template <typename Real, typename VolumeT>
struct ShadedRayField
{
  using Vector = glm::vec<3, Real>;

  const VolumeT& Volume;
  Vector Origin;
  Vector Direction;
  RayShading<Real> Shading;

  Real operator()(Real t) const { return this->Volume(this->Origin + t * this->Direction); }

  Vector Shade(Real t, const Vector& color) const
  {
    const RayShading<Real>& s = this->Shading;
    const Vector gradient =
      s.NormalMatrix * this->Volume.Gradient(this->Origin + t * this->Direction);
    return s.Model->Shade(color, gradient, s.ToViewer, s.WorldOrigin + t * s.WorldDirection);
  }
};

} // namespace numerics
} // namespace avos

#endif
