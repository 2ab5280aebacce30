#include "cli/interrupt.h"

#include <csignal>
#include <unistd.h>

namespace quadfdi::cli {
namespace {

std::atomic<bool> g_interrupted{false};  // process-wide by nature: set from a signal handler
static_assert(std::atomic<bool>::is_always_lock_free, "the flag must be async-signal-safe");

extern "C" void onSignal(int signal_number) {
  if (g_interrupted.exchange(true)) {  // second signal: give up at once
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
    return;
  }
  static const char kMessage[] = "\nquadfdi: stopping at the next safe point (signal again to abort now)\n";
  (void)!write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
}

}  // namespace

const std::atomic<bool>& interruptFlag() {
  static const bool installed = [] {
    struct sigaction action {};
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
    return true;
  }();
  (void)installed;
  return g_interrupted;
}

}  // namespace quadfdi::cli
