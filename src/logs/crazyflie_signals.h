// The Crazyflie extractor: a decoded micro-SD deck log (logs/crazyflie_usd.h) → FlightSignals in
// quadfdi's conventions (README, "Conventions"). What it reads, the frames, the pitch sign, the
// motor order and the thrust maps with their sources: docs/logs/crazyflie-usd.md.
#pragma once

#include "logs/decoded_log.h"
#include "logs/flight_signals.h"

#include <array>
#include <cstdint>

namespace quadfdi {

// How motor commands become per-motor thrust [N].
enum class CrazyflieThrustMap {
  // kBatteryVoltage when pwm.m1_pwm..m4_pwm and pm.vbatMV are logged beside motor.m1..m4,
  // kQuadraticDuty otherwise.
  kAuto,
  // f = a·r² + b·r + c with r = motor.mN / 65535: the firmware's own map (bitcraze
  // crazyflie-firmware, src/modules/src/power_distribution_quadrotor.c, pwmToThrustA/B, from
  // J. Förster, "System Identification of the Crazyflie 2.0 Nano Quadrocopter", ETH Zürich 2015).
  kQuadraticDuty,
  // The battery-voltage model of the firmware's thrust compensation (crazyflie-firmware
  // src/drivers/src/motors.c, motorsCompensateBatteryVoltage): motor voltage
  // V = pwm.mN_pwm / 65535 · pm.vbatMV / 1000 and V = p2·T² + p1·T, T the thrust [g] all four
  // motors would give at V ("65536 <==> 60 grams"); each motor gives T / 4.
  kBatteryVoltage,
};

struct CrazyflieSignalOptions {
  CrazyflieThrustMap thrust_map = CrazyflieThrustMap::kAuto;
  // kQuadraticDuty coefficients, r = duty in [0, 1] (source above).
  double duty_a = 0.091492681;  // [N] per motor, r² term (firmware pwmToThrustA)
  double duty_b = 0.067673604;  // [N] per motor, r term (firmware pwmToThrustB)
  double duty_c = 0.0;          // [N] per motor, offset (firmware: 0; Förster's fit: 5.48456e-4)
  // kBatteryVoltage coefficients (firmware motors.c): V = p2·T² + p1·T, T total thrust [g].
  double voltage_p2 = -0.0006239;  // [V/g²]
  double voltage_p1 = 0.088;       // [V/g]
  double command_full_scale = 65535.0;  // [-] motor.mN / pwm.mN_pwm at 100 % duty (UINT16_MAX)
  double gravity = 9.81;                // [m/s²] grams-force → newtons (the firmware's GRAVITY_MAGNITUDE)
  // When stateEstimate.roll/pitch/yaw are not all logged, take stabilizer.roll/pitch/yaw (the
  // same estimate, same legacy sign, logged by stabilizer.c) if those are.
  bool stabilizer_fallback = true;
};

// The firmware's compressed attitude (stateEstimateZ.quat; crazyflie-firmware
// src/utils/interface/quatcompress.h, the "smallest three" encoding: docs/logs/crazyflie-usd.md)
// → the quaternion in the firmware's order (x, y, z, w), of unit norm. False when the three
// stored components are longer than a unit quaternion allows (`q_xyzw` is then partly written).
bool decompressCrazyflieQuaternion(std::uint32_t packed, std::array<double, 4>& q_xyzw);

// Position (stateEstimate.x/y/z, else stateEstimateZ.x/y/z [mm]), attitude
// (stateEstimate.roll/pitch/yaw, else stabilizer.roll/pitch/yaw, stateEstimate.qw/qx/qy/qz or
// stateEstimateZ.quat, in that order) and per-motor thrust (motor.m1..m4) → `out`, each at its own rate, time from the log's first
// record. Every convention applied is a line of out.conventions. A missing variable → a LogIssue
// (status kMissingSignal, offset 0, topic = the first missing variable) whose message names every
// missing variable; rows whose time does not increase, or an empty series → status kCorrupt;
// `out` is then incomplete.
LogIssue extractCrazyflieSignals(const DecodedLog& log, const CrazyflieSignalOptions& options, FlightSignals& out);

}  // namespace quadfdi
