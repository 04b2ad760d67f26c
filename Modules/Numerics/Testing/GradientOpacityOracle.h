// An independent oracle of the volume rendering integral with gradient
// opacity along a ray through a trilinear volume, for the tests of
// PiecewiseGradientOpacity.h. The ray is cut at cell faces and knot
// crossings (PieceWalk over `pieces`, exact: in VTK's opacity model built at
// PiecewiseTransferFunction's finest relative error, as ShadedOracle.h) and
// where |g| crosses a knot of G (sign changes of |g| - knot between 64
// samples of a piece, refined by bisection). The extinction, the piece's tau
// times GradientOpacity::Factor at each point, is integrated by 8-point
// Gauss-Legendre on parts of at most 1/8 voxel, and the emission (the
// transfer function's colour, lit by `model` where given, grid = world, the
// normals through G's normal matrix) against it by
// adaptive Gauss-Legendre within 1e-10 per voxel: none of the piecewise
// method's models, series or bounds.
#ifndef avos_numerics_GradientOpacityOracle_h
#define avos_numerics_GradientOpacityOracle_h

#include "avos/numerics/Accumulation.h"
#include "avos/numerics/GradientOpacity.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Shading.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace oracles
{

template <typename VolumeT>
glm::dvec4 GradientOpacityRay(const VolumeT& volume,
  const avos::numerics::TransferFunction<double>& tf,
  const avos::numerics::PiecewiseTransferFunction<double>& pieces,
  const avos::numerics::GradientOpacity<double>& opacity, const glm::dvec3& origin,
  const glm::dvec3& direction, double D,
  const avos::numerics::ShadingModel<double>* model = nullptr,
  const glm::dvec3& toViewer = glm::dvec3(0.0, 0.0, 1.0))
{
  namespace an = avos::numerics;
  glm::dvec3 color(0.0);
  double T = 1.0;
  long cells = 0;
  const auto& knots = opacity.Function->GetPieces();
  an::PieceWalk(volume, origin, direction, 0.0, D, pieces, cells,
    [&](const an::RayPiece<double>& rp)
    {
      const auto& p = pieces[rp.TF];
      auto at = [&](double v) { return origin + (rp.Begin + std::min(v, rp.Length)) * direction; };
      auto magnitude = [&](double v)
      { return glm::length(opacity.NormalMatrix * volume.Gradient(at(v))); };
      auto kappa = [&](double v)
      {
        const double d = rp.Q(v);
        const double tau = p.Tau + d * (p.TauSlope + d * (p.TauCurvature + d * p.TauCubic));
        return tau * opacity.Factor(volume.Gradient(at(v)));
      };
      auto emission = [&](double v)
      {
        const glm::dvec3 x = at(v);
        const glm::dvec3 c = tf.GetColor(volume(x));
        return model ? model->Shade(c, opacity.NormalMatrix * volume.Gradient(x), toViewer, x) : c;
      };
      // The cuts: |g| - knot changes sign between samples (two crossings
      // between samples would be missed, and the comparison fail).
      const int n = 64;
      double sampled[n + 1];
      for (int i = 0; i <= n; ++i)
      {
        sampled[i] = magnitude(rp.Length * i / n);
      }
      std::vector<double> cuts{ 0.0, rp.Length };
      for (const auto& knot : knots)
      {
        for (int i = 0; i < n; ++i)
        {
          if ((sampled[i] - knot.Start) * (sampled[i + 1] - knot.Start) >= 0.0)
          {
            continue;
          }
          const bool rising = sampled[i + 1] > knot.Start;
          double a = rp.Length * i / n, b = rp.Length * (i + 1) / n;
          for (int k = 0; k < 60; ++k)
          {
            const double m = 0.5 * (a + b);
            (magnitude(m) > knot.Start) == rising ? b = m : a = m;
          }
          cuts.push_back(0.5 * (a + b));
        }
      }
      std::sort(cuts.begin(), cuts.end());
      // Parts at most 1/8 voxel long over which the depth grows by at most
      // 1/8: the depth from a part's start to any point by 8-point
      // Gauss-Legendre (kappa is smooth between the cuts), the emission's
      // integral by the adaptive rule (the lit colour's kinks).
      using G = an::detail::GaussLegendre<double>;
      auto depthOver = [&](double a, double b)
      { return an::detail::Quadrature(G::N8, G::W8, a, b, kappa); };
      std::function<void(double, double)> part = [&](double a, double b)
      {
        const double grown = depthOver(a, b);
        if (T < 1e-18)
        {
          return; // what is left adds less than that
        }
        if ((grown > 0.125 || b - a > 0.125) && b - a > 1e-9 * rp.Length)
        {
          part(a, 0.5 * (a + b));
          part(0.5 * (a + b), b);
          return;
        }
        for (int c = 0; c < 3; ++c)
        {
          color[c] += T *
            an::detail::AdaptiveGauss(a, b, 1e-10 * (b - a), 0,
              [&](double v) { return emission(v)[c] * kappa(v) * std::exp(-depthOver(a, v)); });
        }
        T *= std::exp(-grown);
      };
      for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
      {
        if (cuts[i + 1] > cuts[i])
        {
          part(cuts[i], cuts[i + 1]);
        }
      }
      return T >= 1e-18;
    });
  return glm::dvec4(color, 1.0 - T);
}

} // namespace oracles

#endif
