// Dynamic symmetry of the quadrotor (docs/symmetry.md): maps that send a fault of motor k
// to a fault of motor 2, acting on states, outputs, inputs, residuals and Θ.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>

#include "model/state.h"
#include "model/vehicle_params.h"

namespace quadfdi {

enum class SymmetryMode {
  kExactGroup,     // {identity, 180° about z, x→−x, y→−y}: exact for any diagonal J (default)
  kPaperRotation,  // the paper's Φ(n): rotations by 90°·k, approximate (yaw torque sign, Euler angles)
};
const char* toString(SymmetryMode m);
// Parses "exact" or "paper"; returns false for anything else.
bool parseSymmetryMode(const std::string& text, SymmetryMode& mode);

// A linear map g with g(x) = state_map·x and the motor permutation π: motor i of the
// original flight plays the role of motor π(i) in the mapped one. For the exact group
// state_map is diagonal (±1); for the paper map it is blockdiag(Rz(α) ×4).
struct SymmetryMap {
  Eigen::Matrix<double, kStateDim, kStateDim> state_map;
  std::array<int, kInputDim> motor_image;  // 0-based: π(i)
  Eigen::Matrix<double, kInputDim, kInputDim> input_map;  // u' = input_map·u, u'_{π(i)} = u_i

  State applyToState(const State& x) const { return state_map * x; }
  Input applyToInput(const Input& u) const { return input_map * u; }
  // Θ transforms like u (one entry per motor).
  Input applyToTheta(const Input& theta) const { return input_map * theta; }
  // y = (position, Euler angles) or (position, body rates); residuals ỹ transform the same way.
  Output applyToOutput(const Output& y, OutputKind kind) const;
  // Motor of the mapped flight that stands for motor `motor` (1..4) of the original.
  int imageOfMotor(int motor) const { return motor_image[static_cast<std::size_t>(motor - 1)] + 1; }
  SymmetryMap inverse() const;
};

// Empty when `mode` is exact for this vehicle's geometry, else a one-line reason. The exact group
// holds for any symmetric X with rotors at (±rotor_x, ±rotor_y) and diagonal J, rectangular
// included; the paper's quarter turns carry the x arm onto the y arm, so they need a square X
// (rollLever = pitchLever). Callers that pick a mode for a vehicle (quadfdi train) refuse on it.
std::string symmetryModeProblem(SymmetryMode mode, const VehicleParams& params);

// The map sending motor `faulty_motor` (1..4) to motor 2.
SymmetryMap mapMotorToMotor2(int faulty_motor, SymmetryMode mode);

// The four exact group elements, indexed by the motor each sends to motor 2 (index 0 = motor 1).
// Their state maps are diagonal; the diagonals are returned for cheap application.
std::array<State, 4> exactGroupStateSigns();

}  // namespace quadfdi
