// What every fuzz target needs: a requirement whose violation is a crash for
// libFuzzer, and a private temporary folder and files for the inputs the
// readers read from files.
#ifndef avosFuzz_h
#define avosFuzz_h

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

namespace avosfuzz
{
inline void Require(bool ok, const char* what)
{
  if (!ok)
  {
    std::fprintf(stderr, "fuzz: violated: %s\n", what);
    std::abort();
  }
}

// Writes `size` bytes to `path` (replacing it).
inline void WriteFile(const std::string& path, const std::uint8_t* data, std::size_t size)
{
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  Require(static_cast<bool>(file), "the input written");
}

// A new folder under /tmp named after `prefix`.
inline std::string TemporaryFolder(const std::string& prefix)
{
  std::string name = "/tmp/" + prefix + "-XXXXXX";
  Require(mkdtemp(&name[0]) != nullptr, "a temporary folder");
  return name;
}
} // namespace avosfuzz

#endif
