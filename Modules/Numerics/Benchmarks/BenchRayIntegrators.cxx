// Time per ray and samples per ray of every integrator on a fixed synthetic ray
// set (the first 256 rays of Testing/RandomRays.h), so that changes can be
// compared:  build/bin/avos-bench-integrators; the cost of one sample; and
// what a second component costs the piecewise method.
#include "RandomRays.h"
#include "avos/numerics/Mixture.h"
#include "avos/numerics/PiecewiseShading.h"
#include "avos/numerics/RayIntegrators.h"
#include "avos/numerics/Volume.h"

#include <benchmark/benchmark.h>

using namespace avos::numerics;

namespace
{
constexpr int Rays = 256;

template <typename Real>
const std::vector<randomrays::Ray<Real>>& RaySet()
{
  static const std::vector<randomrays::Ray<Real>> rays = []
  {
    std::vector<randomrays::Ray<Real>> r;
    for (int i = 0; i < Rays; ++i)
    {
      r.push_back(randomrays::Make<Real>(i));
    }
    return r;
  }();
  return rays;
}

template <typename Real, typename Integrate>
void Run(benchmark::State& state, Integrate integrate)
{
  const auto& rays = RaySet<Real>();
  long samples = 0, rays_done = 0;
  for (auto _ : state)
  {
    for (const auto& ray : rays)
    {
      const auto r = integrate(ray);
      benchmark::DoNotOptimize(r.RGBA);
      samples += r.Statistics.Samples;
      ++rays_done;
    }
  }
  state.SetItemsProcessed(rays_done);
  state.counters["time_per_ray"] = benchmark::Counter(
    double(rays_done), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["samples_per_ray"] = double(samples) / double(rays_done);
}

void Riemann(benchmark::State& state)
{
  const double h = state.range(0) / 100.0;
  Run<double>(state,
    [h](const auto& ray)
    { return IntegrateRiemann(ray, ray.TF, ray.Length, h, RiemannForm::Linear); });
}
BENCHMARK(Riemann)->Arg(50)->Arg(10)->Arg(1)->Unit(benchmark::kMicrosecond);

void Simpson(benchmark::State& state)
{
  const double h = state.range(0) / 100.0;
  Run<double>(state, [h](const auto& ray) { return IntegrateSimpson(ray, ray.TF, ray.Length, h); });
}
BENCHMARK(Simpson)->Arg(200)->Arg(50)->Unit(benchmark::kMicrosecond);

template <typename Real>
void Adaptive(benchmark::State& state)
{
  AdaptiveSettings<Real> s;
  s.Tolerance = Real(state.range(0) / 10000.0);
  s.Coupling = state.range(1) ? Strategy::Decoupled : Strategy::Coupled;
  Run<Real>(state, [&s](const auto& ray) { return IntegrateAdaptive(ray, ray.TF, ray.Length, s); });
}
BENCHMARK_TEMPLATE(Adaptive, double)
  ->ArgsProduct({ { 100, 50, 10 }, { 0, 1 } })
  ->ArgNames({ "eps_x1e4", "decoupled" })
  ->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(Adaptive, float)
  ->ArgsProduct({ { 100, 10 }, { 0 } })
  ->ArgNames({ "eps_x1e4", "decoupled" })
  ->Unit(benchmark::kMicrosecond);

void Reference(benchmark::State& state)
{
  Run<double>(state, [](const auto& ray) { return IntegrateReference(ray, ray.TF, ray.Length); });
}
BENCHMARK(Reference)->Unit(benchmark::kMillisecond);

// What one sample costs on its own, the floor under any ray caster built on
// the core: trilinear interpolation in a 256^3 uint8 volume along a ray
// (0.5-voxel steps, oblique so that every step touches new cells), then the
// transfer function (Classify, 5 knots). Time per sample.
void Sample(benchmark::State& state)
{
  constexpr int N = 256;
  static const std::vector<unsigned char> data = []
  {
    std::vector<unsigned char> v(std::size_t(N) * N * N);
    for (std::size_t i = 0; i < v.size(); ++i)
    {
      v[i] = static_cast<unsigned char>((i * 2654435761u) >> 24);
    }
    return v;
  }();
  const int dims[3] = { N, N, N };
  const TrilinearVolume<double, unsigned char> volume(data.data(), dims);
  TransferFunction<double> tf;
  for (double s : { 0.0, 60.0, 120.0, 200.0, 255.0 })
  {
    tf.AddOpacityKnot(s, s / 255.0);
    tf.AddColorKnot(s, s / 255.0, 0.5, 1.0 - s / 255.0);
  }
  tf.SetOpacityModel(state.range(0) ? OpacityModel::Alpha : OpacityModel::Extinction);
  tf.Finalize();
  const glm::dvec3 origin(3.3, 7.1, 0.4);
  const glm::dvec3 direction = glm::normalize(glm::dvec3(0.31, 0.27, 1.0));
  const RayField<double, TrilinearVolume<double, unsigned char>> field{ volume, origin, direction };
  long samples = 0;
  for (auto _ : state)
  {
    double sum = 0.0;
    for (int i = 0; i < 400; ++i)
    {
      double tau;
      glm::dvec3 color;
      tf.Classify(field(0.5 * i), tau, color);
      sum += tau + color.x;
    }
    benchmark::DoNotOptimize(sum);
    samples += 400;
  }
  state.counters["time_per_sample"] =
    benchmark::Counter(double(samples), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(Sample)->Arg(0)->Arg(1)->ArgName("vtk_opacity");

// What a second component costs the piecewise method (eps 1e-3, VTK's
// opacity model): 256 oblique rays through a smooth 64^3 uint8 volume whose
// second component is the first mirrored along x, with one component, two
// with the second transparent, and two visible. Time and pieces per ray.
struct TwoComponents
{
  static constexpr int N = 64;
  std::vector<unsigned char> Data; // interleaved pairs
  TransferFunction<double> Visible, Clear;

  TwoComponents()
  {
    for (int z = 0; z < N; ++z)
    {
      for (int y = 0; y < N; ++y)
      {
        for (int x = 0; x < N; ++x)
        {
          for (const int u : { x, N - 1 - x })
          {
            const double f = std::sin(0.21 * u) * std::cos(0.17 * y) + std::sin(0.13 * z + 0.4);
            this->Data.push_back(static_cast<unsigned char>(63.75 * (f + 2.0)));
          }
        }
      }
    }
    for (const double s : { 0.0, 60.0, 120.0, 200.0, 255.0 })
    {
      this->Visible.AddOpacityKnot(s, 0.2 * s / 255.0);
      this->Visible.AddColorKnot(s, s / 255.0, 0.5, 1.0 - s / 255.0);
    }
    this->Clear.AddOpacityKnot(0.0, 0.0);
    this->Clear.AddColorKnot(0.0, 1.0, 1.0, 1.0);
    for (TransferFunction<double>* tf : { &this->Visible, &this->Clear })
    {
      tf->SetOpacityModel(OpacityModel::Alpha);
      tf->Finalize();
    }
  }
};

void Components(benchmark::State& state)
{
  static const TwoComponents scene;
  constexpr int N = TwoComponents::N;
  const int dims[3] = { N, N, N };
  using Volume = TrilinearVolume<double, unsigned char>;
  const ComponentVolumes<double, Volume> volumes(
    2, [&](int k) { return Volume(scene.Data.data() + k, dims, 2); });
  const int components = static_cast<int>(state.range(0));
  PiecewiseTransferFunction<double> one;
  one.Build(scene.Visible, 1e-3 / 8.0);
  MixtureTransferFunction<double> mixture;
  const TransferFunction<double>* functions[2] = { &scene.Visible,
    components == 2 ? &scene.Visible : &scene.Clear };
  const double weights[2] = { 1.0, 1.0 };
  mixture.SetIndependent(2, functions, weights);
  PiecewiseMixture<double> pieces;
  pieces.Build(mixture, 1e-3 / 8.0);
  long rays = 0, pieceCount = 0;
  for (auto _ : state)
  {
    for (int i = 0; i < 256; ++i)
    {
      const glm::dvec3 origin(0.5 + (i % 16) * 3.9, 0.5 + (i / 16) * 3.9, 0.0);
      const glm::dvec3 direction = glm::normalize(glm::dvec3(0.31, 0.27, 1.0));
      const double end = (N - 1) / direction.z;
      const Interval<double> whole{ 0.0,
        std::min({ end, (N - 1 - origin.x) / direction.x, (N - 1 - origin.y) / direction.y }) };
      const RayResult<double> r = components == 1
        ? IntegratePiecewise(volumes[0], origin, direction, &whole, 1, one, 1e-3)
        : IntegratePiecewiseMixture(volumes, origin, direction, &whole, 1, pieces, 1e-3);
      benchmark::DoNotOptimize(r.RGBA);
      pieceCount += r.Statistics.Pieces;
      ++rays;
    }
  }
  state.counters["time_per_ray"] =
    benchmark::Counter(double(rays), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["pieces_per_ray"] = double(pieceCount) / double(rays);
}
// 1: one component; 0: two, the second transparent; 2: two visible.
BENCHMARK(Components)->Arg(1)->Arg(0)->Arg(2)->ArgName("visible")->Unit(benchmark::kMicrosecond);

// The shaded piecewise method (PiecewiseShading.h) on the first component of
// the same rays, VTK's default shading (ambient 0.1, diffuse 0.7, specular
// 0.2, power 10) under a white headlight, at eps 10^-k: time per ray, per
// enclosure of the lit colour (a sample), enclosures and pieces per ray.
void Shaded(benchmark::State& state)
{
  static const TwoComponents scene;
  constexpr int N = TwoComponents::N;
  const int dims[3] = { N, N, N };
  const TrilinearVolume<double, unsigned char> volume(scene.Data.data(), dims, 2);
  const double tolerance = std::pow(10.0, -double(state.range(0)));
  PiecewiseTransferFunction<double> tf;
  tf.Build(scene.Visible, tolerance / 8.0);
  ShadingModel<double> model;
  const glm::dvec3 direction = glm::normalize(glm::dvec3(0.31, 0.27, 1.0));
  Light<double> headlight;
  headlight.Direction = -direction;
  headlight.Diffuse = headlight.Specular = glm::dvec3(1.0);
  model.Lights.push_back(headlight);
  RayShading<double> shading;
  shading.Model = &model;
  shading.ToViewer = -direction;
  shading.WorldDirection = direction;
  long rays = 0, samples = 0, pieces = 0;
  for (auto _ : state)
  {
    for (int i = 0; i < 256; ++i)
    {
      const glm::dvec3 origin(0.5 + (i % 16) * 3.9, 0.5 + (i / 16) * 3.9, 0.0);
      const double end = (N - 1) / direction.z;
      const Interval<double> whole{ 0.0,
        std::min({ end, (N - 1 - origin.x) / direction.x, (N - 1 - origin.y) / direction.y }) };
      shading.WorldOrigin = origin;
      const RayResult<double> r =
        IntegratePiecewiseShaded(volume, origin, direction, &whole, 1, tf, tolerance, shading);
      benchmark::DoNotOptimize(r.RGBA);
      samples += r.Statistics.Samples;
      pieces += r.Statistics.Pieces;
      ++rays;
    }
  }
  using C = benchmark::Counter;
  state.counters["time_per_ray"] = C(double(rays), C::kIsRate | C::kInvert);
  state.counters["time_per_sample"] = C(double(samples), C::kIsRate | C::kInvert);
  state.counters["samples_per_ray"] = double(samples) / double(rays);
  state.counters["pieces_per_ray"] = double(pieces) / double(rays);
}
BENCHMARK(Shaded)->Arg(2)->Arg(3)->Arg(9)->ArgName("eps_exponent")->Unit(benchmark::kMicrosecond);
}

BENCHMARK_MAIN();
