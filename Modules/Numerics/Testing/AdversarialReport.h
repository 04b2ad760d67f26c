// The adversarial accuracy suite's report (Markdown): for each case of
// AdversarialCases.h, the exact reference of `rays` random rays, then the
// piecewise, coupled and decoupled methods at eps 0.01, 0.001 and 1e-4: % of
// rays within eps per RGBA channel, the largest error, samples, cells and
// pieces per ray, seconds; then the same lit by SharpLighting on
// `shadedRays` rays (none: no shaded section), the reference the shaded
// piecewise method at eps 1e-10 (certified; TestPiecewiseShading checks it
// against an independent Gauss-Legendre oracle); then lit and with a
// gradient opacity whose knots the gradients cross on as many rays, the
// reference the same method at eps 1e-10 (TestPiecewiseGradientOpacity
// checks it against its oracle); then the volumes of several components
// (MixtureCases.h) on `mixtureRays` rays, against their independent oracle.
// Written by avos-bench-accuracy and avos-bench --adversarial.
#ifndef avos_numerics_AdversarialReport_h
#define avos_numerics_AdversarialReport_h

#include "AdversarialCases.h"
#include "MixtureCases.h"

#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

namespace adversarial
{
inline double Seconds(std::chrono::steady_clock::time_point since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// One section of the report: every case's reference and methods on `rays`
// rays, lit by `lighting` where given, with the case's gradient opacity
// where `graded`.
inline void WriteSection(std::FILE* file, long rays, int threads,
  const an::ShadingModel<double>* lighting, bool graded = false)
{
  std::fprintf(file,
    "| case | method | eps | %% within eps R | G | B | A | max error | max / eps | "
    "samples/ray | cells/ray | pieces/ray | s |\n");
  std::fprintf(file, "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Case& c : MakeSuite())
  {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<glm::dvec4> reference =
      References(c, static_cast<unsigned>(rays), threads, lighting, graded);
    std::fprintf(file, "| %s | reference | 1e-10 | | | | | | | | | | %.2f |\n", c.Name.c_str(),
      Seconds(start));
    for (double eps : { 1e-2, 1e-3, 1e-4 })
    {
      for (Method m : { Method::Piecewise, Method::Coupled, Method::Decoupled })
      {
        const auto begin = std::chrono::steady_clock::now();
        const Tally t = Measure(c, reference, m, eps, threads, lighting, graded);
        std::fprintf(file,
          "| %s | %s | %g | %.3f | %.3f | %.3f | %.3f | %.2e | %.2f | %.1f | %.1f | %.1f "
          "| %.2f |\n",
          c.Name.c_str(), MethodName(m), eps, t.Percent(0), t.Percent(1), t.Percent(2),
          t.Percent(3), t.WorstMaximum(), t.WorstMaximum() / eps, t.Samples, t.Cells, t.Pieces,
          Seconds(begin));
        std::fflush(file);
      }
    }
  }
}

// Calls work(begin, end, t) on `threads` threads t, splitting [0, count).
template <typename Work>
void SplitRays(long count, int threads, Work&& work)
{
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
  {
    pool.emplace_back(work, count * t / threads, count * (t + 1) / threads, t);
  }
  for (auto& t : pool)
  {
    t.join();
  }
}

// The mixtures' section: each case's oracle (mixture::Exact) of `rays`
// random rays, then the piecewise method at eps 0.01, 0.001 and 1e-4, and,
// to show that the cases are not lenient, the Riemann sum at a step of 0.5
// (its "% within" against eps 1e-3).
inline void WriteMixtureSection(std::FILE* file, long rays, int threads)
{
  std::fprintf(file,
    "| case | method | eps | %% within eps R | G | B | A | max error | max / eps | "
    "pieces/ray | s |\n");
  std::fprintf(file, "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const mixture::Case& c : mixture::MakeSuite())
  {
    const auto start = std::chrono::steady_clock::now();
    std::vector<glm::dvec4> exact(static_cast<std::size_t>(rays));
    SplitRays(rays, threads,
      [&](long begin, long end, int)
      {
        for (long i = begin; i < end; ++i)
        {
          exact[i] = mixture::Exact(c, mixture::MakeRay(c, static_cast<unsigned>(i)));
        }
      });
    std::fprintf(file, "| %s | oracle | 1e-14 a part | | | | | | | | %.2f |\n", c.Name.c_str(),
      Seconds(start));
    const mixture::Volumes volumes = c.MakeVolumes();
    const an::MixtureTransferFunction<double> medium = c.Mixture();
    for (const double eps : { 1e-2, 1e-3, 1e-4, 0.0 })
    {
      const bool riemann = eps == 0.0;
      const double bound = riemann ? 1e-3 : eps;
      an::PiecewiseMixture<double> pieces;
      pieces.Build(medium, an::PiecewiseRelativeError(bound));
      const auto begin = std::chrono::steady_clock::now();
      std::vector<Tally> partial(static_cast<std::size_t>(threads));
      SplitRays(rays, threads,
        [&](long first, long end, int t)
        {
          Tally& tally = partial[static_cast<std::size_t>(t)];
          for (long i = first; i < end; ++i)
          {
            const adversarial::Ray ray = mixture::MakeRay(c, static_cast<unsigned>(i));
            const an::RayField<double, mixture::Volumes> field{ volumes, ray.Origin,
              ray.Direction };
            const an::RayResult<double> r = riemann
              ? an::IntegrateRiemann(field, medium, ray.Length, 0.5, an::RiemannForm::Exponential)
              : mixture::Piecewise(c, pieces, ray, eps);
            ++tally.Rays;
            tally.Failures += r.Error.empty() ? 0 : 1;
            tally.Pieces += static_cast<double>(r.Statistics.Pieces);
            for (int ch = 0; ch < 4; ++ch)
            {
              const double e = std::abs(r.RGBA[ch] - exact[i][ch]);
              tally.Within[ch] += e <= bound ? 1 : 0;
              tally.Maximum[ch] = std::max(tally.Maximum[ch], std::isfinite(e) ? e : 1e300);
            }
          }
        });
      Tally total;
      for (const Tally& t : partial)
      {
        total.Add(t);
      }
      char epsText[16];
      std::snprintf(epsText, sizeof(epsText), riemann ? "(%g)" : "%g", bound);
      std::fprintf(file,
        "| %s | %s | %s | %.3f | %.3f | %.3f | %.3f | %.2e | %.2f | %.1f | %.2f |\n",
        c.Name.c_str(), riemann ? "Riemann h 0.5" : "piecewise", epsText, total.Percent(0),
        total.Percent(1), total.Percent(2), total.Percent(3), total.WorstMaximum(),
        total.WorstMaximum() / bound, total.Pieces / std::max(1L, total.Rays), Seconds(begin));
      if (total.Failures > 0)
      {
        std::fprintf(file, "\n%ld rays failed\n\n", total.Failures);
      }
      std::fflush(file);
    }
  }
}

inline void WriteReport(
  std::FILE* file, long rays, int threads, long shadedRays, long mixtureRays = 0)
{
  std::fprintf(
    file, "# Adversarial accuracy suite: %ld random rays per case, %d threads\n\n", rays, threads);
  std::fprintf(file,
    "Volumes of %d^3 points, scalars in [0, 255]; errors against the exact piecewise "
    "reference (eps 1e-10); coupled and decoupled with the paper's steps (h0 0.5, "
    "hmin 0.1, hmax 2).\n\n",
    N);
  WriteSection(file, rays, threads, nullptr);
  if (shadedRays > 0)
  {
    const an::ShadingModel<double> lighting = SharpLighting();
    std::fprintf(file,
      "\n## Shaded: %ld random rays per case\n\nLit by two coloured directional lights, "
      "one-sided, specular power 128, seen along each ray; errors against the shaded "
      "piecewise method at eps 1e-10 (samples: enclosures of the lit colour).\n\n",
      shadedRays);
    WriteSection(file, shadedRays, threads, &lighting);
    std::fprintf(file,
      "\n## Shaded, with gradient opacity: %ld random rays per case\n\nLit as above, the "
      "extinction scaled by G(|grad s|): 0.05 at 0, 1 at a quarter of the case's largest "
      "gradient, 0.35 at 0.6 of it; errors against the piecewise method with gradient opacity "
      "at eps 1e-10 (samples: enclosures of the extinction and the lit colour).\n\n",
      shadedRays);
    WriteSection(file, shadedRays, threads, &lighting, true);
  }
  if (mixtureRays > 0)
  {
    std::fprintf(file,
      "\n## Several components: %ld random rays per case\n\nIndependent components "
      "overlapping (spikes on binary and two-material data, steps and random functions with "
      "weights, three components) and both dependent mixtures; errors against an independent "
      "oracle (cuts at every cell face and knot crossing, adaptive Gauss-Legendre at 1e-14 a "
      "part; MixtureCases.h).\n\n",
      mixtureRays);
    WriteMixtureSection(file, mixtureRays, threads);
  }
}
} // namespace adversarial

#endif
