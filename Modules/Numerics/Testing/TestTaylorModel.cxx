// TaylorModel.h: every model holds its function at points throughout its
// interval (closed forms), for sums, products, powers and chains of them, for
// the kinks (|x|, max(0, x), clamps) and for functions by cases; remainders
// shrink as r^(N+1) on smooth functions; polynomials of degree at most N
// are exact up to rounding; what is not finite is marked unknown.
#include "avos/numerics/TaylorModel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace avos::numerics;

namespace
{
// |f(c + y) - P(y)| <= R at 65 points of [-r, r], up to the samples' own
// rounding (`slack` relative to the value).
template <int N, typename F>
::testing::AssertionResult Holds(const TaylorModel<double, N>& m, double c, double r, F&& f)
{
  for (int i = 0; i <= 64; ++i)
  {
    const double y = -r + 2.0 * r * i / 64.0;
    const double value = f(c + y);
    const double slack = 1e-14 * (1.0 + std::abs(value));
    if (!(std::abs(m.Evaluate(y) - value) <= m.R + slack))
    {
      return ::testing::AssertionFailure()
        << "at v = " << c + y << ": f = " << value << ", P = " << m.Evaluate(y) << ", R = " << m.R;
    }
  }
  return ::testing::AssertionSuccess();
}

// f(v) = (1 + v^2)^-1/2 * (0.3 + v)^3 - 2 / (2 + v^2) + |v - 0.1|^1.5 on
// models of the variable, and in closed form.
template <typename T, typename L>
T Chain(const T& x, const L& line)
{
  const T q = 1.0 + x * x;
  const T cube = (x + 0.3) * (x + 0.3) * (x + 0.3);
  return Pow(q, -0.5) * cube - 2.0 * Pow(2.0 + x * x, -1.0) + Pow(line(x), 1.5);
}
double ChainValue(double v)
{
  return std::pow(1.0 + v * v, -0.5) * std::pow(0.3 + v, 3.0) - 2.0 / (2.0 + v * v) +
    std::pow(std::abs(v - 0.1), 1.5);
}

template <int N>
TaylorModel<double, N> Variable(double c, double r)
{
  const double identity[2] = { 0.0, 1.0 };
  return TaylorModel<double, N>::Polynomial(identity, c, r);
}

template <int N>
void RandomChains(unsigned seed)
{
  using M = TaylorModel<double, N>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  long finite = 0;
  for (int trial = 0; trial < 2000; ++trial)
  {
    // r from 1e-6 to 0.1: 1 + x^2's range stays positive (2 |c| r + r^2 < 1)
    const double c = 2.0 * u(rng), r = std::pow(10.0, -2.5 * (u(rng) + 1.0) - 1.0);
    const M x = Variable<N>(c, r);
    const M f = Chain(x, [](const M& y) { return Abs(y - 0.1); });
    ASSERT_TRUE(Holds(f, c, r, ChainValue)) << "trial " << trial << ", degree " << N;
    finite += f.Finite() ? 1 : 0;
  }
  EXPECT_EQ(finite, 2000) << "every chain is known (its ranges stay positive)";
}
} // namespace

TEST(TaylorModel, ChainsHoldTheirFunction)
{
  RandomChains<0>(1);
  RandomChains<2>(2);
  RandomChains<3>(3);
  RandomChains<5>(4);
  RandomChains<8>(5);
}

// A smooth function's remainder shrinks as r^(N+1): the ratio at r and r / 2
// is about 2^(N+1).
template <int N>
double RemainderRatio()
{
  auto remainder = [](double r)
  {
    const TaylorModel<double, N> x = Variable<N>(0.4, r);
    return Chain(x, [](const TaylorModel<double, N>& y) { return y - 0.1; }).R;
  };
  return remainder(0.02) / remainder(0.01);
}

TEST(TaylorModel, RemainderOrder)
{
  EXPECT_NEAR(RemainderRatio<2>() / 8.0, 1.0, 0.25);
  EXPECT_NEAR(RemainderRatio<3>() / 16.0, 1.0, 0.25);
  EXPECT_NEAR(RemainderRatio<5>() / 64.0, 1.0, 0.25);
}

// A polynomial of degree at most N is exact but for rounding; its product
// and powers are exact while the degree stays within N, and their dropped
// terms are in R beyond.
TEST(TaylorModel, PolynomialsAndProducts)
{
  using M = TaylorModel<double, 4>;
  const double p[4] = { 1.0, -2.0, 0.5, 3.0 };
  const M cubic = M::Polynomial(p, 0.7, 0.1);
  EXPECT_LT(cubic.R, 1e-13);
  EXPECT_GT(cubic.R, 0.0) << "the shift's rounding is taken in";
  auto value = [&p](double v) { return p[0] + v * (p[1] + v * (p[2] + v * p[3])); };
  EXPECT_TRUE(Holds(cubic, 0.7, 0.1, value));
  const M square = cubic * cubic; // degree 6: two terms dropped into R
  EXPECT_GT(square.R, 1e-6);
  EXPECT_TRUE(Holds(square, 0.7, 0.1, [&](double v) { return value(v) * value(v); }));
  const M x = Variable<4>(0.7, 0.1);
  const M x4 = WholePower(x, 4);
  EXPECT_LT(x4.R, 1e-14) << "x^4 has degree 4";
  EXPECT_TRUE(Holds(x4, 0.7, 0.1, [](double v) { return std::pow(v, 4.0); }));
  const M x128 = WholePower(x - 0.7, 128); // (v - 0.7)^128 over |v - 0.7| <= 0.1
  EXPECT_TRUE(Holds(x128, 0.7, 0.1, [](double v) { return std::pow(v - 0.7, 128.0); }));
  EXPECT_LE(x128.R, 1.01e-128);
}

// Kinks: |x|, max(0, x), the clamps, over intervals that hold the kink, that
// touch it and that do not; each holds the function and stays within the
// kink's reach of the smooth part.
TEST(TaylorModel, Kinks)
{
  using M = TaylorModel<double, 3>;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 3000; ++trial)
  {
    const double c = u(rng), r = std::pow(10.0, -2.0 * (u(rng) + 1.0)); // 1e-4 .. 1
    const double a = 2.0 * u(rng), b = u(rng);
    // g(v) = a v + b v^2 - 0.2
    const M x = 0.2 * M(-1.0) + (a * Variable<3>(c, r) + b * WholePower(Variable<3>(c, r), 2));
    auto g = [a, b](double v) { return a * v + b * v * v - 0.2; };
    ASSERT_TRUE(Holds(Abs(x), c, r, [&](double v) { return std::abs(g(v)); })) << trial;
    ASSERT_TRUE(Holds(PositivePart(x), c, r, [&](double v) { return std::max(g(v), 0.0); }))
      << trial;
    ASSERT_TRUE(
      Holds(Clamp(x, 0.0, 0.5), c, r, [&](double v) { return std::min(std::max(g(v), 0.0), 0.5); }))
      << trial;
    ASSERT_TRUE(
      Holds(Cases(
              x, 0.1, [](const M&) { return M(0.0); }, [](const M& y) { return WholePower(y, 3); }),
        c, r, [&](double v) { return g(v) > 0.1 ? std::pow(g(v), 3.0) : 0.0; }))
      << trial;
    // A model crossing the kink keeps its polynomial: its remainder is the
    // excess, at most the range's reach past 0 (plus rounding).
    const Bounds<double> range = x.Range();
    if (range.Lo < 0.0 && range.Hi > 0.0 && x.A[0] > 0.0)
    {
      EXPECT_LE(Abs(x).R, std::min(-range.Lo, range.Magnitude() / 2.0) * (1.0 + 1e-12) + 1e-15)
        << trial;
    }
  }
}

// Powers near and at 0: a negative power of a range that reaches 0 is
// unknown; a positive one is the range's hull; p = 0 is 1.
TEST(TaylorModel, PowersAtZero)
{
  using M = TaylorModel<double, 3>;
  const M x = Variable<3>(0.05, 0.1); // [-0.05, 0.15]
  EXPECT_FALSE(Pow(x, -0.5).Finite());
  const M root = Pow(x, 0.5);
  EXPECT_TRUE(root.Finite());
  EXPECT_TRUE(Holds(root, 0.05, 0.1, [](double v) { return std::sqrt(std::max(v, 0.0)); }));
  EXPECT_EQ(Pow(x, 0.0).A[0], 1.0);
  EXPECT_EQ(Pow(x, 0.0).R, 0.0);
}

// What is not finite is unknown (R infinite), and the clamps bound it.
TEST(TaylorModel, NotFinite)
{
  using M = TaylorModel<double, 3>;
  const double inf = std::numeric_limits<double>::infinity();
  const double p[2] = { std::nan(""), 1.0 };
  EXPECT_FALSE(M::Polynomial(p, 0.0, 0.1).Finite());
  EXPECT_FALSE((M(inf) + M(1.0)).Finite());
  EXPECT_FALSE((M(1e300) * M(1e300)).Finite());
  const M clamped = Clamp(M(inf) * M(0.5), 0.0, 1.0);
  EXPECT_TRUE(clamped.Finite());
  EXPECT_EQ(clamped.A[0], 0.5);
  EXPECT_GE(clamped.R, 0.5);
  EXPECT_EQ((0.0 * M(inf)).R, 0.0) << "0 f = 0";
}

// The tight range holds every value and is within the plain range; on a
// model whose range ends at a root (a kink at the interval's end), it reaches
// past 0 by far less than the plain range does.
TEST(TaylorModel, TightRange)
{
  using M = TaylorModel<double, 5>;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial)
  {
    const double c = u(rng), r = std::pow(10.0, -2.0 * (u(rng) + 1.0));
    const double p[4] = { u(rng), u(rng), u(rng), u(rng) };
    const M m = Pow(M::Polynomial(p, c, r) * M::Polynomial(p, c, r) + 0.5, -0.5);
    const Bounds<double> tight = m.TightRange(), plain = m.Range();
    ASSERT_GE(tight.Lo, plain.Lo);
    ASSERT_LE(tight.Hi, plain.Hi);
    for (int i = 0; i <= 64; ++i)
    {
      const double v = c - r + 2.0 * r * i / 64.0;
      const double q = p[0] + v * (p[1] + v * (p[2] + v * p[3]));
      ASSERT_TRUE(tight.Contains(1.0 / std::sqrt(q * q + 0.5))) << trial;
    }
  }
  // x (1 + x) over [0, 2r]: 0 at the interval's start.
  const double r = 0.01;
  const M x = Variable<5>(r, r);
  const M f = x * (x + 1.0);
  EXPECT_GT(f.TightRange().Lo, -1e-15);
  EXPECT_LT(f.Range().Lo, -1e-4);
}

// The powers by squaring are within (|p| + 8) u of std::pow.
TEST(TaylorModel, WholeAndHalfPowers)
{
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(0.01, 100.0);
  const double unit = std::numeric_limits<double>::epsilon() / 2.0;
  for (int trial = 0; trial < 2000; ++trial)
  {
    const double x = u(rng), p = std::round(2.0 * (u(rng) - 50.0) * 0.64) / 2.0; // -32 .. 32
    const double exact = std::pow(x, p);                                         // within an ulp
    ASSERT_LE(std::abs(detail::PowerOf(x, p) - exact), (std::abs(p) + 10.0) * unit * exact)
      << x << "^" << p;
  }
  EXPECT_EQ(detail::PowerOf(2.0, 10.0), 1024.0);
  EXPECT_DOUBLE_EQ(detail::PowerOf(4.0, -0.5), 0.5);
  EXPECT_DOUBLE_EQ(detail::PowerOf(3.0, 0.3), std::pow(3.0, 0.3));
}
