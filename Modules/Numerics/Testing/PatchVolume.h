// An 8-bit test volume for empty-space maps: 255 for x below `wall` (whole
// superblocks visible), 0 for z above `floor` (superblocks of no visible
// block), elsewhere random values constant on `patch`-cell cubes (partly
// visible blocks, not aligned with them). Shared by the numerical core's
// and the engine's empty-space tests.
#ifndef avos_test_PatchVolume_h
#define avos_test_PatchVolume_h

#include <cstddef>
#include <cstdint>
#include <vector>

namespace avostest
{
inline std::vector<std::uint8_t> PatchVolume(const int dims[3], int patch, int wall, int floor)
{
  std::vector<std::uint8_t> data(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
  std::size_t n = 0;
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        const unsigned value = static_cast<unsigned>((i / patch) * 73856093 ^
                                 (j / patch) * 19349663 ^ (k / patch) * 83492791) %
          256u;
        data[n++] = static_cast<std::uint8_t>(i < wall ? 255 : (k > floor ? 0 : value));
      }
    }
  }
  return data;
}
} // namespace avostest

#endif
