// Scratch file paths for the tests.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <string>

namespace quadfdi::test {

// A path in the test temp folder that no other test process uses: ctest runs each test as its own
// process, two at a time, and a file one test writes must not be rewritten under another's reader.
inline std::string scratchPath(const std::string& suite, const std::string& name) {
  return ::testing::TempDir() + "quadfdi_" + suite + "_" + std::to_string(::getpid()) + "_" + name;
}

}  // namespace quadfdi::test
