// Physical parameters of a quadrotor, as plain data (docs/model.md).
#pragma once

#include <string>

namespace quadfdi {

struct VehicleParams {
  // Rigid body. Source: seed §II and the authors' code (Crazyflie 2.x).
  double mass = 0.0299;        // [kg] m
  double inertia_xx = 1.395e-5;  // [kg·m²] Ixx
  double inertia_yy = 1.395e-5;  // [kg·m²] Iyy
  double inertia_zz = 2.173e-5;  // [kg·m²] Izz (the seed prints "2,173e-5", docs/model.md)
  // Rotors. f_i = C_T ω_i², yaw moment C_D ω_i². Source: seed §II.
  double thrust_coeff = 3.1582e-10;  // [N/rpm²] C_T
  double drag_coeff = 7.9379e-12;    // [N·m/rpm²] C_D
  double arm_length = 0.03973;       // [m] d; the seed's mixer lever is √2·d (docs/model.md)
  // Geometry of a symmetric X (docs/model.md "Geometry"): every rotor sits at (±rotor_x, ±rotor_y)
  // in the body frame. 0 = the seed's convention, √2·d for both (a square X).
  double rotor_x = 0.0;  // [m] |x| of every rotor; multiplies thrust differences in the pitch moment τy
  double rotor_y = 0.0;  // [m] |y| of every rotor; multiplies thrust differences in the roll moment τx
  // Yaw moment per newton of thrust, κ = torque/thrust of one rotor. 0 = C_D/C_T (the seed's).
  double yaw_moment_coeff = 0.0;  // [m]
  double gravity = 9.8;              // [m/s²] g, as in the seed
  // Per-motor thrust limits. Source: the authors' code (docs/model.md).
  double min_thrust = 0.0015;  // [N]
  double max_thrust = 0.15;    // [N]
  // Thrust against the normalised motor command c ∈ [0, 1]: f = max_thrust·((1 − k)·c + k·c²),
  // k = thrust_model_factor. PX4's THR_MDL_FAC convention (PX4 parameter reference, THR_MDL_FAC;
  // PX4 user guide "Thrust Curve"); ArduPilot's MOT_THST_EXPO has the same form. 0 = linear.
  // Used where commands rather than thrusts are given (flight-log import); the model takes thrusts.
  double thrust_model_factor = 0.0;  // [-] in [0, 1]
  // Optional realism, all off (0) by default so the default is the seed's model.
  double motor_time_constant = 0.0;  // [s] first-order lag from command to thrust; 0 = instant
  double linear_drag = 0.0;          // [N·s/m] body-frame drag force −c·v on translation
  double rotational_drag = 0.0;      // [N·m·s/rad] drag torque −c·ω on rotation

  // Derived quantities used by the mixer.
  double rollLever() const;   // [m] rotor_y, or √2·d when 0; multiplies thrusts in the roll moment
  double pitchLever() const;  // [m] rotor_x, or √2·d when 0; multiplies thrusts in the pitch moment
  double yawCoeff() const;    // [m] yaw_moment_coeff, or κ = C_D / C_T when 0; thrusts → yaw moment
  double thrustAtCommand(double command) const;  // [N] f(c) of the thrust curve above (c clamped to [0, 1])
  double commandForThrust(double thrust) const;  // [-] c with f(c) = thrust (clamped to [0, max_thrust])
  double hoverThrust() const; // [N] m g / 4 per motor
};

// [N] The thrust curve above for any max_thrust [N] and model_factor k [-] (c clamped to [0, 1]):
// what a telemetry reader applies to commands with a vehicle description's two numbers.
double thrustAtCommand(double max_thrust, double model_factor, double command);

// Named sets from docs/model.md. Throws std::invalid_argument for an unknown name.
VehicleParams nominalParams();
VehicleParams perturbedParams();        // the paper's table, authors' PERT_2
VehicleParams perturbedStrongParams();  // authors' PERT
bool isNamedParamSet(const std::string& name);
VehicleParams namedParams(const std::string& name);

// Empty when valid, else a one-line description of the first problem found
// (a non-finite or non-positive mass, min_thrust > max_thrust, hover above max thrust, a thrust
// model factor outside [0, 1], …).
std::string validate(const VehicleParams& params);

}  // namespace quadfdi
