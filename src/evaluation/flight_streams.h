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

// How simulateThetaStreams flies and streams; the defaults fly every simulated sample on all cores.
struct ThetaStreamOptions {
  int threads = 0;   // [-] worker threads, 0 = all cores; the result does not depend on it
  int chunk = 64;    // [flights] flown at once, so that hours of flight never sit in memory as raw samples
  const std::atomic<bool>* stop = nullptr;  // set by an interrupt: the flights not yet flown are left empty
  CommandGateConfig gate{};  // the command gate each stream's mask comes from (its hold is set to the window T)
  // [s] > 0: the flight is logged as an autopilot with this sample period would (the first simulated
  // sample at or after each multiple of it) and resampled onto the model's dt as `detect` does
  // (detection/resampler.h: outputs and rates linear, commands held), so that a coarser log's cost is
  // measured on the path it takes; Θ̂ keeps the model grid's index (a decision reaches a pilot up to
  // one log period after its grid time). 0: every simulated sample, as flown.
  double log_period = 0.0;
};

// Flies `jobs` under `rollout` and returns one stream per job, in job order: Θ̂ from the first full
// receptive field on (sample T − 1 of the flight is stream index 0). The model must stream
// (StreamingMotorEstimator::canStream); throws std::invalid_argument otherwise, and for a log
// period that is negative or not finite. A flight cut by a crash keeps the samples before it.
// Each stream also carries the command gate's mask per sample (`gate`).
std::vector<FlightThetaStream> simulateThetaStreams(const TrainedModel& model, const RolloutConfig& rollout,
                                                    const std::vector<TrajectoryJob>& jobs, const ThetaStreamOptions& options = {});

// Every simulated flight starts from the scenario's random initial state (±0.3 rad, ±1 rad/s; the
// paper's training distribution, docs/data.md) and recovers from it during its first second or so:
// a violent manoeuvre, with motors at both thrust limits, that a pilot's flight does not begin with
// and that a one-minute flight would otherwise count 60 times an hour. Long healthy flights whose
// false alarms are calibrated or counted are therefore counted from this many seconds into their
// recording (docs/decisions.md, "The initial upset"). Measured on the 1.5 kg quad's 30 calibration
// hours (2026-11-25, this VM): 10 of its 12 largest failed-level excursions peaked in a recording's
// first 0.85 s, the largest at 11.5 against 2.7 for the largest later one.
inline constexpr double kUpsetRecoverySeconds = 1.0;  // [s]

// Drops the first `samples` estimates (and masks) of a healthy stream, so that its statistics start
// there. A faulty stream's fault index moves with it (a fault inside the dropped part: index 0).
void dropLeadingSamples(FlightThetaStream& stream, long samples);

// Seconds from the recording's start of a stream's estimate `index` once its first `dropped` were
// dropped (dropLeadingSamples): index 0 is sample `window` − 1 of the flight (simulateThetaStreams).
inline double streamIndexSeconds(long index, long dropped, int window, double dt) {
  return static_cast<double>(index + dropped + window - 1) * dt;
}

}  // namespace quadfdi
