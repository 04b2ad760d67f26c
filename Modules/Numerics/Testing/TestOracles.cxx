// Every integrator against the closed forms of Oracles.h, and the measured
// convergence orders of the fixed-step rules.
#include "Oracles.h"
#include "avos/numerics/RayIntegrators.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace avos::numerics;

namespace
{
TransferFunction<double> Constant(double tau, glm::dvec3 c)
{
  TransferFunction<double> tf;
  tf.AddColorKnot(0.0, c.r, c.g, c.b);
  tf.AddOpacityKnot(0.0, tau);
  return tf;
}

// tau(s) = s on [0, 10]; colour = g * s / lambda per channel, clamped to 1.
TransferFunction<double> Identity(glm::dvec3 g, double lambda)
{
  TransferFunction<double> tf;
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(10.0, 10.0);
  tf.AddColorKnot(0.0, 0.0, 0.0, 0.0);
  tf.AddColorKnot(lambda, g.r, g.g, g.b);
  return tf;
}

// A transfer function with kinks, a colour jump and a constant-tau piece.
TransferFunction<double> Piecewise()
{
  TransferFunction<double> tf;
  tf.AddColorKnot(0.0, 0.0, 0.1, 0.9);
  tf.AddColorKnot(0.3, 0.8, 0.4, 0.1);
  tf.AddColorKnot(0.5, 0.2, 0.9, 0.3);
  tf.AddColorKnot(0.5, 1.0, 0.0, 0.5); // jump
  tf.AddColorKnot(1.0, 0.6, 0.6, 0.6);
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(0.2, 0.3);
  tf.AddOpacityKnot(0.45, 0.3);
  tf.AddOpacityKnot(0.7, 1.2);
  tf.AddOpacityKnot(1.0, 0.05);
  return tf;
}

// Oracle 4 of Oracles.h: s = lambda / (1 + t), tau = s, colour g s / lambda.
struct PowerLaw
{
  double Lambda = 1.5;
  glm::dvec3 G{ 1.0, 0.5, 0.25 };
  TransferFunction<double> TF = Identity(G, Lambda);

  double operator()(double t) const { return this->Lambda / (1.0 + t); }
  glm::dvec4 Exact(double D) const
  {
    const double l = this->Lambda;
    const double colour = l / (l + 1.0) * (1.0 - std::pow(1.0 + D, -l - 1.0));
    return glm::dvec4(this->G * colour, 1.0 - std::pow(1.0 + D, -l));
  }
};

double MaxError(const glm::dvec4& a, const glm::dvec4& b)
{
  const glm::dvec4 d = glm::abs(a - b);
  return std::max({ d[0], d[1], d[2], d[3] });
}

AdaptiveSettings<double> Settings(double eps, Strategy strategy)
{
  AdaptiveSettings<double> s;
  s.Tolerance = eps;
  s.MinimumStep = 1e-3;
  s.Coupling = strategy;
  return s;
}
}

TEST(Oracles, SpecialFunctions)
{
  // Dawson's integral and erfcx at tabulated values (Abramowitz and Stegun 7.1, 7.31).
  EXPECT_NEAR(oracles::Dawson(1.0), 0.5380795069127684, 1e-15);
  EXPECT_NEAR(oracles::Dawson(0.5), 0.4244363835020223, 1e-15);
  EXPECT_NEAR(oracles::Dawson(10.0), 0.05025384718759853, 1e-15);
  EXPECT_NEAR(oracles::Dawson(6.0), 0.08454268897454385, 1e-15);
  EXPECT_NEAR(oracles::Erfcx(1.0), 0.4275835761558070, 1e-15);
  EXPECT_NEAR(oracles::Erfcx(30.0), 0.018795888861416751, 1e-14);
  // E(h) against composite Simpson with 2e5 intervals (error ~1e-18 here),
  // across b = 0 and for slopes small and large of both signs.
  for (double a : { 0.0, 0.7, 3.0 })
  {
    for (double b : { -2.0, -0.05, -1e-3, 0.0, 1e-3, 0.05, 2.0 })
    {
      const double h = 3.0;
      const int n = 200000;
      double sum = 0;
      for (int i = 0; i <= n; ++i)
      {
        const double t = h * i / n;
        const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        sum += w * std::exp(-(a * t + 0.5 * b * t * t));
      }
      const double expected = sum * h / (3.0 * n);
      EXPECT_NEAR(oracles::ExpQuadraticIntegral(a, b, h), expected, 1e-12 * std::max(1.0, expected))
        << "a " << a << " b " << b;
    }
  }
}

TEST(Oracles, ConstantMedium)
{
  const glm::dvec3 c(0.2, 0.5, 1.0);
  for (double tau : { 0.0, 0.01, 0.3, 5.0 })
  {
    const auto tf = Constant(tau, c);
    auto field = [](double) { return 0.0; };
    for (double D : { 0.05, 1.0, 17.5 })
    {
      const double alpha = -std::expm1(-tau * D);
      const glm::dvec4 exact(c * alpha, alpha);
      // The reference's early termination moves a channel by at most 2e-10.
      EXPECT_LT(MaxError(IntegrateReference(field, tf, D).RGBA, exact), 2e-10);
      EXPECT_LT(
        MaxError(IntegrateAdaptive(field, tf, D, Settings(1e-3, Strategy::Coupled)).RGBA, exact),
        1e-3);
      // The exponential Riemann form is exact for a constant medium.
      EXPECT_LT(
        MaxError(IntegrateRiemann(field, tf, D, 0.5, RiemannForm::Exponential).RGBA, exact), 1e-14);
    }
  }
}

TEST(Oracles, LinearFieldPiecewiseLinearTransferFunction)
{
  const auto tf = Piecewise();
  struct Case
  {
    double s0, k, D;
  };
  for (const Case& c : { Case{ 0.0, 0.05, 20.0 }, Case{ 1.0, -0.037, 27.0 }, Case{ 0.1, 0.2, 4.5 },
         Case{ -0.2, 0.011, 100.0 }, Case{ 0.35, 0.0, 10.0 } })
  {
    auto field = [&](double t) { return c.s0 + c.k * t; };
    const glm::dvec4 exact = oracles::LinearField(tf, c.s0, c.k, c.D);
    SCOPED_TRACE(testing::Message() << "s0 " << c.s0 << " k " << c.k << " D " << c.D);
    EXPECT_LT(MaxError(IntegrateReference(field, tf, c.D).RGBA, exact), 1e-6);
    for (double eps : { 1e-2, 1e-3 })
    {
      EXPECT_LT(
        MaxError(IntegrateAdaptive(field, tf, c.D, Settings(eps, Strategy::Coupled)).RGBA, exact),
        eps);
      EXPECT_LT(
        MaxError(IntegrateAdaptive(field, tf, c.D, Settings(eps, Strategy::Decoupled)).RGBA, exact),
        eps);
    }
  }
}

TEST(Oracles, SinusoidalField)
{
  const glm::dvec3 c(0.9, 0.4, 0.1);
  TransferFunction<double> tf;
  tf.AddColorKnot(0.0, c.r, c.g, c.b);
  tf.AddOpacityKnot(0.0, 0.0);
  tf.AddOpacityKnot(10.0, 10.0);
  const double A = 0.3, B = 0.25, w = 1.7, D = 12.0;
  auto field = [&](double t) { return A + B * std::sin(w * t); };
  const double theta = A * D + B / w * (1.0 - std::cos(w * D));
  const double alpha = -std::expm1(-theta);
  const glm::dvec4 exact(c * alpha, alpha);
  EXPECT_LT(MaxError(IntegrateReference(field, tf, D).RGBA, exact), 1e-6);
  EXPECT_LT(
    MaxError(IntegrateAdaptive(field, tf, D, Settings(1e-3, Strategy::Coupled)).RGBA, exact), 1e-3);
}

TEST(Oracles, PowerLawField)
{
  const PowerLaw field;
  const double D = 30.0;
  const auto adaptive = IntegrateAdaptive(field, field.TF, D, Settings(1e-3, Strategy::Decoupled));
  EXPECT_LT(MaxError(IntegrateReference(field, field.TF, D).RGBA, field.Exact(D)), 1e-6);
  EXPECT_LT(MaxError(adaptive.RGBA, field.Exact(D)), 1e-3);
}

// Slope of log(error) against log(h) over halving steps, least squares.
double ConvergenceOrder(const std::vector<double>& h, const std::vector<double>& error)
{
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(h.size());
  for (std::size_t i = 0; i < h.size(); ++i)
  {
    const double x = std::log(h[i]), y = std::log(error[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

TEST(Convergence, RiemannFirstOrderSimpsonFourthOrder)
{
  // A smooth non-polynomial ray: the power-law oracle.
  const PowerLaw field;
  const auto& tf = field.TF;
  const double D = 8.0;
  const glm::dvec4 exact = field.Exact(D);

  std::vector<double> hs, riemannLinear, riemannExp, simpson;
  for (double h = 0.5; h > 0.01; h *= 0.5)
  {
    hs.push_back(h);
    riemannLinear.push_back(
      MaxError(IntegrateRiemann(field, tf, D, h, RiemannForm::Linear).RGBA, exact));
    riemannExp.push_back(
      MaxError(IntegrateRiemann(field, tf, D, h, RiemannForm::Exponential).RGBA, exact));
    simpson.push_back(MaxError(IntegrateSimpson(field, tf, D, 4 * h).RGBA, exact));
  }
  const double p1 = ConvergenceOrder(hs, riemannLinear);
  const double p2 = ConvergenceOrder(hs, riemannExp);
  const double p4 = ConvergenceOrder(hs, simpson);
  std::cout << "measured orders: Riemann linear " << p1 << ", exponential " << p2 << ", Simpson "
            << p4 << "\n";
  EXPECT_NEAR(p1, 1.0, 0.15);
  EXPECT_NEAR(p2, 1.0, 0.15);
  EXPECT_NEAR(p4, 4.0, 0.3);
}
