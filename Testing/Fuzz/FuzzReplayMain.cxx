// The main of every fuzz target's replay build (no libFuzzer): runs the
// target's LLVMFuzzerTestOneInput on each file named on the command line (its
// seed corpus and the inputs of the defects it found), so each harness and its
// requirements are exercised in every build and the defects stay fixed.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
// Optional, as with libFuzzer: a target's one-time set-up.
extern "C" __attribute__((weak)) int LLVMFuzzerInitialize(int* argc, char*** argv);

int main(int argc, char* argv[])
{
  if (LLVMFuzzerInitialize)
  {
    LLVMFuzzerInitialize(&argc, &argv);
  }
  for (int i = 1; i < argc; ++i)
  {
    std::ifstream file(argv[i], std::ios::binary);
    if (!file)
    {
      std::fprintf(stderr, "cannot read %s\n", argv[i]);
      return EXIT_FAILURE;
    }
    const std::vector<char> bytes(
      (std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  std::printf("replayed %d input(s)\n", argc - 1);
  return EXIT_SUCCESS;
}
