// Runs the quadfdi executable for the command-line tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "scratch_path.h"

namespace quadfdi::test {

struct CommandResult {
  int exit_code;
  std::string out;  // standard output, and standard error when merged
};

// Runs a shell command line; its exit code (-1 if it did not exit) and its standard output.
inline CommandResult runCommand(const std::string& command_line) {
  FILE* pipe = popen(command_line.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// A file's bytes ("" when it cannot be read).
inline std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

inline CommandResult runQuadfdi(const std::string& args, bool merge_stderr = true) {
  return runCommand(std::string(QUADFDI_EXE) + " " + args + (merge_stderr ? " 2>&1" : " 2>/dev/null"));
}

}  // namespace quadfdi::test
