// The frame engine (avos/engine/Frame.h) without VTK: every pixel of a
// frame cast by FrameCaster against the numerics core on the same ray
// (PixelRay, the map's segments, the clip region's parts, then the core's
// integrator in double on the double volume), for the methods' fast paths
// (a ray per lane of the piecewise and Riemann kernels) and a ray at a time
// (clipped, adaptive, maximum intensity), and for fields constant per cell
// (nearest interpolation, cell scalars); the footprint holds every pixel
// whose ray meets the box; scalars are read in place for every type; a
// threaded loop gives the serial loop's image to the bit.
#include "AdversarialCases.h"

#include "avos/engine/Frame.h"
#include "avos/numerics/Extremum.h"
#include "avos/numerics/Volume.h"

#include "GuardedArray.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <thread>
#include <vector>

namespace an = avos::numerics;
namespace ae = avos::engine;

namespace
{
constexpr int Width = 64, Height = 48;

// A smooth 40^3 volume of integers in [0, 255] (exact in every storage
// type), a transfer function with integer knots (the kernels' unit tables),
// and a camera looking at it obliquely, in perspective, from outside.
struct Scene
{
  adversarial::Case Case;
  avostest::GuardedArray<std::uint8_t> Bytes; // ends where readable memory ends
  an::EmptySpaceMap<double> Map;
  ae::Frame Frame;
  double GridToWorld[16];
  double Projection[16];

  Scene()
  {
    this->Case = adversarial::MakeVolume("smooth", adversarial::Smooth, 3);
    for (double& v : this->Case.Data)
    {
      v = std::round(v);
    }
    this->Case.TF = adversarial::Random(4, 12, 2.0, 255.0, true);
    this->Bytes = avostest::GuardedArray<std::uint8_t>(this->Case.Data);
    this->Map.SetDimensions(this->Case.Dimensions);
    this->Map.ComputeRanges(this->Case.Data.data());
    this->Map.Classify(this->Case.TF);

    // World = grid coordinates scaled by 0.5 (a voxel unit is 0.5 world units).
    const glm::dmat4 gridToWorld = glm::scale(glm::dmat4(1.0), glm::dvec3(0.5));
    const glm::dmat4 view = glm::lookAt(
      glm::dvec3(-14.0, 31.0, 45.0), glm::dvec3(9.5, 10.0, 9.0), glm::dvec3(0.0, 1.0, 0.0));
    const glm::dmat4 projection =
      glm::perspective(glm::radians(40.0), double(Width) / Height, 5.0, 200.0) * view;
    ToRowMajor(gridToWorld, this->GridToWorld);
    ToRowMajor(projection, this->Projection);
    ae::FrameRays& rays = this->Frame.Rays;
    ToRowMajor(glm::inverse(projection), rays.NDCToWorld);
    ToRowMajor(glm::inverse(gridToWorld), rays.WorldToGrid);
    rays.Voxel = 0.5;
    std::copy(this->Case.Dimensions, this->Case.Dimensions + 3, rays.Dimensions);
    rays.Width = Width;
    rays.Height = Height;
    // An opaque object in front of part of the volume (depth 0.97) over a
    // quarter of the viewport, the far plane elsewhere; the viewport is
    // twice the frame's size.
    std::vector<float> viewport(4 * Width * Height, 1.0f);
    for (int y = 0; y < Height; ++y)
    {
      for (int x = 0; x < Width; ++x)
      {
        viewport[static_cast<std::size_t>(y) * 2 * Width + x] = 0.97f;
      }
    }
    this->Frame.SampleDepth(viewport.data(), 2 * Width, 2 * Height);
    this->Frame.SetFootprint(this->GridToWorld, this->Projection);
  }

  static void ToRowMajor(const glm::dmat4& m, double out[16])
  {
    for (int r = 0; r < 4; ++r)
    {
      for (int c = 0; c < 4; ++c)
      {
        out[4 * r + c] = m[c][r];
      }
    }
  }

  an::TrilinearVolume<double, double> Field() const
  {
    return an::TrilinearVolume<double, double>(this->Case.Data.data(), this->Case.Dimensions);
  }

  ae::Scalars Doubles() const
  {
    ae::Scalars s;
    s.Data = this->Case.Data.data();
    s.Type = ae::ScalarType::Float64;
    std::copy(this->Case.Dimensions, this->Case.Dimensions + 3, s.Dimensions);
    return s;
  }

  ae::Volume EngineBytes() const
  {
    ae::Volume v;
    v.Data = this->Bytes.data();
    v.Scalars = ae::Volume::Type::UInt8;
    std::copy(this->Case.Dimensions, this->Case.Dimensions + 3, v.Dimensions);
    return v;
  }
};

void Serial(std::int64_t count, const std::function<void(std::int64_t, std::int64_t)>& body)
{
  for (std::int64_t i = 0; i < count; ++i)
  {
    body(i, i + 1);
  }
}

void Threaded(std::int64_t count, const std::function<void(std::int64_t, std::int64_t)>& body)
{
  std::atomic<std::int64_t> next{ 0 };
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
  {
    threads.emplace_back(
      [&]
      {
        for (std::int64_t i; (i = next.fetch_add(3)) < count;)
        {
          body(i, std::min(i + 3, count));
        }
      });
  }
  for (std::thread& t : threads)
  {
    t.join();
  }
}

std::vector<float> Cast(const Scene& scene, const ae::Scalars& scalars,
  const ae::FrameMethod& method, const ae::ParallelFor& loop, ae::FrameStatistics* stats = nullptr)
{
  EXPECT_EQ(ae::Validate(scalars, method), "");
  std::vector<float> image(4 * Width * Height, 0.0f);
  ae::FrameCaster caster;
  ae::WorkMonitor monitor;
  const ae::FrameStatistics s =
    caster.Cast(scene.Frame, scalars, method, image.data(), loop, monitor);
  EXPECT_EQ(s.Failed, 0) << s.FirstError;
  if (stats)
  {
    *stats = s;
  }
  return image;
}

// The core's RGBA for pixel (x, y); false when its ray misses the box.
template <typename Integrate>
bool CoreRay(const Scene& scene, const ae::FrameMethod& method, int x, int y,
  const Integrate& integrate, glm::dvec4& rgba)
{
  glm::dvec3 origin, direction;
  double D;
  if (!ae::PixelRay(scene.Frame.Rays, x, y, &origin.x, &direction.x, D))
  {
    return false;
  }
  std::vector<an::Interval<double>> segments{ { 0.0, D } }, kept, clipped;
  if (method.Map && method.Mode == ae::Blend::Composite)
  {
    method.Map->Segments(origin, direction, D, ae::SegmentPad, segments);
  }
  if (!scene.Frame.Clip.IsEmpty())
  {
    scene.Frame.Clip.Kept(origin, direction, D, kept);
    an::ClipRegion<double>::Intersect(segments, kept, clipped);
    segments = clipped;
  }
  rgba = segments.empty() ? glm::dvec4(0.0) : integrate(origin, direction, D, segments);
  return true;
}

// The frame against the core: the largest difference of any channel over
// the image, how many pixels' rays meet the box, the largest opacity.
struct Agreement
{
  double Error = 0.0;
  int Hits = 0;
  double Opacity = 0.0;
};

template <typename Integrate>
Agreement Compare(const Scene& scene, const ae::FrameMethod& method,
  const std::vector<float>& image, const Integrate& integrate)
{
  Agreement a;
  for (int y = 0; y < Height; ++y)
  {
    for (int x = 0; x < Width; ++x)
    {
      const float* pixel = &image[4 * (static_cast<std::size_t>(y) * Width + x)];
      glm::dvec4 rgba(0.0);
      const bool hit = CoreRay(scene, method, x, y, integrate, rgba);
      const int* r = scene.Frame.Rect;
      if (hit)
      {
        ++a.Hits;
        EXPECT_TRUE(x >= r[0] && x < r[1] && y >= r[2] && y < r[3])
          << "pixel " << x << ", " << y << " meets the box outside the footprint";
      }
      for (int c = 0; c < 4; ++c)
      {
        // A pixel whose ray misses the box is left as it was (zero).
        a.Error = std::max(a.Error, std::abs(pixel[c] - (hit ? rgba[c] : 0.0)));
      }
      a.Opacity = std::max(a.Opacity, rgba.a);
    }
  }
  return a;
}

// The float image's rounding of the core's double values.
constexpr double ImageRounding = 6e-8;

TEST(Frame, PiecewiseRaysPerLaneMatchTheCore)
{
  const Scene scene;
  for (const double eps : { 1e-3, 1e-2 })
  {
    an::PiecewiseTransferFunction<double> pieces;
    ASSERT_EQ(pieces.Build(scene.Case.TF, an::PiecewiseRelativeError(eps)), "");
    const ae::Volume bytes = scene.EngineBytes();
    ASSERT_EQ(ae::ValidatePiecewiseRays(bytes, pieces), "");
    ae::PiecewiseTable table;
    ASSERT_EQ(table.Build(pieces), "");
    ae::FrameMethod method;
    method.Kind = ae::Integration::Piecewise;
    method.Adaptive.Tolerance = eps;
    method.TF = &scene.Case.TF;
    method.Map = &scene.Map;
    method.Pieces = &pieces;
    method.Kernels = ae::PieceKernels(&bytes);
    method.PieceTable = &table;
    ae::Scalars scalars = scene.Doubles();
    scalars.Data = scene.Bytes.data();
    scalars.Type = ae::ScalarType::UInt8;
    ae::FrameStatistics stats;
    const std::vector<float> image = Cast(scene, scalars, method, Serial, &stats);
    const an::TrilinearVolume<double, double> volume = scene.Field();
    const Agreement a = Compare(scene, method, image,
      [&](const glm::dvec3& o, const glm::dvec3& d, double, const auto& segments)
      {
        return an::IntegratePiecewise(volume, o, d, segments.data(), segments.size(), pieces, eps)
          .RGBA;
      });
    // Lanes against a ray at a time: 8.9e-16 (Engine's RaysPerLane tests).
    EXPECT_LE(a.Error, ImageRounding + 1e-12) << "eps " << eps;
    EXPECT_GT(a.Hits, Width * Height / 4);
    EXPECT_GT(a.Opacity, 0.5);
    EXPECT_EQ(stats.Rays, a.Hits);
    EXPECT_GT(stats.Pieces, stats.Rays);
  }
}

TEST(Frame, RiemannRaysPerLaneMatchTheCore)
{
  const Scene scene;
  const ae::Volume bytes = scene.EngineBytes();
  ae::TransferTable table;
  ASSERT_EQ(table.Build(scene.Case.TF), "");
  ae::FrameMethod method;
  method.Kind = ae::Integration::Riemann;
  method.SampleDistance = 0.5;
  method.TF = &scene.Case.TF;
  method.Map = &scene.Map;
  method.EngineVolume = &bytes;
  method.EngineTable = &table;
  const std::vector<float> image = Cast(scene, scene.Doubles(), method, Serial);
  const an::TrilinearVolume<double, double> volume = scene.Field();
  const Agreement a = Compare(scene, method, image,
    [&](const glm::dvec3& o, const glm::dvec3& d, double D, const auto& segments)
    {
      const an::RayField<double, an::TrilinearVolume<double, double>> field{ volume, o, d };
      return an::IntegrateRiemann(field, scene.Case.TF, D, 0.5, an::RiemannForm::Exponential,
        segments.data(), segments.size(), 0.0)
        .RGBA;
    });
  // The float kernel's bound against the double sum (Riemann.h).
  EXPECT_LE(a.Error, 1e-4);
  EXPECT_GT(a.Opacity, 0.5);
}

// Shaded rays take the scalar double sum even where the method gives the
// kernel's volume (the kernels do not shade): the image is the one cast
// without it, and the shading shows.
TEST(Frame, ShadedRiemannRaysTakeTheScalarSum)
{
  const Scene scene;
  const ae::Volume bytes = scene.EngineBytes();
  ae::TransferTable table;
  ASSERT_EQ(table.Build(scene.Case.TF), "");
  an::ShadingModel<double> shading;
  shading.Lights.push_back(
    { glm::normalize(glm::dvec3(0.3, 0.5, 0.8)), glm::dvec3(1.0), glm::dvec3(1.0) });
  ae::FrameMethod method;
  method.Kind = ae::Integration::Riemann;
  method.SampleDistance = 0.5;
  method.TF = &scene.Case.TF;
  method.Map = &scene.Map;
  const std::vector<float> unshaded = Cast(scene, scene.Doubles(), method, Serial);
  method.Shading = &shading;
  const std::vector<float> scalar = Cast(scene, scene.Doubles(), method, Serial);
  method.EngineVolume = &bytes;
  method.EngineTable = &table;
  EXPECT_EQ(Cast(scene, scene.Doubles(), method, Serial), scalar);
  float difference = 0.0f;
  for (std::size_t i = 0; i < scalar.size(); ++i)
  {
    difference = std::max(difference, std::abs(scalar[i] - unshaded[i]));
  }
  EXPECT_GT(difference, 0.02f);
}

TEST(Frame, ClippedAdaptiveRaysMatchTheCoreForEveryScalarType)
{
  Scene scene;
  // A plane through the volume's middle, keeping the side towards +x + y.
  scene.Frame.Clip.AddPlane(glm::normalize(glm::dvec3(1.0, 1.0, 0.0)), -std::sqrt(2.0) * 19.5);
  ae::FrameMethod method;
  method.Kind = ae::Integration::AdaptiveCoupled;
  method.Adaptive.Tolerance = 1e-3;
  method.Adaptive.FieldMinimum = 0.0;
  method.Adaptive.FieldMaximum = 255.0;
  method.TF = &scene.Case.TF;
  method.Map = &scene.Map;
  const an::TrilinearVolume<double, double> volume = scene.Field();
  // Each type's copy of the integer values: the same field in double.
  const auto typed = [&](auto zero, ae::ScalarType type)
  {
    std::vector<decltype(zero)> data(scene.Case.Data.begin(), scene.Case.Data.end());
    ae::Scalars scalars = scene.Doubles();
    scalars.Data = data.data();
    scalars.Type = type;
    return Cast(scene, scalars, method, Serial);
  };
  const std::vector<float> reference = Cast(scene, scene.Doubles(), method, Serial);
  const Agreement a = Compare(scene, method, reference,
    [&](const glm::dvec3& o, const glm::dvec3& d, double, const auto& segments)
    {
      const an::RayField<double, an::TrilinearVolume<double, double>> field{ volume, o, d };
      return an::IntegrateAdaptive(
        field, scene.Case.TF, segments.data(), segments.size(), method.Adaptive)
        .RGBA;
    });
  EXPECT_LE(a.Error, ImageRounding);
  EXPECT_GT(a.Opacity, 0.2);
  EXPECT_EQ(typed(std::uint8_t(), ae::ScalarType::UInt8), reference);
  EXPECT_EQ(typed(std::int16_t(), ae::ScalarType::Int16), reference);
  EXPECT_EQ(typed(std::uint16_t(), ae::ScalarType::UInt16), reference);
  EXPECT_EQ(typed(std::int32_t(), ae::ScalarType::Int32), reference);
  EXPECT_EQ(typed(std::uint32_t(), ae::ScalarType::UInt32), reference);
  EXPECT_EQ(typed(std::int64_t(), ae::ScalarType::Int64), reference);
  EXPECT_EQ(typed(std::uint64_t(), ae::ScalarType::UInt64), reference);
  EXPECT_EQ(typed(float(), ae::ScalarType::Float32), reference);
}

TEST(Frame, MaximumIntensityMatchesTheCore)
{
  const Scene scene;
  ae::FrameMethod method;
  method.Mode = ae::Blend::Maximum;
  method.TF = &scene.Case.TF;
  method.Map = &scene.Map;
  const std::vector<float> image = Cast(scene, scene.Doubles(), method, Serial);
  const an::TrilinearVolume<double, double> volume = scene.Field();
  const Agreement a = Compare(scene, method, image,
    [&](const glm::dvec3& o, const glm::dvec3& d, double, const auto& segments)
    {
      const an::RayExtremum<double> e =
        an::ExtremumAlongRay(volume, o, d, segments.data(), segments.size(), true);
      const double alpha = std::min(std::max(scene.Case.TF.GetOpacityValue(e.Value), 0.0), 1.0);
      return e.Found ? glm::dvec4(scene.Case.TF.GetColor(e.Value) * alpha, alpha) : glm::dvec4(0.0);
    });
  EXPECT_LE(a.Error, ImageRounding);
  EXPECT_GT(a.Opacity, 0.0);
}

// Fields constant per cell (nearest interpolation of the point scalars, and
// cell scalars) and cell scalars between their centres: the frame against the core in the volume's
// walk coordinates, for the piecewise method (clipped too), Riemann and the maximum; the
// empty-space map (the point one for nearest, the cells' own for cell scalars, with their
// neighbours between centres) skips only what is transparent: the image without it is the same.
TEST(Frame, CellConstantFieldsMatchTheCore)
{
  Scene scene;
  const int* n = scene.Case.Dimensions;
  // Cell scalars: each cell takes its lowest corner's value.
  std::vector<double> cells;
  for (int k = 0; k + 1 < n[2]; ++k)
  {
    for (int j = 0; j + 1 < n[1]; ++j)
    {
      for (int i = 0; i + 1 < n[0]; ++i)
      {
        cells.push_back(scene.Case.Data[i + n[0] * (j + static_cast<std::size_t>(n[1]) * k)]);
      }
    }
  }
  an::EmptySpaceMap<double> cellMap;
  cellMap.SetDimensions(n);
  cellMap.ComputeRanges(cells.data(), an::EmptySpaceMap<double>::Samples::Cells);
  cellMap.Classify(scene.Case.TF);
  an::PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(scene.Case.TF, an::PiecewiseRelativeError(1e-3)), "");
  using Constant = an::CellConstantVolume<double, double>;
  an::EmptySpaceMap<double> centreMap;
  centreMap.SetDimensions(n);
  centreMap.ComputeRanges(cells.data(), an::EmptySpaceMap<double>::Samples::CellCentres);
  centreMap.Classify(scene.Case.TF);
  const Constant nearestVolume(scene.Case.Data.data(), n, Constant::Layout::NearestPoints);
  const Constant cellVolume(cells.data(), n, Constant::Layout::Cells);
  const an::CellCentredVolume<double, double> centredVolume(cells.data(), n);
  for (const ae::ScalarField field :
    { ae::ScalarField::Nearest, ae::ScalarField::Cells, ae::ScalarField::CellCentres })
  {
    const bool nearest = field == ae::ScalarField::Nearest;
    ae::Scalars scalars = scene.Doubles();
    scalars.Field = field;
    scalars.Data = nearest ? scene.Case.Data.data() : cells.data();
    const an::EmptySpaceMap<double>& map = nearest ? scene.Map
      : field == ae::ScalarField::Cells            ? cellMap
                                                   : centreMap;
    // The core on the same field (the walk coordinates of both are the
    // point grid's refined by 2, or the cells' own).
    auto withVolume = [&](auto&& f)
    {
      return nearest                      ? f(nearestVolume)
        : field == ae::ScalarField::Cells ? f(cellVolume)
                                          : f(centredVolume);
    };
    for (const bool clipped : { false, true })
    {
      scene.Frame.Clip = an::ClipRegion<double>();
      if (clipped)
      {
        scene.Frame.Clip.AddPlane(
          glm::normalize(glm::dvec3(1.0, 1.0, 0.0)), -std::sqrt(2.0) * 19.5);
      }
      for (const ae::Integration kind : { ae::Integration::Piecewise, ae::Integration::Riemann })
      {
        for (const ae::Blend mode : { ae::Blend::Composite, ae::Blend::Maximum })
        {
          ae::FrameMethod method;
          method.Kind = kind;
          method.Mode = mode;
          method.Adaptive.Tolerance = 1e-3;
          method.TF = &scene.Case.TF;
          method.Map = &map;
          method.Pieces = &pieces;
          const std::vector<float> image = Cast(scene, scalars, method, Serial);
          const Agreement a = Compare(scene, method, image,
            [&](const glm::dvec3& o, const glm::dvec3& d, double D, const auto& segments)
            {
              return withVolume(
                [&](const auto& volume)
                {
                  using VolumeT = std::decay_t<decltype(volume)>;
                  const glm::dvec3 wo = volume.ToWalk(o), wd = volume.ToWalk(d);
                  if (mode == ae::Blend::Maximum)
                  {
                    const an::RayExtremum<double> e =
                      an::ExtremumAlongRay(volume, wo, wd, segments.data(), segments.size(), true);
                    const double alpha =
                      std::min(std::max(scene.Case.TF.GetOpacityValue(e.Value), 0.0), 1.0);
                    return e.Found ? glm::dvec4(scene.Case.TF.GetColor(e.Value) * alpha, alpha)
                                   : glm::dvec4(0.0);
                  }
                  if (kind == ae::Integration::Riemann)
                  {
                    if (clipped)
                    {
                      // Riemann restarts at the clip plane (ClippedRiemann):
                      // the frame's own ray a time is the reference below.
                      return glm::dvec4(-1.0);
                    }
                    const an::RayField<double, VolumeT> f{ volume, wo, wd };
                    return an::IntegrateRiemann(f, scene.Case.TF, D, 0.5,
                      an::RiemannForm::Exponential, segments.data(), segments.size(), 0.0)
                      .RGBA;
                  }
                  return an::IntegratePiecewise(
                    volume, wo, wd, segments.data(), segments.size(), pieces, 1e-3)
                    .RGBA;
                });
            });
          const bool skipCore =
            clipped && kind == ae::Integration::Riemann && mode == ae::Blend::Composite;
          if (!skipCore)
          {
            EXPECT_LE(a.Error, ImageRounding)
              << "nearest " << nearest << " clipped " << clipped << " kind "
              << static_cast<int>(kind) << " mode " << static_cast<int>(mode);
            EXPECT_GT(a.Opacity, 0.2);
          }
          method.Map = nullptr;
          const std::vector<float> unskipped = Cast(scene, scalars, method, Serial);
          double skipped = 0.0;
          for (std::size_t i = 0; i < image.size(); ++i)
          {
            skipped = std::max(skipped, static_cast<double>(std::abs(image[i] - unskipped[i])));
          }
          // The piecewise method within its eps of the whole ray's integral;
          // Riemann and the maximum sample the same values.
          EXPECT_LE(skipped, kind == ae::Integration::Piecewise ? 1e-3 : 1e-6)
            << "nearest " << nearest << " clipped " << clipped;
        }
      }
    }
  }
}

// Two components read in place (8-bit tuples), an independent mixture: the
// frame against the core ray by ray for the piecewise method (clipped too,
// and the nearest field), Riemann, the adaptive rule and the reference;
// the mixture's empty-space map skips only what is transparent.
TEST(Frame, MixturesMatchTheCore)
{
  Scene scene;
  adversarial::Case second = adversarial::MakeVolume("two materials", adversarial::TwoMaterial, 11);
  const an::TransferFunction<double> spike = adversarial::Spike(125.0, 5.0, 3.0);
  std::vector<std::uint8_t> bytes;
  std::vector<double> doubles;
  for (std::size_t i = 0; i < scene.Case.Data.size(); ++i)
  {
    for (const double v : { scene.Case.Data[i], std::round(second.Data[i]) })
    {
      bytes.push_back(static_cast<std::uint8_t>(v));
      doubles.push_back(v);
    }
  }
  const an::TransferFunction<double>* functions[2] = { &scene.Case.TF, &spike };
  const double weights[2] = { 0.8, 1.0 };
  an::MixtureTransferFunction<double> mixture;
  mixture.SetIndependent(2, functions, weights);
  an::PiecewiseMixture<double> pieces;
  ASSERT_EQ(pieces.Build(mixture, an::PiecewiseRelativeError(1e-3)), "");
  // The second of weight 0: the first alone shows, and the frame is cast as
  // the first component's (its sums, its pieces in the kernels' lanes).
  const double soloWeights[2] = { 0.8, 0.0 };
  an::MixtureTransferFunction<double> solo;
  solo.SetIndependent(2, functions, soloWeights);
  an::PiecewiseMixture<double> soloPieces;
  ASSERT_EQ(soloPieces.Build(solo, an::PiecewiseRelativeError(1e-3)), "");
  ASSERT_NE(soloPieces.GetSingle(), nullptr);
  ASSERT_EQ(solo.GetSingleComponent(), 0);
  an::EmptySpaceMap<double> map;
  map.SetDimensions(scene.Case.Dimensions);
  map.ComputeRanges(bytes.data(), an::EmptySpaceMap<double>::Samples::Points, 2);
  map.ClassifyBlocks([&](const double* lo, const double* hi) { return mixture.IsVisible(lo, hi); });
  ae::Scalars scalars = scene.Doubles();
  scalars.Data = bytes.data();
  scalars.Type = ae::ScalarType::UInt8;
  scalars.Components = 2;
  using Volume = an::TrilinearVolume<double, double>;
  using Constant = an::CellConstantVolume<double, double>;
  const an::ComponentVolumes<double, Volume> volumes(
    2, [&](int k) { return Volume(doubles.data() + k, scene.Case.Dimensions, 2); });
  const an::ComponentVolumes<double, Constant> nearest(2,
    [&](int k)
    {
      return Constant(
        doubles.data() + k, scene.Case.Dimensions, Constant::Layout::NearestPoints, 2);
    });
  struct Run
  {
    ae::Integration Kind;
    bool Clipped;
    ae::ScalarField Field;
    bool Solo = false;
  };
  for (const Run run : { Run{ ae::Integration::Piecewise, false, ae::ScalarField::Trilinear },
         Run{ ae::Integration::Piecewise, true, ae::ScalarField::Trilinear },
         Run{ ae::Integration::Piecewise, false, ae::ScalarField::Nearest },
         Run{ ae::Integration::Piecewise, false, ae::ScalarField::Trilinear, true },
         Run{ ae::Integration::Riemann, false, ae::ScalarField::Trilinear, true },
         Run{ ae::Integration::Reference, false, ae::ScalarField::Trilinear, true },
         Run{ ae::Integration::Riemann, false, ae::ScalarField::Trilinear },
         Run{ ae::Integration::AdaptiveCoupled, false, ae::ScalarField::Trilinear },
         Run{ ae::Integration::Reference, false, ae::ScalarField::Trilinear } })
  {
    const an::PiecewiseMixture<double>& runPieces = run.Solo ? soloPieces : pieces;
    scene.Frame.Clip = an::ClipRegion<double>();
    if (run.Clipped)
    {
      scene.Frame.Clip.AddPlane(glm::normalize(glm::dvec3(1.0, 1.0, 0.0)), -std::sqrt(2.0) * 19.5);
    }
    scalars.Field = run.Field;
    ae::FrameMethod method;
    method.Kind = run.Kind;
    method.Adaptive.Tolerance = 1e-3;
    method.Adaptive.FieldMaximum = 255.0;
    method.SampleDistance = 0.5;
    method.Mixture = run.Solo ? &solo : &mixture;
    method.MixturePieces = &runPieces;
    method.Map = &map;
    ae::FrameStatistics stats;
    const std::vector<float> image = Cast(scene, scalars, method, Serial, &stats);
    auto core =
      [&](const auto& v, const glm::dvec3& o, const glm::dvec3& d, double D, const auto& segments)
    {
      const glm::dvec3 wo = v.ToWalk(o), wd = v.ToWalk(d);
      const an::RayField<double, std::decay_t<decltype(v)>> field{ v, wo, wd };
      switch (run.Kind)
      {
        case ae::Integration::Riemann:
          return an::IntegrateRiemann(field, *method.Mixture, D, 0.5, an::RiemannForm::Exponential,
            segments.data(), segments.size(), 0.0)
            .RGBA;
        case ae::Integration::AdaptiveCoupled:
          return an::IntegrateAdaptive(
            field, *method.Mixture, segments.data(), segments.size(), method.Adaptive)
            .RGBA;
        case ae::Integration::Reference:
          return an::IntegratePiecewiseMixture(v, wo, wd, segments.data(), segments.size(),
            runPieces, an::PiecewiseReferenceTolerance<double>())
            .RGBA;
        default:
          return an::IntegratePiecewiseMixture(
            v, wo, wd, segments.data(), segments.size(), runPieces, 1e-3)
            .RGBA;
      }
    };
    const Agreement a = Compare(scene, method, image,
      [&](const glm::dvec3& o, const glm::dvec3& d, double D, const auto& segments)
      {
        return run.Field == ae::ScalarField::Nearest ? core(nearest, o, d, D, segments)
                                                     : core(volumes, o, d, D, segments);
      });
    const std::string what = "kind " + std::to_string(static_cast<int>(run.Kind)) +
      (run.Clipped ? " clipped" : "") + (run.Field == ae::ScalarField::Nearest ? " nearest" : "") +
      (run.Solo ? " solo" : "");
    EXPECT_LE(a.Error, ImageRounding) << what;
    EXPECT_GT(a.Opacity, 0.2) << what;
    // Without the map: the same image within the method's tolerance.
    method.Map = nullptr;
    const std::vector<float> unskipped = Cast(scene, scalars, method, Serial);
    double skipped = 0.0;
    for (std::size_t i = 0; i < image.size(); ++i)
    {
      skipped = std::max(skipped, static_cast<double>(std::abs(image[i] - unskipped[i])));
    }
    EXPECT_LE(skipped, run.Kind == ae::Integration::Riemann ? ImageRounding : 2e-3) << what;
  }
  // What a mixture cannot take.
  ae::FrameMethod method;
  method.Kind = ae::Integration::Piecewise;
  method.Mixture = &mixture;
  EXPECT_NE(ae::Validate(scalars, method), ""); // no pieces
  method.MixturePieces = &pieces;
  EXPECT_EQ(ae::Validate(scalars, method), "");
  method.Mode = ae::Blend::Maximum;
  EXPECT_NE(ae::Validate(scalars, method), "");
  method.Mode = ae::Blend::Composite;
  an::ShadingModel<double> shading;
  method.Shading = &shading;
  EXPECT_NE(ae::Validate(scalars, method), "");
  method.Shading = nullptr;
  scalars.Components = 3;
  EXPECT_NE(ae::Validate(scalars, method), "");
}

TEST(Frame, ThreadedLoopGivesTheSerialImage)
{
  const Scene scene;
  an::PiecewiseTransferFunction<double> pieces;
  ASSERT_EQ(pieces.Build(scene.Case.TF, an::PiecewiseRelativeError(1e-3)), "");
  ae::FrameMethod method;
  method.Kind = ae::Integration::Piecewise;
  method.Adaptive.Tolerance = 1e-3;
  method.TF = &scene.Case.TF;
  method.Map = &scene.Map;
  method.Pieces = &pieces;
  ae::FrameStatistics serial, threaded;
  const std::vector<float> a = Cast(scene, scene.Doubles(), method, Serial, &serial);
  const std::vector<float> b = Cast(scene, scene.Doubles(), method, Threaded, &threaded);
  EXPECT_EQ(a, b);
  EXPECT_EQ(serial.Rays, threaded.Rays);
  EXPECT_EQ(serial.Pieces, threaded.Pieces);
  EXPECT_EQ(serial.Cells, threaded.Cells);
  EXPECT_EQ(serial.MaximumSamples, threaded.MaximumSamples);
}

TEST(Frame, FootprintCoversEveryRayThatMeetsTheBox)
{
  const Scene scene;
  const int* r = scene.Frame.Rect;
  int inside = 0;
  for (int y = 0; y < Height; ++y)
  {
    for (int x = 0; x < Width; ++x)
    {
      double o[3], d[3], D;
      if (ae::PixelRay(scene.Frame.Rays, x, y, o, d, D))
      {
        ++inside;
        EXPECT_TRUE(x >= r[0] && x < r[1] && y >= r[2] && y < r[3]) << x << ", " << y;
      }
    }
  }
  EXPECT_GT(inside, 0);
  // Tighter than the image: the volume leaves part of it empty.
  EXPECT_LT((r[1] - r[0]) * (r[3] - r[2]), Width * Height);
}

TEST(Frame, RefusesWhatItCannotCast)
{
  const Scene scene;
  ae::FrameMethod method;
  EXPECT_NE(ae::Validate(scene.Doubles(), method), ""); // no transfer function
  method.TF = &scene.Case.TF;
  EXPECT_EQ(ae::Validate(scene.Doubles(), method), "");
  method.Kind = ae::Integration::Piecewise;
  EXPECT_NE(ae::Validate(scene.Doubles(), method), ""); // no pieces
  method.Kind = ae::Integration::Riemann;
  method.Mode = ae::Blend::Average;
  EXPECT_NE(ae::Validate(scene.Doubles(), method), ""); // no range
  method.Mode = ae::Blend::Composite;
  ae::Scalars flat = scene.Doubles();
  flat.Dimensions[2] = 1;
  EXPECT_NE(ae::Validate(flat, method), "");
  flat.Data = nullptr;
  EXPECT_NE(ae::Validate(flat, method), "");
  // A field constant per cell: no kernels, no shading (no gradient).
  ae::Scalars nearest = scene.Doubles();
  nearest.Field = ae::ScalarField::Nearest;
  EXPECT_EQ(ae::Validate(nearest, method), "");
  const ae::Volume bytes = scene.EngineBytes();
  ae::TransferTable table;
  ASSERT_EQ(table.Build(scene.Case.TF), "");
  method.EngineVolume = &bytes;
  method.EngineTable = &table;
  EXPECT_EQ(ae::Validate(scene.Doubles(), method), "");
  EXPECT_NE(ae::Validate(nearest, method), "");
  method.EngineVolume = nullptr;
  method.EngineTable = nullptr;
  const an::ShadingModel<double> shading;
  method.Shading = &shading;
  EXPECT_EQ(ae::Validate(scene.Doubles(), method), "");
  EXPECT_NE(ae::Validate(nearest, method), "");
}
} // namespace
