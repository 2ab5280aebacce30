// Wind over the flight (docs/model.md#wind): a steady mean wind, continuous turbulence and
// discrete gusts, as the air velocity in the world frame that the plant's rotor drag acts on
// (model/dynamics.h: the drag force is −c·(v − Rᵀ·w), v the body velocity). A multirotor that
// holds position in wind tilts into it and its position wanders with every gust: a detector
// trained in still air reads that as an unexplained acceleration. All zero by default (still air).
#pragma once

#include <string>

#include "model/state.h"
#include "simulation/rng.h"

namespace quadfdi {

struct WindConfig {
  double mean_speed = 0.0;      // [m/s] steady horizontal wind
  double mean_direction = 0.0;  // [rad] world-frame heading the mean wind blows toward (0 = +x)
  // Continuous turbulence: each world axis a first-order Gauss–Markov process, the Dryden form
  // in time (MIL-F-8785C §3.7.2; for a hovering vehicle the frozen field is carried past by the
  // wind, so its length scale becomes a correlation time). Vertical σ is kVerticalTurbulenceRatio
  // of the horizontal (the low-altitude model at about 3 m).
  double turbulence_std = 0.0;  // [m/s] stationary std of each horizontal component
  double turbulence_tau = 1.0;  // [s] correlation time (> 0)
  // Discrete gusts: "1 − cosine" shapes (MIL-F-8785C §3.7.2.2), w(t) = ½·A·(1 − cos 2πt/D) for
  // t ∈ [0, D], arriving as a Poisson process, each with a uniform horizontal direction and a
  // peak A uniform in [½, 1]·gust_peak. One gust at a time.
  double gust_rate = 0.0;       // [1/s] mean arrivals per second
  double gust_peak = 0.0;       // [m/s] largest peak
  double gust_duration = 1.0;   // [s] D, rise and fall together (> 0)

  bool active() const { return mean_speed > 0.0 || turbulence_std > 0.0 || (gust_rate > 0.0 && gust_peak > 0.0); }
};

// MIL-F-8785C low-altitude turbulence: σ_w/σ_u = (0.177 + 0.000823·h)^0.4 with h in feet;
// 0.51 at h = 10 ft (3 m), where the library's vehicles fly.
inline constexpr double kVerticalTurbulenceRatio = 0.51;

// Empty when valid, else a one-line description of the first problem.
std::string validate(const WindConfig& config);

class WindModel {
 public:
  // setup: the per-step factors of the turbulence's exact discretisation at period dt [s].
  WindModel(const WindConfig& config, double dt);
  // A new flight: turbulence drawn from its stationary law (no start-up transient), no gust; in
  // still air (config not active) nothing is drawn.
  void reset(Rng& rng);
  // Advances one period; returns the wind velocity [m/s], world frame, to hold over it. A fixed
  // number of draws per step for a given config. No allocation.
  const Vec3& step(Rng& rng);
  // What the plant step takes (model/integrator.h): step()'s wind, or null in still air (no draws).
  const Vec3* advance(Rng& rng) { return config_.active() ? &step(rng) : nullptr; }
  const Vec3& velocity() const { return velocity_; }
  const WindConfig& config() const { return config_; }

 private:
  WindConfig config_;
  double dt_ = 0.002;
  Vec3 std_ = Vec3::Zero();        // [m/s] stationary turbulence std per world axis
  double phi_ = 0.0, gain_ = 0.0;  // [-] AR(1): e^{−dt/τ}, √(1 − φ²)
  double gust_probability_ = 0.0;  // [-] of a gust starting in one period, 1 − e^{−rate·dt}
  Vec3 mean_ = Vec3::Zero();       // [m/s]
  Vec3 turbulence_ = Vec3::Zero(); // [m/s]
  Vec3 gust_direction_ = Vec3::Zero();
  double gust_amplitude_ = 0.0;    // [m/s] A of the gust in progress
  double gust_elapsed_ = -1.0;     // [s] since its start; < 0: none
  Vec3 velocity_ = Vec3::Zero();
};

}  // namespace quadfdi
