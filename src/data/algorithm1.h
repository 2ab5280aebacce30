// Algorithm 1's data side (seed §III-C, docs/data.md): every outer iteration samples N₁ fresh initial
// conditions, flies one trajectory per Θ value (motor 2 by default) from each, and pushes all
// their windows into a FIFO buffer capped at N_buf windows.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "data/rollout.h"
#include "data/scales.h"
#include "data/window_buffer.h"

namespace quadfdi {

struct Algorithm1DataConfig {
  RolloutConfig rollout;
  DataScale scale;
  std::vector<double> thetas{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  std::vector<int> motors{2};
  int threads = 0;  // 0 = all cores
};

class Algorithm1Data {
 public:
  explicit Algorithm1Data(const Algorithm1DataConfig& config);
  const std::string& error() const { return engine_.error(); }
  // Generates outer iteration `iteration()` (scenarios iteration·N₁ … (iteration+1)·N₁ − 1,
  // so iteration j's data is the same whether or not earlier ones were run) and adds it.
  void nextIteration(const ProgressCallback& progress = {});
  // Regenerates the buffer as it stood after `iterations` outer iterations (for resuming).
  void restoreTo(int iterations);
  int iteration() const { return iteration_; }
  const WindowBuffer& buffer() const { return buffer_; }
  const Algorithm1DataConfig& config() const { return config_; }

 private:
  std::shared_ptr<TrajectoryBatch> generate(int iteration, const ProgressCallback& progress) const;
  Algorithm1DataConfig config_;
  RolloutEngine engine_;
  WindowBuffer buffer_;
  int iteration_ = 0;
};

}  // namespace quadfdi
