// Which quad an airframe's four rotors make, and how quadfdi reads it: the body turn that makes
// it the standard X (docs/vehicles.md#plus-and-props-out-frames) and the quadfdi motor of each
// rotor. One rule for every source of a layout — a vehicle description, PX4's CA_ROTORn
// parameters, ArduPilot's frame tables — so that they accept and refuse the same frames.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "core/frames.h"
#include "core/motor_numbering.h"

namespace quadfdi {

// One rotor as autopilots write it.
struct RotorPlacement {
  double x_forward = 0.0;  // [m] (or any length unit) forward of the centre, body FRD
  double y_right = 0.0;    // [m] right of the centre, body FRD
  int spin = 0;            // [-] +1 counter-clockwise seen from above, −1 clockwise, 0 not known
};

enum class QuadLayoutStatus {
  kOk,
  kRotorAtCentre,      // `motor` has no arm
  kMixedAxes,          // `motor` lies on a body axis and `other` does not: neither an X nor a plus
  kDuplicateQuadrant,  // `motor` and `other` fall in one quadrant of the axes turned by `turn`
  kWrongSpinPattern,   // diagonal rotors spin differently, or all four alike (`motor`, `other`)
  kSpinsUnknown,       // a plus frame whose spins are not all known: the turn's sign is not either
};

struct QuadLayout {
  QuadLayoutStatus status = QuadLayoutStatus::kOk;
  int motor = 0, other = 0;  // [-] 1-based rotors the status names (0: none)
  bool plus = false;          // rotors on the body axes, read turned ±45°
  BodyTurn turn;              // the airframe's axes turned this way are the standard X's
  bool spins_checked = false; // every spin was known (and so matched the turned standard pattern)
  std::array<int, 4> quadfdi_motor_of{};    // quadfdi motor (1..4) of rotor i
  std::array<int, 4> rotor_of_quadfdi_motor{};  // rotor (1-based) at quadfdi motor k + 1
  std::array<RotorPlacement, 4> turned{};   // the rotors in the turned axes (FRD), spins as given (kDuplicateQuadrant: in the axes it was found in)
};

// A rotor within 2 % of its distance from a body axis is on it (about 1°: a plus frame's arm as
// drawn; a real X's rotors are 20–60° off both axes).
inline constexpr double kOnAxisTolerance = 0.02;  // [-]

inline QuadLayout quadLayout(const std::array<RotorPlacement, 4>& rotors) {
  QuadLayout out;
  auto fail = [&](QuadLayoutStatus s, int motor, int other) {
    out.status = s;
    out.motor = motor;
    out.other = other;
    return out;
  };
  int on_axis = 0, first_on = 0, first_off = 0;
  for (int i = 0; i < 4; ++i) {
    const RotorPlacement& r = rotors[static_cast<std::size_t>(i)];
    const double d = std::hypot(r.x_forward, r.y_right);
    if (!(d > 0.0)) return fail(QuadLayoutStatus::kRotorAtCentre, i + 1, 0);
    const bool on = std::min(std::abs(r.x_forward), std::abs(r.y_right)) <= kOnAxisTolerance * d;
    on_axis += on ? 1 : 0;
    int& first = on ? first_on : first_off;
    if (first == 0) first = i + 1;
  }
  if (on_axis != 0 && on_axis != 4) return fail(QuadLayoutStatus::kMixedAxes, first_on, first_off);
  out.plus = on_axis == 4;
  // Two turns a quarter apart place the rotors in the quadrants; exactly one of them gives the
  // standard spins (front-right and back-left counter-clockwise). 0 and 90° for an X, ±45° for a plus.
  const std::array<int, 2> candidates = out.plus ? std::array<int, 2>{1, -1} : std::array<int, 2>{0, 2};
  int chosen = 0, consistent = 0;
  std::array<std::array<int, 4>, 2> quadrant_of{};
  std::array<std::array<RotorPlacement, 4>, 2> turned{};
  for (std::size_t c = 0; c < 2; ++c) {
    const BodyTurn turn{candidates[c]};
    const double ca = std::cos(turn.radians()), sa = std::sin(turn.radians());
    std::array<int, 4> owner{};
    for (std::size_t i = 0; i < 4; ++i) {
      const RotorPlacement& r = rotors[i];
      // FRD (x, y_right) is FLU (x, −y_right); turned by −α in FLU, then back to FRD.
      turned[c][i] = {ca * r.x_forward - sa * r.y_right, sa * r.x_forward + ca * r.y_right, r.spin};
      const int q = quadfdiMotorAtFrd(turned[c][i].x_forward, turned[c][i].y_right);
      if (q == 0) return fail(QuadLayoutStatus::kMixedAxes, static_cast<int>(i) + 1, 0);  // not reached: excluded above
      if (owner[static_cast<std::size_t>(q - 1)] != 0) {
        out.turn = turn;  // the quadrant is named in these axes
        out.turned = turned[c];
        return fail(QuadLayoutStatus::kDuplicateQuadrant, owner[static_cast<std::size_t>(q - 1)], static_cast<int>(i) + 1);
      }
      owner[static_cast<std::size_t>(q - 1)] = static_cast<int>(i) + 1;
      quadrant_of[c][i] = q;
    }
    bool fits = true;
    for (std::size_t i = 0; i < 4; ++i) {
      const int q = quadrant_of[c][i];
      const int want = q == 1 || q == 3 ? 1 : -1;  // kYawSign: quadfdi motors 1 and 3 counter-clockwise
      if (rotors[i].spin != 0 && rotors[i].spin != want) fits = false;
    }
    if (fits) {
      if (consistent == 0) chosen = static_cast<int>(c);
      ++consistent;
    }
  }
  if (consistent == 0) {
    // Name the pair that breaks the pattern: diagonal rotors that differ, else two neighbours alike.
    const std::array<int, 4>& q = quadrant_of[0];
    int at[5] = {0, 0, 0, 0, 0};
    for (int i = 0; i < 4; ++i) at[q[static_cast<std::size_t>(i)]] = i + 1;
    const auto spin = [&](int quadrant) { return rotors[static_cast<std::size_t>(at[quadrant] - 1)].spin; };
    if (spin(1) != 0 && spin(3) != 0 && spin(1) != spin(3)) return fail(QuadLayoutStatus::kWrongSpinPattern, at[1], at[3]);
    if (spin(2) != 0 && spin(4) != 0 && spin(2) != spin(4)) return fail(QuadLayoutStatus::kWrongSpinPattern, at[2], at[4]);
    for (int n = 1; n <= 4; ++n) {  // neighbours n and n + 1 (4 and 1) spinning alike
      const int m = n % 4 + 1;
      if (spin(n) != 0 && spin(n) == spin(m)) return fail(QuadLayoutStatus::kWrongSpinPattern, at[n], at[m]);
    }
    return fail(QuadLayoutStatus::kWrongSpinPattern, at[1], at[2]);  // not reached: no known spin contradicts
  }
  if (consistent == 2 && out.plus) return fail(QuadLayoutStatus::kSpinsUnknown, 0, 0);
  out.turn = BodyTurn{candidates[static_cast<std::size_t>(chosen)]};
  out.quadfdi_motor_of = quadrant_of[static_cast<std::size_t>(chosen)];
  out.turned = turned[static_cast<std::size_t>(chosen)];
  out.spins_checked = true;
  for (std::size_t i = 0; i < 4; ++i) {
    out.spins_checked = out.spins_checked && rotors[i].spin != 0;
    out.rotor_of_quadfdi_motor[static_cast<std::size_t>(out.quadfdi_motor_of[i] - 1)] = static_cast<int>(i) + 1;
  }
  return out;
}

// For a report: "" for a standard X; else what the frame is and how it is read.
inline std::string bodyTurnNote(const QuadLayout& layout) {
  if (layout.turn.none()) return "";
  return std::string("; ") + (layout.plus ? "a plus frame" : "a props-out X (every spin reversed)") +
         ", read as the standard quad X in body axes turned " + std::to_string(45 * layout.turn.eighths) +
         "° (counter-clockwise seen from above; attitude and body rates turned with them)";
}

}  // namespace quadfdi
