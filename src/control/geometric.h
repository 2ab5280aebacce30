// Geometric tracking controller on SE(3) (Lee, Leok & McClamroch, "Geometric tracking control of
// a quadrotor UAV on SE(3)", IEEE CDC 2010; Mellinger & Kumar, "Minimum snap trajectory generation
// and control for quadrotors", IEEE ICRA 2011), the family of the Crazyflie firmware's
// controller_mellinger and of many research simulators (docs/control.md, "Geometric").
//
//   position PID ─► desired force F (world) ─► collective f = F·(R e₃), desired axes R_d
//   ─► attitude PID on the rotation-matrix error e_R = ½ (R_dᵀR − RᵀR_d)^∨ and e_Ω ─► torques
//   ─► allocation through the inverse mix matrix; thrust capped from the top, then clipped
//
// Unlike the cascaded PID (control/pid.h) there is no body-rate loop: the torque is one law on the
// attitude error (PD, plus an integral only near the setpoint), and the allocator keeps the torques
// by lowering all four motors when one would exceed its maximum (the Crazyflie's
// powerDistributionCap), so the commands it produces have another shape. No shipped model is
// trained on it; E7 holds it out.
#pragma once

#include "control/controller.h"
#include "control/pid.h"  // MotorAllocator::Matrix, mixMatrixOf
#include "model/vehicle_params.h"

namespace quadfdi {

// Gains as natural frequencies and damping ratios, so that one set flies every airframe: the
// controller multiplies them by the design model's mass and inertia. Position gains: the
// Crazyflie firmware's controller_mellinger defaults (kp_xy 0.4 N/m, kd_xy 0.2 N·s/m, ki_xy
// 0.05 N/(m·s), i_range_xy 2 m·s; kp_z 1.25, kd_z 0.4, ki_z 0.05, i_range_z 0.4) divided by its
// 0.032 kg mass: ω² = 12.5 and 39 /s², 2ζω = 6.25 and 12.5 /s. Attitude: chosen, as the PID's rate
// bandwidth is (pid.h): about four times the position loop's, and the most the 1.5 kg quad with
// the slowest rotor lag the randomisation draws (35 ms) flies without oscillating (20 rad/s does not).
struct GeometricConfig {
  // [steps] position loop period; controller_mellinger runs whole at ATTITUDE_RATE (500 Hz = every step)
  int position_divisor = 1;

  double position_frequency_xy = 3.54;  // [rad/s] √12.5 (controller_mellinger kp_xy / mass)
  double position_damping_xy = 0.88;    // [-] kd_xy / (2 √(kp_xy·mass))
  double position_frequency_z = 6.25;   // [rad/s] √39 (kp_z / mass)
  double position_damping_z = 1.0;      // [-] kd_z / (2 √(kp_z·mass))
  double position_integral = 1.56;      // [1/s³] ki / mass, both axes
  double position_integral_limit_xy = 2.0;  // [m·s] |∫e| per axis (i_range_xy)
  double position_integral_limit_z = 0.4;   // [m·s] (i_range_z)
  // Safety limits Lee's law lacks, as the PID's (PX4 MPC_TILTMAX_AIR 45°, MPC_THR_MIN 0.12).
  double max_tilt = 0.7854;             // [rad] of the desired force to vertical
  double min_thrust_fraction = 0.12;    // [-] least vertical force, of the maximum collective

  double attitude_frequency_rp = 16.0;  // [rad/s]
  double attitude_damping_rp = 0.9;     // [-]
  double attitude_frequency_yaw = 5.0;  // [rad/s] yaw authority is the weakest (drag torque)
  double attitude_damping_yaw = 1.0;    // [-]
  // Attitude integral, torque = J·K_I·∫e_R, K_I = ω³/5 on every axis (its corner a fifth of the
  // loop's bandwidth). The firmware integrates yaw only (ki_m_xy 0, ki_m_z 500); roll and pitch are
  // integrated here too, because a weakened motor needs a steady torque from the others, which a PD
  // holds only at a steady attitude error: without them a 20 % loss on the nominal Crazyflie's 1.5 m/s
  // circle diverged, and without the yaw one the yaw error reached 1 rad (docs/control.md, "Geometric").
  // Bounded as PX4 bounds its rate integrators (MC_*_INT_LIM 0.3 of the largest torque about the axis).
  double attitude_integral_rp = 800.0;   // [1/s³] ≈ 16³/5
  double attitude_integral_yaw = 25.0;   // [1/s³] 5³/5
  double attitude_integral_limit = 0.3;  // [-] of the largest torque about each axis
  // [-] |e_R| (the sine of the error angle) below which an axis integrates (integral separation):
  // a weak motor's steady offset is some degrees, a slew tens of them. Chosen on the nominal
  // Crazyflie (docs/control.md, "Geometric"): without the band the circle flown from the paper's
  // initial upset overshot to 1.05 rad of tilt (0.77 with no integral); 0.3 gives 0.81 and still
  // integrates the offset of a 20 % loss, which at 0.1 stays outside the band and diverges.
  double attitude_integral_band = 0.3;
};

// Empty when valid, else a one-line description of the first problem.
std::string validate(const GeometricConfig& config);
// Every bandwidth multiplied by `scale` (damping kept): the randomisation's gain spread.
GeometricConfig scaledGeometric(GeometricConfig config, double scale);

class GeometricController final : public Controller {
 public:
  // setup: `params` is the design model; dt [s] the step period. Check validate(config) first.
  GeometricController(const VehicleParams& params, const GeometricConfig& config, double dt);
  void setReference(const Reference& reference) override { reference_ = reference; }
  const Reference& reference() const override { return reference_; }
  void reset() override;
  void compute(const State& x, ControlStep& out) override;
  const GeometricConfig& config() const { return config_; }

  const Vec3& desiredForce() const { return force_; }  // [N] world, position loop
  const Mat3& desiredAttitude() const { return desired_; }
  const Vec3& torqueCommand() const { return torque_; }  // [N·m] body

 private:
  void positionLoop(const Vec3& p, const Vec3& v_world);
  // Crazyflie powerDistributionCap: all motors lowered by the largest excess, then each clipped.
  bool allocate(double collective, Input& thrusts, Input& unconstrained) const;

  GeometricConfig config_;
  double dt_;        // [s]
  double mass_;      // [kg]
  double gravity_;   // [m/s²]
  Vec3 inertia_;     // [kg·m²]
  double min_thrust_, max_thrust_;  // [N] per motor
  MotorAllocator::Matrix inverse_mix_;  // wrench (collective, τx, τy, τz) → thrusts
  Vec3 kp_, kv_, ki_, integral_limit_;  // [1/s²], [1/s], [1/s³], [m·s] position, per world axis
  Vec3 kr_, kw_, kri_;                  // [1/s²], [1/s], [1/s³] attitude, per body axis (× inertia → torque)
  Vec3 attitude_integral_limit_;        // [rad·s] |∫e_R| per body axis (0 where K_I = 0)

  Reference reference_;
  long step_ = 0;
  Vec3 integral_ = Vec3::Zero();  // [m·s] ∫(p_ref − p)
  Vec3 attitude_integral_ = Vec3::Zero();  // [rad·s] ∫e_R
  bool saturated_ = false;                 // the last allocation hit a bound
  Vec3 force_ = Vec3::Zero();     // [N] world, held between position updates
  Mat3 desired_ = Mat3::Identity();
  Vec3 torque_ = Vec3::Zero();    // [N·m]
};

}  // namespace quadfdi
