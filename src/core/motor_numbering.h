// Which motor a pilot must look at. quadfdi numbers motors as the Crazyflie does (1 front-right,
// 2 back-right, 3 back-left, 4 front-left, seen from above with x forward; docs/conventions.md),
// but the pilot's autopilot numbers its outputs its own way: PX4's quad X calls the back-right
// motor 4, ArduPilot's Betaflight-ordered X calls it 1. The log extractors (and a vehicle
// description's [motor.N] tables) fill this in, and `detect` reports both numbers and the position.
#pragma once

#include <array>
#include <string>

#include "core/frames.h"
#include "core/types.h"

namespace quadfdi {

struct MotorNumbering {
  std::string name = "quadfdi";  // whose numbers: "PX4", "ArduPilot", "Crazyflie", a vehicle's motor_numbering
  std::array<int, kMotors> autopilot_motor{1, 2, 3, 4};  // [-] that numbering's motor (1-based) for quadfdi motor k + 1
  // The axes quadfdi reads the airframe in (core/frames.h): a plus or props-out frame's motors
  // sit elsewhere on the airframe than quadfdi's numbers say in its turned axes.
  BodyTurn body_turn;
  bool isQuadfdis() const { return name == "quadfdi"; }  // no autopilot's numbering is known
};

// "front-right", "back-right", "back-left", "front-left" for quadfdi motor 1..4; "" otherwise.
inline const char* motorPosition(int quadfdi_motor) {
  static const char* const kNames[] = {"front-right", "back-right", "back-left", "front-left"};
  return quadfdi_motor >= 1 && quadfdi_motor <= kMotors ? kNames[quadfdi_motor - 1] : "";
}

// Where quadfdi motor 1..4 sits on an airframe read in axes turned by `turn`: "front-right" … for
// an X, "front", "left" … for a plus frame; "" for another number.
inline const char* motorPosition(int quadfdi_motor, BodyTurn turn) {
  static const char* const kByEighth[] = {"front", "front-left", "left", "back-left", "back", "back-right", "right", "front-right"};
  static const int kEighthOf[] = {-1, -3, 3, 1};  // FR, BR, BL, FL: 45° steps counter-clockwise from the nose
  if (quadfdi_motor < 1 || quadfdi_motor > kMotors) return "";
  return kByEighth[((kEighthOf[quadfdi_motor - 1] + turn.eighths) % 8 + 8) % 8];
}
inline const char* motorPosition(const MotorNumbering& numbering, int quadfdi_motor) {
  return motorPosition(quadfdi_motor, numbering.body_turn);
}

// The motor as its pilot finds it: "back-right, PX4 motor 4" for quadfdi motor 2 of a PX4 log;
// the position alone under quadfdi's own numbering.
inline std::string motorForPilot(const MotorNumbering& numbering, int quadfdi_motor) {
  std::string s = motorPosition(quadfdi_motor, numbering.body_turn);
  if (quadfdi_motor < 1 || quadfdi_motor > kMotors || numbering.isQuadfdis()) return s;
  return s + ", " + numbering.name + " motor " + std::to_string(numbering.autopilot_motor[static_cast<std::size_t>(quadfdi_motor - 1)]);
}

// quadfdi motor (1..4) of a rotor at (x forward, y right) of the centre, FRD as PX4 and
// ArduPilot write positions; 0 on an axis (a plus frame, or a rotor at the centre).
inline int quadfdiMotorAtFrd(double x_forward, double y_right) {
  if (x_forward == 0.0 || y_right == 0.0) return 0;
  if (x_forward > 0.0) return y_right > 0.0 ? 1 : 4;
  return y_right > 0.0 ? 2 : 3;
}

}  // namespace quadfdi
