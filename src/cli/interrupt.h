// SIGINT / SIGTERM for the long-running commands: the first signal raises a flag that generation
// and training poll (they stop at a consistent point, keep their last checkpoint and leave no
// half-written file); a second signal ends the process at once.
#pragma once

#include <atomic>
#include <stdexcept>

namespace quadfdi::cli {

// Installs the handlers (idempotent) and returns the flag they raise.
const std::atomic<bool>& interruptFlag();

// Thrown by a command that stopped on the flag; main() prints it and exits with 130.
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace quadfdi::cli
