// Trajectories stored contiguously, trajectory-major (docs/data.md), and windows as views.
#pragma once

#include <cstdint>
#include <vector>

#include "model/integrator.h"
#include "model/state.h"

namespace quadfdi {

// Sample k of a trajectory is taken at t = k·dt, k = 0 … 2T: y(k) and x(k) measured, u(k) the
// command computed from x(k), ỹ(k) the residual of the step k−1 → k (ỹ(0) = 0, never used).
// The fault acts from step F on, so sample F+1 is the first whose y it changes; a window ending
// at sample k (T ≤ k ≤ 2T) holds samples k−T+1 … k and its faulty length is k − F.
struct TrajectoryBatch {
  int count = 0;    // trajectories
  int samples = 0;  // samples per trajectory (2T + 1)
  // Per sample, [trajectory][sample][channel], float32 (what the networks consume).
  std::vector<float> outputs;    // kOutputDim channels: y
  std::vector<float> inputs;     // kInputDim channels: u_cmd [N]
  std::vector<float> states;     // kStateDim channels: true x
  std::vector<float> residuals;  // kOutputDim channels: ỹ = y − ȳ (nominal one-step prediction)
  // kRateDim channels: body rates p, q, r [rad/s] as the log has them — the estimate's (gyro
  // noise, low-pass and delay) where a sensor model is flown, the true state's otherwise. Empty
  // when read from a dataset written before they were recorded (2026-12-02).
  std::vector<float> rates;
  // Per trajectory.
  std::vector<float> theta;                  // [count][4] effectiveness after the fault
  std::vector<std::int32_t> fault_step;      // F
  std::vector<std::int32_t> length;          // valid samples (< samples when the flight was cut)
  std::vector<std::uint8_t> end_status;      // StepStatus of the cut, kOk if complete
  std::vector<double> initial_state;         // [count][12] x at sample 0 (after any pre-roll)
  std::vector<double> goal;                  // [count][3]
  std::vector<std::uint64_t> scenario_index; // RNG stream of the initial condition

  // setup: allocates for `n` trajectories of `samples_per_trajectory` samples. Per-sample
  // contents are left for the writer (RolloutEngine writes every sample).
  void resize(int n, int samples_per_trajectory);
  std::size_t sampleOffset(int trajectory, int sample) const {
    return static_cast<std::size_t>(trajectory) * static_cast<std::size_t>(samples) + static_cast<std::size_t>(sample);
  }
  std::size_t bytes() const;
};

// A window is a view: which trajectory, and the sample it ends at.
struct WindowRef {
  std::int32_t trajectory;
  std::int32_t end_sample;  // k, inclusive
};

// The label of a window (docs/data.md): Θ if it holds at least one faulty sample (k > F), else ones.
Input windowLabel(const TrajectoryBatch& batch, const WindowRef& w);
int faultyLength(const TrajectoryBatch& batch, const WindowRef& w);  // max(0, k − F)

// Dense (per-position) labels of trajectory `trajectory`, for causal networks trained on whole
// trajectories (docs/networks.md, "Dense training"): for every position k = first … samples − 1,
// labels[k − first] is the label of the window ending at k (Θ once k > F, else ones) and
// mask[k − first] is 1 where sample k is valid (k < length), else 0. labels: (samples − first) × 4.
void positionLabels(const TrajectoryBatch& batch, int trajectory, int first, float* labels, float* mask);

// All windows of length `window` of every trajectory whose samples are valid and that end at
// or after the fault step: k ∈ [max(T, F), length − 1] (docs/data.md: k ∈ [T, 2T]). Appends to `out`.
void enumerateWindows(const TrajectoryBatch& batch, int window, std::vector<WindowRef>& out);

}  // namespace quadfdi
