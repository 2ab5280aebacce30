#include "simulation/wind.h"

#include <cmath>

#include "simulation/sensor_model.h"  // standardNormal

namespace quadfdi {

std::string validate(const WindConfig& c) {
  for (double v : {c.mean_speed, c.turbulence_std, c.gust_rate, c.gust_peak})
    if (!(v >= 0.0) || !std::isfinite(v)) return "wind speeds, turbulence and gust rate must be finite and >= 0";
  if (!std::isfinite(c.mean_direction)) return "wind direction must be finite";
  if (!(c.turbulence_tau > 0.0) || !std::isfinite(c.turbulence_tau)) return "turbulence correlation time must be finite and > 0";
  if (!(c.gust_duration > 0.0) || !std::isfinite(c.gust_duration)) return "gust duration must be finite and > 0";
  return {};
}

WindModel::WindModel(const WindConfig& config, double dt)
    : config_(config),
      dt_(dt),
      std_(config.turbulence_std, config.turbulence_std, kVerticalTurbulenceRatio * config.turbulence_std),
      phi_(std::exp(-dt / config.turbulence_tau)),
      gain_(std::sqrt(1.0 - phi_ * phi_)),
      gust_probability_(1.0 - std::exp(-config.gust_rate * dt)),
      mean_(config.mean_speed * std::cos(config.mean_direction), config.mean_speed * std::sin(config.mean_direction), 0.0) {}

void WindModel::reset(Rng& rng) {
  turbulence_.setZero();
  if (config_.active())
    for (int i = 0; i < 3; ++i) turbulence_(i) = std_(i) * standardNormal(rng);
  gust_elapsed_ = -1.0;
  gust_amplitude_ = 0.0;
  velocity_ = mean_ + turbulence_;
}

const Vec3& WindModel::step(Rng& rng) {
  for (int i = 0; i < 3; ++i) turbulence_(i) = phi_ * turbulence_(i) + gain_ * std_(i) * standardNormal(rng);
  // Three uniforms every step, used or not, so that the stream does not depend on the gusts' timing.
  const double arrival = rng.uniform(), heading = rng.uniform(-M_PI, M_PI), size = rng.uniform(0.5, 1.0);
  if (gust_elapsed_ >= 0.0) {
    gust_elapsed_ += dt_;
    if (gust_elapsed_ > config_.gust_duration) gust_elapsed_ = -1.0;
  }
  if (gust_elapsed_ < 0.0 && arrival < gust_probability_) {
    gust_elapsed_ = 0.0;
    gust_direction_ = Vec3(std::cos(heading), std::sin(heading), 0.0);
    gust_amplitude_ = size * config_.gust_peak;
  }
  const double gust = gust_elapsed_ >= 0.0
                          ? 0.5 * gust_amplitude_ * (1.0 - std::cos(2.0 * M_PI * gust_elapsed_ / config_.gust_duration))
                          : 0.0;
  velocity_ = mean_ + turbulence_ + gust * gust_direction_;
  return velocity_;
}

}  // namespace quadfdi
