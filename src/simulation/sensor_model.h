// What a flight controller's estimator hands its controller and its log: the true state seen
// through white noise, first-order low-pass filtering and a transport delay (docs/model.md#sensors).
// The controller flies on this estimate and the log records it, so a detector trained on it sees
// the noise, lag and delay of a real autopilot rather than the simulator's truth.
#pragma once

#include <string>
#include <vector>

#include "model/state.h"
#include "simulation/rng.h"

namespace quadfdi {

// Defaults are all zero: the estimate is the true state (the paper's setting). Typical values of
// real estimators are in docs/model.md#sensors with their sources.
struct SensorModelConfig {
  double position_std = 0.0;         // [m] white noise on the position estimate
  double velocity_std = 0.0;         // [m/s] white noise on the velocity estimate (body frame)
  double attitude_std = 0.0;         // [rad] white noise on roll, pitch and yaw, before the filter
  double rate_std = 0.0;             // [rad/s] gyro noise on the body rates, before the filter
  double attitude_filter_tau = 0.0;  // [s] first-order low-pass of the attitude estimate; 0 = none
  double rate_filter_tau = 0.0;      // [s] gyro low-pass, 1/(2π f_c); 0 = none
  int delay_steps = 0;               // [steps] transport delay of the whole estimate
  // Correlation time of the position, velocity and attitude errors: a navigation filter's error
  // is a first-order Gauss–Markov process (Farrell, Aided Navigation, 2008, §4.9), not white
  // noise at the control rate; the stds above stay the errors' stationary stds. 0 = white.
  double estimate_error_tau = 0.0;   // [s]

  bool active() const {
    return position_std > 0.0 || velocity_std > 0.0 || attitude_std > 0.0 || rate_std > 0.0 ||
           attitude_filter_tau > 0.0 || rate_filter_tau > 0.0 || delay_steps > 0 || estimate_error_tau > 0.0;
  }
};

// Empty when valid, else a one-line description of the first problem.
std::string validate(const SensorModelConfig& config);

// Standard normal by Box–Muller on the portable Rng (no library-dependent distributions).
double standardNormal(Rng& rng);

class SensorModel {
 public:
  // setup: allocates the delay line. `dt` [s] is the step the model is called at.
  SensorModel(const SensorModelConfig& config, double dt);
  // Starts a flight at the true state x0: filters and delay line hold x0 (no start-up transient).
  void reset(const State& x0);
  // One step: the estimate available now for the true state x_true. Does not allocate.
  const State& measure(const State& x_true, Rng& rng);
  const SensorModelConfig& config() const { return config_; }

 private:
  SensorModelConfig config_;
  double attitude_alpha_ = 1.0, rate_alpha_ = 1.0;  // [-] exact discretisation 1 − e^{−dt/τ}
  double error_phi_ = 0.0, error_gain_ = 1.0;       // [-] AR(1) of the estimate errors: e^{−dt/τ}, √(1 − φ²)
  Eigen::Matrix<double, 9, 1> error_ = Eigen::Matrix<double, 9, 1>::Zero();  // position, velocity, attitude errors
  State filtered_ = State::Zero();
  std::vector<State> delay_line_;  // ring of delay_steps + 1 filtered states
  int head_ = 0;
  State estimate_ = State::Zero();
};

}  // namespace quadfdi
