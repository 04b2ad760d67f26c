// What every fuzz target needs: a requirement whose violation is a crash for
// libFuzzer, and a private temporary folder for the inputs the readers read
// from files.
#ifndef avosFuzz_h
#define avosFuzz_h

#include <cstdio>
#include <cstdlib>
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

// A new folder under /tmp named after `prefix`, made once per process.
inline std::string TemporaryFolder(const std::string& prefix)
{
  std::string name = "/tmp/" + prefix + "-XXXXXX";
  Require(mkdtemp(&name[0]) != nullptr, "a temporary folder");
  return name;
}
} // namespace avosfuzz

#endif
