// Infinite-horizon discrete LQR about hover (docs/control.md).
#pragma once

#include <Eigen/Core>
#include <string>

#include "control/controller.h"
#include "model/vehicle_params.h"

namespace quadfdi {

using StateMatrix = Eigen::Matrix<double, kStateDim, kStateDim>;
using InputMatrix = Eigen::Matrix<double, kStateDim, kInputDim>;
using GainMatrix = Eigen::Matrix<double, kInputDim, kStateDim>;
using StateWeights = Eigen::Matrix<double, kStateDim, 1>;

enum class Discretization { kZeroOrderHold, kForwardEuler };

struct LqrConfig {
  // Diagonal of Q (per state, state.h order) and of R (per motor) for the cost
  // Σ xᵀQx + uᵀRu on deviations from hover.
  StateWeights q_diag = StateWeights::Ones();  // [1/unit²]
  Input r_diag = Input::Ones();                // [1/N²]
  Discretization discretization = Discretization::kZeroOrderHold;

  // Default: Bryson's rule, Q_ii = 1/x_max², R_jj = 1/u_max², with the maximum
  // acceptable deviations listed in lqr.cpp; chosen so the healthy loop settles from
  // the docs/control.md initial-condition set in about 2 s without long saturation.
  static LqrConfig bryson();
  // Bryson's rule for another vehicle: the same maximum deviations, but the per-motor thrust
  // deviation scaled with the vehicle's hover thrust (0.02 N is 27 % of the Crazyflie's; on a
  // 0.75 kg racer it would be 1 % and give a loop fast enough to saturate its 33 ms motors into a
  // crash). Exactly bryson() for the nominal Crazyflie (the ratio of its hover thrust to itself is 1).
  static LqrConfig brysonFor(const VehicleParams& vehicle);
  // The authors' choice: Q = I, R = I on the forward-Euler discretisation (docs/control.md, docs/model.md).
  static LqrConfig authors();
};

struct LinearModel {
  StateMatrix A = StateMatrix::Zero();
  InputMatrix B = InputMatrix::Zero();
};

// Continuous-time Jacobians of stateDerivative at hover (ψ = 0, f_i = m g / 4), analytic.
LinearModel linearizeAtHover(const VehicleParams& params);
// Discretises with period dt [s]: exact zero-order hold or x⁺ = (I + A dt) x + B dt u.
LinearModel discretize(const LinearModel& continuous, double dt, Discretization method);

struct LqrDesign {
  LinearModel discrete;
  StateMatrix riccati_solution = StateMatrix::Zero();
  GainMatrix gain = GainMatrix::Zero();      // u = u_hover − K (x − x_goal), symmetrised
  GainMatrix raw_gain = GainMatrix::Zero();  // K straight from the Riccati solution
  double riccati_residual = 0.0;             // relative DARE residual of riccati_solution
  std::string error;                         // empty on success
  bool ok() const { return error.empty(); }
};

// Solves the DARE (SLICOT) and forms K. The gain is then projected onto the
// vehicle's symmetry group (symmetry/) so that the closed loop is exactly
// equivariant: K differs from raw_gain by round-off only, which tests check.
LqrDesign designLqr(const VehicleParams& params, const LqrConfig& config, double dt);

class LqrController final : public Controller {
 public:
  // setup: the gain comes from designLqr(); bounds and hover thrust from params.
  LqrController(const VehicleParams& params, const GainMatrix& gain);
  void setReference(const Reference& reference) override { reference_ = reference; }
  const Reference& reference() const override { return reference_; }
  void compute(const State& x, ControlStep& out) override;
  const GainMatrix& gain() const { return gain_; }

 private:
  GainMatrix gain_;
  double hover_thrust_;  // [N]
  double min_thrust_;    // [N]
  double max_thrust_;    // [N]
  Reference reference_;
};

}  // namespace quadfdi
