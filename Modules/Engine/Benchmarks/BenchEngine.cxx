// Google Benchmark rows of the vectorised kernels on each dispatch target
// against the scalar code of the numerical core, on the same rays through a
// 256^3 smooth volume: the Riemann kernel (64-knot transfer function, h 0.5,
// no early termination; time per ray and per sample; a ray's samples in
// lanes, and a ray per lane) and the packet walk of
// the empty-space map (a transfer function transparent below 150, bundles of
// 16 neighbouring rays as a tile's row casts them; time per ray), and the
// piecewise method with its pieces' kernels scalar or vectorised (the same
// rays, VTK's alpha model at eps 1e-3 and 1e-2; time per ray and per piece).
//   build/bin/avos-bench-engine
#include "AdversarialCases.h"

#include "avos/engine/EmptySpace.h"
#include "avos/engine/PieceKernels.h"
#include "avos/engine/Riemann.h"

#include "hwy/targets.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace an = avos::numerics;
namespace ae = avos::engine;

namespace
{
constexpr int Size = 256;
constexpr int Rays = 512;

struct Fixture
{
  std::vector<double> Data;
  std::vector<float> DataF;
  std::vector<std::uint8_t> Bytes; // Data rounded
  int Dimensions[3] = { Size, Size, Size };
  an::TransferFunction<double> TF;
  ae::TransferTable Table;
  std::vector<adversarial::Ray> RaySet;

  Fixture(bool alpha)
  {
    Data.resize(std::size_t(Size) * Size * Size);
    for (int k = 0; k < Size; ++k)
    {
      for (int j = 0; j < Size; ++j)
      {
        for (int i = 0; i < Size; ++i)
        {
          Data[i + Size * (j + std::size_t(Size) * k)] = adversarial::Smooth(
            2.0 * i / (Size - 1) - 1.0, 2.0 * j / (Size - 1) - 1.0, 2.0 * k / (Size - 1) - 1.0, 3);
        }
      }
    }
    DataF.assign(Data.begin(), Data.end());
    for (double v : Data)
    {
      Bytes.push_back(static_cast<std::uint8_t>(std::lround(v)));
    }
    TF = adversarial::Random(5, 64, alpha ? 0.05 : 0.02);
    if (alpha)
    {
      TF.SetOpacityModel(an::OpacityModel::Alpha, 1.0);
      TF.Finalize();
    }
    Table.Build(TF);
    adversarial::Case shape;
    std::copy(Dimensions, Dimensions + 3, shape.Dimensions);
    for (unsigned i = 0; i < Rays; ++i)
    {
      RaySet.push_back(adversarial::MakeRay(shape, i));
    }
  }
};

const Fixture& Get(bool alpha)
{
  static const std::unique_ptr<Fixture> extinction(new Fixture(false));
  static const std::unique_ptr<Fixture> vtk(new Fixture(true));
  return alpha ? *vtk : *extinction;
}

// The fixture's volume with a transfer function transparent below 150.
const an::EmptySpaceMap<double>& GetMap()
{
  static const std::unique_ptr<an::EmptySpaceMap<double>> map(
    []
    {
      const Fixture& f = Get(false);
      an::TransferFunction<double> tf;
      tf.AddColorKnot(0.0, 1.0, 1.0, 1.0);
      tf.AddOpacityKnot(0.0, 0.0);
      tf.AddOpacityKnot(150.0, 0.0);
      tf.AddOpacityKnot(255.0, 1.0);
      tf.Finalize();
      auto* m = new an::EmptySpaceMap<double>();
      m->SetDimensions(f.Dimensions);
      m->ComputeRanges(f.Data.data());
      m->Classify(tf);
      return m;
    }());
  return *map;
}

// Bundles of 16 rays as a tile's row of pixels casts them: from one eye, 2
// mrad apart (half a voxel at the volume's far side), clipped to the box;
// one bundle per ray of the fixture's first 64.
const std::vector<adversarial::Ray>& GetBundles()
{
  static const std::unique_ptr<std::vector<adversarial::Ray>> bundles(
    []
    {
      const Fixture& f = Get(false);
      auto* rays = new std::vector<adversarial::Ray>();
      for (std::size_t b = 0; b < 64; ++b)
      {
        const adversarial::Ray& base = f.RaySet[b];
        const glm::dvec3 eye = base.Origin - 300.0 * base.Direction;
        const glm::dvec3 axis =
          std::abs(base.Direction.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
        const glm::dvec3 across = glm::normalize(glm::cross(base.Direction, axis));
        for (int k = 0; k < 16; ++k)
        {
          const glm::dvec3 d = glm::normalize(base.Direction + (k - 7.5) * 0.002 * across);
          double t0 = 0.0, t1 = 1e4;
          if (an::ClipToGrid(eye, d, f.Dimensions, t0, t1))
          {
            rays->push_back({ eye + t0 * d, d, t1 - t0 });
          }
        }
      }
      return rays;
    }());
  return *bundles;
}

void ReportWalk(benchmark::State& state, long rays, long segments)
{
  state.counters["time_per_ray"] =
    benchmark::Counter(double(rays), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["segments_per_ray"] = double(segments) / double(std::max(rays, 1L));
}

void WalkScalar(benchmark::State& state)
{
  const an::EmptySpaceMap<double>& map = GetMap();
  std::vector<an::Interval<double>> segments;
  long rays = 0, count = 0;
  for (auto _ : state)
  {
    for (const auto& ray : GetBundles())
    {
      map.Segments(ray.Origin, ray.Direction, ray.Length, 1e-6, segments);
      benchmark::DoNotOptimize(segments.data());
      count += static_cast<long>(segments.size());
      ++rays;
    }
  }
  ReportWalk(state, rays, count);
}
BENCHMARK(WalkScalar)->Unit(benchmark::kMillisecond);

void WalkPacket(benchmark::State& state)
{
  const an::EmptySpaceMap<double>& map = GetMap();
  hwy::SetSupportedTargetsForTest(state.range(0));
  state.SetLabel(ae::PacketSegmentsTarget());
  constexpr std::size_t Packet = 16; // the mapper's (a tile's row)
  std::vector<double> origins, directions, lengths;
  for (const auto& ray : GetBundles())
  {
    for (int a = 0; a < 3; ++a)
    {
      origins.push_back(ray.Origin[a]);
      directions.push_back(ray.Direction[a]);
    }
    lengths.push_back(ray.Length);
  }
  std::vector<std::vector<an::Interval<double>>> segments(Packet);
  long rays = 0, count = 0;
  for (auto _ : state)
  {
    for (std::size_t first = 0; first < lengths.size(); first += Packet)
    {
      const std::size_t n = std::min(Packet, lengths.size() - first);
      ae::PacketSegments(map, n, origins.data() + 3 * first, directions.data() + 3 * first,
        lengths.data() + first, 1e-6, segments.data());
      for (std::size_t i = 0; i < n; ++i)
      {
        count += static_cast<long>(segments[i].size());
      }
      rays += static_cast<long>(n);
    }
  }
  hwy::SetSupportedTargetsForTest(0);
  ReportWalk(state, rays, count);
}

// Time per ray and per `unit` ("sample", or "piece" for the piecewise method).
void Report(benchmark::State& state, long rays, long count, const std::string& unit = "sample")
{
  state.counters["time_per_ray"] =
    benchmark::Counter(double(rays), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["time_per_" + unit] =
    benchmark::Counter(double(count), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters[unit + "s_per_ray"] = double(count) / double(std::max(rays, 1L));
}

void Scalar(benchmark::State& state)
{
  const Fixture& f = Get(state.range(0) != 0);
  const an::TrilinearVolume<double, double> volume(f.Data.data(), f.Dimensions);
  long rays = 0, samples = 0;
  for (auto _ : state)
  {
    for (const auto& ray : f.RaySet)
    {
      const an::RayField<double, an::TrilinearVolume<double, double>> field{ volume, ray.Origin,
        ray.Direction };
      const auto r =
        an::IntegrateRiemann(field, f.TF, ray.Length, 0.5, an::RiemannForm::Exponential);
      benchmark::DoNotOptimize(r.RGBA);
      samples += r.Statistics.Samples;
      ++rays;
    }
  }
  Report(state, rays, samples);
}
BENCHMARK(Scalar)->ArgName("vtk_opacity")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The vectorised Riemann kernel on the fixture's rays: a ray's samples in
// lanes (CastRiemann, ray by ray) or a ray per lane (CastRiemannRays, all
// rays at once).
void RiemannKernel(benchmark::State& state, bool perLane)
{
  const Fixture& f = Get(state.range(1) != 0);
  hwy::SetSupportedTargetsForTest(state.range(0));
  state.SetLabel(ae::CastRiemannTarget());
  ae::Volume volume;
  volume.Data = f.DataF.data();
  std::copy(f.Dimensions, f.Dimensions + 3, volume.Dimensions);
  std::vector<an::Interval<double>> whole;
  for (const auto& ray : f.RaySet)
  {
    whole.push_back({ 0.0, ray.Length });
  }
  std::vector<ae::RiemannRay> rays(f.RaySet.size());
  for (std::size_t i = 0; i < rays.size(); ++i)
  {
    const auto& ray = f.RaySet[i];
    for (int a = 0; a < 3; ++a)
    {
      rays[i].Origin[a] = ray.Origin[a];
      rays[i].Direction[a] = ray.Direction[a];
    }
    rays[i].D = ray.Length;
    rays[i].Segments = &whole[i];
    rays[i].Count = 1;
  }
  std::vector<ae::RayOutput> out(rays.size());
  long count = 0, samples = 0;
  for (auto _ : state)
  {
    if (perLane)
    {
      ae::CastRiemannRays(volume, f.Table, 0.5, 0.0, rays.data(), rays.size(), out.data());
    }
    else
    {
      for (std::size_t i = 0; i < rays.size(); ++i)
      {
        const ae::RiemannRay& r = rays[i];
        ae::CastRiemann(
          volume, f.Table, r.Origin, r.Direction, r.D, 0.5, r.Segments, 1, 0.0, out[i]);
      }
    }
    benchmark::DoNotOptimize(out.data());
    for (const auto& o : out)
    {
      samples += o.Samples;
    }
    count += static_cast<long>(rays.size());
  }
  hwy::SetSupportedTargetsForTest(0);
  Report(state, count, samples);
}

void Vectorised(benchmark::State& state)
{
  RiemannKernel(state, false);
}

void RaysPerLane(benchmark::State& state)
{
  RiemannKernel(state, true);
}

// The fixture's alpha-model transfer function prepared for the piecewise
// method at eps 1e-3 (index 0) or 1e-2 (1).
const an::PiecewiseTransferFunction<double>& GetPieces(int coarse)
{
  static const std::unique_ptr<an::PiecewiseTransferFunction<double>> pieces[2] = {
    std::unique_ptr<an::PiecewiseTransferFunction<double>>(
      new an::PiecewiseTransferFunction<double>()),
    std::unique_ptr<an::PiecewiseTransferFunction<double>>(
      new an::PiecewiseTransferFunction<double>())
  };
  if (pieces[coarse]->GetNumberOfPieces() == 0)
  {
    pieces[coarse]->Build(Get(true).TF, an::PiecewiseRelativeError(coarse ? 1e-2 : 1e-3));
  }
  return *pieces[coarse];
}

template <typename VolumeT, typename Kernels>
void PiecesOn(benchmark::State& state, const VolumeT& volume, const Kernels& kernels, int coarse)
{
  const Fixture& f = Get(true);
  const an::PiecewiseTransferFunction<double>& tf = GetPieces(coarse);
  long rays = 0, pieces = 0;
  for (auto _ : state)
  {
    for (const auto& ray : f.RaySet)
    {
      const an::Interval<double> whole{ 0.0, ray.Length };
      const auto r = an::IntegratePiecewise(volume, ray.Origin, ray.Direction, &whole, 1, tf,
        coarse ? 1e-2 : 1e-3, true, nullptr, kernels);
      benchmark::DoNotOptimize(r.RGBA);
      pieces += r.Statistics.Pieces;
      ++rays;
    }
  }
  Report(state, rays, pieces, "piece");
}

// On the double fixture, or on its 8-bit copy (bytes).
template <typename Kernels>
void Pieces(benchmark::State& state, const Kernels& kernels, int coarse, bool bytes = false)
{
  const Fixture& f = Get(true);
  if (bytes)
  {
    PiecesOn(state, an::TrilinearVolume<double, std::uint8_t>(f.Bytes.data(), f.Dimensions),
      kernels, coarse);
    return;
  }
  PiecesOn(
    state, an::TrilinearVolume<double, double>(f.Data.data(), f.Dimensions), kernels, coarse);
}

void PiecesScalar(benchmark::State& state)
{
  Pieces(state, an::ScalarPieceKernels<double>(), static_cast<int>(state.range(0)));
}
BENCHMARK(PiecesScalar)->ArgName("coarse")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BytePiecesScalar(benchmark::State& state)
{
  Pieces(state, an::ScalarPieceKernels<double>(), static_cast<int>(state.range(0)), true);
}
BENCHMARK(BytePiecesScalar)->ArgName("coarse")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void PiecesVectorised(benchmark::State& state)
{
  hwy::SetSupportedTargetsForTest(state.range(0));
  state.SetLabel(ae::PieceKernelsTarget());
  Pieces(state, ae::PieceKernels(), static_cast<int>(state.range(1)));
  hwy::SetSupportedTargetsForTest(0);
}

// The cells' stage vectorised too (8-bit scalars).
void BytePiecesVectorised(benchmark::State& state)
{
  const Fixture& f = Get(true);
  ae::Volume volume;
  volume.Data = f.Bytes.data();
  volume.Scalars = ae::Volume::Type::UInt8;
  std::copy(f.Dimensions, f.Dimensions + 3, volume.Dimensions);
  hwy::SetSupportedTargetsForTest(state.range(0));
  state.SetLabel(ae::PieceKernelsTarget());
  Pieces(state, ae::PieceKernels(&volume), static_cast<int>(state.range(1)), true);
  hwy::SetSupportedTargetsForTest(0);
}

void RegisterTargets()
{
  for (int64_t target : hwy::SupportedAndGeneratedTargets())
  {
    for (int alpha : { 0, 1 })
    {
      benchmark::RegisterBenchmark((std::string("Vectorised/") + hwy::TargetName(target) +
                                     "/vtk_opacity:" + std::to_string(alpha))
                                     .c_str(),
        Vectorised)
        ->Args({ target, alpha })
        ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark((std::string("RaysPerLane/") + hwy::TargetName(target) +
                                     "/vtk_opacity:" + std::to_string(alpha))
                                     .c_str(),
        RaysPerLane)
        ->Args({ target, alpha })
        ->Unit(benchmark::kMillisecond);
    }
    for (int coarse : { 0, 1 })
    {
      benchmark::RegisterBenchmark((std::string("PiecesVectorised/") + hwy::TargetName(target) +
                                     "/coarse:" + std::to_string(coarse))
                                     .c_str(),
        PiecesVectorised)
        ->Args({ target, coarse })
        ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark((std::string("BytePiecesVectorised/") + hwy::TargetName(target) +
                                     "/coarse:" + std::to_string(coarse))
                                     .c_str(),
        BytePiecesVectorised)
        ->Args({ target, coarse })
        ->Unit(benchmark::kMillisecond);
    }
    benchmark::RegisterBenchmark(
      (std::string("WalkPacket/") + hwy::TargetName(target)).c_str(), WalkPacket)
      ->Arg(target)
      ->Unit(benchmark::kMillisecond);
  }
}
} // namespace

int main(int argc, char** argv)
{
  RegisterTargets();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
