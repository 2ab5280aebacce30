// Telemetry at any rate onto the model's grid (issue 6). Real logs arrive at their own rate
// with jitter and dropped packets; the network was trained on samples every dt. Outputs are
// interpolated linearly (yaw along the short way round); the commanded thrust is held, as the
// flight controller holds it, from one logged command to the next.
#pragma once

#include "core/types.h"

namespace quadfdi {

struct ResamplerConfig {
  double dt = 0.002;                // [s] the model's sample period (from the model file)
  double max_input_period = 0.008;  // [s] logs coarser than this are refused: a fault's first
                                    //     4 model samples would be pure interpolation
  double max_gap = 0.02;            // [s] a longer hole in the log restarts the grid (and the detector)
  int coarse_check_intervals = 16;  // [-] intervals looked at before judging the log's rate
};

enum class ResampleStatus {
  kOk,
  kRestarted,      // gap longer than max_gap: the grid starts again at this sample
  kNotIncreasing,  // t did not increase: the sample is refused
  kTooCoarse,      // most of the first intervals exceed max_input_period
};

class Resampler {
 public:
  explicit Resampler(const ResamplerConfig& config) : config_(config) {}

  // Feeds one input sample; calls emit(const TelemetrySample&) for every grid sample it completes
  // (time t0 + j·dt, j counting from the last (re)start), and on_restart() after a gap, before the
  // new stretch's first sample is emitted. No allocation.
  template <class Emit, class OnRestart>
  ResampleStatus push(const TelemetrySample& s, Emit&& emit, OnRestart&& on_restart);
  template <class Emit>
  ResampleStatus push(const TelemetrySample& s, Emit&& emit) {
    return push(s, emit, [] {});
  }


 private:
  static TelemetrySample interpolate(const TelemetrySample& a, const TelemetrySample& b, double t);
  ResamplerConfig config_;
  bool started_ = false;
  TelemetrySample previous_{};
  double t0_ = 0.0;        // grid origin [s]
  long next_ = 0;          // next grid index to emit
  int intervals_ = 0, coarse_intervals_ = 0;
};

template <class Emit, class OnRestart>
ResampleStatus Resampler::push(const TelemetrySample& s, Emit&& emit, OnRestart&& on_restart) {
  if (!started_) {
    started_ = true;
    previous_ = s;
    t0_ = s.t;
    next_ = 1;
    emit(s);
    return ResampleStatus::kOk;
  }
  const double interval = s.t - previous_.t;
  if (!(interval > 0.0)) return ResampleStatus::kNotIncreasing;
  if (intervals_ < config_.coarse_check_intervals) {
    ++intervals_;
    if (interval > config_.max_input_period) ++coarse_intervals_;
    if (2 * coarse_intervals_ > config_.coarse_check_intervals) return ResampleStatus::kTooCoarse;
  }
  if (interval > config_.max_gap) {
    on_restart();
    previous_ = s;
    t0_ = s.t;
    next_ = 1;
    emit(s);
    return ResampleStatus::kRestarted;
  }
  const double eps = 1e-6 * config_.dt;  // printed times are rounded; a grid point "at" t_b is at t_b
  for (;;) {
    const double t = t0_ + static_cast<double>(next_) * config_.dt;
    if (t > s.t + eps) break;
    emit(t >= s.t - eps ? s : interpolate(previous_, s, t));
    ++next_;
  }
  previous_ = s;
  return ResampleStatus::kOk;
}

}  // namespace quadfdi
