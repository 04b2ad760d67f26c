// Shading (Shading.h): the analytic gradient of the trilinear interpolant, the
// Blinn-Phong model term by term, and the shaded volume rendering integral
// against a closed form. On a linear field the gradient is constant, so each
// channel's lit colour is A C(s) + B with constants A and B: for colours that
// stay below 1 this is again piecewise linear in s, and the Williams-Max
// oracle of the unshaded integral, applied to the transfer function with
// colour knots A C_k + B, is exact for the shaded one: the adaptive rules and
// the piecewise method (PiecewiseShading.h) must meet their tolerance on it.
#include "avos/numerics/PiecewiseShading.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/Shading.h"
#include "avos/numerics/Volume.h"

#include "Oracles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace avos::numerics;

namespace
{
constexpr int N[3] = { 6, 5, 4 };

double MaxError(const glm::dvec4& a, const glm::dvec4& b)
{
  double e = 0.0;
  for (int c = 0; c < 4; ++c)
  {
    e = std::max(e, std::abs(a[c] - b[c]));
  }
  return e;
}
} // namespace

TEST(Shading, GradientOfTheTrilinearInterpolantIsExact)
{
  // A trilinear function: its interpolant is itself, its gradient exact.
  auto f = [](double x, double y, double z) { return 1 + 2 * x - y + 0.5 * z + 0.25 * x * y * z; };
  std::vector<double> data;
  for (int k = 0; k < N[2]; ++k)
    for (int j = 0; j < N[1]; ++j)
      for (int i = 0; i < N[0]; ++i)
        data.push_back(f(i, j, k));
  const TrilinearVolume<double, double> volume(data.data(), N);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int r = 0; r < 1000; ++r)
  {
    const glm::dvec3 p(u(rng) * (N[0] - 1), u(rng) * (N[1] - 1), u(rng) * (N[2] - 1));
    const glm::dvec3 g = volume.Gradient(p);
    EXPECT_NEAR(g.x, 2 + 0.25 * p.y * p.z, 1e-12);
    EXPECT_NEAR(g.y, -1 + 0.25 * p.x * p.z, 1e-12);
    EXPECT_NEAR(g.z, 0.5 + 0.25 * p.x * p.y, 1e-12);
  }
}

TEST(Shading, BlinnPhongTermByTerm)
{
  ShadingModel<double> model;
  model.Ambient = 0.2;
  model.Diffuse = 0.5;
  model.Specular = 0.3;
  model.SpecularPower = 4.0;
  model.TwoSided = false;
  const glm::dvec3 up(0, 0, 1);
  model.Lights.push_back({ up, glm::dvec3(1.0), glm::dvec3(1.0) });
  ASSERT_EQ(model.Validate(), "");
  const glm::dvec3 c(0.4, 0.6, 0.8);
  const glm::dvec3 origin(0.0); // directional lights do not read the position

  // No gradient, no normal: ambient only.
  EXPECT_LT(glm::length(model.Shade(c, glm::dvec3(0.0), up, origin) - 0.2 * c), 1e-15);
  // Normal, light and viewer aligned: every term at its full weight.
  const glm::dvec3 full = model.Shade(c, 3.0 * up, up, origin);
  EXPECT_LT(glm::length(full - glm::clamp(0.7 * c + 0.3, 0.0, 1.0)), 1e-15);
  // Light at 60 degrees from the normal, viewer along the normal: n.l = 1/2,
  // n.h = cos 30 degrees.
  const double a = M_PI / 3;
  model.Lights[0].Direction = glm::dvec3(std::sin(a), 0, std::cos(a));
  const glm::dvec3 tilted = model.Shade(c, up, up, origin);
  const double nh = std::cos(a / 2);
  EXPECT_LT(glm::length(tilted - (0.2 * c + 0.5 * 0.5 * c + 0.3 * std::pow(nh, 4.0))), 1e-14);
  // A normal facing away: one-sided lighting leaves the ambient term,
  // two-sided lighting lights it as if it faced the light.
  EXPECT_LT(glm::length(model.Shade(c, -up, up, origin) - 0.2 * c), 1e-15);
  model.TwoSided = true;
  EXPECT_LT(glm::length(model.Shade(c, -up, up, origin) - tilted), 1e-14);
  // A coloured light: each channel's diffuse and specular terms take its
  // own colour (grey lights share one sum for all channels).
  model.Lights[0].Diffuse = glm::dvec3(1.0, 0.5, 0.25);
  model.Lights[0].Specular = glm::dvec3(0.2, 0.4, 1.0);
  const glm::dvec3 coloured = model.Shade(c, up, up, origin);
  const glm::dvec3 expected = 0.2 * c + 0.5 * 0.5 * model.Lights[0].Diffuse * c +
    0.3 * std::pow(nh, 4.0) * model.Lights[0].Specular;
  EXPECT_LT(glm::length(coloured - expected), 1e-14);
  // Bright lights saturate at 1 per channel.
  model.Lights[0].Diffuse = glm::dvec3(10.0);
  EXPECT_EQ(model.Shade(c, up, up, origin), glm::dvec3(1.0));

  ShadingModel<double> bad = model;
  bad.SpecularPower = -1;
  EXPECT_NE(bad.Validate(), "");
  bad = model;
  bad.Lights[0].Direction = glm::dvec3(0, 0, 2);
  EXPECT_NE(bad.Validate(), "");
}

// A point light and a spot (vtkLight's PositionalOn, ConeAngle < 90): the
// direction towards the light, the attenuation and the cone, term by term.
TEST(Shading, PositionalAndSpotLightsTermByTerm)
{
  ShadingModel<double> model;
  model.Ambient = 0.2;
  model.Diffuse = 0.5;
  model.Specular = 0.3;
  model.SpecularPower = 4.0;
  const glm::dvec3 up(0, 0, 1), c(0.4, 0.6, 0.8), origin(0.0);
  Light<double> bulb;
  bulb.Positional = true;
  bulb.Position = glm::dvec3(0, 0, 5);
  bulb.Attenuation = glm::dvec3(1.0, 0.1, 0.02); // 1 / (1 + 0.5 + 0.5) at d = 5
  bulb.Diffuse = bulb.Specular = glm::dvec3(1.0);
  model.Lights.push_back(bulb);
  ASSERT_EQ(model.Validate(), "");
  EXPECT_TRUE(model.HasPositionalLights());
  EXPECT_DOUBLE_EQ(model.ColourGain(), 0.2 + 0.5 * 1.0);
  // Light straight above, viewer along the normal: n.l = n.h = 1, A = 1/2.
  EXPECT_LT(glm::length(model.Shade(c, up, up, origin) - (0.2 * c + 0.25 * c + 0.15)), 1e-15);
  // At x = (5, 0, 0): l = (-1, 0, 1) / sqrt 2, d = 5 sqrt 2.
  const glm::dvec3 x(5, 0, 0);
  const double d = 5.0 * std::sqrt(2.0), A = 1.0 / (1.0 + 0.1 * d + 0.02 * d * d);
  const glm::dvec3 l = glm::normalize(bulb.Position - x), h = glm::normalize(l + up);
  EXPECT_LT(glm::length(model.Shade(c, up, up, x) -
              (0.2 * c + 0.5 * A * l.z * c + 0.3 * A * std::pow(h.z, 4.0))),
    1e-15);
  // At the light itself there is no direction: ambient only.
  EXPECT_LT(glm::length(model.Shade(c, up, up, bulb.Position) - 0.2 * c), 1e-15);

  // A spot aimed straight down, cone 30 degrees, exponent 2: inside at x =
  // (2, 0, 0) (21.8 degrees off its axis), outside at (3, 0, 0) (31.0).
  model.Lights[0].ConeAngle = 30.0;
  model.Lights[0].Exponent = 2.0;
  model.Lights[0].Axis = -up;
  ASSERT_EQ(model.Validate(), "");
  const glm::dvec3 inside(2, 0, 0), outside(3, 0, 0);
  const glm::dvec3 li = glm::normalize(bulb.Position - inside), hi = glm::normalize(li + up);
  const double di = glm::length(bulb.Position - inside);
  const double Ai = li.z * li.z / (1.0 + 0.1 * di + 0.02 * di * di);
  EXPECT_LT(glm::length(model.Shade(c, up, up, inside) -
              (0.2 * c + 0.5 * Ai * li.z * c + 0.3 * Ai * std::pow(hi.z, 4.0))),
    1e-15);
  EXPECT_LT(glm::length(model.Shade(c, up, up, outside) - 0.2 * c), 1e-15);
  // A cone of 90 degrees or more is no spot (vtkLight): the point light.
  model.Lights[0].ConeAngle = 90.0;
  const glm::dvec3 lo = glm::normalize(bulb.Position - outside), ho = glm::normalize(lo + up);
  const double dout = glm::length(bulb.Position - outside);
  const double Ao = 1.0 / (1.0 + 0.1 * dout + 0.02 * dout * dout);
  EXPECT_LT(glm::length(model.Shade(c, up, up, outside) -
              (0.2 * c + 0.5 * Ao * lo.z * c + 0.3 * Ao * std::pow(ho.z, 4.0))),
    1e-15);

  ShadingModel<double> bad = model;
  bad.Lights[0].Attenuation = glm::dvec3(0.0, 0.0, 1.0);
  EXPECT_NE(bad.Validate().find("attenuation"), std::string::npos);
  bad = model;
  bad.Lights[0].ConeAngle = 30.0;
  bad.Lights[0].Axis = glm::dvec3(0.0);
  EXPECT_NE(bad.Validate().find("spot"), std::string::npos);
  bad.Lights[0].Axis = -up;
  bad.Lights[0].Exponent = -1.0;
  EXPECT_NE(bad.Validate().find("spot"), std::string::npos);
  bad = model;
  bad.Lights[0].Position.x = std::nan("");
  EXPECT_NE(bad.Validate(), "");
}

TEST(Shading, ShadedIntegralOfALinearFieldMatchesItsClosedForm)
{
  // s = 0.1 + 0.15 z on a 4 x 4 x 8 grid (spacing 1): the gradient is
  // (0, 0, 0.15) everywhere.
  const int dims[3] = { 4, 4, 8 };
  std::vector<double> data;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        data.push_back(0.1 + 0.15 * k);
  const TrilinearVolume<double, double> volume(data.data(), dims);

  TransferFunction<double> tf;
  const double knots[][5] = { { 0.0, 0.1, 0.2, 0.5, 0.0 }, { 0.4, 0.5, 0.3, 0.2, 0.6 },
    { 0.7, 0.2, 0.5, 0.4, 0.2 }, { 1.2, 0.6, 0.1, 0.3, 0.9 } };
  for (const auto& k : knots)
  {
    tf.AddColorKnot(k[0], k[1], k[2], k[3]);
    tf.AddOpacityKnot(k[0], k[4]);
  }
  tf.Finalize();

  ShadingModel<double> model;
  model.Ambient = 0.15;
  model.Diffuse = 0.6;
  model.Specular = 0.25;
  model.SpecularPower = 8.0;
  const glm::dvec3 toLight = glm::normalize(glm::dvec3(0.3, -0.2, 1.0));
  model.Lights.push_back({ toLight, glm::dvec3(0.9, 0.8, 1.0), glm::dvec3(1.0, 1.0, 0.7) });
  ASSERT_EQ(model.Validate(), "");

  // A ray from the volume's top face downwards and sideways.
  const glm::dvec3 origin(0.4, 0.7, 7.0);
  const glm::dvec3 direction = glm::normalize(glm::dvec3(0.2, 0.1, -1.0));
  double t0 = 0.0, t1 = 100.0;
  ASSERT_TRUE(ClipToGrid(origin, direction, dims, t0, t1));
  const double D = t1 - t0;
  const glm::dvec3 start = origin + t0 * direction;
  const glm::dmat3 normalMatrix(1.0); // world = grid here
  const RayShading<double> rayShading{ &model, normalMatrix, -direction, start, direction };
  const ShadedRayField<double, TrilinearVolume<double, double>> shaded{ volume, start, direction,
    rayShading };

  // The oracle: the colour knots lit by the constant gradient.
  TransferFunction<double> lit;
  for (const auto& k : knots)
  {
    const glm::dvec3 c =
      model.Shade(glm::dvec3(k[1], k[2], k[3]), volume.Gradient(start), -direction, start);
    ASSERT_LT(std::max({ c.r, c.g, c.b }), 1.0) << "no clamping: the lit colours stay linear";
    lit.AddColorKnot(k[0], c.r, c.g, c.b);
    lit.AddOpacityKnot(k[0], k[4]);
  }
  lit.Finalize();
  const double s0 = 0.1 + 0.15 * start.z, slope = 0.15 * direction.z;
  const glm::dvec4 exact = oracles::LinearField(lit, s0, slope, D);
  const glm::dvec4 unlit = oracles::LinearField(tf, s0, slope, D);
  ASSERT_GT(MaxError(exact, unlit), 0.05) << "the shading changes the ray";

  PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(tf, 1e-3), "");
  const Interval<double> whole{ 0.0, D };
  for (double eps : { 1e-2, 1e-3, 1e-4 })
  {
    const auto piecewise =
      IntegratePiecewiseShaded(volume, start, direction, &whole, 1, pieces, eps, rayShading);
    ASSERT_EQ(piecewise.Error, "");
    EXPECT_LT(MaxError(piecewise.RGBA, exact), eps) << "piecewise, eps " << eps;
    for (Strategy strategy : { Strategy::Coupled, Strategy::Decoupled })
    {
      AdaptiveSettings<double> settings;
      settings.Tolerance = eps;
      settings.Coupling = strategy;
      settings.MinimumStep = 1e-3;
      const auto r = IntegrateAdaptive(shaded, tf, D, settings);
      ASSERT_EQ(r.Error, "");
      EXPECT_LT(MaxError(r.RGBA, exact), eps) << "eps " << eps;
    }
  }
  // Riemann: first order, so within a constant times h.
  const double e1 =
    MaxError(IntegrateRiemann(shaded, tf, D, 0.01, RiemannForm::Exponential).RGBA, exact);
  const double e2 =
    MaxError(IntegrateRiemann(shaded, tf, D, 0.005, RiemannForm::Exponential).RGBA, exact);
  EXPECT_LT(e1, 0.01);
  EXPECT_NEAR(e1 / e2, 2.0, 0.3) << "first order";
}
