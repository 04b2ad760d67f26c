// Google Benchmark rows of the vectorised Riemann kernel on each dispatch
// target against the scalar double sum of the numerical core, on the same
// rays through a 256^3 smooth volume with a 64-knot transfer function
// (h 0.5, no early termination): time per ray and per sample.
//   build/bin/avos-bench-engine
#include "AdversarialCases.h"

#include "avos/engine/Riemann.h"

#include "hwy/targets.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
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

void Report(benchmark::State& state, long rays, long samples)
{
  state.counters["time_per_ray"] =
    benchmark::Counter(double(rays), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["time_per_sample"] =
    benchmark::Counter(double(samples), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["samples_per_ray"] = double(samples) / double(std::max(rays, 1L));
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

void Vectorised(benchmark::State& state)
{
  const Fixture& f = Get(state.range(1) != 0);
  hwy::SetSupportedTargetsForTest(state.range(0));
  state.SetLabel(ae::CastRiemannTarget());
  ae::Volume volume;
  volume.Data = f.DataF.data();
  std::copy(f.Dimensions, f.Dimensions + 3, volume.Dimensions);
  long rays = 0, samples = 0;
  for (auto _ : state)
  {
    for (const auto& ray : f.RaySet)
    {
      const an::Interval<double> whole{ 0.0, ray.Length };
      const double o[3] = { ray.Origin.x, ray.Origin.y, ray.Origin.z };
      const double d[3] = { ray.Direction.x, ray.Direction.y, ray.Direction.z };
      ae::RayOutput out;
      ae::CastRiemann(volume, f.Table, o, d, ray.Length, 0.5, &whole, 1, 0.0, out);
      benchmark::DoNotOptimize(out.RGBA);
      samples += out.Samples;
      ++rays;
    }
  }
  hwy::SetSupportedTargetsForTest(0);
  Report(state, rays, samples);
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
    }
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
