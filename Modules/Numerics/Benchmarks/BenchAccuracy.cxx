// avos-bench-accuracy: the adversarial accuracy suite (Testing/AdversarialCases.h)
// at full size: for each case, the exact piecewise reference of N random rays
// (default 100,000), then the piecewise, coupled and decoupled methods at
// eps 0.01, 0.001 and 1e-4: % of rays within eps per RGBA channel, the
// largest error, samples, cells and pieces per ray, seconds. Markdown on
// standard output.
//   avos-bench-accuracy [--rays N] [--threads T]
#include "AdversarialCases.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace
{
double Seconds(std::chrono::steady_clock::time_point since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

bool ParseCount(const char* text, long low, long high, long& value)
{
  char* end = nullptr;
  value = std::strtol(text, &end, 10);
  return end && *end == '\0' && value >= low && value <= high;
}
} // namespace

int main(int argc, char* argv[])
{
  long rays = 100000, threads = 2;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    const bool ok = i + 1 < argc &&
      ((arg == "--rays" && ParseCount(argv[i + 1], 1, 10000000, rays)) ||
        (arg == "--threads" && ParseCount(argv[i + 1], 1, 256, threads)));
    if (!ok)
    {
      std::fprintf(stderr,
        "usage: avos-bench-accuracy [--rays N (1..1e7)] [--threads T (1..256)]\n");
      return arg == "--help" ? 0 : 2;
    }
    ++i;
  }
  std::printf("# Adversarial accuracy suite: %ld random rays per case, %ld threads\n\n", rays,
    threads);
  std::printf("Volumes of %d^3 points, scalars in [0, 255]; errors against the exact piecewise "
              "reference (eps 1e-10); coupled and decoupled with the paper's steps (h0 0.5, "
              "hmin 0.1, hmax 2).\n\n",
    adversarial::N);
  std::printf("| case | method | eps | %% within eps R | G | B | A | max error | max / eps | "
              "samples/ray | cells/ray | pieces/ray | s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const adversarial::Case& c : adversarial::MakeSuite())
  {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<glm::dvec4> reference =
      adversarial::References(c, static_cast<unsigned>(rays), static_cast<int>(threads));
    std::printf("| %s | reference | 1e-10 | | | | | | | | | | %.2f |\n", c.Name.c_str(),
      Seconds(start));
    for (double eps : { 1e-2, 1e-3, 1e-4 })
    {
      for (adversarial::Method m : { adversarial::Method::Piecewise, adversarial::Method::Coupled,
             adversarial::Method::Decoupled })
      {
        const auto begin = std::chrono::steady_clock::now();
        const adversarial::Tally t =
          adversarial::Measure(c, reference, m, eps, static_cast<int>(threads));
        std::printf("| %s | %s | %g | %.3f | %.3f | %.3f | %.3f | %.2e | %.2f | %.1f | %.1f | %.1f "
                    "| %.2f |\n",
          c.Name.c_str(), adversarial::MethodName(m), eps, t.Percent(0), t.Percent(1),
          t.Percent(2), t.Percent(3), t.WorstMaximum(), t.WorstMaximum() / eps, t.Samples,
          t.Cells, t.Pieces, Seconds(begin));
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
