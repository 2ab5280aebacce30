// Telemetry at any rate onto the model's grid (issue 6). Real logs arrive at their own rate
// with jitter and dropped packets; the network was trained on samples every dt. Outputs and body
// rates are interpolated linearly (yaw along the short way round); the commanded thrust is held,
// as the flight controller holds it, from one logged command to the next.
#pragma once

#include <cmath>

#include "core/frames.h"
#include "core/types.h"

namespace quadfdi {

struct ResamplerConfig {
  double dt = 0.002;                // [s] the model's sample period (from the model file)
  double max_input_period = 0.008;  // [s] logs coarser than this are refused: a fault's first
                                    //     4 model samples would be pure interpolation
  double max_gap = 0.02;            // [s] a longer hole in the log restarts the grid (and the detector)
  int coarse_check_intervals = 16;  // [-] intervals looked at before judging the log's rate
  // A step between two input samples faster than any flight is an estimator reset (a GNSS
  // glitch, a height-source switch, a heading realignment), not motion: the network never saw
  // one, and a 5 m height step read as flight raised a false `failed` (docs/conventions.md).
  // The grid starts again after it, as after a gap.
  double max_speed = 100.0;         // [m/s] racing quads fly up to ~50 m/s
  double max_angular_rate = 100.0;  // [rad/s] ~5700 °/s; MEMS gyros of flight controllers saturate at 2000 °/s (35 rad/s)
};

// The step that made push() return kJumped.
struct EstimateJump {
  double position = 0.0;  // [m] straight-line distance between the two samples
  double angle = 0.0;     // [rad] rotation between their attitudes
  double interval = 0.0;  // [s] time between them
};

enum class ResampleStatus {
  kOk,
  kRestarted,      // gap longer than max_gap: the grid starts again at this sample
  kNotIncreasing,  // t did not increase: the sample is refused
  kTooCoarse,      // most of the first intervals exceed max_input_period
  kJumped,         // position or attitude stepped faster than max_speed / max_angular_rate: the grid starts again at this sample
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
  const EstimateJump& lastJump() const { return last_jump_; }


 private:
  static TelemetrySample interpolate(const TelemetrySample& a, const TelemetrySample& b, double t);
  ResamplerConfig config_;
  bool started_ = false;
  TelemetrySample previous_{};
  double t0_ = 0.0;        // grid origin [s]
  long next_ = 0;          // next grid index to emit
  int intervals_ = 0, coarse_intervals_ = 0;
  EstimateJump last_jump_;
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
  const bool gap = interval > config_.max_gap;
  bool jumped = false;
  if (!gap) {
    const double dx = s.y[0] - previous_.y[0], dy = s.y[1] - previous_.y[1], dz = s.y[2] - previous_.y[2];
    const double position = std::sqrt(dx * dx + dy * dy + dz * dz);
    // The rotation between two attitudes is at most the sum of their Euler angles' differences
    // (each the short way round): only when that sum is over the bound is the rotation (twelve
    // sines and cosines) computed, so an ordinary sample costs three wraps and a sum.
    const double max_angle = config_.max_angular_rate * interval;
    double euler_sum = 0.0;
    for (int i = 3; i < 6; ++i)
      euler_sum += std::abs(wrapAngle(s.y[static_cast<std::size_t>(i)] - previous_.y[static_cast<std::size_t>(i)]));
    auto rotation = [&] { return rotationAngleBetween({previous_.y[3], previous_.y[4], previous_.y[5]}, {s.y[3], s.y[4], s.y[5]}); };
    if (position > config_.max_speed * interval || (euler_sum > max_angle && rotation() > max_angle)) {
      jumped = true;
      last_jump_ = {position, rotation(), interval};
    }
  }
  if (gap || jumped) {
    on_restart();
    previous_ = s;
    t0_ = s.t;
    next_ = 1;
    emit(s);
    return jumped ? ResampleStatus::kJumped : ResampleStatus::kRestarted;
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
