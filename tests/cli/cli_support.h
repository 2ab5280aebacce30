// Runs the quadfdi executable for the command-line tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include "scratch_path.h"

namespace quadfdi::test {

struct CommandResult {
  int exit_code;
  std::string out;  // standard output, and standard error when merged
};

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
