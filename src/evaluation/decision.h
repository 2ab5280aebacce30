// The decision layer (docs/decisions.md): per-motor Θ̂ through the symmetry maps, the alarm rule and
// isolation — ours (min over motors of the motor-2 read-back) and the paper's printed rule.
#pragma once

#include <array>
#include <vector>

#include "data/features.h"
#include "inference/weights_file.h"

namespace quadfdi {

struct Decision {
  bool alarm = false;   // min_k Θ̂_k < Θ_tol
  int motor = 0;        // 1..4 when alarm, else 0
  double min_theta = 1.0;
};

// Ties go to the lowest motor number (documented, deterministic).
Decision decide(const Input& theta_hat, double theta_tol);

// The paper's printed rule: with out[n] the network's four outputs on the window mapped by the
// map for motor n+1, alarm if min over n and i of out[n](i) < Θ_tol; the faulty motor is the one
// that output stands for in the original flight (i read back through map n).
Decision decidePaperRule(const std::array<Input, 4>& outputs_per_map, SymmetryMode mode, double theta_tol);

// Θ̂ for every motor of every window: motor k's effectiveness is the network's output for its
// trained motor on g_k(window) (g_k sends motor k to the trained motor). Runs on the LibTorch-free
// inference engine (networks/inference.h), `threads` workers (0 = all cores), with results that do
// not depend on the thread count. If `raw` is given it receives the network's four outputs for
// each (window, map) pair, for the paper rule.
// `mode` chooses the maps (normally the model's own metadata.symmetry).
std::vector<Input> estimateAllMotors(const TrainedModel& model, SymmetryMode mode, const TrajectoryBatch& batch,
                                     const std::vector<WindowRef>& windows,
                                     std::vector<std::array<Input, 4>>* raw = nullptr, int threads = 0);

}  // namespace quadfdi
