// Gradient shading of the emission, as VTK's volume mappers light a sample
// (Blinn-Phong with the property's ambient, diffuse, specular and specular
// power, directional lights):
//
//   C'(x) = clamp(C(s) (ka + kd sum_l D_l max(0, n.l)) + ks sum_l S_l max(0, n.h_l)^p, 0, 1)
//
// per RGB channel, n the unit gradient of the scalar field at x (world
// space), l the unit direction towards light l, h_l = normalize(l + v), v the
// unit direction towards the viewer, D_l and S_l the light's diffuse and
// specular colours times its intensity. Two-sided lighting (VTK's default)
// takes |n.l| and |n.h|. Where the gradient vanishes there is no normal: the
// sample is lit by the ambient term only. The emission in the volume
// rendering integral becomes tau(s) C'(x): the optical depth is unchanged.
//
// The gradient is that of the trilinear interpolant, exact (a polynomial in
// the cell; TrilinearVolume::Gradient), not central differences of the grid
// values, and not quantised as VTK's fixed-point mapper's encoded normals.
// The clamp keeps every channel of a ray in [0, 1] and keeps the integrators'
// early-termination bound (which assumes a colour of at most max(1, max C))
// valid. The shaded integrand is smooth except where the gradient vanishes,
// changes cell, or a max(0, .) or the clamp switches: the adaptive rules
// control its error as they do the unshaded one's (by Simpson's estimate).
#ifndef avos_numerics_Shading_h
#define avos_numerics_Shading_h

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

template <typename Real>
struct DirectionalLight
{
  using Vector = glm::vec<3, Real>;
  Vector Direction; // unit, from the scene towards the light, world space
  Vector Diffuse;   // colour times intensity
  Vector Specular;  // colour times intensity
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
  std::vector<DirectionalLight<Real>> Lights;

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
    for (const DirectionalLight<Real>& light : this->Lights)
    {
      const Real length = glm::length(light.Direction);
      if (!(std::abs(length - Real(1)) < Real(1e-6)))
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

  // The lit colour of a sample of colour `color` whose world-space gradient is
  // `gradient`, seen from the unit direction `toViewer`.
  Vector Shade(const Vector& color, const Vector& gradient, const Vector& toViewer) const
  {
    Vector lit = this->Ambient * color;
    const Real length = glm::length(gradient);
    if (length > Real(0) && std::isfinite(length))
    {
      const Vector n = gradient / length;
      Vector diffuse(Real(0)), specular(Real(0));
      for (const DirectionalLight<Real>& light : this->Lights)
      {
        Real nl = glm::dot(n, light.Direction);
        const Vector half = light.Direction + toViewer;
        const Real halfLength = glm::length(half);
        Real nh = halfLength > Real(0) ? glm::dot(n, half) / halfLength : Real(0);
        if (this->TwoSided)
        {
          nl = std::abs(nl);
          nh = std::abs(nh);
        }
        if (nl > Real(0))
        {
          diffuse += nl * light.Diffuse;
        }
        if (nh > Real(0))
        {
          specular += std::pow(nh, this->SpecularPower) * light.Specular;
        }
      }
      lit += this->Diffuse * diffuse * color + this->Specular * specular;
    }
    return glm::clamp(lit, Vector(Real(0)), Vector(Real(1)));
  }
};

// A ray through a trilinear volume whose emission is shaded: the `field`
// argument of IntegrateRiemann / IntegrateAdaptive (RayIntegrators.h), which
// call Shade() on every sample's colour. `NormalMatrix` maps a gradient in
// grid coordinates to world space (the transpose of the world-to-grid
// matrix's linear part); `ToViewer` is constant along a ray.
template <typename Real, typename VolumeT>
struct ShadedRayField
{
  using Vector = glm::vec<3, Real>;

  const VolumeT& Volume;
  Vector Origin;
  Vector Direction;
  glm::mat<3, 3, Real> NormalMatrix;
  Vector ToViewer;
  const ShadingModel<Real>& Model;

  Real operator()(Real t) const { return this->Volume(this->Origin + t * this->Direction); }

  Vector Shade(Real t, const Vector& color) const
  {
    const Vector gradient =
      this->NormalMatrix * this->Volume.Gradient(this->Origin + t * this->Direction);
    return this->Model.Shade(color, gradient, this->ToViewer);
  }
};

} // namespace numerics
} // namespace avos

#endif
