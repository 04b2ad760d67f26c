// Gradient opacity (vtkVolumeProperty::SetGradientOpacity): the scalar
// opacity scaled by a function G of the gradient's magnitude, in the
// sampled methods (RayIntegrators.h) and the piecewise one
// (PiecewiseGradientOpacity.h).
//
// At a sample, g = |NormalMatrix grad s| is the magnitude of the exact
// gradient of the trilinear interpolant in scalar units per world unit
// (NormalMatrix maps a gradient in grid coordinates to world space), G(g)
// the function's value there, clamped to [0, 1], and the extinction tau
// G(g), in both opacity models. VTK's mappers multiply each sample's
// opacity, corrected for their step h, by G: 1 - (1 - alpha)^(h / d) times
// G, which as h shrinks is tau h G: the same extinction.
#ifndef avos_numerics_GradientOpacity_h
#define avos_numerics_GradientOpacity_h

#include "avos/numerics/TransferFunction.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <string>

namespace avos
{
namespace numerics
{

template <typename Real>
struct GradientOpacity
{
  // G as the opacity knots of a transfer function over g (its colours
  // unused).
  const TransferFunction<Real>* Function = nullptr;
  glm::mat<3, 3, Real> NormalMatrix{ Real(1) };

  // Empty when usable, else why.
  std::string Validate() const
  {
    return this->Function ? this->Function->Validate() : "no gradient opacity function";
  }

  // G at the sample whose gradient is `gridGradient` (grid coordinates).
  Real Factor(const glm::vec<3, Real>& gridGradient) const
  {
    const Real g = glm::length(this->NormalMatrix * gridGradient);
    return std::min(std::max(this->Function->GetOpacityValue(g), Real(0)), Real(1));
  }
};

// A ray field (RayField, ShadedRayField) whose samples' extinction is scaled
// by gradient opacity: RayIntegrators.h's samplers call Modulate() on every
// sample's tau.
template <typename Real, typename Field>
struct GradientOpacityField : Field
{
  const GradientOpacity<Real>* Opacity = nullptr;

  Real Modulate(Real t, Real tau) const
  {
    return tau * this->Opacity->Factor(this->Volume.Gradient(this->Origin + t * this->Direction));
  }
};

} // namespace numerics
} // namespace avos

#endif
