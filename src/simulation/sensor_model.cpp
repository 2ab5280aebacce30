#include "simulation/sensor_model.h"

#include <cmath>

#include "core/frames.h"

namespace quadfdi {
namespace {

double smoothingFactor(double tau, double dt) { return tau > 0.0 ? 1.0 - std::exp(-dt / tau) : 1.0; }

}  // namespace

std::string validate(const SensorModelConfig& c) {
  for (double v : {c.position_std, c.velocity_std, c.attitude_std, c.rate_std, c.attitude_filter_tau, c.rate_filter_tau,
                   c.estimate_error_tau})
    if (!(v >= 0.0) || !std::isfinite(v)) return "sensor noise and filter time constants must be finite and >= 0";
  if (c.delay_steps < 0 || c.delay_steps > 10000) return "sensor delay must be in 0 … 10000 steps";
  return {};
}

double standardNormal(Rng& rng) {
  const double u1 = 1.0 - rng.uniform();  // (0, 1]
  const double u2 = rng.uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

SensorModel::SensorModel(const SensorModelConfig& config, double dt)
    : config_(config),
      attitude_alpha_(smoothingFactor(config.attitude_filter_tau, dt)),
      rate_alpha_(smoothingFactor(config.rate_filter_tau, dt)),
      error_phi_(config.estimate_error_tau > 0.0 ? std::exp(-dt / config.estimate_error_tau) : 0.0),
      error_gain_(std::sqrt(1.0 - error_phi_ * error_phi_)),
      delay_line_(static_cast<std::size_t>(config.delay_steps) + 1, State::Zero()) {}

void SensorModel::reset(const State& x0) {
  filtered_ = x0;
  for (State& s : delay_line_) s = x0;
  head_ = 0;
  estimate_ = x0;
  error_.setZero();
}

const State& SensorModel::measure(const State& x, Rng& rng) {
  // Estimate errors of position, velocity and attitude: AR(1) with the stated stationary stds
  // (white when estimate_error_tau = 0: φ = 0, gain 1).
  const double stds[3] = {config_.position_std, config_.velocity_std, config_.attitude_std};
  for (int i = 0; i < 9; ++i) {
    const double std_dev = stds[i / 3];
    if (std_dev > 0.0) error_(i) = error_phi_ * error_(i) + error_gain_ * std_dev * standardNormal(rng);
  }
  // Position and velocity: the estimator's output with its error, unfiltered.
  for (int i = 0; i < 3; ++i) {
    filtered_(idx::kPos + i) = x(idx::kPos + i) + error_(i);
    filtered_(idx::kVel + i) = x(idx::kVel + i) + error_(3 + i);
  }
  // Attitude: angles with their error through a first-order low-pass, stepped along the wrapped
  // difference so that a yaw jump of 2π between representations does not swing the filter through zero.
  for (int i = 0; i < 3; ++i) {
    const double noisy = x(idx::kAtt + i) + error_(6 + i);
    double& f = filtered_(idx::kAtt + i);
    f = attitude_alpha_ == 1.0 ? noisy : f + attitude_alpha_ * wrapAngle(noisy - f);
  }
  // Body rates: gyro noise through the gyro low-pass.
  for (int i = 0; i < 3; ++i) {
    const double noisy = x(idx::kRate + i) + (config_.rate_std > 0.0 ? config_.rate_std * standardNormal(rng) : 0.0);
    double& f = filtered_(idx::kRate + i);
    f = rate_alpha_ == 1.0 ? noisy : f + rate_alpha_ * (noisy - f);
  }
  // Transport delay: the ring holds the last delay_steps + 1 filtered states.
  const int n = static_cast<int>(delay_line_.size());
  delay_line_[static_cast<std::size_t>(head_)] = filtered_;
  head_ = (head_ + 1) % n;
  estimate_ = delay_line_[static_cast<std::size_t>(head_)];  // the oldest: delay_steps ago
  return estimate_;
}

}  // namespace quadfdi
