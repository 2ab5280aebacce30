// The signals the detector needs, taken out of a decoded log by an autopilot's extractor
// (PX4, ArduPilot, Crazyflie) and already in quadfdi's conventions (docs/conventions.md), each
// at its own native rate. What is still open here — putting them on the model's clock, turning
// thrust fractions into newtons, choosing the airborne phases — is done once, for every
// autopilot, by the conventions layer.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/motor_numbering.h"
#include "core/types.h"

namespace quadfdi {

// Where a signal came from, for the import report and for refusals ("vehicle_local_position
// at 5.2 Hz is too coarse: …").
struct SignalSource {
  std::string topic;   // message/topic/variable group, e.g. "vehicle_attitude", "ATT", "stateEstimate"
  std::string fields;  // e.g. "q[0..3]", "Roll,Pitch,Yaw"
  std::string note;    // conventions applied, e.g. "NED→ENU, FRD→FLU, quaternion → ZYX Euler"
};

template <int N>
struct SignalSeries {
  std::vector<double> t;                   // [s] from the log's time origin, increasing
  std::vector<std::array<double, N>> v;    // values, in the units the owner says
  SignalSource source;
  bool empty() const { return t.empty(); }
};

enum class CommandKind {
  kThrustNewton,    // the log (or a known thrust map) gives thrust per motor [N]
  kThrustFraction,  // thrust as a fraction of the motor's maximum [0, 1], already linear in thrust
                    // (the autopilot's thrust curve inverted); scaled to N by the conventions layer
};

// Armed / landed state as the autopilot logged it (PX4 vehicle_status + vehicle_land_detected,
// ArduPilot EV/ARM/MODE); empty when the log has none.
struct FlightStateEvent {
  double t = 0.0;         // [s]
  bool armed = false;
  bool landed = true;     // the autopilot's own landed/maybe-landed flag
};

// A moment when a signal jumps by an amount the log does not record (say, two estimator resets
// between two logged rows, of which only the last one's shift was logged): nothing is evaluated
// across it, as across a hole.
struct SignalBreak {
  double t = 0.0;            // [s] the first sample after the jump
  double last_before = 0.0;  // [s] the last sample before it: nothing later is interpolated toward the jump
  std::string why;           // for the import report, e.g. "vehicle_local_position: 2 position resets between two rows"
};

struct FlightSignals {
  SignalSeries<3> position;        // x, y, z [m], world frame, z up
  SignalSeries<3> attitude;        // roll, pitch, yaw [rad], ZYX, body x forward, y left, z up
  // Body rates p, q, r [rad/s], body FLU, the gyro as the flight controller filters it (PX4
  // vehicle_angular_velocity, ArduPilot RATE, Crazyflie gyro); empty when the log has none. Read
  // only by models on scale-free-rates features.
  SignalSeries<3> rates;
  SignalSeries<kMotors> command;   // per motor, quadfdi numbering (1 FR, 2 BR, 3 BL, 4 FL)
  // Only when the log gives the motors' commands at times of their own (a merged export with a
  // row per motor): each motor's sample times, whose rates and holes the conventions layer checks
  // one by one, as `command`'s times no longer show them; `command` then holds all four at every
  // time one of them was given, each held from its own last sample. Empty otherwise.
  std::vector<std::vector<double>> command_times_per_motor;
  CommandKind command_kind = CommandKind::kThrustFraction;
  MotorNumbering numbering;        // the autopilot's own motor numbers, for reporting a motor to its pilot
  std::vector<FlightStateEvent> states;  // in time order
  std::vector<SignalBreak> breaks;       // in any order
  std::vector<std::string> conventions;  // one line per convention applied, for the report
};

}  // namespace quadfdi
