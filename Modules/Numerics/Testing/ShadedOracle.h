// An independent oracle of the shaded volume rendering integral along a ray
// through a trilinear volume, for the tests of PiecewiseShading.h: on each
// smooth piece of the ray (PieceWalk, the exact depth of PieceDepth), the
// lit emission integrated by adaptive Gauss-Legendre (4 against 8 nodes,
// 1e-14 per part) on parts where the depth grows by at most 1/4, each sample lit through
// TrilinearVolume::Gradient and ShadingModel::Shade with the colour of TransferFunction::GetColor
// (at its world position gridToWorld x + offset): none of the piecewise method's enclosures,
// gradient polynomials or series.
#ifndef avos_numerics_ShadedOracle_h
#define avos_numerics_ShadedOracle_h

#include "avos/numerics/Accumulation.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Shading.h"

#include <glm/glm.hpp>

#include <cmath>
#include <functional>

namespace oracles
{

template <typename VolumeT>
glm::dvec4 ShadedRay(const VolumeT& volume, const avos::numerics::TransferFunction<double>& tf,
  const avos::numerics::PiecewiseTransferFunction<double>& pieces, const glm::dvec3& origin,
  const glm::dvec3& direction, double D, const avos::numerics::ShadingModel<double>& model,
  const glm::dmat3& normalMatrix, const glm::dvec3& toViewer,
  const glm::dmat3& gridToWorld = glm::dmat3(1.0), const glm::dvec3& offset = glm::dvec3(0.0))
{
  namespace an = avos::numerics;
  glm::dvec3 color(0.0);
  double T = 1.0;
  long cells = 0;
  an::PieceWalk(volume, origin, direction, 0.0, D, pieces, cells,
    [&](const an::RayPiece<double>& rp)
    {
      const auto& p = pieces[rp.TF];
      const an::detail::PieceDepth<double> depth(
        rp.Q, p.Tau, p.TauSlope, p.TauCurvature, p.TauCubic);
      // Parts over which the depth grows by at most 1/4, so that no
      // Gauss-Legendre rule misses where the weight tau T is concentrated.
      std::function<void(double, double)> part = [&](double a, double b)
      {
        if (depth(b) - depth(a) > 0.25 && b - a > 1e-12 * rp.Length)
        {
          part(a, 0.5 * (a + b));
          part(0.5 * (a + b), b);
          return;
        }
        for (int c = 0; c < 3; ++c)
        {
          color[c] += an::detail::AdaptiveGauss(a, b, 1e-14, 0,
            [&](double v)
            {
              const glm::dvec3 x = origin + (rp.Begin + v) * direction;
              const double d = rp.Q(v);
              const double tau = p.Tau + d * (p.TauSlope + d * (p.TauCurvature + d * p.TauCubic));
              const glm::dvec3 lit = model.Shade(tf.GetColor(volume(x)),
                normalMatrix * volume.Gradient(x), toViewer, gridToWorld * x + offset);
              return lit[c] * tau * T * std::exp(-depth(v));
            });
        }
      };
      part(0.0, rp.Length);
      T *= std::exp(-depth(rp.Length));
      return true;
    });
  return glm::dvec4(color, 1.0 - T);
}

} // namespace oracles

#endif
