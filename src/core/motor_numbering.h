// Which motor a pilot must look at. quadfdi numbers motors as the Crazyflie does (1 front-right,
// 2 back-right, 3 back-left, 4 front-left, seen from above with x forward; docs/conventions.md),
// but the pilot's autopilot numbers its outputs its own way: PX4's quad X calls the back-right
// motor 4, ArduPilot's Betaflight-ordered X calls it 1. The log extractors (and a vehicle
// description's [motor.N] tables) fill this in, and `detect` reports both numbers and the position.
#pragma once

#include <array>
#include <string>

#include "core/types.h"

namespace quadfdi {

struct MotorNumbering {
  std::string name = "quadfdi";  // whose numbers: "PX4", "ArduPilot", "Crazyflie", a vehicle's motor_numbering
  std::array<int, kMotors> autopilot_motor{1, 2, 3, 4};  // [-] that numbering's motor (1-based) for quadfdi motor k + 1
  bool isQuadfdis() const { return name == "quadfdi"; }  // no autopilot's numbering is known
};

// "front-right", "back-right", "back-left", "front-left" for quadfdi motor 1..4; "" otherwise.
inline const char* motorPosition(int quadfdi_motor) {
  static const char* const kNames[] = {"front-right", "back-right", "back-left", "front-left"};
  return quadfdi_motor >= 1 && quadfdi_motor <= kMotors ? kNames[quadfdi_motor - 1] : "";
}

// The motor as its pilot finds it: "back-right, PX4 motor 4" for quadfdi motor 2 of a PX4 log;
// the position alone under quadfdi's own numbering.
inline std::string motorForPilot(const MotorNumbering& numbering, int quadfdi_motor) {
  std::string s = motorPosition(quadfdi_motor);
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
