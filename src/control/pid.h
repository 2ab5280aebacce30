// Cascaded PID flight controller in the style of PX4's multicopter controllers
// (mc_pos_control → mc_att_control → mc_rate_control → control allocator) and the Crazyflie's
// controller_pid (docs/control.md, "PID").
//
//   position P ─► velocity PID (+ velocity and acceleration feed-forward, anti-windup)
//   ─► thrust vector (tilt and thrust limits) ─► desired attitude
//   ─► attitude P on the quaternion error (tilt first, yaw weighted lower) ─► body-rate setpoint
//   ─► body-rate PID (D on measurement, bounded integrators) ─► torques
//   ─► allocation through the inverse mix matrix, desaturated (roll/pitch kept, yaw reduced
//      first, collective shifted, clip last) ─► motor thrusts
//
// Each loop runs every N-th step (N a divisor of the step rate) and holds its output in between.
// Gains are loop bandwidths in vehicle-independent units; the controller turns them into forces
// and torques through the design model's mass, inertia and rotor levers.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "control/controller.h"
#include "model/dynamics.h"
#include "model/vehicle_params.h"

namespace quadfdi {

// Defaults: the PX4 v1.14 multicopter defaults where PX4's parameter is already in
// vehicle-independent units (MPC_*_ACC gains [m/s² per m/s], MC_*_P attitude gains
// [rad/s per rad], rate and tilt limits), and the Crazyflie 2.x controller_pid
// (platform_defaults_cf2.h) for the rate loop, whose ratios I/P and D/P are kept; the rate
// bandwidth itself is chosen (see rate_gain_rp). Loop rates: Crazyflie (position 100 Hz,
// attitude and rate 500 Hz), PX4 (attitude ~250 Hz). docs/control.md lists every source.
struct PidConfig {
  // Loop periods as multiples of the step dt (500 Hz steps: 100 Hz, 250 Hz, 500 Hz).
  int position_divisor = 5;  // [steps] position and velocity loops (Crazyflie POSITION_RATE 100 Hz)
  int attitude_divisor = 2;  // [steps] attitude loop (PX4 mc_att_control, ~250 Hz)
  int rate_divisor = 1;      // [steps] body-rate loop and allocation (Crazyflie ATTITUDE_RATE 500 Hz)

  // Position P: velocity setpoint = v_ref + K·(p_ref − p).
  double position_gain_xy = 0.95;  // [1/s] PX4 MPC_XY_P
  double position_gain_z = 1.0;    // [1/s] PX4 MPC_Z_P
  // Velocity PID: acceleration setpoint = a_ref + P·e_v + I·∫e_v − D·dv/dt (D on measurement).
  double velocity_gain_xy = 1.8;        // [1/s] PX4 MPC_XY_VEL_P_ACC
  double velocity_integral_xy = 0.4;    // [1/s²] PX4 MPC_XY_VEL_I_ACC
  double velocity_derivative_xy = 0.2;  // [-] PX4 MPC_XY_VEL_D_ACC
  double velocity_gain_z = 4.0;         // [1/s] PX4 MPC_Z_VEL_P_ACC
  double velocity_integral_z = 2.0;     // [1/s²] PX4 MPC_Z_VEL_I_ACC
  double velocity_derivative_z = 0.0;   // [-] PX4 MPC_Z_VEL_D_ACC
  double velocity_integral_limit = 9.81;  // [m/s²] |I term| per axis; PX4 bounds the vertical one by g
  // The D term's numerical velocity derivative is low-passed (first order) as PX4's is: raw, a
  // velocity estimate's noise of ~0.02 m/s differenced at 100 Hz swings the tilt setpoint by ~0.05 rad
  // every position update, which the attitude and rate loops pass to the motors as commands slammed
  // between their limits (measured on the 1.5 kg quad, docs/control.md "PID"). 0: no filter.
  double velocity_derivative_cutoff = 5.0;  // [Hz] PX4 MPC_VELD_LP default
  // Thrust vector limits.
  double max_tilt = 0.7854;  // [rad] angle of the thrust vector to vertical; PX4 MPC_TILTMAX_AIR 45°
  double min_thrust_fraction = 0.12;  // [-] least vertical thrust, of the maximum collective; PX4 MPC_THR_MIN

  // Attitude P on the quaternion error → body-rate setpoint.
  double attitude_gain_rp = 6.5;   // [1/s] PX4 MC_ROLL_P, MC_PITCH_P (Crazyflie PID_ROLL_KP 6)
  double attitude_gain_yaw = 2.8;  // [1/s] PX4 MC_YAW_P
  double yaw_weight = 0.4;         // [-] share of the yaw error corrected with the tilt; PX4 MC_YAW_WEIGHT
  double max_rate_rp = 3.8397;     // [rad/s] PX4 MC_ROLLRATE_MAX, MC_PITCHRATE_MAX 220°/s
  double max_rate_yaw = 3.4907;    // [rad/s] PX4 MC_YAWRATE_MAX 200°/s

  // Body-rate PID: angular-acceleration command = P·e_ω + I·∫e_ω − D·dω/dt; torque = J·command.
  // Bandwidth 30/s: ~4.6× the attitude gain (cascade separation), a tenth of the 500 Hz
  // Nyquist rate; I/P = 2/s and D/P = 0.01 s as the Crazyflie's PID_ROLL_RATE_KP/KI/KD = 250/500/2.5.
  double rate_gain_rp = 30.0;        // [1/s]
  double rate_integral_rp = 60.0;    // [1/s²]
  double rate_derivative_rp = 0.3;   // [-]
  // Yaw: I/P ≈ 0.14/s as the Crazyflie's PID_YAW_RATE_KP/KI = 120/16.7, no D.
  double rate_gain_yaw = 15.0;       // [1/s]
  double rate_integral_yaw = 2.0;    // [1/s²]
  // |I term| per axis as a fraction of the largest torque the motors can make about that axis;
  // PX4 MC_RR_INT_LIM = MC_PR_INT_LIM = 0.3 (of normalised torque).
  double rate_integral_limit = 0.3;  // [-]
};

// Empty when valid, else a one-line description of the first problem.
std::string validate(const PidConfig& config);
// Every loop bandwidth multiplied by `scale` (integral gains, which are bandwidth², by scale²),
// keeping the derivative ratios: the same controller tuned `scale` times faster; the
// randomisation's gain spread (as scaledGeometric, control/geometric.h).
PidConfig scaledPid(PidConfig config, double scale);

// Per-motor allocation with PX4-like priorities, through the inverse mix matrix of a model.
class MotorAllocator {
 public:
  using Matrix = Eigen::Matrix<double, kInputDim, kInputDim>;
  MotorAllocator() = default;
  // setup: the mix matrix of the design model (the one place that reads its rotor levers) and
  // the per-motor bounds [N].
  MotorAllocator(const RigidBodyModel& model, double min_thrust, double max_thrust);
  // (collective [N], torque [N·m]) → thrusts [N]. `unconstrained` gets M⁻¹·w. Returns true when
  // the command had to be changed to fit the bounds: roll and pitch torques are scaled down only
  // when their spread alone exceeds the thrust range; the collective is shifted by the least
  // amount that fits them; then the yaw torque is scaled down to what fits with the upper bound
  // raised by 15 % of the range, and the collective lowered to pay for that headroom; then
  // round-off is clipped. Every step is symmetric in the motors.
  bool allocate(double collective, const Vec3& torque, Input& thrusts, Input& unconstrained) const;
  // The largest |torque| about each axis the bounds allow with the others zero [N·m].
  const Vec3& maxTorque() const { return max_torque_; }
  // Wrench → thrusts and its inverse (rows: collective, τx, τy, τz).
  const Matrix& mixMatrix() const { return mix_; }
  const Matrix& inverseMix() const { return inverse_; }

 private:
  Matrix mix_ = Matrix::Zero();
  Matrix inverse_ = Matrix::Zero();
  Vec3 max_torque_ = Vec3::Zero();
  double min_thrust_ = 0.0, max_thrust_ = 0.0;  // [N]
};

// The thrust vector's limits, PX4 PositionControl's, shared by the PID and the geometric law: the
// vertical part at least `min_vertical` [N], the angle to vertical at most `max_tilt` [rad] (the
// horizontal part scaled). True when either acted.
bool limitThrustVector(Vec3& force, double min_vertical, double max_tilt);

// The mix matrix of a model, rows (collective, τx, τy, τz) per motor: the only use of the rotor
// levers in the PID (RigidBodyModel::roll_lever, pitch_lever).
MotorAllocator::Matrix mixMatrixOf(const RigidBodyModel& model);

class PidController final : public Controller {
 public:
  // setup: `params` is the design model; dt [s] the step period. Check validate(config) first.
  PidController(const VehicleParams& params, const PidConfig& config, double dt);
  void setReference(const Reference& reference) override { reference_ = reference; }
  const Reference& reference() const override { return reference_; }
  void reset() override;
  void compute(const State& x, ControlStep& out) override;
  const PidConfig& config() const { return config_; }

  // Held outputs of the loops, for tests and logs.
  const Vec3& thrustVector() const { return thrust_vector_; }   // [N] world, position loop
  const Vec3& rateSetpoint() const { return rate_setpoint_; }   // [rad/s] body, attitude loop
  const Vec3& torqueCommand() const { return torque_; }         // [N·m] body, rate loop

 private:
  void positionLoop(const Vec3& p, const Vec3& v_world);
  void attitudeLoop(const Eigen::Quaterniond& q);
  void rateLoop(const Vec3& w);

  PidConfig config_;
  double dt_;             // [s]
  double mass_;           // [kg]
  double gravity_;        // [m/s²]
  Vec3 inertia_;          // [kg·m²]
  double min_collective_, max_collective_;  // [N] 4·min_thrust, 4·max_thrust
  MotorAllocator allocator_;
  Vec3 rate_integral_limit_ = Vec3::Zero();  // [rad/s²] per axis

  Reference reference_;
  // Loop state.
  long step_ = 0;
  Vec3 velocity_integral_ = Vec3::Zero();  // [m/s²]
  Vec3 previous_velocity_ = Vec3::Zero();  // [m/s] world, for D on measurement
  Vec3 velocity_derivative_ = Vec3::Zero();  // [m/s²] low-passed dv/dt
  double velocity_derivative_alpha_ = 1.0;   // [-] its filter's step gain, 1 − e^{−2π f_c·period}
  bool have_previous_velocity_ = false;
  bool thrust_limited_ = false;            // tilt or thrust limit active at the last position update
  Vec3 rate_integral_ = Vec3::Zero();      // [rad/s²]
  Vec3 previous_rate_ = Vec3::Zero();      // [rad/s]
  bool have_previous_rate_ = false;
  bool allocation_saturated_ = false;
  // Held outputs.
  Vec3 thrust_vector_ = Vec3::Zero();      // [N] world
  Eigen::Quaterniond attitude_setpoint_ = Eigen::Quaterniond::Identity();
  double yaw_rate_feedforward_ = 0.0;      // [rad/s] world z
  double collective_ = 0.0;                // [N]
  Vec3 rate_setpoint_ = Vec3::Zero();      // [rad/s]
  Vec3 torque_ = Vec3::Zero();             // [N·m]
  Input thrusts_ = Input::Zero();          // [N]
  Input unconstrained_ = Input::Zero();    // [N]
};

}  // namespace quadfdi
