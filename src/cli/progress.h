// A progress bar on standard error for long jobs: redrawn in place on a terminal, silent
// otherwise (logs get the final summary line instead). Thread-safe.
#pragma once

#include <chrono>
#include <mutex>
#include <string>

namespace quadfdi::cli {

class ProgressBar {
 public:
  ProgressBar(std::string label, bool enabled);
  ~ProgressBar();
  void update(long long done, long long total, const std::string& extra = {});
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace quadfdi::cli
