// A physics check for lost motors (issue 14: complete failures `failed` within 50 ms;
// docs/decisions.md "The thrust-loss observer"). From what the detector already has — the measured
// attitude and the commanded thrusts — and the vehicle's description (inertia, rotor positions, yaw
// moment, motor lag), it estimates how much of each motor's commanded thrust the body's rotation
// says is missing.
//
// Method: a disturbance observer (a Kalman filter per body axis on [angle, rate, unexplained angular
// acceleration], the last a random walk; Chen et al. 2016, "Disturbance-observer-based control and
// related methods — an overview", IEEE Trans. Ind. Electron. 63(2)). The known angular acceleration
// is J⁻¹(τ(f) − ω × Jω) with f the commanded thrusts through the described motor lag, so the
// controller's own commands are explained and only what they do not explain is left. A motor k that
// delivers (1 − ν)·f_k instead of f_k leaves −ν f_k J⁻¹ m_k, m_k its column of the mixer; the
// least-squares ν over the three axes is
//
//     ν̂_k = −(g_k · â) / (f_k |g_k|²),   g_k = J⁻¹ m_k,
//
// and the observer reports Θ_k = 1 − ν̂_k per motor, clipped to [0, 1]: the same scale as the network's
// Θ̂, so that the sequential rule's CUSUM and its calibration take it unchanged. A loss of motor k
// drives ν̂ of the opposite motor negative (its column is −m_k in roll and pitch), and of the two
// neighbours to (ℓx² − ℓy²)/(ℓx² + ℓy²)-ish fractions, so the argmin isolates the motor.
//
// What it needs that the network does not: the vehicle's description. Errors in it (inertia, thrust
// per command, motor lag) leave unexplained acceleration during manoeuvres; the CUSUM's threshold,
// calibrated on healthy flights with such errors drawn, prices them.
//
// Pure: no I/O; the constructor allocates (nothing beyond its members), step() does not.
#pragma once

#include <array>
#include <string>

#include "core/types.h"
#include "model/vehicle_params.h"

namespace quadfdi {

struct ThrustLossObserverConfig {
  double dt = 0.002;                // [s] sample period (the model's)
  double attitude_noise = 0.002;    // [rad] σ of the measured attitude, the filter's measurement noise: the middle of
                                    //     configs/randomisation-default.toml's estimator noise (0–5 mrad)
  double disturbance_walk = 3000.0; // [rad/s² per √s] random-walk intensity of the unexplained angular acceleration:
                                    //     sets the observer's bandwidth (docs/decisions.md "The thrust-loss observer")
  double min_share = 0.3;           // [-] a motor whose lagged command is below this share of the mean gives no
                                    //     evidence (as CommandGateConfig::min_share: ν̂ divides by it)
  int settle = 50;                  // [samples] after a reset, Θ = 1 until the filter has converged (100 ms at 500 Hz)
};

// Empty when valid, else a one-line description of the first problem.
std::string validate(const ThrustLossObserverConfig& config);

class ThrustLossObserver {
 public:
  // setup: the steady-state Kalman gain (Riccati iteration) and the mixer's columns. Throws
  // std::invalid_argument for an invalid config or vehicle.
  ThrustLossObserver(const VehicleParams& vehicle, const ThrustLossObserverConfig& config);

  // One sample: y (position, then roll, pitch, yaw [rad], ZYX, body FLU) measured at t_k, u the thrusts
  // [N] commanded at t_k and held to t_{k+1}. Returns Θ per motor (1 − ν̂, clipped to [0, 1]).
  MotorTheta step(const std::array<double, kOutputDim>& y, const std::array<double, kInputDim>& u);
  void reset();  // a new flight or a gap

  // Inspection (tests): the unexplained angular acceleration [rad/s²], body axes, after the last step.
  std::array<double, 3> disturbance() const { return {axis_[0][2], axis_[1][2], axis_[2][2]}; }
  const std::array<double, 3>& gain() const { return gain_; }

 private:
  ThrustLossObserverConfig config_;
  std::array<double, 3> inertia_{};                   // [kg·m²] diagonal of J
  std::array<std::array<double, 3>, kMotors> column_{};  // g_k = J⁻¹ m_k [rad/s² per N]
  std::array<double, kMotors> column_norm2_{};        // |g_k|²
  double roll_lever_ = 0, pitch_lever_ = 0, yaw_coeff_ = 0, lag_ = 0, rotational_drag_ = 0;
  std::array<double, 3> gain_{};                      // steady-state Kalman gain on [angle, rate, disturbance]
  // State.
  std::array<std::array<double, 3>, 3> axis_{};  // per body axis: predicted [angle, rate, disturbance]
  std::array<double, 9> last_rotation_{};        // R of the previous sample, row-major
  std::array<double, 3> accumulated_{};          // [rad] body rotation since the reset (the filter's measurement)
  std::array<double, kMotors> thrust_{};         // [N] lagged commanded thrust at the start of the step
  long samples_ = 0;
};

}  // namespace quadfdi
