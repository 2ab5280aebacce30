// Θ̂ streams of simulated flights (issues 13 and 14): every flight of a rollout configuration —
// randomised or not — is flown, streamed sample by sample through a streaming model, and its
// per-sample estimates kept with the truth, for the sequential rule's evaluation and calibration
// (evaluation/sequential_metrics.h, detection/calibration.h) and experiment E7.
#pragma once

#include <atomic>
#include <vector>

#include "data/rollout.h"
#include "detection/command_gate.h"
#include "evaluation/sequential_metrics.h"
#include "inference/weights_file.h"

namespace quadfdi {

// Flies `jobs` under `rollout` (chunks of `chunk` flights, so that hours of flight never sit in
// memory as raw samples) and returns one stream per job, in job order: Θ̂ from the first full
// receptive field on (sample T − 1 of the flight is stream index 0). The model must stream
// (StreamingMotorEstimator::canStream); throws std::invalid_argument otherwise. `threads` 0 = all
// cores; the result does not depend on it. A flight cut by a crash keeps the samples before it.
// Each stream also carries the command gate's mask per sample (`gate`, its hold set to T).
std::vector<FlightThetaStream> simulateThetaStreams(const TrainedModel& model, const RolloutConfig& rollout,
                                                    const std::vector<TrajectoryJob>& jobs, int threads = 0, int chunk = 64,
                                                    const std::atomic<bool>* stop = nullptr, const CommandGateConfig& gate = {});

}  // namespace quadfdi
