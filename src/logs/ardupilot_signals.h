// ArduPilot (Copter, quad X) extractor: a DecodedLog read from a DataFlash log → FlightSignals in
// quadfdi's conventions (README "Conventions"; the derivations are in docs/logs/dataflash.md).
//
//  * time: TimeUS [µs since boot] → t [s] = TimeUS·1e-6 (boot is the log's time origin);
//    rows whose time does not increase are dropped (counted in a conventions line).
//  * world frame: ArduPilot's NED (x north, y east, z down) rotated 180° about north, i.e.
//    x north, y west, z up; body: FRD rotated 180° about forward, i.e. FLU. With T = diag(1,−1,−1)
//    R_quadfdi = T·R_NED·T = Rz(−ψ)·Ry(−θ)·Rx(φ), so roll = Roll, pitch = −Pitch, yaw = −Yaw
//    (ArduPilot pitch is nose-up positive, quadfdi's nose-down; ArduPilot yaw is clockwise from
//    north seen from above, quadfdi's counter-clockwise about z up), and position
//    (x, y, z) = (PN, −PE, −PD).
//  * attitude: ATT Roll, Pitch, Yaw [deg].
//  * body rates (optional): RATE R, P, Y [deg/s]; without RATE, IMU GyrX, GyrY, GyrZ [rad/s] of
//    instance I = 0.
//  * position: XKF1 (EKF3) PN, PE, PD [m] of core `ekf_core`, by default of the primary core as
//    XKF4 PI names it over time (a lane switch is a SignalBreak); else NKF1 (EKF2) likewise; else
//    POS Lat, Lng [deg], Alt [m] on a flat earth around the first fix. Rows XKF4 SS flags without
//    a position estimate are skipped; XKF4 OFN/OFE reset shifts are taken out.
//  * commands: RCOU C<n> [µs] of the servo output driving each motor (SERVOn_FUNCTION 33..36 =
//    motors 1..4 when logged, else outputs 1..4) → thrust fraction with ArduPilot's own model
//    (AP_MotorsMulticopter / Thrust_Linearization): a = (pwm − MOT_PWM_MIN)/(MOT_PWM_MAX −
//    MOT_PWM_MIN), x = (a − MOT_SPIN_MIN)/(MOT_SPIN_MAX − MOT_SPIN_MIN) clamped to [0, 1],
//    thrust fraction = (1 − e)·x + e·x² with e = MOT_THST_EXPO (the inverse of ArduPilot's
//    apply_thrust_curve_and_volt_scaling without voltage compensation, lift_max = 1).
//  * motors: ArduPilot quad X (AP_MotorsMatrix::setup_quad_matrix, MOTOR_FRAME_TYPE_X): motor 1
//    at 45° front-right CCW, 2 at −135° back-left CCW, 3 at −45° front-left CW, 4 at 135°
//    back-right CW. quadfdi 1 FR, 2 BR, 3 BL, 4 FL ← ArduPilot motors 1, 4, 2, 3. Spin
//    directions agree (quadfdi τz = κ(−f1 + f2 − f3 + f4): FR and BL CCW seen from above).
//    The same X numbered Betaflight's way (FRAME_TYPE 12: ← 2, 1, 3, 4), DJI's (13: ← 1, 4, 3, 2)
//    or clockwise (14: ← 1, 2, 3, 4) is read too; FlightSignals::numbering keeps ArduPilot's
//    numbers so that `detect` names the motor as the pilot's autopilot does.
//  * states: EV Id 10 ARMED, 11 DISARMED, 17 LAND_COMPLETE_MAYBE, 18 LAND_COMPLETE,
//    28 NOT_LANDED (AP_Logger.h enum LogEvent) and ARM ArmState (1 armed, 0 disarmed); one
//    FlightStateEvent per change, starting disarmed and landed.
// A missing ATT, position or RCOU, or a frame that is not a quad X with the standard spins
// (FRAME_CLASS 1, FRAME_TYPE 1, 12, 13 or 14 where logged; H and BF_X_REV are props-out), comes back as a LogIssue (status kMissingSignal for a missing message or field, kCorrupt for
// unusable parameters or another frame; topic = the message or PARM).
#pragma once

#include "logs/decoded_log.h"
#include "logs/flight_signals.h"

namespace quadfdi {

// Values used where the log has no PARM of that name. Sources: ArduPilot
// libraries/AP_Motors/AP_MotorsMulticopter.cpp/.h parameter table (Copter 4.x defaults).
struct ArdupilotSignalOptions {
  int ekf_core = -1;           // [-] EKF core (XKF1/NKF1 field C, FMTU instance) whose position is used;
                               //     −1: the primary core, as XKF4/NKF4 PI says over time (core 0 if not logged)
  double pwm_min = 1000.0;     // [µs] MOT_PWM_MIN default (4.x; 0 in older firmware meant RC3_MIN)
  double pwm_max = 2000.0;     // [µs] MOT_PWM_MAX default (4.x; 0 in older firmware meant RC3_MAX)
  double rc3_min = 1100.0;     // [µs] RC3_MIN default, used when MOT_PWM_MIN is logged as 0
  double rc3_max = 1900.0;     // [µs] RC3_MAX default, used when MOT_PWM_MAX is logged as 0
  double spin_min = 0.15;      // [-] MOT_SPIN_MIN default (AP_MOTORS_SPIN_MIN_DEFAULT)
  double spin_max = 0.95;      // [-] MOT_SPIN_MAX default (AP_MOTORS_SPIN_MAX_DEFAULT)
  double thrust_expo = 0.65;   // [-] MOT_THST_EXPO default (AP_MOTORS_THST_EXPO_DEFAULT)
  double earth_radius = 6378137.0;  // [m] WGS-84 equatorial radius, for the POS fallback only
};

// ArduPilot's thrust model, exposed for tests: PWM [µs] → thrust fraction [0, 1] of the motor's
// maximum on a full battery. `voltage_ratio` v is ArduPilot's battery voltage ratio (MOTB BatVolt:
// its 0.5 Hz filtered resting voltage over MOT_BAT_VOLT_MAX, in [0.6, 1]; 1 without voltage
// compensation): a motor's throttle drives it as the throttle × v would on a full battery, which is
// what ArduPilot's compensation assumes when it divides the throttle by v
// (AP_MotorsMulticopter::apply_thrust_curve_and_volt_scaling). A v outside (0, 1] counts as 1.
struct ArdupilotThrustMap {
  double pwm_min = 1000.0;   // [µs]
  double pwm_max = 2000.0;   // [µs]
  double spin_min = 0.15;    // [-] of the PWM range
  double spin_max = 0.95;    // [-] of the PWM range
  double expo = 0.65;        // [-] MOT_THST_EXPO, clamped to [−1, 1] as ArduPilot does
  double thrustFraction(double pwm, double voltage_ratio = 1.0) const;
  // ArduPilot's forward direction (thrust_to_actuator, apply_thrust_curve_and_volt_scaling, output_to_pwm).
  double pwmFor(double thrust_fraction, double voltage_ratio = 1.0) const;
  // v from MOTB's LiftMax = v(1 − e) + e·v² (update_lift_max_from_batt_voltage), for logs without BatVolt.
  double voltageRatioOfLiftMax(double lift_max) const;
};

LogIssue extractArdupilotSignals(const DecodedLog& log, const ArdupilotSignalOptions& options, FlightSignals& out);

}  // namespace quadfdi
