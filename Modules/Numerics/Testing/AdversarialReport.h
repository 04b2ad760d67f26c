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
// checks it against its oracle). Written by avos-bench-accuracy and
// avos-bench --adversarial.
#ifndef avos_numerics_AdversarialReport_h
#define avos_numerics_AdversarialReport_h

#include "AdversarialCases.h"

#include <chrono>
#include <cstdio>

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

inline void WriteReport(std::FILE* file, long rays, int threads, long shadedRays)
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
}
} // namespace adversarial

#endif
