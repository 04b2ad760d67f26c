// The vectorised Riemann kernel on every dispatch target the library was
// built with and the CPU runs (each forced with hwy::SetSupportedTargetsForTest),
// against the scalar double sum of the numerical core (IntegrateRiemann,
// exponential form) on the same rays: within the bound stated in Riemann.h
// (1e-4 per channel, the same samples) without early termination, within
// 1e-4 plus the termination bound with it; in both opacity models, over whole
// rays and over empty-space segments.
#include "AdversarialCases.h"

#include "avos/engine/PieceKernels.h"
#include "avos/engine/Riemann.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/Volume.h"

#include "GuardedArray.h"
#include "TargetTest.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace an = avos::numerics;
namespace ae = avos::engine;

namespace
{
// A smooth volume stored as the kernels read it (float, or 8- or 16-bit,
// signed or not, ending where readable memory ends), its values in double
// for the scalar sum, and a random transfer function over its range.
struct Scene
{
  adversarial::Case Case;
  ae::Volume::Type Type = ae::Volume::Type::Float32;
  std::vector<float> Floats;
  avostest::GuardedArray<std::uint8_t> Bytes;
  avostest::GuardedArray<std::uint16_t> Words;
  avostest::GuardedArray<std::int8_t> SignedBytes;
  avostest::GuardedArray<std::int16_t> SignedWords;
  // The scalars are component Component of tuples of Stride values.
  int Stride = 1, Component = 0;

  ae::Volume View() const
  {
    ae::Volume volume;
    volume.Scalars = this->Type;
    switch (this->Type)
    {
      case ae::Volume::Type::UInt8:
        volume.Data = this->Bytes.data() + this->Component;
        break;
      case ae::Volume::Type::UInt16:
        volume.Data = this->Words.data() + this->Component;
        break;
      case ae::Volume::Type::Int8:
        volume.Data = this->SignedBytes.data() + this->Component;
        break;
      case ae::Volume::Type::Int16:
        volume.Data = this->SignedWords.data() + this->Component;
        break;
      default:
        volume.Data = this->Floats.data() + this->Component;
    }
    std::copy(this->Case.Dimensions, this->Case.Dimensions + 3, volume.Dimensions);
    volume.Stride = this->Stride;
    volume.Trailing = this->Stride - 1 - this->Component;
    return volume;
  }
};

Scene MakeScene(unsigned seed, bool alpha, ae::Volume::Type type = ae::Volume::Type::Float32,
  bool integralKnots = false, int stride = 1, int component = 0)
{
  using Type = ae::Volume::Type;
  Scene scene;
  scene.Type = type;
  scene.Stride = stride;
  scene.Component = component;
  scene.Case = adversarial::MakeVolume("smooth", adversarial::Smooth, seed);
  // 16-bit data spans 65536 values (the high byte matters), signed data
  // starts at the type's lowest (the sign bit matters).
  const bool words = type == Type::UInt16 || type == Type::Int16;
  const double span = words ? 65535.0 : 255.0;
  const double bottom = type == Type::Int8 ? -128.0 : (type == Type::Int16 ? -32768.0 : 0.0);
  for (double& v : scene.Case.Data)
  {
    v = type == Type::Float32 ? v : std::round(v * span / 255.0) + bottom;
  }
  // 3, 12 or 64 knots: tables that fit one vector of every target, of
  // AVX-512 only, and of none (lane permutations and gathers both tested).
  const int knots[3] = { 3, 12, 64 };
  scene.Case.TF = adversarial::Random(
    seed + 1, knots[seed % 3], alpha ? 1.0 : 2.0, bottom + span, integralKnots, bottom);
  if (alpha)
  {
    scene.Case.TF.SetOpacityModel(an::OpacityModel::Alpha, 0.7);
    scene.Case.TF.Finalize();
  }
  // The tuples: the scene's values, the other components the type's lowest.
  std::vector<double> stored;
  for (const double v : scene.Case.Data)
  {
    for (int k = 0; k < stride; ++k)
    {
      stored.push_back(k == component ? v : bottom);
    }
  }
  // Only the storage of the scene's type: 16-bit values do not fit a byte
  // (converting them would be undefined behaviour, found by clang's UBSan).
  switch (type)
  {
    case Type::UInt8:
      scene.Bytes = avostest::GuardedArray<std::uint8_t>(stored);
      break;
    case Type::UInt16:
      scene.Words = avostest::GuardedArray<std::uint16_t>(stored);
      break;
    case Type::Int8:
      scene.SignedBytes = avostest::GuardedArray<std::int8_t>(stored);
      break;
    case Type::Int16:
      scene.SignedWords = avostest::GuardedArray<std::int16_t>(stored);
      break;
    default:
      scene.Floats.assign(stored.begin(), stored.end());
  }
  return scene;
}

struct Worst
{
  double Error = 0.0;
  long SampleMismatches = 0;
  long Rays = 0;
  double Opacity = 0.0; // the largest alpha met: the rays do see the volume
};

// Engine against the double sum on rays [0, count) of a scene.
Worst Compare(const Scene& scene, unsigned count, double h, double terminationBound, bool split)
{
  const adversarial::Case& c = scene.Case;
  const ae::Volume volume = scene.View();
  EXPECT_EQ(ae::Validate(volume), "");
  ae::TransferTable table;
  EXPECT_EQ(table.Build(c.TF), "");
  const an::TrilinearVolume<double, double> field(c.Data.data(), c.Dimensions);
  Worst worst;
  // Random rays, and one from the last point (the array's last scalars)
  // along the diagonal.
  const glm::dvec3 last(c.Dimensions[0] - 1, c.Dimensions[1] - 1, c.Dimensions[2] - 1);
  for (unsigned i = 0; i <= count; ++i)
  {
    const adversarial::Ray ray = i < count
      ? adversarial::MakeRay(c, i)
      : adversarial::Ray{ last, -glm::normalize(last), glm::length(last) };
    std::vector<an::Interval<double>> segments{ { 0.0, ray.Length } };
    if (split && ray.Length > 4.0 && i < count)
    {
      // Three segments with gaps, as empty-space skipping hands them over.
      const double L = ray.Length;
      segments = { { 0.1 * L, 0.3 * L }, { 0.35 * L + 0.01, 0.6 * L }, { 0.8 * L, L } };
    }
    const an::RayField<double, an::TrilinearVolume<double, double>> rayField{ field, ray.Origin,
      ray.Direction };
    const auto expected = an::IntegrateRiemann(rayField, c.TF, ray.Length, h,
      an::RiemannForm::Exponential, segments.data(), segments.size(), terminationBound);
    ae::RayOutput out;
    const double origin[3] = { ray.Origin.x, ray.Origin.y, ray.Origin.z };
    const double direction[3] = { ray.Direction.x, ray.Direction.y, ray.Direction.z };
    ae::CastRiemann(volume, table, origin, direction, ray.Length, h, segments.data(),
      segments.size(), terminationBound, out);
    for (int ch = 0; ch < 4; ++ch)
    {
      worst.Error = std::max(worst.Error, std::abs(out.RGBA[ch] - expected.RGBA[ch]));
    }
    worst.SampleMismatches += out.Samples != expected.Statistics.Samples ? 1 : 0;
    worst.Opacity = std::max(worst.Opacity, expected.RGBA[3]);
    ++worst.Rays;
  }
  return worst;
}

class RiemannTargets : public avostest::TargetTest
{
};
} // namespace

TEST_P(RiemannTargets, DispatchesToTheForcedTarget)
{
  EXPECT_STREQ(ae::CastRiemannTarget(), hwy::TargetName(this->GetParam()));
}

TEST_P(RiemannTargets, EqualsTheDoubleSumWithoutTermination)
{
  for (bool alpha : { false, true })
  {
    for (unsigned seed : { 1u, 2u, 3u })
    {
      const Scene scene = MakeScene(seed, alpha);
      for (double h : { 0.5, 0.1 })
      {
        for (bool split : { false, true })
        {
          const Worst w = Compare(scene, 300, h, 0.0, split);
          EXPECT_LE(w.Error, 1e-4) << "alpha " << alpha << " seed " << seed << " h " << h;
          EXPECT_GT(w.Opacity, 0.5) << "the rays see the volume";
          EXPECT_EQ(w.SampleMismatches, 0) << "the same samples";
        }
      }
    }
  }
}

// 8- and 16-bit volumes, signed or not, read in place (pairs of neighbours
// from one 32-bit gather, none past the array's end), against the double sum
// of the same values.
TEST_P(RiemannTargets, IntegerScalars)
{
  using Type = ae::Volume::Type;
  for (Type type : { Type::UInt8, Type::UInt16, Type::Int8, Type::Int16 })
  {
    for (unsigned seed : { 1u, 3u })
    {
      const Scene scene = MakeScene(seed, seed == 3, type);
      const Worst w = Compare(scene, 300, 0.5, 0.0, true);
      EXPECT_LE(w.Error, 1e-4) << "type " << int(type) << " seed " << seed;
      EXPECT_EQ(w.SampleMismatches, 0);
      EXPECT_GT(w.Opacity, 0.5) << "the rays see the volume";
    }
  }
}

// One component of interleaved tuples read in place (the first of 2, the
// last of 3: the array's last scalar), every type.
TEST_P(RiemannTargets, OneComponentOfSeveral)
{
  using Type = ae::Volume::Type;
  for (Type type : { Type::Float32, Type::UInt8, Type::UInt16, Type::Int8, Type::Int16 })
  {
    for (const int stride : { 2, 3 })
    {
      const Scene scene = MakeScene(2, stride == 3, type, false, stride, stride == 2 ? 0 : 2);
      const Worst w = Compare(scene, 200, 0.5, 0.0, true);
      EXPECT_LE(w.Error, 1e-4) << "type " << int(type) << " stride " << stride;
      EXPECT_EQ(w.SampleMismatches, 0);
      EXPECT_GT(w.Opacity, 0.5) << "the rays see the volume";
    }
  }
}

// Integer knots: the transfer table laid out per scalar unit (used where
// the knots do not fit one vector), 8-bit and float data.
TEST_P(RiemannTargets, IntegerKnots)
{
  for (ae::Volume::Type type : { ae::Volume::Type::UInt8, ae::Volume::Type::Float32 })
  {
    for (unsigned seed : { 1u, 2u })
    {
      const Scene scene = MakeScene(seed, seed == 2, type, true);
      ae::TransferTable table;
      ASSERT_EQ(table.Build(scene.Case.TF), "");
      EXPECT_GT(table.UnitCount, 200) << "laid out per unit";
      const Worst w = Compare(scene, 300, 0.5, 0.0, true);
      EXPECT_LE(w.Error, 1e-4) << "type " << int(type) << " seed " << seed;
      EXPECT_EQ(w.SampleMismatches, 0);
      EXPECT_GT(w.Opacity, 0.5) << "the rays see the volume";
    }
  }
}

TEST_P(RiemannTargets, EqualsTheDoubleSumWithTermination)
{
  const double bound = 0.002; // the mapper's at its default tolerance
  for (bool alpha : { false, true })
  {
    const Scene scene = MakeScene(7, alpha);
    const Worst w = Compare(scene, 2000, 0.5, bound, true);
    EXPECT_LE(w.Error, 1e-4 + bound);
    EXPECT_GT(w.Opacity, 0.99) << "some rays terminate early";
    // A flip needs T within float rounding of the bound: rare.
    EXPECT_LE(w.SampleMismatches, w.Rays / 100);
  }
}

// A ray per lane against CastRiemann ray by ray on the same target: the
// same samples, and each lane's arithmetic is CastRiemann's (the positions
// from the sample index, the classification, double compositing), so the
// colours agree to the last bits of double.
TEST_P(RiemannTargets, RaysPerLaneEqualTheSampleLanes)
{
  struct Setting
  {
    ae::Volume::Type Type;
    bool Alpha, Split;
    double H, Bound;
  };
  const Setting settings[] = { { ae::Volume::Type::Float32, false, false, 0.5, 0.0 },
    { ae::Volume::Type::Float32, true, true, 0.1, 0.0 },
    { ae::Volume::Type::UInt8, true, true, 0.5, 0.002 },
    { ae::Volume::Type::UInt16, false, true, 0.5, 0.002 },
    { ae::Volume::Type::UInt8, false, false, 0.3, 0.02 } };
  unsigned seed = 11;
  for (const Setting& setting : settings)
  {
    const Scene scene = MakeScene(seed++, setting.Alpha, setting.Type);
    const adversarial::Case& c = scene.Case;
    const ae::Volume volume = scene.View();
    ae::TransferTable table;
    ASSERT_EQ(table.Build(c.TF), "");
    // 203 rays: lanes refilled many times, and a last round that leaves
    // lanes idle; some rays empty (no segment, or none with a sample), some
    // with a one-sample segment.
    const unsigned count = 203;
    std::vector<std::vector<an::Interval<double>>> segments(count);
    std::vector<ae::RiemannRay> rays(count);
    for (unsigned i = 0; i < count; ++i)
    {
      const adversarial::Ray ray = adversarial::MakeRay(c, i);
      const double L = ray.Length;
      if (i % 17 == 5)
      {
        segments[i].clear();
      }
      else if (i % 17 == 9)
      {
        segments[i] = { { 0.2 * L + 1e-3, 0.2 * L + 2e-3 } };
      }
      else if (i % 17 == 13 && L > 8.0 * setting.H)
      {
        // One sample (index 3), then a segment ending exactly on a sample.
        const double h = setting.H;
        segments[i] = { { 3.0 * h - 1e-3, 3.0 * h + 1e-3 }, { 4.5 * h, 7.0 * h } };
      }
      else if (setting.Split && L > 4.0)
      {
        segments[i] = { { 0.1 * L, 0.3 * L }, { 0.35 * L + 0.01, 0.6 * L }, { 0.8 * L, L } };
      }
      else
      {
        segments[i] = { { 0.0, L } };
      }
      ae::RiemannRay& r = rays[i];
      for (int a = 0; a < 3; ++a)
      {
        r.Origin[a] = ray.Origin[a];
        r.Direction[a] = ray.Direction[a];
      }
      r.D = i % 41 == 7 ? 0.0 : L;
      r.Segments = segments[i].data();
      r.Count = segments[i].size();
    }
    std::vector<ae::RayOutput> lanes(count);
    ae::CastRiemannRays(
      volume, table, setting.H, setting.Bound, rays.data(), rays.size(), lanes.data());
    double worst = 0.0, opacity = 0.0;
    long mismatches = 0;
    for (unsigned i = 0; i < count; ++i)
    {
      const ae::RiemannRay& r = rays[i];
      ae::RayOutput one;
      ae::CastRiemann(volume, table, r.Origin, r.Direction, r.D, setting.H, r.Segments, r.Count,
        setting.Bound, one);
      for (int ch = 0; ch < 4; ++ch)
      {
        worst = std::max(worst, std::abs(lanes[i].RGBA[ch] - one.RGBA[ch]));
      }
      mismatches += lanes[i].Samples != one.Samples ? 1 : 0;
      opacity = std::max(opacity, one.RGBA[3]);
    }
    EXPECT_LE(worst, 1e-12) << "setting " << seed;
    EXPECT_EQ(mismatches, 0) << "setting " << seed;
    EXPECT_GT(opacity, 0.5) << "the rays see the volume";
  }
}

AVOS_ENGINE_TARGETS(RiemannTargets);

// The kernels refuse what their 32-bit indices cannot address.
TEST(Riemann, Validate)
{
  ae::Volume volume;
  EXPECT_NE(ae::Validate(volume), "");
  std::vector<float> data(8, 0.0f);
  volume.Data = data.data();
  volume.Dimensions[0] = volume.Dimensions[1] = volume.Dimensions[2] = 2;
  EXPECT_EQ(ae::Validate(volume), "");
  volume.Dimensions[0] = volume.Dimensions[1] = volume.Dimensions[2] = 1300;
  EXPECT_NE(ae::Validate(volume), "");
  volume.Dimensions[2] = 1;
  EXPECT_NE(ae::Validate(volume), "");
  // 2^30 + 2^20 points: 8-bit ones by index, not 16-bit ones by byte offset.
  volume.Dimensions[0] = volume.Dimensions[1] = 1024;
  volume.Dimensions[2] = 1025;
  volume.Scalars = ae::Volume::Type::UInt8;
  EXPECT_EQ(ae::Validate(volume), "");
  volume.Scalars = ae::Volume::Type::UInt16;
  EXPECT_NE(ae::Validate(volume), "");
  // Nor does the piecewise method's cells' kernel take them.
  EXPECT_EQ(ae::PieceKernels(&volume).Scalars, nullptr);
  ae::TransferTable table;
  EXPECT_NE(table.Build(an::TransferFunction<double>()), "");
}
