// Helpers shared by the fuzz targets.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace quadfdi::fuzz {

// Writes the input to a file unique to this process (the parsers under test take a path) and
// returns its path; the same path is reused for every input of a run and removed at exit.
inline const std::string& writeTempFile(const std::uint8_t* data, std::size_t size, const char* suffix) {
  static const std::string path = [suffix] {
    const char* dir = std::getenv("TMPDIR");
    std::string p = std::string(dir && *dir ? dir : "/tmp") + "/quadfdi-fuzz-" + std::to_string(::getpid()) + suffix;
    static std::string removed_at_exit;
    removed_at_exit = p;
    std::atexit([] { std::remove(removed_at_exit.c_str()); });
    return p;
  }();
  std::remove(path.c_str());  // a new file (inode) every time, as a real file would be
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  if (std::fclose(f) != 0) std::abort();
  return path;
}

// The input as text (NUL bytes included).
inline std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// With QUADFDI_FUZZ_VERBOSE=1 in the environment, the targets print the message of every error
// they catch (for triage: run the binary on single files).
inline void report(const std::exception& e) {
  static const bool verbose = std::getenv("QUADFDI_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "caught: %s\n", e.what());
}

// A property of the code under test does not hold: report and crash so libFuzzer keeps the input.
#define QUADFDI_FUZZ_CHECK(cond)                                                            \
  do {                                                                                      \
    if (!(cond)) {                                                                          \
      std::fprintf(stderr, "%s:%d: fuzz check failed: %s\n", __FILE__, __LINE__, #cond);    \
      std::abort();                                                                         \
    }                                                                                       \
  } while (0)

}  // namespace quadfdi::fuzz
