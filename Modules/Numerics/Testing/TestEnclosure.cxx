// Enclosure.h and Linearization.h: every enclosure holds the function's
// values and derivatives (closed forms) at points throughout its interval,
// for chains of operations and for functions defined by cases; the
// certified linearization keeps the chord within its tolerance of closed
// forms (smooth, with kinks, with an unbounded second derivative), places
// close to the fewest knots the bound allows, and refuses rather than
// certify when its model disagrees with the reference or the knots run out.
// The extinction budget: a perturbed extinction moves exactly composited
// pixels by no more than its bound (and by half of it in its worst case),
// and opacities linearized with ExtinctionChordTolerance keep its
// hypothesis.
#include "avos/numerics/Enclosure.h"
#include "avos/numerics/Linearization.h"
// The integrators beside the enclosures in one unit, as certified shading
// will have them: their names must not clash.
#include "avos/numerics/RayIntegrators.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

using namespace avos::numerics;
using J = Jet<double>;
using I = Bounds<double>;

namespace
{
// f(x) = sin(x^1.5) / (1 + x) + log(2 + cos x): value, f', f''.
template <typename T>
T Composite(const T& x)
{
  return Sin(Pow(x, 1.5)) / (1.0 + x) + Log(2.0 + Cos(x));
}
double CompositeValue(double x)
{
  return std::sin(std::pow(x, 1.5)) / (1 + x) + std::log(2 + std::cos(x));
}
// Derivatives by central differences of high accuracy (h small, f smooth).
double Derivative(double (*f)(double), double x, int order)
{
  const double h = order == 1 ? 1e-5 : 1e-4;
  if (order == 1)
  {
    return (f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h);
  }
  return (-f(x - 2 * h) + 16 * f(x - h) - 30 * f(x) + 16 * f(x + h) - f(x + 2 * h)) / (12 * h * h);
}
} // namespace

TEST(Enclosure, IntervalsHoldTheirFunctionsValues)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int trial = 0; trial < 2000; ++trial)
  {
    const double a = u(rng), b = a + std::abs(u(rng));
    const I x(a, b);
    const I c = Cos(x), s = Sin(x), sq = Square(x), p = Pow(x, 2.5), l = Log(I(a + 6, b + 6));
    for (int k = 0; k <= 20; ++k)
    {
      const double t = std::min(b, a + (b - a) * k / 20.0);
      EXPECT_TRUE(c.Contains(std::cos(t)));
      EXPECT_TRUE(s.Contains(std::sin(t)));
      EXPECT_TRUE(sq.Contains(t * t));
      EXPECT_TRUE(t < 0 || p.Contains(std::pow(t, 2.5)));
      EXPECT_TRUE(l.Contains(std::log(t + 6)));
    }
  }
  EXPECT_EQ((I(1, 2) / I(-1, 1)).Width(), std::numeric_limits<double>::infinity());
}

TEST(Enclosure, JetsHoldValueSlopeAndCurvature)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.05, 6.0), w(1e-4, 1.0);
  for (int trial = 0; trial < 500; ++trial)
  {
    const double a = u(rng), b = a + w(rng);
    const J f = Composite(J::Variable(I(a, b)));
    ASSERT_TRUE(f.Smooth);
    for (int k = 0; k <= 10; ++k)
    {
      const double t = std::min(b, a + (b - a) * k / 10.0);
      EXPECT_TRUE(f.V.Contains(CompositeValue(t))) << t;
      const double d1 = Derivative(CompositeValue, t, 1), d2 = Derivative(CompositeValue, t, 2);
      EXPECT_TRUE(d1 >= f.D1.Lo - 1e-7 && d1 <= f.D1.Hi + 1e-7) << t;
      EXPECT_TRUE(d2 >= f.D2.Lo - 1e-5 && d2 <= f.D2.Hi + 1e-5) << t;
    }
  }
}

TEST(Enclosure, CentredFormsKeepEnclosuresNarrow)
{
  // x - x is 0: plain interval arithmetic gives width 2w, the mean-value
  // form nothing but rounding; x x / x stays close to x's own range, where
  // plain interval arithmetic widens it at every step.
  const J x = J::Variable(I(1.0, 1.1));
  EXPECT_LT((x - x).V.Width(), 1e-12);
  J chain = x;
  I plain = x.V;
  for (int k = 0; k < 5; ++k)
  {
    chain = chain * x / x;
    plain = plain * x.V / x.V;
  }
  EXPECT_LT(chain.V.Width(), 0.12);
  EXPECT_GT(plain.Width(), 0.5);
  EXPECT_TRUE(chain.V.Contains(1.0) && chain.V.Contains(1.1));
}

TEST(Enclosure, CasesJoinTheirSidesWhereUndecided)
{
  // |x - 0.3| as cases: smooth on one side, Rough across the kink, and the
  // hull still holds every value.
  auto abs = [](const J& x)
  {
    return Cases(
      x, 0.3, [](const J& v) { return 0.3 - v; }, [](const J& v) { return v - 0.3; });
  };
  const J left = abs(J::Variable(I(0.0, 0.2)));
  EXPECT_TRUE(left.Smooth);
  EXPECT_TRUE(left.D1.Contains(-1.0));
  const J across = abs(J::Variable(I(0.2, 0.5)));
  EXPECT_FALSE(across.Smooth);
  for (double t : { 0.2, 0.3, 0.45, 0.5 })
  {
    EXPECT_TRUE(across.V.Contains(std::abs(t - 0.3)));
  }
  EXPECT_LE(across.V.Width(), 0.2 + 1e-12);
  EXPECT_EQ(Cases(
              0.1, 0.3, [](double v) { return -v; }, [](double v) { return v; }),
    -0.1);
}

namespace
{
using Knots = std::vector<LinearKnot<double, 1>>;

// The largest distance between the chord through (a, f(a)) and `knots` and
// f itself, on 100,001 points.
template <typename F>
double ChordError(double a, double b, const Knots& knots, F&& f)
{
  double worst = 0.0, x0 = a, y0 = f(a);
  std::size_t k = 0;
  for (int i = 0; i <= 100000; ++i)
  {
    const double x = a + (b - a) * i / 100000.0;
    while (k < knots.size() && knots[k].X < x)
    {
      x0 = knots[k].X;
      y0 = knots[k].Value[0];
      ++k;
    }
    const double x1 = k < knots.size() ? knots[k].X : b;
    const double y1 = k < knots.size() ? knots[k].Value[0] : f(b);
    const double chord = x1 > x0 ? y0 + (y1 - y0) * (x - x0) / (x1 - x0) : y1;
    worst = std::max(worst, std::abs(chord - f(x)));
  }
  return worst;
}

template <typename Model, typename F>
bool Linearized(double a, double b, double tolerance, Model&& model, F&& f, Knots& knots,
  std::size_t maxKnots = 100000)
{
  knots.clear();
  return Linearize<double, 1>(
    a, b, tolerance, 1e-15, [&](const I& x) { return std::array<J, 1>{ model(J::Variable(x)) }; },
    [&](double x) { return std::array<double, 1>{ f(x) }; }, knots, maxKnots);
}
} // namespace

TEST(Linearization, SmoothFunctionWithinToleranceNearTheFewestKnots)
{
  auto f = [](double x) { return std::sin(x); };
  auto model = [](const J& x) { return Sin(x); };
  for (double tolerance : { 1e-3, 1e-5, 1e-7 })
  {
    Knots knots;
    ASSERT_TRUE(Linearized(0.0, 10.0, tolerance, model, f, knots));
    EXPECT_LE(ChordError(0.0, 10.0, knots, f), tolerance);
    // Equal chords of sin need 10 / sqrt(8 tolerance) pieces; bisection
    // with a bound over each piece may take up to about twice as many.
    const double fewest = 10.0 / std::sqrt(8.0 * tolerance);
    EXPECT_GE(knots.size(), 0.9 * fewest);
    EXPECT_LE(knots.size(), 2.5 * fewest);
    EXPECT_EQ(knots.back().X, 10.0);
  }
}

TEST(Linearization, KinksAndUnboundedCurvature)
{
  // A kink inside (cases) and x^1.1 near 0, whose second derivative is
  // unbounded there: both certified, with few knots near the trouble.
  auto kink = [](double x) { return std::abs(x - 1.0 / 3.0) + 0.5 * x * x; };
  auto kinkModel = [](const J& x)
  {
    return Cases(
             x, 1.0 / 3.0, [](const J& v) { return 1.0 / 3.0 - v; },
             [](const J& v) { return v - 1.0 / 3.0; }) +
      0.5 * x * x;
  };
  auto root = [](double x) { return std::pow(x, 1.1); };
  auto rootModel = [](const J& x) { return Pow(x, 1.1); };
  for (double tolerance : { 1e-4, 1e-6 })
  {
    Knots knots;
    ASSERT_TRUE(Linearized(0.0, 1.0, tolerance, kinkModel, kink, knots));
    EXPECT_LE(ChordError(0.0, 1.0, knots, kink), tolerance);
    EXPECT_LE(knots.size(), 3.0 / std::sqrt(8.0 * tolerance) + 120);
    ASSERT_TRUE(Linearized(0.0, 1.0, tolerance, rootModel, root, knots));
    EXPECT_LE(ChordError(0.0, 1.0, knots, root), tolerance);
  }
}

TEST(Linearization, RefusesWhatItCannotCertify)
{
  Knots knots{ { -1.0, { 0.0 } } };
  auto f = [](double x) { return std::sin(x); };
  // A model that disagrees with the reference (cos for sin).
  auto cosine = [](const I& x) { return std::array<J, 1>{ Cos(J::Variable(x)) }; };
  auto sine = [](const I& x) { return std::array<J, 1>{ Sin(J::Variable(x)) }; };
  auto reference = [&](double x) { return std::array<double, 1>{ f(x) }; };
  EXPECT_FALSE((Linearize<double, 1>(0.0, 10.0, 1e-4, 1e-15, cosine, reference, knots, 100000)));
  EXPECT_EQ(knots.size(), 1u) << "the knots are left as they were";
  // Too few knots allowed.
  EXPECT_FALSE((Linearize<double, 1>(0.0, 10.0, 1e-8, 1e-15, sine, reference, knots, 100)));
  EXPECT_EQ(knots.size(), 1u);
  // A jump larger than the tolerance: no chord can follow it.
  auto step = [](double x) { return x > 0.5 ? 1.0 : 0.0; };
  auto stepModel = [](const J& x)
  {
    return Cases(
      x, 0.5, [](const J&) { return J(0.0); }, [](const J&) { return J(1.0); });
  };
  EXPECT_FALSE(Linearized(0.0, 1.0, 1e-3, stepModel, step, knots));
  // An empty interval needs nothing.
  EXPECT_TRUE(Linearized(1.0, 1.0, 1e-3, stepModel, step, knots));
  EXPECT_TRUE(knots.empty());
}

namespace
{
// A ray of segments with constant extinction and colour, composited exactly.
struct Segment
{
  double Length, Tau, Colour;
};
struct Pixel
{
  double Colour = 0.0, Alpha = 0.0;
};
Pixel Composite(const std::vector<Segment>& ray)
{
  Pixel p;
  double T = 1.0;
  for (const Segment& s : ray)
  {
    const double opacity = -std::expm1(-s.Tau * s.Length);
    p.Colour += s.Colour * T * opacity;
    T *= 1.0 - opacity;
  }
  p.Alpha = 1.0 - T;
  return p;
}
} // namespace

TEST(ExtinctionBudget, BoundsThePixelOfAPerturbedExtinction)
{
  // Random rays (extinctions from 0 to 50 per unit, lengths up to 500,
  // colours up to G) with every segment's extinction moved as far as the
  // hypothesis allows, up or down: the pixel within 2 G (Relative +
  // Absolute L) of the exact one, the opacity within Relative + Absolute L.
  // The first ray is the absolute part's worst case (nothing, then D
  // everywhere), which reaches half the bound: the bound is not vacuous.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 3000; ++trial)
  {
    const double L = trial == 0 ? 1.0 : 1.0 + 499.0 * unit(random);
    const double G = trial % 2 ? 2.5 : 1.0;
    const double relative = trial == 0 ? 0.0 : 1e-2 * unit(random);
    const double absolute = 1e-3 / L;
    const int n = 1 + static_cast<int>(199 * unit(random));
    std::vector<Segment> exact, moved;
    for (int i = 0; i < n; ++i)
    {
      const double tau =
        trial == 0 || unit(random) < 0.2 ? 0.0 : std::pow(10.0, -4.0 + 5.7 * unit(random));
      const double u = trial == 0 ? 1.0 : unit(random);
      const double up = tau + (relative * tau + absolute) * u;
      const double down = std::max(0.0, (tau - absolute * u) / (1.0 + relative * u));
      exact.push_back({ L / n, tau, G * (trial == 0 ? 1.0 : unit(random)) });
      moved.push_back({ L / n, trial == 0 || unit(random) < 0.5 ? up : down, exact.back().Colour });
    }
    const Pixel a = Composite(exact), b = Composite(moved);
    const double bound = 2.0 * G * (relative + absolute * L);
    ASSERT_LE(std::abs(a.Colour - b.Colour), bound * (1.0 + 1e-9)) << "trial " << trial;
    ASSERT_LE(std::abs(a.Alpha - b.Alpha), (relative + absolute * L) * (1.0 + 1e-9));
    worst = std::max(worst, std::abs(a.Colour - b.Colour) / bound);
  }
  EXPECT_GT(worst, 0.45);
}

TEST(ExtinctionBudget, LinearizedOpacitiesKeepTheHypothesis)
{
  // Opacities VTK's Hermite curves produce at their ends: leaving 0 as
  // x^2.1 and flattening towards 1 - 1e-6 as (1 - 1e-6)(1 - (1 - x)^3), in
  // the alpha model (unit distance 1), and an extinction above 1 in the
  // extinction model. The knots keep |tau~ - tau| <= Relative min(tau, tau~)
  // + Absolute on 100,001 points, with a bounded number of knots. A curve
  // that reaches an opacity of 1 flatly is refused: between the last double
  // below 1 (extinction 36.7) and 1 (the cap, 40) no chord is within a
  // relative error of the extinction.
  TransferFunction<double> alpha, extinction;
  alpha.SetOpacityModel(OpacityModel::Alpha, 1.0);
  struct Curve
  {
    const TransferFunction<double>* Model;
    J (*Enclose)(const J&);
    double (*Value)(double);
  };
  const Curve curves[] = {
    { &alpha, [](const J& x) { return 0.8 * Pow(x, 2.1); },
      [](double x) { return 0.8 * std::pow(x, 2.1); } },
    { &alpha, [](const J& x) { return (1.0 - 1e-6) * (1.0 - (1.0 - x) * (1.0 - x) * (1.0 - x)); },
      [](double x) { return (1.0 - 1e-6) * (1.0 - std::pow(1.0 - x, 3.0)); } },
    { &alpha, [](const J& x) { return 1.0 - (1.0 - x) * (1.0 - x) * (1.0 - x); },
      [](double x) { return 1.0 - std::pow(1.0 - x, 3.0); } },
    { &extinction, [](const J& x) { return 3.0 * Pow(x, 2.1); },
      [](double x) { return 3.0 * std::pow(x, 2.1); } },
  };
  for (const Curve& c : curves)
  {
    const bool reachesOne = c.Value(1.0) == 1.0 && c.Model == &alpha;
    for (double pixel : { 1e-2, 1e-3 })
    {
      const auto budget = ExtinctionBudget<double>::Within(pixel, 400.0, 1.0);
      const double slack = 1e-15;
      Knots knots;
      auto tau = [&c](double v) { return c.Model->ToExtinction(v); };
      const bool linearized = LinearizeWithin<double, 1>(
        0.0, 1.0,
        [&](const std::array<J, 1>& f)
        {
          return ExtinctionChordTolerance(
            f[0].V, slack, budget, tau, [&c](double v) { return c.Model->ExtinctionSlope(v); });
        },
        slack, [&c](const I& x) { return std::array<J, 1>{ c.Enclose(J::Variable(x)) }; },
        [&c](double x) { return std::array<double, 1>{ c.Value(x) }; }, knots, 4096,
        [](double, double) { return false; });
      ASSERT_EQ(linearized, !reachesOne);
      if (reachesOne)
      {
        continue;
      }
      EXPECT_LT(knots.size(), 4096u);
      double x0 = 0.0, y0 = c.Value(0.0), excess = 0.0;
      std::size_t k = 0;
      for (int i = 0; i <= 100000; ++i)
      {
        const double x = i / 100000.0;
        while (k < knots.size() && knots[k].X < x)
        {
          x0 = knots[k].X;
          y0 = knots[k].Value[0];
          ++k;
        }
        const double x1 = knots[k].X, y1 = knots[k].Value[0];
        const double chord = tau(y0 + (y1 - y0) * (x - x0) / (x1 - x0)), exact = tau(c.Value(x));
        excess = std::max(excess,
          std::abs(chord - exact) - budget.Relative * std::min(chord, exact) - budget.Absolute);
      }
      EXPECT_LE(excess, 1e-15) << "pixel budget " << pixel;
    }
  }
}
