#include "data/trajectory_batch.h"

#include <algorithm>

namespace quadfdi {

void TrajectoryBatch::resize(int n, int samples_per_trajectory) {
  count = n;
  samples = samples_per_trajectory;
  const std::size_t ns = static_cast<std::size_t>(n) * static_cast<std::size_t>(samples_per_trajectory);
  const auto un = static_cast<std::size_t>(n);
  // Per-sample arrays are only resized, not cleared: every sample is written by the rollout
  // (samples after a crash are zeroed there), so a reused batch costs no extra memory pass.
  outputs.resize(ns * kOutputDim);
  inputs.resize(ns * kInputDim);
  states.resize(ns * kStateDim);
  residuals.resize(ns * kOutputDim);
  rates.resize(ns * kRateDim);
  theta.assign(un * kInputDim, 1.0f);
  fault_step.assign(un, 0);
  length.assign(un, 0);
  end_status.assign(un, 0);
  initial_state.assign(un * kStateDim, 0.0);
  goal.assign(un * 3, 0.0);
  scenario_index.assign(un, 0);
}

std::size_t TrajectoryBatch::bytes() const {
  return (outputs.size() + inputs.size() + states.size() + residuals.size() + rates.size() + theta.size()) * sizeof(float) +
         (fault_step.size() + length.size()) * sizeof(std::int32_t) + end_status.size() +
         (initial_state.size() + goal.size()) * sizeof(double) + scenario_index.size() * sizeof(std::uint64_t);
}

int faultyLength(const TrajectoryBatch& batch, const WindowRef& w) {
  return std::max(0, w.end_sample - batch.fault_step[static_cast<std::size_t>(w.trajectory)]);
}

Input windowLabel(const TrajectoryBatch& batch, const WindowRef& w) {
  if (faultyLength(batch, w) == 0) return Input::Ones();
  const float* t = &batch.theta[static_cast<std::size_t>(w.trajectory) * kInputDim];
  return Input(static_cast<double>(t[0]), static_cast<double>(t[1]), static_cast<double>(t[2]), static_cast<double>(t[3]));
}

void positionLabels(const TrajectoryBatch& batch, int trajectory, int first, float* labels, float* mask) {
  const auto s = static_cast<std::size_t>(trajectory);
  for (int k = first; k < batch.samples; ++k) {
    const Input label = windowLabel(batch, {trajectory, k});
    for (int j = 0; j < kInputDim; ++j) *labels++ = static_cast<float>(label(j));
    *mask++ = k < batch.length[s] ? 1.0f : 0.0f;
  }
}

void enumerateWindows(const TrajectoryBatch& batch, int window, std::vector<WindowRef>& out) {
  for (int i = 0; i < batch.count; ++i) {
    const auto s = static_cast<std::size_t>(i);
    const int last = batch.length[s] - 1;
    for (int k = std::max(window, static_cast<int>(batch.fault_step[s])); k <= last; ++k) out.push_back({i, k});
  }
}

}  // namespace quadfdi
