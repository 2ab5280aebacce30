// Runs the quadfdi executable for the command-line tests.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <string>

namespace quadfdi::test {

struct CommandResult {
  int exit_code;
  std::string out;  // standard output, and standard error when merged
};

// A path in the test temp folder that no other test process uses: ctest runs each test as its own
// process, two at a time, and a file one test writes must not be rewritten under another's reader.
inline std::string scratchPath(const std::string& suite, const std::string& name) {
  return ::testing::TempDir() + "quadfdi_" + suite + "_" + std::to_string(::getpid()) + "_" + name;
}

inline CommandResult runQuadfdi(const std::string& args, bool merge_stderr = true) {
  const std::string cmd = std::string(QUADFDI_EXE) + " " + args + (merge_stderr ? " 2>&1" : " 2>/dev/null");
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

}  // namespace quadfdi::test
