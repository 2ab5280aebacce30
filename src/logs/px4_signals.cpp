#include "logs/px4_signals.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/frames.h"
#include "core/quad_layout.h"

// PX4 conventions applied here (sources: PX4 msg/VehicleLocalPosition.msg, VehicleAttitude.msg,
// ActuatorMotors.msg, ActuatorOutputs.msg, VehicleStatus.msg, VehicleLandDetected.msg; the PX4
// parameter reference for THR_MDL_FAC and PWM_*; the PX4 Airframe Reference, "Quadrotor X").
//
// Frames. PX4: world NED (x north, y east, z down), body FRD; vehicle_attitude.q = (w, x, y, z)
// rotates FRD body vectors into NED. quadfdi: world z up, body FLU (x forward, y left, z up),
// R = Rz(yaw)·Ry(pitch)·Rx(roll) maps body to world. We turn both PX4 frames by 180° about their
// x axis, T = diag(1, −1, −1) (a proper rotation): world = north, west, up; body = FLU. Then
// R_quadfdi = T·R_px4·T, so quadfdi (roll, pitch, yaw) = (φ, −θ, −ψ) of PX4's NED Euler angles:
// nose down is positive pitch (README), a right turn (ψ growing in NED) is negative yaw.
//
// Motors. PX4 quad-X (airframe reference / mixer geometry quad_x), 1-based:
//   PX4 1: front right, CCW    PX4 2: back left, CCW    PX4 3: front left, CW    PX4 4: back right, CW
// quadfdi (README): 1 front right, 2 back right, 3 back left, 4 front left; yaw torque
// κ(−f1 + f2 − f3 + f4) makes 1 and 3 the CCW propellers — the same spins as PX4's.
//   quadfdi 1 (FR) = PX4 1,  quadfdi 2 (BR) = PX4 4,  quadfdi 3 (BL) = PX4 2,  quadfdi 4 (FL) = PX4 3
// That is the default; a log with the control allocation's geometry (CA_ROTORn_PX/PY/KM) is read
// by it instead (motorTable below), and FlightSignals::numbering keeps PX4's numbers for reporting.
//
// Thrust. PX4 models thrust against the motor signal as rel_thrust = (1 − f)·x + f·x² with
// f = THR_MDL_FAC and x the normalised signal in [0, 1]. actuator_motors.control is the thrust
// setpoint *before* the output driver inverts that model, so it already is a thrust fraction;
// actuator_outputs.output is the PWM *after* it, so x = (pwm − min) / (max − min) and the model
// is applied to get the thrust fraction back.

namespace quadfdi {
namespace {

LogIssue missing(const std::string& topic, const std::string& what, LogStatus status = LogStatus::kMissingSignal) {
  return LogIssue{status, 0, topic, what};
}

// Column indices of the named fields, or a LogIssue naming the first that is absent.
LogIssue columnsOf(const LogTopic& topic, const std::vector<std::string>& names, std::vector<const std::vector<double>*>& cols) {
  cols.clear();
  for (const std::string& n : names) {
    const int i = topic.fieldIndex(n);
    if (i < 0) return missing(topic.name, "topic " + topic.name + " has no field '" + n + "'");
    cols.push_back(&topic.columns[static_cast<std::size_t>(i)]);
  }
  return {};
}

const LogTopic* findNonEmpty(const DecodedLog& log, const std::string& name, int instance = 0) {
  const LogTopic* t = log.find(name, instance);
  return t && t->rows() > 0 ? t : nullptr;
}

constexpr double kDegreesPerRadian = 180.0 / 3.14159265358979323846;

double seconds(std::int64_t us) { return static_cast<double>(us) * 1e-6; }

// Appends a sample if its time is after the last one and every value is finite; counts the rest.
template <int N>
void append(SignalSeries<N>& s, double t, const std::array<double, N>& v, std::size_t& skipped) {
  bool finite = std::isfinite(t);
  for (double x : v) finite = finite && std::isfinite(x);
  if (!finite || (!s.t.empty() && t <= s.t.back())) {
    ++skipped;
    return;
  }
  s.t.push_back(t);
  s.v.push_back(v);
}

void noteSkipped(FlightSignals& out, const std::string& topic, std::size_t skipped) {
  if (skipped > 0)
    out.conventions.push_back(topic + ": " + std::to_string(skipped) +
                              " rows skipped (non-finite values or time not increasing)");
}

double parameter(const DecodedLog& log, const std::string& name, double fallback, bool& found) {
  auto it = log.parameters.find(name);
  found = it != log.parameters.end();
  return found ? it->second : fallback;
}

// PWM range of output channel `channel` (0-based): per-channel PWM_MAIN_MIN<n>/MAX<n> (PX4 ≥ 1.13;
// −1 means "not set"), else PWM_MAIN_MIN/MAX, else PWM_MIN/MAX (older PX4), else the defaults.
double pwmLimit(const DecodedLog& log, const char* which, int channel, double fallback, std::string& source) {
  const std::string w(which);
  const std::string names[] = {"PWM_MAIN_" + w + std::to_string(channel + 1), "PWM_MAIN_" + w, "PWM_" + w};
  for (const std::string& n : names) {
    auto it = log.parameters.find(n);
    if (it != log.parameters.end() && it->second > 0.0) {
      source = n;
      return it->second;
    }
  }
  source = "default";
  return fallback;
}

// A field that only some PX4 versions log (validity flags, reset counters), or nullptr.
const std::vector<double>* optionalColumn(const LogTopic& topic, const std::string& name) {
  const int i = topic.fieldIndex(name);
  return i < 0 ? nullptr : &topic.columns[static_cast<std::size_t>(i)];
}

// Resets of an estimator state between row r − 1 and row r: the step of its uint8 reset counter,
// which wraps at 256 (PX4 msg/VehicleLocalPosition.msg, VehicleAttitude.msg).
// A counter that is not a uint8 (a damaged log) counts as stepping by 2: a break, not a shift.
int resetsBefore(const std::vector<double>& counter, std::size_t r) {
  const double a = counter[r - 1], b = counter[r];
  if (a == b) return 0;
  if (!(a >= 0.0 && a <= 255.0 && b >= 0.0 && b <= 255.0)) return 2;
  const int step = static_cast<int>(b) - static_cast<int>(a);
  return (step % 256 + 256) % 256;
}

// The resets of one estimator state found in a log, for the conventions line.
struct ResetTally {
  int count = 0;         // resets whose shift was taken out
  double largest = 0.0;  // [m or rad] largest shift taken out
  int unlogged = 0;      // counter steps whose shift the log does not hold (breaks)
  void add(double shift) {
    ++count;
    largest = std::max(largest, shift);
  }
  std::string text(const std::string& what, const char* unit, double scale) const {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%d %s reset%s (largest %.3g%s)", count, what.c_str(), count == 1 ? "" : "s",
                  largest * scale, unit);
    return buf;
  }
};

// Records a counter step whose shift is not in the log: two or more resets between two logged
// rows (each row holds only the last one's shift, or their sum within one estimator update: the
// log cannot tell which), or a non-finite shift.
void breakAt(FlightSignals& out, double before, double t, const std::string& topic, int resets, const std::string& what) {
  out.breaks.push_back({t, before, topic + ": " + std::to_string(resets) + " " + what + " reset" + (resets == 1 ? "" : "s") +
                                       " whose shift the log does not hold"});
}

// Position, continuous across the estimator's resets and only where the estimator says it is
// valid. EKF2 shifts its position at a reset (GPS regained, a height source switched) and logs
// the shift: delta_xy = position after − before, delta_z likewise, with the counters
// xy_reset_counter and z_reset_counter (PX4 ekf2 resetHorizontalPositionTo / resetVerticalPositionTo).
// Subtracting the sum of the shifts so far removes the step, which the detector would otherwise see
// as a sudden acceleration; every feature is relative to the window or the previous sample, so the
// resulting offset does not matter. Without horizontal or vertical aiding EKF2 holds x, y (or z) and
// flags them invalid (xy_valid, z_valid): those rows are skipped, and a log in which no row is
// valid is refused — held values are not a measured motion.
LogIssue extractPosition(const DecodedLog& log, FlightSignals& out) {
  const std::string name = "vehicle_local_position";
  const LogTopic* t = findNonEmpty(log, name);
  if (!t) return missing(name, "the log has no vehicle_local_position data (needed for position)");
  std::vector<const std::vector<double>*> c;
  if (LogIssue e = columnsOf(*t, {"x", "y", "z"}, c); !e.ok()) return e;
  const std::vector<double>* xy_valid = optionalColumn(*t, "xy_valid");
  const std::vector<double>* z_valid = optionalColumn(*t, "z_valid");
  const std::vector<double>* xy_counter = optionalColumn(*t, "xy_reset_counter");
  const std::vector<double>* dx = optionalColumn(*t, "delta_xy[0]");
  const std::vector<double>* dy = optionalColumn(*t, "delta_xy[1]");
  const std::vector<double>* z_counter = optionalColumn(*t, "z_reset_counter");
  const std::vector<double>* dz = optionalColumn(*t, "delta_z");
  const bool xy_resets = xy_counter && dx && dy, z_resets = z_counter && dz;
  double north = 0.0, east = 0.0, down = 0.0;  // [m] sum of the resets' shifts so far
  ResetTally xy_tally, z_tally;
  std::size_t skipped = 0, xy_invalid = 0, z_invalid = 0, invalid = 0;
  for (std::size_t r = 0; r < t->rows(); ++r) {
    const double time = seconds(t->timestamp_us[r]);
    if (r > 0 && xy_resets) {
      if (const int n = resetsBefore(*xy_counter, r); n > 0) {
        const double sx = (*dx)[r], sy = (*dy)[r];
        if (n == 1 && std::isfinite(sx) && std::isfinite(sy)) {
          north += sx;
          east += sy;
          xy_tally.add(std::hypot(sx, sy));
        } else {
          ++xy_tally.unlogged;
          breakAt(out, seconds(t->timestamp_us[r - 1]), time, name, n, "horizontal position");
        }
      }
    }
    if (r > 0 && z_resets) {
      if (const int n = resetsBefore(*z_counter, r); n > 0) {
        const double sz = (*dz)[r];
        if (n == 1 && std::isfinite(sz)) {
          down += sz;
          z_tally.add(std::abs(sz));
        } else {
          ++z_tally.unlogged;
          breakAt(out, seconds(t->timestamp_us[r - 1]), time, name, n, "height");
        }
      }
    }
    const bool bad_xy = xy_valid && (*xy_valid)[r] == 0.0, bad_z = z_valid && (*z_valid)[r] == 0.0;
    xy_invalid += bad_xy;
    z_invalid += bad_z;
    if (bad_xy || bad_z) {
      ++invalid;
      continue;
    }
    append<3>(out.position, time, {(*c[0])[r] - north, -((*c[1])[r] - east), -((*c[2])[r] - down)}, skipped);
  }
  const std::size_t rows = t->rows();
  if (out.position.empty() && invalid > 0) {
    const bool xy = xy_invalid == rows;
    return missing(name, std::string(xy ? "xy_valid" : z_invalid == rows ? "z_valid" : "xy_valid or z_valid") +
                             " is false in all " + std::to_string(rows) + " rows: PX4's estimator had no " +
                             (xy ? "horizontal " : "") +
                             "position (with no GPS, optical flow, vision or motion capture it holds x and y, it "
                             "does not measure them), and the detector needs the vehicle's measured motion");
  }
  out.position.source = {name, "x,y,z", "NED → north, west, up: (x, −y, −z)"};
  if (invalid > 0)
    out.conventions.push_back(name + ": " + std::to_string(invalid) + " of " + std::to_string(rows) +
                              " rows skipped: the estimator flagged its position invalid (" +
                              (xy_invalid ? std::to_string(xy_invalid) + " xy_valid false" : std::string()) +
                              (xy_invalid && z_invalid ? ", " : "") +
                              (z_invalid ? std::to_string(z_invalid) + " z_valid false" : std::string()) +
                              "); nothing is evaluated across the holes they leave");
  if (xy_tally.count + z_tally.count > 0) {
    const std::string xy = xy_tally.count ? xy_tally.text("horizontal position", " m", 1.0) : "";
    const std::string z = z_tally.count ? z_tally.text("height", " m", 1.0) : "";
    out.conventions.push_back(name + ": " + xy + (xy.empty() || z.empty() ? "" : " and ") + z + " taken out with " +
                              (xy.empty() ? "delta_z" : z.empty() ? "delta_xy" : "delta_xy and delta_z") +
                              ", so the track is continuous");
  }
  if (xy_tally.unlogged + z_tally.unlogged > 0)
    out.conventions.push_back(name + ": " + std::to_string(xy_tally.unlogged + z_tally.unlogged) +
                              " reset counter steps without their shift in the log: the flight is cut there");
  noteSkipped(out, name, skipped);
  return {};
}

// Attitude, continuous across the estimator's resets (yaw alignment, a heading source switched):
// EKF2 logs each reset's rotation delta_q_reset = q_after · q_before⁻¹ with quat_reset_counter
// (PX4 ekf2 resetQuatStateYaw), so q_continuous = (d₁⁻¹ · d₂⁻¹ · …) · q.
LogIssue extractAttitude(const DecodedLog& log, FlightSignals& out) {
  const std::string name = "vehicle_attitude";
  const LogTopic* t = findNonEmpty(log, name);
  if (!t) return missing(name, "the log has no vehicle_attitude data (needed for attitude)");
  std::vector<const std::vector<double>*> c;
  if (LogIssue e = columnsOf(*t, {"q[0]", "q[1]", "q[2]", "q[3]"}, c); !e.ok()) return e;
  const std::vector<double>* counter = optionalColumn(*t, "quat_reset_counter");
  std::vector<const std::vector<double>*> d;
  const bool resets = counter && columnsOf(*t, {"delta_q_reset[0]", "delta_q_reset[1]", "delta_q_reset[2]", "delta_q_reset[3]"}, d).ok();
  Quaternion undo;  // the inverse of every reset so far, composed
  ResetTally tally;
  std::size_t skipped = 0;
  for (std::size_t r = 0; r < t->rows(); ++r) {
    const double time = seconds(t->timestamp_us[r]);
    if (r > 0 && resets) {
      if (const int n = resetsBefore(*counter, r); n > 0) {
        Quaternion shift{(*d[0])[r], (*d[1])[r], (*d[2])[r], (*d[3])[r]};
        const double norm = std::sqrt(shift.w * shift.w + shift.x * shift.x + shift.y * shift.y + shift.z * shift.z);
        constexpr double kUnitTolerance = 0.01;  // [-] a logged float unit quaternion is within 1e-6 of norm 1
        if (n == 1 && std::abs(norm - 1.0) < kUnitTolerance) {
          shift = {shift.w / norm, shift.x / norm, shift.y / norm, shift.z / norm};
          undo = undo * conjugate(shift);
          tally.add(rotationAngle(shift));
        } else {
          ++tally.unlogged;
          breakAt(out, seconds(t->timestamp_us[r - 1]), time, name, n, "attitude");
        }
      }
    }
    const Quaternion q = undo * Quaternion{(*c[0])[r], (*c[1])[r], (*c[2])[r], (*c[3])[r]};
    EulerZyx frd;
    if (!eulerZyxFromQuaternion(q.w, q.x, q.y, q.z, frd)) {
      ++skipped;
      continue;
    }
    // q rotates FRD into NED; both frames turned 180° about x give quadfdi's (core/frames.h).
    const EulerZyx e = turnedAboutX(frd);
    append<3>(out.attitude, time, {e.roll, e.pitch, e.yaw}, skipped);
  }
  out.attitude.source = {name, "q[0..3]",
                         "q (w,x,y,z) FRD→NED; both frames turned 180° about x: ZYX Euler (φ, −θ, −ψ)"};
  if (tally.count > 0)
    out.conventions.push_back(name + ": " + tally.text("attitude", "°", kDegreesPerRadian) +
                              " taken out with delta_q_reset, so the attitude is continuous");
  if (tally.unlogged > 0)
    out.conventions.push_back(name + ": " + std::to_string(tally.unlogged) +
                              " reset counter steps without their rotation in the log: the flight is cut there");
  noteSkipped(out, name, skipped);
  return {};
}

// Body rates: vehicle_angular_velocity.xyz, the bias-corrected, filtered gyro the rate controller
// flies on (PX4 msg/VehicleAngularVelocity.msg, rad/s, FRD); older logs without it have the raw
// sensor_combined.gyro_rad (msg/SensorCombined.msg). Optional: none leaves `rates` empty.
void extractRates(const DecodedLog& log, FlightSignals& out) {
  std::string name = "vehicle_angular_velocity", field = "xyz";
  const LogTopic* t = findNonEmpty(log, name);
  if (!t || t->fieldIndex("xyz[0]") < 0) {
    name = "sensor_combined";
    field = "gyro_rad";
    t = findNonEmpty(log, name);
  }
  std::vector<const std::vector<double>*> c;
  if (!t || !columnsOf(*t, {field + "[0]", field + "[1]", field + "[2]"}, c).ok()) return;
  std::size_t skipped = 0;
  for (std::size_t r = 0; r < t->rows(); ++r)  // FRD → FLU: the body turned 180° about x
    append<3>(out.rates, seconds(t->timestamp_us[r]), {(*c[0])[r], -(*c[1])[r], -(*c[2])[r]}, skipped);
  out.rates.source = {name, field + "[0..2]", "rad/s, FRD → FLU (p, −q, −r)"};
  noteSkipped(out, name, skipped);
}

std::string motorTableText(const std::array<int, kMotors>& table) {
  std::string s;
  for (int k = 0; k < kMotors; ++k)
    s += (k ? ", " : "") + std::to_string(k + 1) + "←PX4 " + std::to_string(table[static_cast<std::size_t>(k)] + 1);
  return s;
}

// The PX4 motor (0-based) at each quadfdi motor, from the control allocation's geometry when the
// log has it (PX4 ≥ 1.13 logs every parameter: CA_AIRFRAME, CA_ROTOR_COUNT, CA_ROTORn_PX/PY [m,
// FRD] and CA_ROTORn_KM, positive for a counter-clockwise rotor — PX4 parameter reference), else
// options.px4_motor_for_quadfdi. So an airframe whose outputs PX4 numbers unlike its quad X is read
// as it flies, and a frame the model does not describe is refused by its parameters.
LogIssue motorTable(const DecodedLog& log, const Px4SignalOptions& options, std::array<int, kMotors>& table, BodyTurn& turn,
                    std::string& note) {
  table = options.px4_motor_for_quadfdi;
  for (int index : table)
    if (index < 0 || index > 15)
      return missing("", "px4_motor_for_quadfdi holds " + std::to_string(index) + ", not a PX4 motor index 0..15", LogStatus::kCorrupt);
  // A frame the parameters rule out: the log's parameters are the "topic" of the message.
  const auto refuse = [](const std::string& what) { return LogIssue{LogStatus::kCorrupt, 0, "parameters", what}; };
  bool found = false;
  const double count = parameter(log, "CA_ROTOR_COUNT", 0.0, found);
  if (!options.motor_table_from_parameters || !found) {
    note = options.motor_table_from_parameters ? " (PX4's quad-X numbering: the log has no CA_ROTOR_COUNT)" : "";
    return {};
  }
  const double airframe = parameter(log, "CA_AIRFRAME", 0.0, found);
  if (airframe != 0.0)
    return refuse("CA_AIRFRAME is " + shortNumber(airframe) + ", not 0 (multicopter): quadfdi reads quad X multicopters");
  if (count != 4.0)
    return refuse("CA_ROTOR_COUNT is " + shortNumber(count) + ": quadfdi's model is a quad X (4 rotors)");
  std::array<RotorPlacement, kMotors> rotors{};
  for (int i = 0; i < kMotors; ++i) {
    const std::string rotor = "CA_ROTOR" + std::to_string(i) + "_";
    bool has_x = false, has_y = false, has_km = false;
    const double x = parameter(log, rotor + "PX", 0.0, has_x);
    const double y = parameter(log, rotor + "PY", 0.0, has_y);
    const double km = parameter(log, rotor + "KM", 0.0, has_km);
    if (!has_x || !has_y)
      return refuse("CA_ROTOR_COUNT is 4 but the log has no " + rotor + (has_x ? "PY" : "PX"));
    rotors[static_cast<std::size_t>(i)] = {x, y, has_km && km != 0.0 ? (km > 0.0 ? 1 : -1) : 0};
  }
  // An X, a plus or a props-out frame, by the rule every layout goes through (core/quad_layout.h).
  const QuadLayout layout = quadLayout(rotors);
  const auto at = [&](int rotor) {  // "PX4 motor 2 (CA_ROTOR1_PX 0.25, CA_ROTOR1_PY 0)"
    const RotorPlacement& r = rotors[static_cast<std::size_t>(rotor - 1)];
    const std::string p = "CA_ROTOR" + std::to_string(rotor - 1) + "_";
    return "PX4 motor " + std::to_string(rotor) + " (" + p + "PX " + shortNumber(r.x_forward) + ", " + p + "PY " + shortNumber(r.y_right) + ")";
  };
  const auto spin = [&](int rotor) { return rotors[static_cast<std::size_t>(rotor - 1)].spin > 0 ? "counter-clockwise" : "clockwise"; };
  switch (layout.status) {
    case QuadLayoutStatus::kOk: break;
    case QuadLayoutStatus::kRotorAtCentre: return refuse(at(layout.motor) + " is at the centre: every rotor needs an arm");
    case QuadLayoutStatus::kMixedAxes:
      return refuse(at(layout.motor) + " is on a body axis and " + at(layout.other) +
                    " is not: quadfdi reads quad X frames and plus frames (every rotor on an axis)");
    case QuadLayoutStatus::kDuplicateQuadrant:
      return refuse(at(layout.motor) + " and " + at(layout.other) + " are in one quadrant" +
                    (layout.plus ? " of the plus frame turned 45°" : "") + ": a quad has one rotor in each");
    case QuadLayoutStatus::kWrongSpinPattern:
      return refuse("PX4 motors " + std::to_string(layout.motor) + " and " + std::to_string(layout.other) + " spin " +
                    spin(layout.motor) + " and " + spin(layout.other) +
                    " (CA_ROTORn_KM > 0: counter-clockwise): a quad's opposite rotors spin alike and its neighbours the "
                    "other way, or it has no yaw moment to hover with");
    case QuadLayoutStatus::kSpinsUnknown:
      return refuse("a plus frame with a CA_ROTORn_KM of 0: which way its axes turn onto an X depends on the spins");
  }
  for (int k = 0; k < kMotors; ++k) table[static_cast<std::size_t>(k)] = layout.rotor_of_quadfdi_motor[static_cast<std::size_t>(k)] - 1;
  turn = layout.turn;
  note = std::string(" (from the log's CA_ROTORn_PX/PY") +
         (layout.spins_checked ? ", spins checked by CA_ROTORn_KM)" : "; a KM of 0 left a spin unchecked)") + bodyTurnNote(layout);
  return {};
}

// PX4's battery scaling undone. Where MC_BAT_SCALE_EN is set, mc_rate_control multiplies its
// thrust and torque setpoints by battery_status.scale (≥ 1 as the battery drains: its charged cell
// voltage over the one its state of charge implies, capped at 1.3 — PX4's Battery::computeScale) before the control
// allocation, so that a draining battery gives the same thrust: a command then is the thrust of a
// full battery × scale, and each is divided by the scale in force at its time (the last
// battery_status row of instance 0 at or before it, connected, with scale > 0; none before the
// first, as PX4 starts unscaled). Returns the conventions line.
std::string undoBatteryScale(const DecodedLog& log, SignalSeries<kMotors>& command) {
  bool found = false;
  const double enabled = parameter(log, "MC_BAT_SCALE_EN", 0.0, found);
  if (!found) return "battery: MC_BAT_SCALE_EN not in the log: PX4's default (0, no battery scaling) assumed; commands as logged";
  if (enabled == 0.0) return "battery: PX4 does not scale its commands for the battery (MC_BAT_SCALE_EN 0); commands as logged";
  const LogTopic* battery = findNonEmpty(log, "battery_status");
  const std::vector<double>* scale = battery ? optionalColumn(*battery, "scale") : nullptr;
  if (!scale)
    return "battery: MC_BAT_SCALE_EN 1 but the log has no battery_status.scale: PX4's battery scaling not undone (a draining "
           "battery reads as more thrust on every motor)";
  const std::vector<double>* connected = optionalColumn(*battery, "connected");
  std::size_t row = 0, rows_used = 0;
  double in_force = 1.0, lo = 0.0, hi = 0.0;
  bool any = false;
  for (std::size_t k = 0; k < command.t.size(); ++k) {
    for (; row < battery->rows() && seconds(battery->timestamp_us[row]) <= command.t[k]; ++row) {
      const double x = (*scale)[row];
      if (std::isfinite(x) && x > 0.0 && (!connected || (*connected)[row] != 0.0)) {
        in_force = x;
        ++rows_used;
        lo = any ? std::min(lo, x) : x;
        hi = any ? std::max(hi, x) : x;
        any = true;
      }
    }
    for (double& u : command.v[k]) u = std::clamp(u / in_force, 0.0, 1.0);
  }
  if (!any) return "battery: MC_BAT_SCALE_EN 1 but no battery_status row before the last command holds a scale: commands as logged";
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.3f … %.3f", lo, hi);
  return "battery: PX4's battery scaling undone (MC_BAT_SCALE_EN 1): each command ÷ battery_status.scale, " + std::string(buf) +
         " (" + std::to_string(rows_used) + " rows), so the thrust fractions are of a full battery's maximum";
}

LogIssue extractCommands(const DecodedLog& log, const Px4SignalOptions& options, FlightSignals& out) {
  std::array<int, kMotors> table{};
  std::string table_note;
  if (LogIssue e = motorTable(log, options, table, out.numbering.body_turn, table_note); !e.ok()) return e;
  out.numbering.name = "PX4";
  for (std::size_t k = 0; k < kMotors; ++k) out.numbering.autopilot_motor[k] = table[k] + 1;
  out.command_kind = CommandKind::kThrustFraction;
  std::size_t skipped = 0;
  const LogTopic* motors = options.prefer_actuator_motors ? findNonEmpty(log, "actuator_motors") : nullptr;
  if (motors) {
    std::vector<std::string> names;
    for (int index : table) names.push_back("control[" + std::to_string(index) + "]");
    std::vector<const std::vector<double>*> c;
    if (LogIssue e = columnsOf(*motors, names, c); !e.ok()) return e;
    for (std::size_t r = 0; r < motors->rows(); ++r) {
      std::array<double, kMotors> u{};
      for (std::size_t k = 0; k < kMotors; ++k) {
        const double v = (*c[k])[r];
        u[k] = std::isnan(v) ? 0.0 : std::clamp(v, 0.0, 1.0);  // NaN: disarmed, motor stopped
      }
      append<kMotors>(out.command, seconds(motors->timestamp_us[r]), u, skipped);
    }
    out.command.source = {"actuator_motors", "control[0..3]", "thrust setpoints (already linear in thrust); NaN → 0"};
    out.conventions.push_back("commands: actuator_motors.control as thrust fractions (PX4 applies THR_MDL_FAC after "
                              "this topic); NaN (disarmed) → 0; clamped to [0, 1]");
  } else {
    const LogTopic* outputs = findNonEmpty(log, "actuator_outputs", options.outputs_instance);
    if (!outputs)
      return missing("actuator_motors",
                     "the log has neither actuator_motors nor actuator_outputs (instance " +
                         std::to_string(options.outputs_instance) + ") data (needed for motor commands)");
    std::vector<std::string> names;
    for (int index : table) names.push_back("output[" + std::to_string(index) + "]");
    std::vector<const std::vector<double>*> c;
    if (LogIssue e = columnsOf(*outputs, names, c); !e.ok()) return e;
    bool has_factor = false;
    const double f = std::clamp(parameter(log, "THR_MDL_FAC", options.default_thrust_model_factor, has_factor), 0.0, 1.0);
    std::array<double, kMotors> lo{}, hi{};
    std::string limits;
    for (std::size_t k = 0; k < kMotors; ++k) {
      const int channel = table[k];
      std::string lo_source, hi_source;
      lo[k] = pwmLimit(log, "MIN", channel, options.default_pwm_min, lo_source);
      hi[k] = pwmLimit(log, "MAX", channel, options.default_pwm_max, hi_source);
      if (!(hi[k] > lo[k]))
        return missing("actuator_outputs", "PWM range of output " + std::to_string(channel + 1) + " is empty (" +
                                               lo_source + " " + std::to_string(lo[k]) + ", " + hi_source + " " +
                                               std::to_string(hi[k]) + ")",
                     LogStatus::kCorrupt);
      limits += (k ? ", " : "") + std::to_string(static_cast<int>(lo[k])) + "–" + std::to_string(static_cast<int>(hi[k])) +
                " (" + lo_source + "/" + hi_source + ")";
    }
    for (std::size_t r = 0; r < outputs->rows(); ++r) {
      std::array<double, kMotors> u{};
      for (std::size_t k = 0; k < kMotors; ++k) {
        const double x = std::clamp(((*c[k])[r] - lo[k]) / (hi[k] - lo[k]), 0.0, 1.0);
        u[k] = (1.0 - f) * x + f * x * x;
      }
      append<kMotors>(out.command, seconds(outputs->timestamp_us[r]), u, skipped);
    }
    out.command.source = {"actuator_outputs", "output[0..3]",
                          "PWM → x = (pwm − min)/(max − min) → thrust (1 − f)x + f x², f = THR_MDL_FAC"};
    out.conventions.push_back("commands: actuator_outputs[" + std::to_string(options.outputs_instance) +
                              "] PWM normalised with per-motor ranges " + limits + ", clamped to [0, 1]");
    out.conventions.push_back("thrust model: thrust fraction = (1 − f)·x + f·x², f = THR_MDL_FAC = " + std::to_string(f) +
                              (has_factor ? "" : options.default_thrust_model_factor == 0.0 ? " (not in the log: assumed 0, linear)"
                                                                              : " (not in the log: the vehicle description's)"));
  }
  out.conventions.push_back(undoBatteryScale(log, out.command));
  out.conventions.push_back("motors: PX4's numbering mapped to quadfdi's: " + motorTableText(table) + table_note);
  noteSkipped(out, out.command.source.topic, skipped);
  return {};
}

// Armed (vehicle_status.arming_state == 2, ARMED in every PX4 release) and landed
// (vehicle_land_detected.landed || maybe_landed), merged in time order; an event whenever either changes.
void extractStates(const DecodedLog& log, FlightSignals& out) {
  struct Change {
    std::int64_t t;
    int which;  // 0 armed, 1 landed
    bool value;
  };
  std::vector<Change> changes;
  const LogTopic* status = findNonEmpty(log, "vehicle_status");
  std::vector<const std::vector<double>*> c;
  if (status && columnsOf(*status, {"arming_state"}, c).ok()) {
    for (std::size_t r = 0; r < status->rows(); ++r) changes.push_back({status->timestamp_us[r], 0, (*c[0])[r] == 2.0});
  } else {
    out.conventions.push_back("states: no vehicle_status.arming_state; armed is reported false throughout");
  }
  const LogTopic* land = findNonEmpty(log, "vehicle_land_detected");
  if (land && columnsOf(*land, {"landed"}, c).ok()) {
    const int maybe = land->fieldIndex("maybe_landed");
    for (std::size_t r = 0; r < land->rows(); ++r) {
      const bool landed = (*c[0])[r] != 0.0 || (maybe >= 0 && land->columns[static_cast<std::size_t>(maybe)][r] != 0.0);
      changes.push_back({land->timestamp_us[r], 1, landed});
    }
  } else {
    out.conventions.push_back("states: no vehicle_land_detected.landed; landed is reported true throughout");
  }
  std::stable_sort(changes.begin(), changes.end(), [](const Change& a, const Change& b) { return a.t < b.t; });
  bool armed = false, landed = true;
  for (const Change& ch : changes) {
    (ch.which == 0 ? armed : landed) = ch.value;
    const double t = seconds(ch.t);
    if (!out.states.empty() && out.states.back().armed == armed && out.states.back().landed == landed) continue;
    if (!out.states.empty() && out.states.back().t == t)
      out.states.back() = {t, armed, landed};  // both changed at the same instant
    else
      out.states.push_back({t, armed, landed});
  }
  if (status || land)
    out.conventions.push_back("states: armed = vehicle_status.arming_state == 2; landed = vehicle_land_detected.landed "
                              "or maybe_landed");
}

}  // namespace

LogIssue extractPx4Signals(const DecodedLog& log, const Px4SignalOptions& options, FlightSignals& out) {
  out = FlightSignals{};
  out.conventions.push_back("time: the log's clock (µs since boot) in seconds");
  out.conventions.push_back("world frame: x north, y west, z up (PX4 NED turned 180° about north: x, −y, −z)");
  out.conventions.push_back("attitude: vehicle_attitude.q (FRD → NED) as ZYX Euler of the FLU body in that frame: "
                            "roll = φ, pitch = −θ, yaw = −ψ of PX4's NED angles (positive pitch = nose down)");
  if (LogIssue e = extractPosition(log, out); !e.ok()) return e;
  if (LogIssue e = extractAttitude(log, out); !e.ok()) return e;
  if (LogIssue e = extractCommands(log, options, out); !e.ok()) return e;
  extractRates(log, out);
  extractStates(log, out);
  return {};
}

}  // namespace quadfdi
