#include "model/vehicle_params.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace quadfdi {

// The seed's lever √2·d is kept as the expression it always was, so the default stays bit-identical.
double VehicleParams::rollLever() const { return rotor_y > 0.0 ? rotor_y : std::sqrt(2.0) * arm_length; }
double VehicleParams::pitchLever() const { return rotor_x > 0.0 ? rotor_x : std::sqrt(2.0) * arm_length; }
double VehicleParams::yawCoeff() const { return yaw_moment_coeff > 0.0 ? yaw_moment_coeff : drag_coeff / thrust_coeff; }

double thrustAtCommand(double max_thrust, double model_factor, double command) {
  const double c = std::clamp(command, 0.0, 1.0), k = model_factor;
  return max_thrust * ((1.0 - k) * c + k * c * c);
}

double VehicleParams::thrustAtCommand(double command) const {
  return quadfdi::thrustAtCommand(max_thrust, thrust_model_factor, command);
}

double VehicleParams::commandForThrust(double thrust) const {
  const double r = std::clamp(thrust / max_thrust, 0.0, 1.0), k = thrust_model_factor;
  if (k <= 0.0 || r <= 0.0) return r;
  // k c² + (1 − k) c − r = 0, the root in [0, 1]; written as 2r / (b + √(b² + 4kr)) to avoid cancellation.
  const double b = 1.0 - k;
  return 2.0 * r / (b + std::sqrt(b * b + 4.0 * k * r));
}
double VehicleParams::hoverThrust() const { return mass * gravity / 4.0; }

VehicleParams nominalParams() { return VehicleParams{}; }

VehicleParams perturbedParams() {
  VehicleParams p;
  p.mass = 0.02;  // the code's value; the paper's table prints 0.015 (docs/model.md)
  p.inertia_xx = 2.0e-5;
  p.inertia_yy = 1.0e-5;
  p.inertia_zz = 3.0e-5;
  p.thrust_coeff = 2.5e-10;
  p.drag_coeff = 9.0e-12;
  p.arm_length = 0.05;
  return p;
}

VehicleParams perturbedStrongParams() {
  VehicleParams p;
  p.mass = 0.015;
  p.inertia_xx = 1.0e-5;
  p.inertia_yy = 1.0e-5;
  p.inertia_zz = 1.0e-5;
  p.thrust_coeff = 2.0e-10;
  p.drag_coeff = 5.0e-12;
  p.arm_length = 0.02;
  return p;
}

bool isNamedParamSet(const std::string& name) {
  return name == "nominal" || name == "perturbed" || name == "perturbed-strong";
}

VehicleParams namedParams(const std::string& name) {
  if (name == "nominal") return nominalParams();
  if (name == "perturbed") return perturbedParams();
  if (name == "perturbed-strong") return perturbedStrongParams();
  throw std::invalid_argument("unknown parameter set '" + name +
                              "' (expected nominal, perturbed, perturbed-strong or a file)");
}

std::string validate(const VehicleParams& p) {
  std::ostringstream msg;
  auto positive = [&](double v, const char* name) {
    if (!(std::isfinite(v) && v > 0.0) && msg.tellp() == 0) msg << name << " must be finite and > 0, got " << v;
  };
  auto nonNegative = [&](double v, const char* name) {
    if (!(std::isfinite(v) && v >= 0.0) && msg.tellp() == 0) msg << name << " must be finite and >= 0, got " << v;
  };
  positive(p.mass, "mass");
  positive(p.inertia_xx, "inertia_xx");
  positive(p.inertia_yy, "inertia_yy");
  positive(p.inertia_zz, "inertia_zz");
  positive(p.thrust_coeff, "thrust_coeff");
  nonNegative(p.drag_coeff, "drag_coeff");
  positive(p.arm_length, "arm_length");
  nonNegative(p.rotor_x, "rotor_x");
  nonNegative(p.rotor_y, "rotor_y");
  nonNegative(p.yaw_moment_coeff, "yaw_moment_coeff");
  nonNegative(p.thrust_model_factor, "thrust_model_factor");
  positive(p.gravity, "gravity");
  nonNegative(p.min_thrust, "min_thrust");
  positive(p.max_thrust, "max_thrust");
  nonNegative(p.motor_time_constant, "motor_time_constant");
  nonNegative(p.linear_drag, "linear_drag");
  nonNegative(p.rotational_drag, "rotational_drag");
  if (msg.tellp() != 0) return msg.str();
  if (p.thrust_model_factor > 1.0)
    return "thrust_model_factor must lie in [0, 1] (PX4 THR_MDL_FAC convention), got " + std::to_string(p.thrust_model_factor);
  if (!(std::isfinite(p.yawCoeff()) && p.yawCoeff() > 0.0))
    return "the yaw moment coefficient (yaw_moment_coeff, or drag_coeff / thrust_coeff) must be finite and > 0";
  if (p.min_thrust >= p.max_thrust)
    return "min_thrust (" + std::to_string(p.min_thrust) + ") must be below max_thrust (" +
           std::to_string(p.max_thrust) + ")";
  if (p.hoverThrust() >= p.max_thrust || p.hoverThrust() <= p.min_thrust)
    return "hover thrust m·g/4 = " + std::to_string(p.hoverThrust()) +
           " N must lie strictly inside [min_thrust, max_thrust]";
  return {};
}

}  // namespace quadfdi
