// PX4 extractor: the detector's signals out of a decoded PX4 ULog, in quadfdi's conventions.
// Frames, quaternion, motor table and thrust model: docs/logs/ulog.md ("PX4 conventions").
#pragma once

#include <array>

#include "logs/decoded_log.h"
#include "logs/flight_signals.h"

namespace quadfdi {

struct Px4SignalOptions {
  bool prefer_actuator_motors = true;  // [-] thrust setpoints of actuator_motors over PWM of actuator_outputs
  int outputs_instance = 0;            // [-] actuator_outputs multi_id whose output[0..3] drive motors 1..4
  double default_pwm_min = 1000.0;     // [µs] PWM at zero thrust when the log has no PWM_MAIN_MIN / PWM_MIN
  double default_pwm_max = 2000.0;     // [µs] PWM at full thrust when the log has no PWM_MAIN_MAX / PWM_MAX
  double default_thrust_model_factor = 0.0;  // [-] THR_MDL_FAC when the log has none (PX4's default 0, linear;
                                             //     a vehicle description's thrust curve, `--vehicle`)
  // PX4 motor (0-based) that drives quadfdi motor k + 1; the default is PX4's quad-X (see the .cpp).
  // Used when the log has no control-allocation geometry (CA_ROTOR_COUNT, CA_ROTORn_PX/PY/KM), or
  // when motor_table_from_parameters is false.
  std::array<int, kMotors> px4_motor_for_quadfdi = {0, 3, 1, 2};  // [-] indices into control[] / output[]
  bool motor_table_from_parameters = true;  // [-] the table from the log's CA_ROTORn_* (PX4 ≥ 1.13) where logged
};

// Position (vehicle_local_position), attitude (vehicle_attitude), per-motor commands
// (actuator_motors, else actuator_outputs) and armed/landed states (vehicle_status,
// vehicle_land_detected; optional). A missing required topic or field gives a LogIssue naming
// it (status kMissingSignal: the decoded log lacks what a PX4 flight log must hold for detection).
LogIssue extractPx4Signals(const DecodedLog& log, const Px4SignalOptions& options, FlightSignals& out);

}  // namespace quadfdi
