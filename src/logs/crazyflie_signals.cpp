// Crazyflie micro-SD log → FlightSignals; conventions and sources: docs/logs/crazyflie-usd.md.
#include "logs/crazyflie_signals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/frames.h"

namespace quadfdi {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
constexpr const char* kPreferredTopic = "fixedFrequency";  // usddeck.c FIXED_FREQUENCY_EVENT_NAME

// Where a set of variables lives: one topic holding all of them (fixedFrequency preferred).
struct Located {
  const LogTopic* topic = nullptr;
  std::vector<int> columns;
};

bool hasAll(const LogTopic& t, const std::vector<std::string>& names) {
  for (const std::string& n : names)
    if (t.fieldIndex(n) < 0) return false;
  return true;
}

Located locate(const DecodedLog& log, const std::vector<std::string>& names) {
  Located l;
  for (const LogTopic& t : log.topics) {
    if (!hasAll(t, names)) continue;
    if (l.topic == nullptr || (t.name == kPreferredTopic && l.topic->name != kPreferredTopic)) l.topic = &t;
  }
  if (l.topic != nullptr)
    for (const std::string& n : names) l.columns.push_back(l.topic->fieldIndex(n));
  return l;
}

// The names of `names` that no topic logs (all of them if they are split over topics).
std::vector<std::string> missingOf(const DecodedLog& log, const std::vector<std::string>& names) {
  std::vector<std::string> missing;
  for (const std::string& n : names) {
    bool found = false;
    for (const LogTopic& t : log.topics) found = found || t.fieldIndex(n) >= 0;
    if (!found) missing.push_back(n);
  }
  if (missing.empty() && locate(log, names).topic == nullptr) return names;  // split over events
  return missing;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
  return s;
}

LogIssue refuse(const std::string& topic, const std::string& message, LogStatus status = LogStatus::kCorrupt) {
  return LogIssue{status, 0, topic, message};
}

// Rows of `loc` → series; `convert(row, values)` fills one row's values (false: skip the row).
template <int N, typename Convert>
LogIssue fill(const Located& loc, std::int64_t origin_us, const std::string& fields, Convert convert,
              SignalSeries<N>& s, std::size_t& skipped) {
  const LogTopic& t = *loc.topic;
  s = SignalSeries<N>{};
  s.source.topic = t.name;
  s.source.fields = fields;
  skipped = 0;
  for (std::size_t r = 0; r < t.rows(); ++r) {
    std::array<double, N> v{};
    if (!convert(r, v)) {
      ++skipped;
      continue;
    }
    const double time = static_cast<double>(t.timestamp_us[r] - origin_us) * 1e-6;
    if (!s.t.empty() && !(time > s.t.back()))
      return refuse(t.name, "event '" + t.name + "': time does not increase at row " + std::to_string(r) + " (t = " +
                                std::to_string(time) + " s after " + std::to_string(s.t.back()) + " s)");
    s.t.push_back(time);
    s.v.push_back(v);
  }
  if (s.t.empty())
    return refuse(t.name, "event '" + t.name + "' has no usable rows of " + fields +
                              (t.rows() ? " (every row holds a non-finite value)" : " (no records)"));
  return {};
}

std::string rateNote(const std::vector<double>& t) {
  if (t.size() < 2 || !(t.back() > t.front())) return "one row";
  const double hz = static_cast<double>(t.size() - 1) / (t.back() - t.front());
  return std::to_string(static_cast<long long>(std::lround(hz))) + " Hz mean over " +
         std::to_string(static_cast<long long>(std::lround(t.back() - t.front()))) + " s";
}

bool finite(double v) { return std::isfinite(v); }

// The conventions lines for rows a series dropped: those with a non-finite value, and the
// `for_reason` of them dropped for `reason`, each line only where there are some.
void noteSkippedRows(std::vector<std::string>& conventions, const std::string& series, std::size_t skipped,
                     std::size_t for_reason = 0, const std::string& reason = "") {
  if (skipped > for_reason)
    conventions.push_back(series + ": " + std::to_string(skipped - for_reason) + " rows with a non-finite value skipped");
  if (for_reason) conventions.push_back(series + ": " + std::to_string(for_reason) + " rows " + reason + " skipped");
}

// Body rates (optional): gyro.x/y/z, the filtered gyro the stabilizer flies on (sensors.c, deg/s,
// body x forward, y left, z up: FLU already), else the controller's copies controller.r_roll,
// r_pitch, r_yaw (controller_pid.c: radians(gyro.x), −radians(gyro.y), radians(gyro.z)). None, or
// a series that cannot be read, leaves `rates` empty: only a model on body rates needs them.
void extractRates(const DecodedLog& log, std::int64_t origin, FlightSignals& out) {
  bool controller = false;
  Located loc = locate(log, {"gyro.x", "gyro.y", "gyro.z"});
  if (!loc.topic) {
    loc = locate(log, {"controller.r_roll", "controller.r_pitch", "controller.r_yaw"});
    controller = true;
  }
  if (!loc.topic) return;
  const LogTopic& t = *loc.topic;
  std::size_t skipped = 0;
  const LogIssue issue = fill<3>(
      loc, origin, controller ? "controller.r_roll,r_pitch,r_yaw" : "gyro.x,y,z",
      [&](std::size_t r, std::array<double, 3>& v) {
        for (int k = 0; k < 3; ++k) v[static_cast<std::size_t>(k)] = t.columns[static_cast<std::size_t>(loc.columns[static_cast<std::size_t>(k)])][r];
        if (controller) v[1] = -v[1];
        else for (double& x : v) x *= kDegToRad;
        return finite(v[0]) && finite(v[1]) && finite(v[2]);
      },
      out.rates, skipped);
  if (!issue.ok()) {
    out.conventions.push_back("body rates not read: " + issue.message);
    out.rates = {};
    return;
  }
  out.rates.source.note = std::string(controller ? "rad/s, pitch rate sign restored (−r_pitch)" : "deg/s → rad/s") +
                          ", body FLU as logged; " + rateNote(out.rates.t);
  noteSkippedRows(out.conventions, "body rates", skipped);
}

// How the log gives the attitude, in the order they are looked for.
enum class AttitudeSource {
  kEuler,                 // stateEstimate.roll/pitch/yaw [deg], legacy pitch sign
  kStabilizerEuler,       // stabilizer.roll/pitch/yaw: the same state.attitude
  kQuaternion,            // stateEstimate.qw/qx/qy/qz: state.attitudeQuaternion
  kCompressedQuaternion,  // stateEstimateZ.quat: the same quaternion, compressed
};

// A stateEstimateZ int16 at its limit: the firmware's float → int16 conversion saturated there.
bool saturatedInt16(double v) { return v >= 32767.0 || v <= -32768.0; }

}  // namespace

bool decompressCrazyflieQuaternion(std::uint32_t packed, std::array<double, 4>& q_xyzw) {
  // Bits 31–30: the index of the largest component (order x, y, z, w); then three 10-bit groups,
  // the other components in index order, the last in the lowest bits: a sign bit over a 9-bit
  // magnitude in units of (1/√2)/511. The largest is positive (q and −q are the same rotation)
  // and follows from the unit norm.
  constexpr double kSmallMax = 0.70710678118654752440;  // 1/√2: the second-largest component's bound
  constexpr std::uint32_t kMagnitudeMask = (1u << 9) - 1u;
  const unsigned largest = packed >> 30;
  double sum_squares = 0.0;
  for (int i = 3; i >= 0; --i) {
    if (static_cast<unsigned>(i) == largest) continue;
    const double magnitude = kSmallMax * static_cast<double>(packed & kMagnitudeMask) / kMagnitudeMask;
    q_xyzw[static_cast<std::size_t>(i)] = ((packed >> 9) & 1u) ? -magnitude : magnitude;
    sum_squares += magnitude * magnitude;
    packed >>= 10;
  }
  if (sum_squares > 1.0) return false;  // no unit quaternion has these three components
  q_xyzw[largest] = std::sqrt(1.0 - sum_squares);
  return true;
}

LogIssue extractCrazyflieSignals(const DecodedLog& log, const CrazyflieSignalOptions& o, FlightSignals& out) {
  out = FlightSignals{};
  const std::vector<std::string> pos_names = {"stateEstimate.x", "stateEstimate.y", "stateEstimate.z"};
  const std::vector<std::string> zpos_names = {"stateEstimateZ.x", "stateEstimateZ.y", "stateEstimateZ.z"};
  const std::vector<std::string> att_names = {"stateEstimate.roll", "stateEstimate.pitch", "stateEstimate.yaw"};
  const std::vector<std::string> stab_names = {"stabilizer.roll", "stabilizer.pitch", "stabilizer.yaw"};
  const std::vector<std::string> quat_names = {"stateEstimate.qw", "stateEstimate.qx", "stateEstimate.qy",
                                               "stateEstimate.qz"};
  const std::vector<std::string> zquat_names = {"stateEstimateZ.quat"};
  const std::vector<std::string> motor_names = {"motor.m1", "motor.m2", "motor.m3", "motor.m4"};
  const std::vector<std::string> pwm_names = {"pwm.m1_pwm", "pwm.m2_pwm", "pwm.m3_pwm", "pwm.m4_pwm", "pm.vbatMV"};

  if (!(o.command_full_scale > 0.0) || !(o.gravity > 0.0) || !(o.voltage_p1 > 0.0) || !(o.voltage_p2 <= 0.0) ||
      !finite(o.duty_a) || !finite(o.duty_b) || !finite(o.duty_c))
    return refuse("", "invalid CrazyflieSignalOptions (full scale, gravity and voltage_p1 must be > 0, voltage_p2 "
                      "<= 0, duty coefficients finite)");

  // --- What is there: every missing variable is named at once. ---
  std::vector<std::string> missing;
  Located pos = locate(log, pos_names);
  const bool pos_compressed = pos.topic == nullptr && (pos = locate(log, zpos_names)).topic != nullptr;
  if (pos.topic == nullptr)
    for (const std::string& n : missingOf(log, pos_names)) missing.push_back(n);
  // The attitude: Euler angles first (what every earlier log of ours read), then the quaternion the
  // firmware derives them from, full and compressed.
  Located att;
  AttitudeSource att_source = AttitudeSource::kEuler;
  const std::pair<AttitudeSource, const std::vector<std::string>*> att_candidates[] = {
      {AttitudeSource::kEuler, &att_names},
      {AttitudeSource::kStabilizerEuler, &stab_names},
      {AttitudeSource::kQuaternion, &quat_names},
      {AttitudeSource::kCompressedQuaternion, &zquat_names}};
  for (const auto& [source, names] : att_candidates) {
    if (source == AttitudeSource::kStabilizerEuler && !o.stabilizer_fallback) continue;
    if ((att = locate(log, *names)).topic != nullptr) {
      att_source = source;
      break;
    }
  }
  std::string att_missing_note;
  if (att.topic == nullptr) {
    for (const std::string& n : missingOf(log, att_names)) missing.push_back(n);
    att_missing_note = std::string(" (nor ") + (o.stabilizer_fallback ? "stabilizer.roll/pitch/yaw, " : "") +
                       "stateEstimate.qw/qx/qy/qz or stateEstimateZ.quat)";
  }
  bool battery = false;
  Located cmd;
  if (o.thrust_map != CrazyflieThrustMap::kQuadraticDuty) {
    cmd = locate(log, pwm_names);
    battery = cmd.topic != nullptr;
  }
  if (!battery && o.thrust_map == CrazyflieThrustMap::kBatteryVoltage) {
    for (const std::string& n : missingOf(log, pwm_names)) missing.push_back(n);
  } else if (!battery) {
    cmd = locate(log, motor_names);
    if (cmd.topic == nullptr)
      for (const std::string& n : missingOf(log, motor_names)) missing.push_back(n);
  }
  if (!missing.empty()) {
    std::string msg = "the log has no " + join(missing);
    if (!att_missing_note.empty()) msg += att_missing_note;
    msg += ": quadfdi needs position (stateEstimate.x/y/z or stateEstimateZ.x/y/z), attitude "
           "(stateEstimate.roll/pitch/yaw";
    msg += o.stabilizer_fallback ? ", stabilizer.roll/pitch/yaw" : "";
    msg += ", stateEstimate.qw/qx/qy/qz or stateEstimateZ.quat)";
    msg += o.thrust_map == CrazyflieThrustMap::kBatteryVoltage ? " and pwm.m1_pwm..m4_pwm with pm.vbatMV"
                                                               : " and motor commands (motor.m1..m4)";
    msg += "; add them to the deck's config.txt";
    return refuse(missing.front(), msg, LogStatus::kMissingSignal);
  }

  // --- The time origin: the log's first record. ---
  std::int64_t origin = std::numeric_limits<std::int64_t>::max();
  for (const LogTopic& t : log.topics)
    for (std::int64_t ts : t.timestamp_us) origin = std::min(origin, ts);

  std::size_t skipped = 0;
  // Position: the Crazyflie's world frame is already z up; stateEstimateZ holds millimetres.
  const LogTopic& pt = *pos.topic;
  const std::string pos_group = pos_compressed ? "stateEstimateZ" : "stateEstimate";
  std::size_t pos_saturated = 0;
  if (LogIssue i = fill<3>(pos, origin, pos_group + ".x,y,z",
                           [&](std::size_t r, std::array<double, 3>& v) {
                             for (int k = 0; k < 3; ++k) v[k] = pt.columns[pos.columns[k]][r];
                             if (!(finite(v[0]) && finite(v[1]) && finite(v[2]))) return false;
                             if (!pos_compressed) return true;
                             if (saturatedInt16(v[0]) || saturatedInt16(v[1]) || saturatedInt16(v[2])) {
                               ++pos_saturated;
                               return false;
                             }
                             for (double& x : v) x *= 1e-3;  // [mm] → [m]
                             return true;
                           },
                           out.position, skipped);
      !i.ok())
    return i;
  out.position.source.note = std::string(pos_compressed ? "mm → m, " : "") + "world frame z up [m], as logged; " +
                             rateNote(out.position.t);
  out.conventions.push_back("position: " + pt.name + " " + pos_group + ".x/y/z " +
                            (pos_compressed ? "[mm] → [m] (int16: 1 mm steps, ±32.767 m)" : "[m] as logged") +
                            " (the Crazyflie world frame is z up, x/y those of its positioning system)");
  noteSkippedRows(out.conventions, "position", skipped, pos_saturated, "at the int16 limit (±32.767 m, saturated)");

  // Attitude → quadfdi's ZYX Euler angles, body FLU. The Euler angles are degrees with the pitch
  // negated (the firmware logs positive = nose up); the quaternion is the FLU body → world rotation
  // they are computed from, with the standard sign.
  const LogTopic& at = *att.topic;
  std::size_t att_rejected = 0;  // quaternions that are not a rotation (zero, or no unit decompression)
  auto from_quaternion = [&](double w, double x, double y, double z, std::array<double, 3>& v) {
    EulerZyx e;
    if (!eulerZyxFromQuaternion(w, x, y, z, e)) {
      ++att_rejected;
      return false;
    }
    v = {e.roll, e.pitch, e.yaw};
    return true;
  };
  std::string att_fields;
  std::string att_note;
  auto describe = [&](const std::string& fields, const std::string& note, const std::string& convention) {
    att_fields = fields;
    att_note = note;
    out.conventions.push_back("attitude: " + at.name + " " + convention);
  };
  switch (att_source) {
    case AttitudeSource::kEuler:
    case AttitudeSource::kStabilizerEuler: {
      const std::string group = att_source == AttitudeSource::kStabilizerEuler ? "stabilizer" : "stateEstimate";
      describe(group + ".roll,pitch,yaw", "deg → rad, pitch negated; ",
               group + ".roll/pitch/yaw [deg] → [rad]; pitch negated (the firmware logs −pitch, positive = nose up: "
                       "kalman_core.c 'legacy CF2 body coordinate system'; quadfdi: positive = nose down); roll "
                       "(positive = right side down) and yaw (positive = counter-clockwise from above) unchanged, ZYX, "
                       "body x forward, y left, z up");
      if (att_source == AttitudeSource::kStabilizerEuler)
        out.conventions.push_back("attitude: stateEstimate.roll/pitch/yaw not all logged; stabilizer.roll/pitch/yaw "
                                  "used instead (the same state estimate, same sign convention)");
      break;
    }
    case AttitudeSource::kQuaternion:
      describe("stateEstimate.qw,qx,qy,qz", "quaternion → ZYX Euler; ",
               "stateEstimate.qw/qx/qy/qz (state.attitudeQuaternion, the FLU body → world rotation) → ZYX Euler "
               "angles, normalised; no sign change (the legacy pitch negation applies to the logged Euler pitch only)");
      break;
    case AttitudeSource::kCompressedQuaternion:
      describe("stateEstimateZ.quat", "compressed quaternion → ZYX Euler; ",
               "stateEstimateZ.quat (state.attitudeQuaternion in the firmware's quatcompress.h format: the three "
               "smallest components, 9 bits and a sign each, steps of 0.0014, about 0.16°) → ZYX Euler angles; no sign "
               "change");
      break;
  }
  if (LogIssue i = fill<3>(att, origin, att_fields,
                           [&](std::size_t r, std::array<double, 3>& v) {
                             const auto cell = [&](int k) { return at.columns[att.columns[static_cast<std::size_t>(k)]][r]; };
                             switch (att_source) {
                               case AttitudeSource::kEuler:
                               case AttitudeSource::kStabilizerEuler:
                                 v = {cell(0) * kDegToRad, -cell(1) * kDegToRad, cell(2) * kDegToRad};
                                 return finite(v[0]) && finite(v[1]) && finite(v[2]);
                               case AttitudeSource::kQuaternion:
                                 return from_quaternion(cell(0), cell(1), cell(2), cell(3), v);
                               case AttitudeSource::kCompressedQuaternion: {
                                 const double packed = cell(0);
                                 std::array<double, 4> q{};
                                 if (!(packed >= 0.0 && packed <= 4294967295.0) ||
                                     !decompressCrazyflieQuaternion(static_cast<std::uint32_t>(packed), q)) {
                                   ++att_rejected;
                                   return false;
                                 }
                                 return from_quaternion(q[3], q[0], q[1], q[2], v);
                               }
                             }
                             return false;
                           },
                           out.attitude, skipped);
      !i.ok())
    return i;
  out.attitude.source.note = att_note + rateNote(out.attitude.t);
  noteSkippedRows(out.conventions, "attitude", skipped, att_rejected,
                  "whose quaternion is no rotation (zero, or no unit quaternion)");

  // Motors: Crazyflie M1..M4 are quadfdi 1..4 (FR, BR, BL, FL).
  const LogTopic& ct = *cmd.topic;
  const double fs = o.command_full_scale;
  std::size_t clamped = 0;
  std::size_t saturated = 0;
  const double vertex_v = -o.voltage_p1 * o.voltage_p1 / (4.0 * o.voltage_p2);  // [V] top of the fit (∞ if p2 = 0)
  auto duty = [&](double command) {
    double r = command / fs;
    if (r < 0.0 || r > 1.0) {
      ++clamped;
      r = std::clamp(r, 0.0, 1.0);
    }
    return r;
  };
  auto convert = [&](std::size_t r, std::array<double, kMotors>& v) {
    if (battery) {
      const double vbat = ct.columns[cmd.columns[4]][r] * 1e-3;  // [mV] → [V]
      if (!finite(vbat)) return false;
      for (int k = 0; k < kMotors; ++k) {
        const double raw = ct.columns[cmd.columns[k]][r];
        if (!finite(raw)) return false;
        const double volts = duty(raw) * std::max(vbat, 0.0);
        double total_g = 0.0;  // [g] thrust of all four motors at this voltage
        if (o.voltage_p2 == 0.0) {
          total_g = volts / o.voltage_p1;
        } else if (volts >= vertex_v) {
          ++saturated;
          total_g = -o.voltage_p1 / (2.0 * o.voltage_p2);
        } else {
          const double disc = o.voltage_p1 * o.voltage_p1 + 4.0 * o.voltage_p2 * volts;
          total_g = (-o.voltage_p1 + std::sqrt(disc)) / (2.0 * o.voltage_p2);
        }
        v[k] = total_g / 4.0 * 1e-3 * o.gravity;
      }
      return true;
    }
    for (int k = 0; k < kMotors; ++k) {
      const double raw = ct.columns[cmd.columns[k]][r];
      if (!finite(raw)) return false;
      const double d = duty(raw);
      v[k] = o.duty_a * d * d + o.duty_b * d + o.duty_c;
    }
    return true;
  };
  const std::string cmd_fields = battery ? "pwm.m1_pwm..m4_pwm, pm.vbatMV" : "motor.m1..m4";
  if (LogIssue i = fill<kMotors>(cmd, origin, cmd_fields, convert, out.command, skipped); !i.ok()) return i;
  out.command_kind = CommandKind::kThrustNewton;
  out.numbering = {"Crazyflie", {1, 2, 3, 4}, BodyTurn{}};  // M1..M4 are quadfdi's 1..4 (quadfdi numbers as the Crazyflie does)
  out.command.source.note = (battery ? "battery-voltage thrust model; " : "quadratic duty → thrust map; ") +
                            rateNote(out.command.t);
  out.conventions.push_back("motors: Crazyflie M1..M4 → quadfdi motors 1..4 unchanged (M1 front-right, M2 "
                            "back-right, M3 back-left, M4 front-left: power_distribution_quadrotor.c adds +roll "
                            "torque to M3/M4 and +pitch torque to M2/M3)");
  if (battery) {
    out.conventions.push_back(
        "thrust: battery-voltage model of the firmware's thrust compensation (motors.c): motor voltage V = " +
        ct.name + " pwm.mN_pwm / " + std::to_string(static_cast<long long>(fs)) +
        " · pm.vbatMV / 1000, V = " + std::to_string(o.voltage_p2) + "·T² + " + std::to_string(o.voltage_p1) +
        "·T with T the thrust of all four motors [g]; each motor T/4 · " + std::to_string(o.gravity) + " mN/g");
    if (saturated)
      out.conventions.push_back("thrust: " + std::to_string(saturated) + " motor samples beyond the voltage fit's "
                                "maximum, set to its maximum");
  } else {
    out.conventions.push_back(
        "thrust: " + ct.name + " motor.mN / " + std::to_string(static_cast<long long>(fs)) + " = r, f = " +
        std::to_string(o.duty_a) + "·r² + " + std::to_string(o.duty_b) + "·r + " + std::to_string(o.duty_c) +
        " N (firmware pwmToThrustA/B, Förster 2015); no battery-voltage correction" +
        (locate(log, {"pm.vbatMV"}).topic != nullptr ? " (pm.vbatMV is logged, but not pwm.m1_pwm..m4_pwm)" : ""));
  }
  if (clamped)
    out.conventions.push_back("thrust: " + std::to_string(clamped) + " motor commands outside [0, " +
                              std::to_string(static_cast<long long>(fs)) + "] clamped");
  noteSkippedRows(out.conventions, "motors", skipped);
  extractRates(log, origin, out);
  out.conventions.push_back("time: micro-SD timestamps [µs since boot] minus the log's first record, in seconds");
  return {};
}

}  // namespace quadfdi
