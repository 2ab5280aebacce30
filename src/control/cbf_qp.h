// CBF-QP safety filter (docs/control.md): the LQR command projected, every step, onto the set of
// motor commands that satisfy high-order control-barrier-function constraints.
#pragma once

#include "control/lqr.h"
#include "control/qp_solver.h"
#include "model/dynamics.h"

namespace quadfdi {

// Safe set and class-K gains. Each barrier h has relative degree 2 in the thrusts; the
// high-order CBF condition is ḧ + (α₁ + α₂) ḣ + α₁α₂ h ≥ 0 (Xiao & Belta, 2019).
struct CbfConfig {
  bool altitude_floor_enabled = true;
  double min_altitude = 0.5;      // [m] h = z − z_min; the authors' safe set has z ≥ 0.5 m
  double altitude_alpha1 = 3.0;   // [1/s]
  double altitude_alpha2 = 3.0;   // [1/s]
  bool tilt_limit_enabled = true;
  double max_tilt = 0.5;          // [rad] h = cos φ cos θ − cos(max_tilt): angle of body z to vertical
  // Large gains for the tilt: its barrier is flat at zero tilt, so small gains let the LQR
  // build rates that the motors cannot stop later (infeasible QPs); 30/s keeps every sampled
  // flight feasible while α·dt = 0.06 stays small for the 500 Hz discretisation.
  double tilt_alpha1 = 30.0;      // [1/s]
  double tilt_alpha2 = 30.0;      // [1/s]
  // A constraint counts as active when its slack at the solution is below this.
  double active_tolerance = 1e-9;  // [constraint units]
};

// Barrier values of a state (positive = safe), for checking and reporting.
struct BarrierValues {
  double altitude;  // [m]
  double tilt;      // [-]
};
BarrierValues barrierValues(const State& x, const CbfConfig& config);

// The enabled constraints as rows a·u ≥ b, where a·u − b = ḧ + (α₁+α₂)ḣ + α₁α₂h; also h, ḣ
// and the drift c of ḧ = a·u + c, so tests can check them against the dynamics.
struct CbfRows {
  int count = 0;
  Eigen::Matrix<double, 2, kInputDim> a = Eigen::Matrix<double, 2, kInputDim>::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  Eigen::Vector2d h = Eigen::Vector2d::Zero();
  Eigen::Vector2d hdot = Eigen::Vector2d::Zero();
  Eigen::Vector2d drift = Eigen::Vector2d::Zero();
  std::uint8_t bits[2] = {0, 0};  // ConstraintBit of each row
};
void computeCbfRows(const RigidBodyModel& model, const CbfConfig& config, const State& x, CbfRows& rows);

class CbfQpController final : public Controller {
 public:
  // setup: `params` is the model the filter believes (the controller's design model).
  CbfQpController(const VehicleParams& params, const GainMatrix& lqr_gain, const CbfConfig& config);
  void setReference(const Reference& reference) override { lqr_.setReference(reference); }
  const Reference& reference() const override { return lqr_.reference(); }
  void compute(const State& x, ControlStep& out) override;
  const CbfConfig& config() const { return config_; }

 private:
  static constexpr int kMaxRows = 2;
  using Qp = QpProblem<kInputDim, kMaxRows>;
  LqrController lqr_;
  RigidBodyModel model_;
  CbfConfig config_;
  double min_thrust_, max_thrust_;
  DenseQpSolver<kInputDim, kMaxRows> solver_;
  CbfRows rows_;
  Qp qp_;                                  // preallocated problem, rows refilled each step
  QpSolution<kInputDim, kMaxRows> solution_;
};

}  // namespace quadfdi
