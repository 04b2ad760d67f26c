// avos-bench-accuracy: the adversarial accuracy suite (Testing/AdversarialCases.h)
// at full size: for each case, the exact piecewise reference of N random rays
// (default 100,000), then the piecewise, coupled and decoupled methods at
// eps 0.01, 0.001 and 1e-4: % of rays within eps per RGBA channel, the
// largest error, samples, cells and pieces per ray, seconds; then the same
// shaded on M rays (default 10,000), and shaded with a gradient opacity on M
// rays; then the volumes of several components on K rays (default 2,000),
// against their oracle. Markdown on standard output.
//   avos-bench-accuracy [--rays N] [--shaded-rays M] [--mixture-rays K] [--threads T]
#include "AdversarialReport.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace
{
bool ParseCount(const char* text, long low, long high, long& value)
{
  char* end = nullptr;
  value = std::strtol(text, &end, 10);
  return end && *end == '\0' && value >= low && value <= high;
}
} // namespace

int main(int argc, char* argv[])
{
  long rays = 100000, shadedRays = 10000, mixtureRays = 2000, threads = 2;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    const bool ok = i + 1 < argc &&
      ((arg == "--rays" && ParseCount(argv[i + 1], 1, 10000000, rays)) ||
        (arg == "--shaded-rays" && ParseCount(argv[i + 1], 0, 10000000, shadedRays)) ||
        (arg == "--mixture-rays" && ParseCount(argv[i + 1], 0, 10000000, mixtureRays)) ||
        (arg == "--threads" && ParseCount(argv[i + 1], 1, 256, threads)));
    if (!ok)
    {
      std::fprintf(stderr,
        "usage: avos-bench-accuracy [--rays N (1..1e7)] [--shaded-rays M (0..1e7)] "
        "[--mixture-rays K (0..1e7)] [--threads T (1..256)]\n");
      return arg == "--help" ? 0 : 2;
    }
    ++i;
  }
  adversarial::WriteReport(stdout, rays, static_cast<int>(threads), shadedRays, mixtureRays);
  return 0;
}
