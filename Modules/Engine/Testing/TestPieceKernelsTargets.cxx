// The piecewise method's vectorised kernels on every dispatch target the
// library was built with and the CPU runs, against the scalar kernels of the
// numerical core (numerics::ScalarPieceKernels) on the batches real rays make
// (the adversarial suite, in the extinction model and in VTK's alpha model,
// whose cubic pieces use every coefficient), lane by lane within the bound
// stated in PieceKernels.h; then whole rays integrated with either kernel,
// and the vectorised one against the exact reference within eps.
#include "AdversarialCases.h"

#include "avos/engine/PieceKernels.h"
#include "avos/engine/PiecewiseRays.h"
#include "avos/numerics/PiecewiseIntegrator.h"
#include "avos/numerics/Volume.h"

#include "GuardedArray.h"
#include "TargetTest.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

namespace an = avos::numerics;
namespace ae = avos::engine;

namespace
{
using Batch = an::PieceBatch<double>;
using SeriesBatch = an::SeriesBatch<double>;

// The largest differences between the two kernels, each in units of the
// magnitude its rounding is relative to.
struct Differences
{
  long Pieces = 0, Tested = 0, MonotoneMismatches = 0;
  long SeriesPieces = 0, Settled = 0, SettledMismatches = 0;
  long Crossings = 0, CrossingMismatches = 0;
  double Depth = 0.0, Transmittance = 0.0, J = 0.0;
};

// Runs the scalar kernels (their results go on: the ray is the scalar one)
// and the vectorised ones on a copy of every batch, and records how far
// apart they are.
struct ComparingKernels : an::ScalarCellKernels<double>
{
  Differences* Record;

  // Knot crossings: the same to the bit.
  void Crossings(an::CrossingBatch<double>& b) const
  {
    an::CrossingBatch<double> vectorised = b;
    ae::PieceKernels().Crossings(vectorised);
    an::ScalarCellKernels<double>().Crossings(b);
    for (int i = 0; i < b.Count; ++i)
    {
      ++this->Record->Crossings;
      this->Record->CrossingMismatches += vectorised.Root[i] != b.Root[i] ? 1 : 0;
    }
  }

  void Depths(Batch& b) const
  {
    Batch vectorised = b, magnitude = b;
    double known[Batch::Capacity]; // whether the walk knew s monotone
    std::copy(b.Monotone, b.Monotone + Batch::Capacity, known);
    ae::PieceKernels().Depths(vectorised);
    an::ScalarPieceKernels<double>().Depths(b);
    // Depth's coefficients from |q| and |tau|: what each one's rounding is
    // relative to (the sums may cancel).
    for (int i = 0; i < b.Count; ++i)
    {
      for (int k = 0; k < 4; ++k)
      {
        magnitude.Q[k][i] = std::abs(b.Q[k][i]);
        magnitude.Tau[k][i] = std::abs(b.Tau[k][i]);
      }
    }
    an::ScalarPieceKernels<double>().Depths(magnitude);
    Differences& r = *this->Record;
    for (int i = 0; i < b.Count; ++i)
    {
      ++r.Pieces;
      r.Tested += known[i] == 0.0 ? 1 : 0;
      r.MonotoneMismatches += vectorised.Monotone[i] != b.Monotone[i] ? 1 : 0;
      double thetaMagnitude = 0.0;
      for (int k = Batch::Degree; k >= 1; --k)
      {
        const double m = magnitude.Depth[k][i];
        thetaMagnitude = (thetaMagnitude + m) * b.Length[i];
        if (m > 0.0)
        {
          r.Depth = std::max(r.Depth, std::abs(vectorised.Depth[k][i] - b.Depth[k][i]) / m);
        }
        else
        {
          EXPECT_EQ(vectorised.Depth[k][i], 0.0);
        }
      }
      // e^{-theta} moves by e^{-theta} times theta's rounding (relative to
      // its magnitude) plus the exponential's own (1 ulp).
      const double E = b.Transmittance[i];
      r.Transmittance = std::max(r.Transmittance,
        std::abs(vectorised.Transmittance[i] - E) / (E * (1.0 + thetaMagnitude) + 1e-300));
    }
  }

  void Series(SeriesBatch& b) const
  {
    SeriesBatch vectorised = b;
    ae::PieceKernels().Series(vectorised);
    an::ScalarPieceKernels<double>().Series(b);
    Differences& r = *this->Record;
    for (int i = 0; i < b.Count; ++i)
    {
      ++r.SeriesPieces;
      if (vectorised.Settled[i] != b.Settled[i])
      {
        ++r.SettledMismatches;
        continue;
      }
      if (b.Settled[i] == 0.0)
      {
        continue;
      }
      ++r.Settled;
      // J's terms are bounded by l max|q'| e^A (A <= 1).
      const double l = b.Length[i];
      const double gmax =
        std::abs(b.Slope[0][i]) + l * (std::abs(b.Slope[1][i]) + l * std::abs(b.Slope[2][i]));
      r.J = std::max(r.J, std::abs(vectorised.J[i] - b.J[i]) / (l * gmax * std::exp(1.0) + 1e-300));
    }
  }
};

// The suite's cases, and the smooth random ones in VTK's alpha model (cubic
// extinction between extra knots: every coefficient of the depth).
std::vector<adversarial::Case> Cases()
{
  std::vector<adversarial::Case> cases = adversarial::MakeSuite();
  for (unsigned seed : { 3u, 9u })
  {
    adversarial::Case c = adversarial::MakeVolume("smooth, alpha", adversarial::Smooth, seed);
    c.TF = adversarial::Random(seed + 20, 24, 0.9);
    c.TF.SetOpacityModel(an::OpacityModel::Alpha, 1.0);
    c.TF.Finalize();
    cases.push_back(std::move(c));
  }
  return cases;
}

class PieceKernelsTargets : public avostest::TargetTest
{
};

TEST_P(PieceKernelsTargets, BatchesWithinRoundingOfScalar)
{
  // The kernels dispatch to the target forced.
  EXPECT_STREQ(ae::PieceKernelsTarget(), hwy::TargetName(this->GetParam()));
  Differences d;
  const ComparingKernels kernels{ {}, &d };
  for (const adversarial::Case& c : Cases())
  {
    for (double eps : { 1e-2, 1e-3, 1e-5 })
    {
      an::PiecewiseTransferFunction<double> tf;
      ASSERT_EQ(tf.Build(c.TF, an::PiecewiseRelativeError(eps)), "");
      const an::TrilinearVolume<double, double> volume(c.Data.data(), c.Dimensions);
      for (unsigned i = 0; i < 40; ++i)
      {
        const adversarial::Ray ray = adversarial::MakeRay(c, i);
        const an::Interval<double> whole{ 0.0, ray.Length };
        const auto r = an::IntegratePiecewise(
          volume, ray.Origin, ray.Direction, &whole, 1, tf, eps, true, nullptr, kernels);
        ASSERT_EQ(r.Error, "");
      }
    }
  }
  // Measured: depth 6.4e-16, transmittance 2.6e-16, J 1.3e-16 (AVX-512).
  EXPECT_GT(d.Pieces, 10000);
  EXPECT_GT(d.Tested, 1000);
  EXPECT_EQ(d.MonotoneMismatches, 0);
  EXPECT_GT(d.Settled, 1000);
  EXPECT_LE(d.Depth, 1e-13);
  EXPECT_LE(d.Transmittance, 1e-13);
  EXPECT_LE(d.J, 1e-13);
  EXPECT_EQ(d.SettledMismatches, 0);
  EXPECT_GT(d.Crossings, 10000);
  EXPECT_EQ(d.CrossingMismatches, 0);
  std::printf("%s: %ld pieces (%ld tested for monotony), %ld series (%ld settled on the whole "
              "piece); largest differences: depth %.2g, transmittance %.2g, J %.2g; %ld knot "
              "crossings, %ld different\n",
    ae::PieceKernelsTarget(), d.Pieces, d.Tested, d.SeriesPieces, d.Settled, d.Depth,
    d.Transmittance, d.J, d.Crossings, d.CrossingMismatches);
}

// Lanes past the batch's count, pieces of length 0, extinction whose
// transmittance underflows, a NaN depth: the vectorised kernels agree with the
// scalar ones.
TEST_P(PieceKernelsTargets, EdgeLanes)
{
  Batch b;
  b.Count = 5;
  const double q[5][4] = { { 1, 2, 3, 4 }, { 0, 0, 0, 0 }, { 0.5, -1, 0.25, 0.1 }, { 1, 1, 0, 0 },
    { 0, 1, 0, 0 } };
  const double tau[5][4] = { { 1, 2, 0.5, 0.1 }, { 0, 0, 0, 0 }, { 2000, 0, 0, 0 }, { 1, 0, 0, 0 },
    { NAN, 0, 0, 0 } };
  const double length[5] = { 0.3, 0.0, 1.0, 0.5, 0.5 };
  for (int i = 0; i < b.Count; ++i)
  {
    for (int k = 0; k < 4; ++k)
    {
      b.Q[k][i] = q[i][k];
      b.Tau[k][i] = tau[i][k];
    }
    b.Length[i] = length[i];
    b.Monotone[i] = 0.0; // not known: tested
  }
  b.Pad();
  Batch vectorised = b;
  ae::PieceKernels().Depths(vectorised);
  an::ScalarPieceKernels<double>().Depths(b);
  EXPECT_EQ(vectorised.Transmittance[1], 1.0);
  EXPECT_EQ(vectorised.Transmittance[2], 0.0);
  EXPECT_TRUE(std::isnan(vectorised.Transmittance[4]));
  for (int i = 0; i < 4; ++i)
  {
    EXPECT_NEAR(vectorised.Transmittance[i], b.Transmittance[i], 1e-15) << i;
  }
  // A series batch of pieces 3 (A = 0.5: settled) and 0 (A > 1: left to
  // SeriesIntegral); the padded lanes settle at once.
  SeriesBatch s;
  s.Count = 2;
  const int from[2] = { 3, 0 };
  for (int j = 0; j < 2; ++j)
  {
    const int i = from[j];
    for (int k = 1; k <= SeriesBatch::Degree; ++k)
    {
      s.Depth[k][j] = b.Depth[k][i];
    }
    s.Slope[0][j] = b.Q[1][i];
    s.Slope[1][j] = 2.0 * b.Q[2][i];
    s.Slope[2][j] = 3.0 * b.Q[3][i];
    s.Length[j] = b.Length[i];
    s.Transmittance[j] = b.Transmittance[i];
    s.Scale[j] = 1e-6;
    s.Front[j] = 1.0;
  }
  s.InverseLength = 0.01;
  s.Pad();
  SeriesBatch v = s;
  ae::PieceKernels().Series(v);
  an::ScalarPieceKernels<double>().Series(s);
  EXPECT_EQ(v.Settled[0], 1.0);
  EXPECT_EQ(s.Settled[0], 1.0);
  EXPECT_NEAR(v.J[0], s.J[0], 1e-15);
  // int_0^0.5 e^{-v} dv
  EXPECT_NEAR(s.J[0], 1.0 - std::exp(-0.5), 1e-6);
  EXPECT_EQ(v.Settled[1], 0.0);
  EXPECT_EQ(s.Settled[1], 0.0);
}

// One ray integrated with the scalar kernels, with `kernels` and with the
// exact reference: the same pieces as the scalar kernels, and the largest
// channel differences so far.
template <typename VolumeT>
void CompareRay(const VolumeT& volume, const adversarial::Ray& ray,
  const an::PiecewiseTransferFunction<double>& tf,
  const an::PiecewiseTransferFunction<double>& exact, double eps, const ae::PieceKernels& kernels,
  double& worstScalar, double& worstReference)
{
  const an::Interval<double> whole{ 0.0, ray.Length };
  const auto scalar = an::IntegratePiecewise(volume, ray.Origin, ray.Direction, &whole, 1, tf, eps);
  const auto vectorised = an::IntegratePiecewise(
    volume, ray.Origin, ray.Direction, &whole, 1, tf, eps, true, nullptr, kernels);
  const auto reference = an::IntegratePiecewise(volume, ray.Origin, ray.Direction, &whole, 1, exact,
    an::PiecewiseReferenceTolerance<double>(), false);
  ASSERT_EQ(vectorised.Error, "");
  EXPECT_EQ(vectorised.Statistics.Pieces, scalar.Statistics.Pieces);
  EXPECT_EQ(vectorised.Statistics.Cells, scalar.Statistics.Cells);
  for (int ch = 0; ch < 4; ++ch)
  {
    worstScalar = std::max(worstScalar, std::abs(vectorised.RGBA[ch] - scalar.RGBA[ch]));
    worstReference = std::max(worstReference, std::abs(vectorised.RGBA[ch] - reference.RGBA[ch]));
  }
}

// Whole rays: the vectorised kernels give the scalar ones' colours within
// 1e-10 (the rounding above, spread over a ray), the same pieces, and stay
// within eps of the exact reference.
TEST_P(PieceKernelsTargets, RaysMatchScalarAndHoldTolerance)
{
  double worstScalar = 0.0, worstReference = 0.0;
  long rays = 0;
  for (const adversarial::Case& c : Cases())
  {
    an::PiecewiseTransferFunction<double> exact;
    ASSERT_EQ(exact.Build(c.TF, 1e-7), "");
    const double eps = 1e-3;
    an::PiecewiseTransferFunction<double> tf;
    ASSERT_EQ(tf.Build(c.TF, an::PiecewiseRelativeError(eps)), "");
    const an::TrilinearVolume<double, double> volume(c.Data.data(), c.Dimensions);
    for (unsigned i = 0; i < 60; ++i)
    {
      CompareRay(volume, adversarial::MakeRay(c, i), tf, exact, eps, ae::PieceKernels(),
        worstScalar, worstReference);
      ++rays;
    }
  }
  EXPECT_LE(worstScalar, 1e-10);
  EXPECT_LE(worstReference, 1e-3);
  std::printf("%s: %ld rays, largest difference from the scalar kernels %.2g, from the "
              "reference %.2g (eps 1e-3)\n",
    ae::PieceKernelsTarget(), rays, worstScalar, worstReference);
}

// 8- and 16-bit volumes from the suite's fields (rounded; the 16-bit ones
// scaled by 200) and their transfer functions over the same span, as the
// walk reads them and as the engine does (in place, the array ending where
// readable memory ends).
// Component Component of tuples of Stride scalars (1: contiguous), the
// others holding other values: the kernels read one component of
// interleaved tuples in place, up to the guarded array's end where the
// component is the tuple's last.
struct Narrow
{
  std::string Name;
  int Dimensions[3] = { 0, 0, 0 };
  bool Sixteen = false;
  int Stride = 1, Component = 0;
  avostest::GuardedArray<std::uint8_t> Bytes; // the scalars, little endian
  an::TransferFunction<double> TF;

  ae::Volume Engine() const
  {
    ae::Volume v;
    v.Data = this->Bytes.data() + this->Component * (this->Sixteen ? 2 : 1);
    v.Scalars = this->Sixteen ? ae::Volume::Type::UInt16 : ae::Volume::Type::UInt8;
    std::copy(this->Dimensions, this->Dimensions + 3, v.Dimensions);
    v.Stride = this->Stride;
    v.Trailing = this->Stride - 1 - this->Component;
    return v;
  }
};

std::vector<Narrow> NarrowCases()
{
  std::vector<Narrow> cases;
  unsigned seed = 0;
  for (const adversarial::Case& c : adversarial::MakeSuite())
  {
    for (bool sixteen : { false, true })
    {
      Narrow n;
      // Contiguous, the first of 2, the last of 2, the last of 3, in turn.
      const int layout = static_cast<int>(cases.size() % 4);
      n.Stride = layout == 0 ? 1 : (layout == 3 ? 3 : 2);
      n.Component = layout == 0 || layout == 1 ? 0 : n.Stride - 1;
      n.Name = c.Name + " (component " + std::to_string(n.Component) + " of " +
        std::to_string(n.Stride) + ")";
      n.Sixteen = sixteen;
      std::copy(c.Dimensions, c.Dimensions + 3, n.Dimensions);
      const double scale = sixteen ? 200.0 : 1.0;
      std::vector<std::uint8_t> bytes;
      for (double v : c.Data)
      {
        const auto q = static_cast<std::uint16_t>(std::lround(v * scale));
        for (int k = 0; k < n.Stride; ++k)
        {
          const std::uint16_t w = k == n.Component ? q : static_cast<std::uint16_t>(q * 7u + 13u);
          bytes.push_back(static_cast<std::uint8_t>(w & 0xFF));
          if (sixteen)
          {
            bytes.push_back(static_cast<std::uint8_t>(w >> 8));
          }
        }
      }
      n.Bytes = avostest::GuardedArray<std::uint8_t>(bytes);
      // Knots at fractions and at integers, over all of the range or over
      // the middle of it (cells below and above the tables), transparent
      // between some, in both models.
      ++seed;
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      const bool middle = seed % 3 == 0;
      std::vector<double> knots;
      for (int k = 0; k < 8 + static_cast<int>(seed % 4) * 6; ++k)
      {
        const double v = (middle ? 60.0 + 120.0 * u(rng) : 255.0 * u(rng)) * scale;
        knots.push_back(seed % 2 == 0 ? std::round(v) : v);
      }
      std::sort(knots.begin(), knots.end());
      for (double v : knots)
      {
        n.TF.AddOpacityKnot(v, u(rng) < 0.4 ? 0.0 : 1.5 * u(rng) * u(rng));
        n.TF.AddColorKnot(v, u(rng), u(rng), u(rng));
      }
      if (seed % 3 == 1)
      {
        n.TF.SetOpacityModel(an::OpacityModel::Alpha, 1.0);
      }
      n.TF.Finalize();
      cases.push_back(std::move(n));
    }
  }
  return cases;
}

// Runs the scalar cells' stage (its results go on) and the vectorised one on
// a copy of every batch, and counts where they differ.
struct ComparingCells : an::ScalarPieceKernels<double>
{
  const ae::Volume* Engine = nullptr;
  long* Total = nullptr;
  long* Visible = nullptr;
  long* Mismatches = nullptr;
  double* Cubic = nullptr; // largest difference, relative to the corners' largest value
  long* Crossed = nullptr;
  long* RootMismatches = nullptr;

  void Crossings(an::CrossingBatch<double>& b) const
  {
    an::CrossingBatch<double> v = b;
    ae::PieceKernels().Crossings(v);
    an::ScalarCellKernels<double>().Crossings(b);
    for (int i = 0; i < b.Count; ++i)
    {
      ++*this->Crossed;
      *this->RootMismatches += v.Root[i] != b.Root[i] ? 1 : 0;
    }
  }

  template <typename VolumeT>
  void Cells(const VolumeT& volume, const an::PiecewiseTransferFunction<double>& tf,
    const glm::dvec3& origin, const glm::dvec3& direction, an::CellBatch<double>& b) const
  {
    an::CellBatch<double> v = b;
    ae::PieceKernels(this->Engine).Cells(volume, tf, origin, direction, v);
    an::ScalarCellKernels<double>().Cells(volume, tf, origin, direction, b);
    for (int i = 0; i < b.Count; ++i)
    {
      ++*this->Total;
      if (v.Visible[i] != b.Visible[i])
      {
        ++*this->Mismatches;
        continue;
      }
      if (b.Visible[i] == 0)
      {
        continue;
      }
      ++*this->Visible;
      *this->Mismatches += v.First[i] != b.First[i] || v.Crossings[i] != b.Crossings[i] ? 1 : 0;
      double c[8];
      volume.GetCorners(b.Index[0][i], b.Index[1][i], b.Index[2][i], c);
      const double top = std::max(1.0, *std::max_element(c, c + 8));
      for (int k = 0; k < 4; ++k)
      {
        *this->Cubic = std::max(*this->Cubic, std::abs(v.K[k][i] - b.K[k][i]) / top);
      }
    }
  }
};

template <typename Storage>
an::TrilinearVolume<double, Storage> WalkVolume(const Narrow& n)
{
  return an::TrilinearVolume<double, Storage>(
    reinterpret_cast<const Storage*>(n.Bytes.data()) + n.Component, n.Dimensions, n.Stride);
}

// The cells' stage on 8- and 16-bit volumes, contiguous or one component of
// interleaved tuples: the vectorised kernel takes them (unit tables) and
// gives what the scalar one does to the bit: the same classification and
// the same cubic; never a read past the array's end.
TEST_P(PieceKernelsTargets, CellsMatchScalar)
{
  long cells = 0, visible = 0, mismatches = 0, crossed = 0, rootMismatches = 0;
  double cubic = 0.0;
  for (const Narrow& n : NarrowCases())
  {
    const ae::Volume engine = n.Engine();
    ASSERT_NE(ae::PieceKernels(&engine).Scalars, nullptr) << n.Name;
    const double eps = 1e-3;
    an::PiecewiseTransferFunction<double> tf;
    ASSERT_EQ(tf.Build(n.TF, an::PiecewiseRelativeError(eps)), "");
    ASSERT_GT(tf.GetUnitTables().Count, 0u) << n.Name;
    ComparingCells kernels;
    kernels.Engine = &engine;
    kernels.Total = &cells;
    kernels.Visible = &visible;
    kernels.Mismatches = &mismatches;
    kernels.Cubic = &cubic;
    kernels.Crossed = &crossed;
    kernels.RootMismatches = &rootMismatches;
    // Random rays, and one from the last point (the array's last scalars:
    // the last cell's corners first) along the diagonal.
    const glm::dvec3 last(n.Dimensions[0] - 1, n.Dimensions[1] - 1, n.Dimensions[2] - 1);
    for (unsigned i = 0; i <= 40; ++i)
    {
      adversarial::Case shape;
      std::copy(n.Dimensions, n.Dimensions + 3, shape.Dimensions);
      const adversarial::Ray ray = i < 40
        ? adversarial::MakeRay(shape, i)
        : adversarial::Ray{ last, -glm::normalize(last), glm::length(last) };
      const an::Interval<double> whole{ 0.0, ray.Length };
      const auto r = n.Sixteen ? an::IntegratePiecewise(WalkVolume<std::uint16_t>(n), ray.Origin,
                                   ray.Direction, &whole, 1, tf, eps, true, nullptr, kernels)
                               : an::IntegratePiecewise(WalkVolume<std::uint8_t>(n), ray.Origin,
                                   ray.Direction, &whole, 1, tf, eps, true, nullptr, kernels);
      ASSERT_EQ(r.Error, "");
    }
  }
  EXPECT_GT(cells, 10000);
  EXPECT_GT(visible, 1000);
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(cubic, 0.0);
  EXPECT_GT(crossed, 1000);
  EXPECT_EQ(rootMismatches, 0);
  std::printf("%s: %ld cells (%ld visible), %ld classified differently, cubic within %.2g of the "
              "corners' magnitude; %ld knot crossings, %ld different\n",
    ae::PieceKernelsTarget(), cells, visible, mismatches, cubic, crossed, rootMismatches);
}

// Whole rays through 8- and 16-bit volumes with every stage vectorised:
// within 1e-10 of the scalar kernels, and within eps of the exact reference.
TEST_P(PieceKernelsTargets, NarrowRaysMatchScalarAndHoldTolerance)
{
  double worstScalar = 0.0, worstReference = 0.0;
  long rays = 0;
  for (const Narrow& n : NarrowCases())
  {
    const ae::Volume engine = n.Engine();
    an::PiecewiseTransferFunction<double> exact;
    ASSERT_EQ(exact.Build(n.TF, 1e-7), "");
    const double eps = 1e-3;
    an::PiecewiseTransferFunction<double> tf;
    ASSERT_EQ(tf.Build(n.TF, an::PiecewiseRelativeError(eps)), "");
    adversarial::Case shape;
    std::copy(n.Dimensions, n.Dimensions + 3, shape.Dimensions);
    for (unsigned i = 0; i < 40; ++i)
    {
      const adversarial::Ray ray = adversarial::MakeRay(shape, i);
      if (n.Sixteen)
      {
        CompareRay(WalkVolume<std::uint16_t>(n), ray, tf, exact, eps, ae::PieceKernels(&engine),
          worstScalar, worstReference);
      }
      else
      {
        CompareRay(WalkVolume<std::uint8_t>(n), ray, tf, exact, eps, ae::PieceKernels(&engine),
          worstScalar, worstReference);
      }
      ++rays;
    }
  }
  EXPECT_LE(worstScalar, 1e-10);
  EXPECT_LE(worstReference, 1e-3);
  std::printf("%s: %ld rays through 8- and 16-bit volumes, largest difference from the scalar "
              "kernels %.2g, from the reference %.2g (eps 1e-3)\n",
    ae::PieceKernelsTarget(), rays, worstScalar, worstReference);
}

// The ray-per-lane integrator (PiecewiseRays.h) against IntegratePiecewise
// with the engine's kernels, ray by ray, on the 8- and 16-bit volumes in
// both opacity models and at two tolerances: a batch of rays refilling the
// lanes, among them rays of several segments (the walk restarted inside the
// volume), rays without segments, of length 0, and a non-finite one. The
// same pieces and cells (but those cut past early termination), colours
// within 1e-10 (the kernels' rounding in another order, spread over a ray),
// the same errors.
TEST_P(PieceKernelsTargets, RaysPerLaneMatchOneRayAtATime)
{
  double worst = 0.0;
  long rays = 0, pieces = 0, terminated = 0;
  for (const Narrow& n : NarrowCases())
  {
    const ae::Volume engine = n.Engine();
    adversarial::Case shape;
    std::copy(n.Dimensions, n.Dimensions + 3, shape.Dimensions);
    for (const double eps : { 1e-3, 1e-2 })
    {
      an::PiecewiseTransferFunction<double> tf;
      ASSERT_EQ(tf.Build(n.TF, an::PiecewiseRelativeError(eps)), "");
      ASSERT_EQ(ae::ValidatePiecewiseRays(engine, tf), "") << n.Name;
      ae::PiecewiseTable table;
      ASSERT_EQ(table.Build(tf), "");
      constexpr unsigned Count = 45;
      std::vector<std::vector<an::Interval<double>>> segments(Count);
      std::vector<ae::RiemannRay> batch(Count);
      for (unsigned i = 0; i < Count; ++i)
      {
        const adversarial::Ray ray = adversarial::MakeRay(shape, i);
        const double L = ray.Length;
        if (i % 3 == 1)
        {
          segments[i] = { { 0.0, 0.3 * L }, { 0.45 * L, 0.8 * L }, { 0.9 * L, L } };
        }
        else if (i % 11 == 5)
        {
          segments[i] = {}; // nothing visible
        }
        else if (i % 11 == 7)
        {
          segments[i] = { { 0.5 * L, 0.5 * L } }; // length 0
        }
        else
        {
          segments[i] = { { 0.0, L } };
        }
        for (int a = 0; a < 3; ++a)
        {
          batch[i].Origin[a] = ray.Origin[a];
          batch[i].Direction[a] = ray.Direction[a];
        }
        batch[i].Segments = segments[i].data();
        batch[i].Count = segments[i].size();
      }
      batch[Count - 1].Direction[1] = std::numeric_limits<double>::quiet_NaN();
      std::vector<ae::PiecewiseOutput> out(Count);
      ae::CastPiecewiseRays(engine, tf, table, eps, batch.data(), Count, out.data());
      for (unsigned i = 0; i < Count; ++i)
      {
        const glm::dvec3 o(batch[i].Origin[0], batch[i].Origin[1], batch[i].Origin[2]);
        const glm::dvec3 dir(batch[i].Direction[0], batch[i].Direction[1], batch[i].Direction[2]);
        const auto one = n.Sixteen
          ? an::IntegratePiecewise(WalkVolume<std::uint16_t>(n), o, dir, segments[i].data(),
              segments[i].size(), tf, eps, true, nullptr, ae::PieceKernels(&engine))
          : an::IntegratePiecewise(WalkVolume<std::uint8_t>(n), o, dir, segments[i].data(),
              segments[i].size(), tf, eps, true, nullptr, ae::PieceKernels(&engine));
        ASSERT_EQ(out[i].Error, one.Error) << n.Name << " ray " << i;
        // One ray at a time the walk may cut up to 7 cells past early
        // termination (PiecewiseIntegrator.h); a lane stops at once.
        if (one.Statistics.Terminated)
        {
          EXPECT_LE(out[i].Cells, one.Statistics.Cells) << n.Name << " ray " << i;
          EXPECT_GE(out[i].Cells, one.Statistics.Cells - 7) << n.Name << " ray " << i;
        }
        else
        {
          EXPECT_EQ(out[i].Cells, one.Statistics.Cells) << n.Name << " ray " << i;
        }
        EXPECT_EQ(out[i].Pieces, one.Statistics.Pieces) << n.Name << " ray " << i;
        for (int ch = 0; ch < 4; ++ch)
        {
          worst = std::max(worst, std::abs(out[i].RGBA[ch] - one.RGBA[ch]));
        }
        ++rays;
        pieces += out[i].Pieces;
        terminated += one.Statistics.Terminated ? 1 : 0;
      }
      EXPECT_NE(out[Count - 1].Error, "");
    }
  }
  EXPECT_LE(worst, 1e-10);
  EXPECT_GT(pieces, 10000);
  EXPECT_GT(terminated, 50);
  std::printf("%s: %ld rays a ray per lane (%ld pieces, %ld terminated early), largest difference "
              "from one ray at a time %.2g\n",
    ae::PieceKernelsTarget(), rays, pieces, terminated, worst);
}

// What CastPiecewiseRays cannot honour is refused, every ray with the
// reason and an empty pixel: float scalars, a transfer function without
// unit tables or a table built from another one, a tolerance outside the
// piecewise method's range.
TEST_P(PieceKernelsTargets, RaysPerLaneRefuseWhatTheyCannotHonour)
{
  const std::vector<Narrow> cases = NarrowCases();
  const Narrow& n = cases.front();
  const ae::Volume engine = n.Engine();
  an::PiecewiseTransferFunction<double> tf;
  ASSERT_EQ(tf.Build(n.TF, an::PiecewiseRelativeError(1e-3)), "");
  ae::PiecewiseTable table;
  ASSERT_EQ(table.Build(tf), "");
  adversarial::Case shape;
  std::copy(n.Dimensions, n.Dimensions + 3, shape.Dimensions);
  const adversarial::Ray r = adversarial::MakeRay(shape, 3);
  const an::Interval<double> whole{ 0.0, r.Length };
  ae::RiemannRay ray;
  for (int a = 0; a < 3; ++a)
  {
    ray.Origin[a] = r.Origin[a];
    ray.Direction[a] = r.Direction[a];
  }
  ray.Segments = &whole;
  ray.Count = 1;
  auto refused = [&](const ae::Volume& volume, const ae::PiecewiseTable& t, double eps)
  {
    ae::PiecewiseOutput out;
    out.RGBA[3] = 0.5; // overwritten
    ae::CastPiecewiseRays(volume, tf, t, eps, &ray, 1, &out);
    return !out.Error.empty() && out.RGBA[0] == 0.0 && out.RGBA[3] == 0.0;
  };
  ae::PiecewiseOutput out;
  ae::CastPiecewiseRays(engine, tf, table, 1e-3, &ray, 1, &out);
  ASSERT_EQ(out.Error, "");
  EXPECT_GT(out.RGBA[3], 0.0);
  ae::Volume floats = engine;
  floats.Scalars = ae::Volume::Type::Float32;
  EXPECT_NE(ae::ValidatePiecewiseRays(floats, tf), "");
  EXPECT_TRUE(refused(floats, table, 1e-3));
  EXPECT_TRUE(refused(engine, ae::PiecewiseTable(), 1e-3));
  EXPECT_TRUE(refused(engine, table, 0.0));
  EXPECT_TRUE(refused(engine, table, 2.0));
  EXPECT_TRUE(refused(engine, table, std::numeric_limits<double>::quiet_NaN()));
  EXPECT_NE(ae::ValidatePiecewiseRays(engine, an::PiecewiseTransferFunction<double>()), "");
  EXPECT_NE(ae::PiecewiseTable().Build(an::PiecewiseTransferFunction<double>()), "");
}

// Kernels given another volume's scalars (other dimensions) leave the cells
// to the scalar stage: the same rays as kernels given none, to the bit.
TEST_P(PieceKernelsTargets, CellsOfAnotherVolumeAreNotRead)
{
  const std::vector<Narrow> cases = NarrowCases();
  const Narrow& n = cases.front();
  ae::Volume other = n.Engine();
  other.Dimensions[0] -= 1; // other strides: other corners
  ASSERT_NE(ae::PieceKernels(&other).Scalars, nullptr);
  an::PiecewiseTransferFunction<double> tf;
  ASSERT_EQ(tf.Build(n.TF, an::PiecewiseRelativeError(1e-3)), "");
  adversarial::Case shape;
  std::copy(n.Dimensions, n.Dimensions + 3, shape.Dimensions);
  const auto volume = WalkVolume<std::uint8_t>(n);
  for (unsigned i = 0; i < 20; ++i)
  {
    const adversarial::Ray ray = adversarial::MakeRay(shape, i);
    const an::Interval<double> whole{ 0.0, ray.Length };
    const auto given = an::IntegratePiecewise(volume, ray.Origin, ray.Direction, &whole, 1, tf,
      1e-3, true, nullptr, ae::PieceKernels(&other));
    const auto none = an::IntegratePiecewise(
      volume, ray.Origin, ray.Direction, &whole, 1, tf, 1e-3, true, nullptr, ae::PieceKernels());
    for (int ch = 0; ch < 4; ++ch)
    {
      EXPECT_EQ(given.RGBA[ch], none.RGBA[ch]);
    }
    EXPECT_EQ(given.Statistics.Pieces, none.Statistics.Pieces);
  }
}

AVOS_ENGINE_TARGETS(PieceKernelsTargets);
} // namespace
