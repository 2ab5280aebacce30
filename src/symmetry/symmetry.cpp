#include "symmetry/symmetry.h"

#include <cmath>
#include <stdexcept>

namespace quadfdi {
namespace {

using StateMap = Eigen::Matrix<double, kStateDim, kStateDim>;

Eigen::Matrix<double, kInputDim, kInputDim> permutationMatrix(const std::array<int, 4>& image) {
  Eigen::Matrix<double, kInputDim, kInputDim> p = Eigen::Matrix4d::Zero();
  for (int i = 0; i < kInputDim; ++i) p(image[static_cast<std::size_t>(i)], i) = 1.0;
  return p;
}

// Exact group element as the reflection/rotation S = diag(sx, sy, 1) of space and body.
// p → S p, v → S v, ω → det(S)·S ω (pseudo-vector); Euler angles follow from
// R' = S R S: roll flips with sy, pitch with sx, yaw with det(S).
SymmetryMap exactElement(double sx, double sy, const std::array<int, 4>& image) {
  const double det = sx * sy;
  State d;
  d << sx, sy, 1.0,             // position
      sx, sy, 1.0,              // body velocity
      sy, sx, det,              // roll, pitch, yaw
      det * sx, det * sy, det;  // body rates
  SymmetryMap g;
  g.state_map = d.asDiagonal();
  g.motor_image = image;
  g.input_map = permutationMatrix(image);
  return g;
}

// Paper map: every 3-vector block rotated by Rz(α), α = 90°·k, with the cyclic motor
// permutation that matches it. The seed prints R_θ = [[c, s, 0], [−s, c, 0], [0, 0, 1]],
// i.e. Rz(−θ) applied to coordinates, which would carry motor 3 onto motor 4's arm; we use
// Rz(+θ) so that the printed angles (π/2, π, 3π/2 for n = 3, 4, 1) send motor n to motor 2.
SymmetryMap paperElement(int quarter_turns) {
  const double alpha = quarter_turns * M_PI / 2.0;
  // Exact cos/sin of multiples of 90° so that the map is a signed permutation.
  const double c = std::round(std::cos(alpha)), s = std::round(std::sin(alpha));
  Mat3 rz;
  rz << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  SymmetryMap g;
  g.state_map = StateMap::Zero();
  for (int b = 0; b < 4; ++b) g.state_map.block<3, 3>(3 * b, 3 * b) = rz;
  // A CCW quarter turn moves each arm to the previous motor number (1 → 4 → 3 → 2 → 1).
  for (int i = 0; i < 4; ++i) g.motor_image[static_cast<std::size_t>(i)] = ((i - quarter_turns) % 4 + 4) % 4;
  g.input_map = permutationMatrix(g.motor_image);
  return g;
}

}  // namespace

const char* toString(SymmetryMode m) { return m == SymmetryMode::kExactGroup ? "exact" : "paper"; }

bool parseSymmetryMode(const std::string& text, SymmetryMode& mode) {
  if (text == "exact") { mode = SymmetryMode::kExactGroup; return true; }
  if (text == "paper") { mode = SymmetryMode::kPaperRotation; return true; }
  return false;
}

Output SymmetryMap::applyToOutput(const Output& y, OutputKind kind) const {
  const int second = kind == OutputKind::kPositionEuler ? idx::kAtt : idx::kRate;
  Output out;
  out.head<3>() = state_map.block<3, 3>(idx::kPos, idx::kPos) * y.head<3>();
  out.tail<3>() = state_map.block<3, 3>(second, second) * y.tail<3>();
  return out;
}

SymmetryMap SymmetryMap::inverse() const {
  SymmetryMap inv;
  inv.state_map = state_map.transpose();  // orthogonal: signed permutation or rotation
  inv.input_map = input_map.transpose();
  for (int i = 0; i < kInputDim; ++i) inv.motor_image[static_cast<std::size_t>(motor_image[static_cast<std::size_t>(i)])] = i;
  return inv;
}

std::string symmetryModeProblem(SymmetryMode mode, const VehicleParams& p) {
  if (mode != SymmetryMode::kPaperRotation || p.rollLever() == p.pitchLever()) return {};
  return "the paper's rotation map needs a square X, but this vehicle's rotors sit at |x| = " +
         std::to_string(p.pitchLever()) + " m, |y| = " + std::to_string(p.rollLever()) +
         " m (a rectangular X): a quarter turn does not map it onto itself; use --symmetry exact";
}

SymmetryMap mapMotorToMotor2(int faulty_motor, SymmetryMode mode) {
  if (faulty_motor < 1 || faulty_motor > 4)
    throw std::invalid_argument("motor must be 1..4, got " + std::to_string(faulty_motor));
  if (mode == SymmetryMode::kExactGroup) {
    switch (faulty_motor) {
      case 1: return exactElement(-1.0, 1.0, {1, 0, 3, 2});   // x → −x: 1↔2, 3↔4
      case 2: return exactElement(1.0, 1.0, {0, 1, 2, 3});    // identity
      case 3: return exactElement(1.0, -1.0, {3, 2, 1, 0});   // y → −y: 2↔3, 1↔4
      default: return exactElement(-1.0, -1.0, {2, 3, 0, 1});  // 180° about z: 1↔3, 2↔4
    }
  }
  // Quarter turns that carry motor n's arm onto motor 2's: n = 3 → 1, 4 → 2, 1 → 3.
  const int quarter_turns = ((faulty_motor - 2) % 4 + 4) % 4;
  return paperElement(quarter_turns);
}

std::array<State, 4> exactGroupStateSigns() {
  std::array<State, 4> signs;
  for (int k = 1; k <= 4; ++k)
    signs[static_cast<std::size_t>(k - 1)] = mapMotorToMotor2(k, SymmetryMode::kExactGroup).state_map.diagonal();
  return signs;
}

}  // namespace quadfdi
