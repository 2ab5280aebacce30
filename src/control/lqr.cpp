#include "control/lqr.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <unsupported/Eigen/MatrixFunctions>

#include "control/riccati.h"
#include "core/frames.h"
#include "model/dynamics.h"
#include "symmetry/symmetry.h"

namespace quadfdi {

LqrConfig LqrConfig::bryson() {
  // Largest deviations we are willing to see (Bryson's rule, Q_ii = 1/x_max²).
  const double pos = 0.2;     // [m]
  const double vel = 0.6;     // [m/s]
  const double tilt = 0.5;    // [rad] roll, pitch
  const double yaw = 0.3;     // [rad]
  const double rate = 1.5;    // [rad/s] p, q
  const double yaw_rate = 1.5;  // [rad/s] r
  const double thrust = 0.02;   // [N] per-motor deviation from hover (hover ≈ 0.073 N)
  LqrConfig c;
  StateWeights x_max;
  x_max << pos, pos, pos, vel, vel, vel, tilt, tilt, yaw, rate, rate, yaw_rate;
  c.q_diag = x_max.cwiseAbs2().cwiseInverse();
  c.r_diag = Input::Constant(1.0 / (thrust * thrust));
  c.discretization = Discretization::kZeroOrderHold;
  return c;
}

LqrConfig LqrConfig::brysonFor(const VehicleParams& vehicle) {
  LqrConfig c = bryson();
  const double scale = vehicle.hoverThrust() / nominalParams().hoverThrust();  // [-] 1 for the nominal set
  c.r_diag /= scale * scale;
  return c;
}

LqrConfig LqrConfig::authors() {
  LqrConfig c;
  c.q_diag = StateWeights::Ones();
  c.r_diag = Input::Ones();
  c.discretization = Discretization::kForwardEuler;
  return c;
}

LinearModel linearizeAtHover(const VehicleParams& params) {
  const RigidBodyModel m = RigidBodyModel::fromParams(params);
  LinearModel lin;
  auto& A = lin.A;
  auto& B = lin.B;
  // ṗ = R v → I at hover.
  A.block<3, 3>(idx::kPos, idx::kVel).setIdentity();
  // v̇: gravity through the tilt, and linear drag.
  A(idx::kVx, idx::kPitch) = m.gravity;
  A(idx::kVy, idx::kRoll) = -m.gravity;
  for (int i = 0; i < 3; ++i) A(idx::kVel + i, idx::kVel + i) = -m.linear_drag_per_mass;
  // η̇ = W ω → I at hover.
  A.block<3, 3>(idx::kAtt, idx::kRate).setIdentity();
  // ω̇: rotational drag (the gyroscopic term is quadratic in ω and vanishes).
  for (int i = 0; i < 3; ++i) A(idx::kRate + i, idx::kRate + i) = -m.rotational_drag * m.inv_inertia(i);
  for (int j = 0; j < kInputDim; ++j) {
    B(idx::kVz, j) = m.inv_mass;
    B(idx::kP, j) = m.roll_lever * kRollSign[j] * m.inv_inertia.x();
    B(idx::kQ, j) = m.pitch_lever * kPitchSign[j] * m.inv_inertia.y();
    B(idx::kR, j) = m.yaw_coeff * kYawSign[j] * m.inv_inertia.z();
  }
  return lin;
}

LinearModel discretize(const LinearModel& c, double dt, Discretization method) {
  LinearModel d;
  if (method == Discretization::kForwardEuler) {
    d.A = StateMatrix::Identity() + dt * c.A;
    d.B = dt * c.B;
    return d;
  }
  // Exact ZOH: exp([[A, B], [0, 0]] dt) = [[Ad, Bd], [0, I]].
  constexpr int n = kStateDim + kInputDim;
  Eigen::Matrix<double, n, n> aug = Eigen::Matrix<double, n, n>::Zero();
  aug.topLeftCorner<kStateDim, kStateDim>() = c.A * dt;
  aug.topRightCorner<kStateDim, kInputDim>() = c.B * dt;
  const Eigen::Matrix<double, n, n> e = aug.exp();
  d.A = e.topLeftCorner<kStateDim, kStateDim>();
  d.B = e.topRightCorner<kStateDim, kInputDim>();
  return d;
}

LqrDesign designLqr(const VehicleParams& params, const LqrConfig& config, double dt) {
  LqrDesign design;
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    design.error = "time step must be finite and > 0";
    return design;
  }
  if ((config.q_diag.array() < 0.0).any() || !config.q_diag.allFinite() ||
      (config.r_diag.array() <= 0.0).any() || !config.r_diag.allFinite()) {
    design.error = "LQR weights must be finite, Q ⪰ 0 and R ≻ 0";
    return design;
  }
  design.discrete = discretize(linearizeAtHover(params), dt, config.discretization);
  const Eigen::MatrixXd A = design.discrete.A, B = design.discrete.B;
  const Eigen::MatrixXd Q = config.q_diag.asDiagonal();
  const Eigen::MatrixXd R = config.r_diag.asDiagonal();
  const RiccatiResult ric = solveDiscreteRiccati(A, B, Q, R);
  if (!ric.ok()) {
    design.error = "Riccati equation: " + ric.message;
    return design;
  }
  design.riccati_solution = ric.X;
  design.riccati_residual = discreteRiccatiResidual(A, B, Q, R, ric.X);
  const auto& X = design.riccati_solution;
  const auto& Bd = design.discrete.B;
  const Eigen::Matrix<double, kInputDim, kInputDim> gram =
      config.r_diag.asDiagonal().toDenseMatrix() + Bd.transpose() * X * Bd;
  design.raw_gain = gram.lu().solve(Bd.transpose() * X * design.discrete.A);

  // Equivariance K·G_k = P_k·K for the exact group (G_k state signs, P_k motor permutation)
  // holds for the exact Riccati solution when Q and R are invariant (diagonal Q, R ∝ I).
  // Average over the group, then build every row from motor 2's so the identity holds to
  // the last bit: row k = row 2 ∘ signs of g_k.
  const bool r_invariant = (config.r_diag.array() == config.r_diag(0)).all();
  GainMatrix k = design.raw_gain;
  if (r_invariant) {
    GainMatrix avg = GainMatrix::Zero();
    for (int motor = 1; motor <= 4; ++motor) {
      const SymmetryMap g = mapMotorToMotor2(motor, SymmetryMode::kExactGroup);
      avg += g.input_map.transpose() * design.raw_gain * g.state_map;
    }
    avg *= 0.25;
    const auto signs = exactGroupStateSigns();
    for (int motor = 1; motor <= 4; ++motor)
      k.row(motor - 1) = avg.row(1).cwiseProduct(signs[static_cast<std::size_t>(motor - 1)].transpose());
  }
  design.gain = k;
  return design;
}

LqrController::LqrController(const VehicleParams& params, const GainMatrix& gain)
    : gain_(gain),
      hover_thrust_(params.hoverThrust()),
      min_thrust_(params.min_thrust),
      max_thrust_(params.max_thrust) {}

void LqrController::compute(const State& x, ControlStep& out) {
  // e = x − x_ref, x_ref = (reference position, reference velocity in the body frame, 0, 0,
  // reference yaw, 0, 0, reference yaw rate). The hover reference skips the rotations: e is then
  // bit for bit the hover LQR's (x − 0 = x).
  State err = x;
  err.segment<3>(idx::kPos) -= reference_.position;
  // The gain is designed at yaw 0, where body x is world x. Under a turning or turned reference the
  // position error is taken in the frame of the body's heading ψ, Rz(ψ)ᵀ·(p − p_ref), as the
  // velocity error already is (body axes): the linearisation about heading ψ is the yaw-0 one
  // turned by ψ. Without it a heading far from 0 couples the axes and the loop diverges (a circle
  // flown nose first crashed within 3 s). A reference at yaw 0 is flown as the paper's LQR flies it.
  if (reference_.yaw != 0.0 || reference_.yaw_rate != 0.0) {
    const double c = std::cos(x(idx::kYaw)), s = std::sin(x(idx::kYaw));
    const double ex = err(idx::kPos), ey = err(idx::kPos + 1);
    err(idx::kPos) = c * ex + s * ey;
    err(idx::kPos + 1) = -s * ex + c * ey;
  }
  if ((reference_.velocity.array() != 0.0).any())
    err.segment<3>(idx::kVel) -=
        rotationBodyToWorld(x(idx::kRoll), x(idx::kPitch), x(idx::kYaw)).transpose() * reference_.velocity;
  err(idx::kYaw) = wrapAngle(err(idx::kYaw) - reference_.yaw);
  err(idx::kR) -= reference_.yaw_rate;  // a turning reference is tracked, not damped (r ≈ ψ̇ near level)
  out.u_nominal = Input::Constant(hover_thrust_) - gain_ * err;
  out.u_cmd = out.u_nominal.cwiseMax(min_thrust_).cwiseMin(max_thrust_);
  const bool saturated = (out.u_cmd.array() != out.u_nominal.array()).any();
  out.status = saturated ? ControlStatus::kSaturated : ControlStatus::kOk;
  out.active_constraints = saturated ? kMotorBoundActive : 0;
}

}  // namespace quadfdi
