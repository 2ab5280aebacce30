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
  double arm_length = 0.03973;       // [m] d; the mixer's lever is √2·d (docs/model.md)
  double gravity = 9.8;              // [m/s²] g, as in the seed
  // Per-motor thrust limits. Source: the authors' code (docs/model.md).
  double min_thrust = 0.0015;  // [N]
  double max_thrust = 0.15;    // [N]
  // Optional realism, all off (0) by default so the default is the seed's model.
  double motor_time_constant = 0.0;  // [s] first-order lag from command to thrust; 0 = instant
  double linear_drag = 0.0;          // [N·s/m] body-frame drag force −c·v on translation
  double rotational_drag = 0.0;      // [N·m·s/rad] drag torque −c·ω on rotation

  // Derived quantities used by the mixer.
  double lever() const;       // [m] √2·d, multiplies thrusts in the roll/pitch moments
  double yawCoeff() const;    // [m] κ = C_D / C_T, multiplies thrusts in the yaw moment
  double hoverThrust() const; // [N] m g / 4 per motor
};

// Named sets from docs/model.md. Throws std::invalid_argument for an unknown name.
VehicleParams nominalParams();
VehicleParams perturbedParams();        // the paper's table, authors' PERT_2
VehicleParams perturbedStrongParams();  // authors' PERT
bool isNamedParamSet(const std::string& name);
VehicleParams namedParams(const std::string& name);

// Empty when valid, else a one-line description of the first problem found
// (a non-positive mass, min_thrust > max_thrust, hover above max thrust, …).
std::string validate(const VehicleParams& params);

}  // namespace quadfdi
