#include "logs/ardupilot_signals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/frames.h"
#include "core/quad_layout.h"
#include "logs/reset_steps.h"

namespace quadfdi {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

// ArduPilot's quad frames (AP_MotorsMatrix::setup_quad_matrix): motor n's arm angle, clockwise
// from the nose in degrees, and its yaw factor's sign (AP_MOTORS_MATRIX_YAW_FACTOR_CCW = +1, CW =
// −1), with FRAME_TYPE from the motor_frame_type enum of AP_Motors_Class.h. Each is read through
// core/quad_layout.h: the Xs with the standard spins as they are, the props-out Xs (H, BF_X_REV)
// in axes turned 90°, the plus frames in axes turned ±45°.
struct ApQuadFrame {
  int frame_type;                  // [-] FRAME_TYPE
  const char* name;                // ArduPilot's frame string
  std::array<int, kMotors> angle;  // [deg] motor n's arm, clockwise from the nose
  std::array<int, kMotors> spin;   // [-] motor n's yaw factor sign: +1 counter-clockwise
};
constexpr ApQuadFrame kApQuadFrames[] = {
    {0, "PLUS", {90, -90, 0, 180}, {1, 1, -1, -1}},
    {1, "X", {45, -135, -45, 135}, {1, 1, -1, -1}},
    {3, "H", {45, -135, -45, 135}, {-1, -1, 1, 1}},
    {6, "PLUSREV", {90, -90, 0, 180}, {-1, -1, 1, 1}},
    {12, "BF_X", {135, 45, -135, -45}, {-1, 1, 1, -1}},
    {13, "DJI_X", {45, -45, -135, 135}, {1, -1, 1, -1}},
    {14, "CW_X", {45, 135, -135, -45}, {1, -1, 1, -1}},
    {18, "BF_X_REV", {135, 45, -135, -45}, {1, -1, -1, 1}},
};

// The frame above with FRAME_TYPE `frame_type`, or nullptr.
const ApQuadFrame* quadFrame(int frame_type) {
  for (const ApQuadFrame& f : kApQuadFrames)
    if (f.frame_type == frame_type) return &f;
  return nullptr;
}

// Why a quad frame type that is not one of the frames above is refused.
const char* refusedQuadFrame(int frame_type) {
  switch (frame_type) {
    case 16: case 17: return "a quad without differential yaw torque (NYT_PLUS, NYT_X); quadfdi's model needs the rotors' yaw moments";
    case 2: case 4: case 5: case 19:
      return "a V, V-tail, A-tail or Y4 quad, whose rotors are not at the corners of a rectangle; quadfdi reads quad X and plus frames";
    default: return "not a quad frame quadfdi reads (FRAME_TYPE 0, 1, 3, 6, 12, 13, 14 and 18: the X and plus frames)";
  }
}

// The layout of `frame` through the one rule every source of a layout shares.
QuadLayout apQuadLayout(const ApQuadFrame& frame, std::string& text) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  std::array<RotorPlacement, kMotors> rotors{};
  for (std::size_t i = 0; i < kMotors; ++i)
    rotors[i] = {std::cos(frame.angle[i] * kDeg), std::sin(frame.angle[i] * kDeg), frame.spin[i]};
  const QuadLayout layout = quadLayout(rotors);
  for (std::size_t i = 0; i < kMotors; ++i)
    text += (i ? ", " : "") + std::to_string(i + 1) + " " + motorPosition(layout.quadfdi_motor_of[i], layout.turn) +
            (frame.spin[i] > 0 ? " CCW" : " CW");
  return layout;
}

// SRV_Channel::k_motor1 = 33 … k_motor4 = 36 (SERVOn_FUNCTION values).
constexpr int kServoFunctionMotor1 = 33;
// RCOU logs outputs C1..C14 (AP_Logger Write_RCOUT).
constexpr int kRcouChannels = 14;

// ArduPilot LogEvent ids (AP_Logger.h).
constexpr int kEvArmed = 10;
constexpr int kEvDisarmed = 11;
constexpr int kEvLandMaybe = 17;
constexpr int kEvLandComplete = 18;
constexpr int kEvNotLanded = 28;

LogIssue missing(const std::string& topic, const std::string& what) {
  return LogIssue{LogStatus::kMissingSignal, 0, topic, what};
}

const double* column(const LogTopic& t, const char* name) {
  const int i = t.fieldIndex(name);
  return i < 0 ? nullptr : t.columns[static_cast<std::size_t>(i)].data();
}

double seconds(std::int64_t us) { return static_cast<double>(us) * 1e-6; }

// Rows of a topic with increasing time, optionally only those whose `filter` column equals
// `value`; returns the row indices and counts the dropped non-increasing ones. Compared in
// seconds, as they are output: beyond 2^53 µs distinct TimeUS can round to the same double.
std::vector<std::size_t> usableRows(const LogTopic& t, const double* filter, double value, std::size_t& dropped) {
  std::vector<std::size_t> rows;
  rows.reserve(t.rows());
  double last = 0.0;
  bool any = false;
  for (std::size_t r = 0; r < t.rows(); ++r) {
    if (filter && filter[r] != value) continue;
    const double s = seconds(t.timestamp_us[r]);
    if (any && !(s > last)) {
      ++dropped;
      continue;
    }
    rows.push_back(r);
    last = s;
    any = true;
  }
  return rows;
}

double param(const DecodedLog& log, const char* name, double fallback, bool* found = nullptr) {
  const auto it = log.parameters.find(name);
  if (found) *found = it != log.parameters.end();
  return it == log.parameters.end() ? fallback : it->second;
}

// nav_filter_status bits the EKF logs as XKF4/NKF4 SS (AP_Nav_Common.h NavFilterStatusBit).
constexpr std::uint32_t kHorizPosRel = 8;  // relative horizontal position valid (false in constant-position mode)
constexpr std::uint32_t kVertPos = 32;     // vertical position valid

// The EKF's own word on the position of one core: XKF4 (EKF3) or NKF4 (EKF2), written by the same
// Log_Write call as XKF1/NKF1 and with the same TimeUS. SS is the solution status; OFN, OFE [m]
// the shift of the latest horizontal position reset (posResetNE = after − before), float since
// Copter 4.0 (older NKF4 logs int8 of unknown scale: not used).
struct EkfStatus {
  std::string name;                 // "XKF4", "NKF4"; empty when the log has none
  std::vector<double> t;            // [s]
  std::vector<std::uint32_t> solution;
  std::vector<double> north, east;  // [m] shift of the latest reset; empty when not logged as float
};

// The topic holding EKF core `core`'s rows of message `name`: with FMTU the log splits the
// message by its instance field C, so that core's own topic; without, the one topic, whose rows
// are then filtered on C. nullptr if the log has neither.
const LogTopic* coreTopic(const DecodedLog& log, const std::string& name, int core) {
  const LogTopic* t = log.find(name, core);
  return t ? t : log.find(name, 0);
}

EkfStatus ekfStatus(const DecodedLog& log, const std::string& name, int core) {
  EkfStatus s;
  const LogTopic* t = coreTopic(log, name, core);
  const double* ss = t ? column(*t, "SS") : nullptr;
  if (!ss) return s;
  s.name = name;
  const double* c = column(*t, "C");
  const int ofn = t->fieldIndex("OFN"), ofe = t->fieldIndex("OFE");
  const bool shifts = ofn >= 0 && ofe >= 0 && t->fields[static_cast<std::size_t>(ofn)].type == FieldType::kFloat &&
                      t->fields[static_cast<std::size_t>(ofe)].type == FieldType::kFloat;
  std::size_t dropped = 0;
  for (std::size_t r : usableRows(*t, c, static_cast<double>(core), dropped)) {
    s.t.push_back(seconds(t->timestamp_us[r]));
    // A value no uint32 holds (a damaged log) flags nothing valid.
    s.solution.push_back(ss[r] >= 0.0 && ss[r] <= 4294967295.0 ? static_cast<std::uint32_t>(ss[r]) : 0u);
    if (shifts) {
      s.north.push_back(t->columns[static_cast<std::size_t>(ofn)][r]);
      s.east.push_back(t->columns[static_cast<std::size_t>(ofe)][r]);
    }
  }
  return s;
}

// The EKF core ArduPilot flew on from `from` [s] on.
struct LaneSpan {
  double from = 0.0;  // [s]
  int core = 0;
};

// The primary core over time, from the status messages' PI (AP_NavEKF3::getPrimaryCoreIndex,
// the same in every core's row); empty when the log does not say.
std::vector<LaneSpan> primaryLanes(const DecodedLog& log, const std::string& status_name) {
  std::vector<std::pair<std::int64_t, int>> said;
  for (const LogTopic& t : log.topics) {
    if (t.name != status_name) continue;
    const double* pi = column(t, "PI");
    if (!pi) continue;
    for (std::size_t r = 0; r < t.rows(); ++r)
      if (pi[r] >= 0.0 && pi[r] <= 255.0) said.emplace_back(t.timestamp_us[r], static_cast<int>(pi[r]));
  }
  std::stable_sort(said.begin(), said.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<LaneSpan> lanes;
  for (const auto& [us, core] : said)
    if (lanes.empty() || lanes.back().core != core) lanes.push_back({lanes.empty() ? -std::numeric_limits<double>::infinity() : seconds(us), core});
  return lanes;
}

// One core's position: the rows its status flags valid, each reset's shift taken out.
struct LanePosition {
  std::vector<double> t;                  // [s]
  std::vector<std::array<double, 3>> v;   // x north, y west, z up [m]
  std::size_t rows = 0, invalid = 0, resets = 0;
  double largest = 0.0;                   // [m] largest reset shift taken out
  // Resets ArduPilot does not log (height; horizontal where OFN, OFE are not usable), found as
  // position steps the EKF's own velocity (VN, VE, VD of the same row) does not explain.
  bool velocity_checked = false, horizontal_checked = false;
  std::size_t unlogged[2] = {0, 0};       // horizontal, height
  double unlogged_largest[2] = {0.0, 0.0};  // [m]
  double unlogged_largest_t[2] = {0.0, 0.0};  // [s]
  double unexplained_left[2] = {0.0, 0.0};  // [m] largest unexplained step left in
};

// [m] The smallest position step taken for a reset ArduPilot does not log. A step left in reads as
// a burst of speed between two EKF rows: a 0.3 m horizontal one put Θ̂ at 0.42 for a window on a
// PX4 log (docs/logs/ulog.md); a tenth of that moves it by less than its noise.
constexpr double kMinPositionReset = 0.05;
// [s] EKF rows further apart (a hole, skipped invalid rows) are not compared.
constexpr double kMaxEkfInterval = 0.2;

// Takes out of `lane` the steps its velocity does not explain: per axis, row k's change less the
// mean of the two rows' velocities times the interval (exact for a constant acceleration).
// `horizontal` false: the height only (the horizontal resets were taken out with OFN, OFE).
void takeOutUnloggedResets(LanePosition& lane, const std::vector<std::array<double, 3>>& velocity, bool horizontal) {
  const std::size_t n = lane.t.size();
  if (n < 2 || velocity.size() != n) return;
  lane.velocity_checked = true;
  lane.horizontal_checked = horizontal;
  for (std::size_t axis = horizontal ? 0 : 2; axis < 3; ++axis) {
    std::vector<double> unexplained(n, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t k = 1; k < n; ++k) {
      const double dt = lane.t[k] - lane.t[k - 1];
      if (dt > 0.0 && dt <= kMaxEkfInterval)
        unexplained[k] = (lane.v[k][axis] - lane.v[k - 1][axis]) - 0.5 * (velocity[k][axis] + velocity[k - 1][axis]) * dt;
    }
    ResetStepRule rule;
    rule.min_step = kMinPositionReset;
    const ResetSteps steps = findResetSteps(unexplained, rule);
    const std::size_t which = axis == 2 ? 1 : 0;
    lane.unlogged[which] += steps.count;
    if (steps.count > 0 && steps.largest > lane.unlogged_largest[which]) {
      lane.unlogged_largest[which] = steps.largest;
      lane.unlogged_largest_t[which] = lane.t[steps.largest_row];
    }
    lane.unexplained_left[which] = std::max(lane.unexplained_left[which], steps.largest_left);
    double shift = 0.0;
    for (std::size_t k = 1; k < n; ++k) {
      shift += steps.step[k];
      lane.v[k][axis] -= shift;
    }
  }
}

// The status rows of core `core` are checked against its position rows: rows it flags without
// a position estimate are skipped (without GPS, flow or beacons EKF3 holds PN, PE in
// constant-position mode), and the shifts of its horizontal position resets are taken out so that
// the track is continuous (every feature is relative to the window or the previous sample: the
// offset does not matter).
LanePosition lanePosition(const DecodedLog& log, const char* pos_name, const std::string& status_name, int core,
                          std::size_t& dropped) {
  LanePosition lane;
  const LogTopic* pos = coreTopic(log, pos_name, core);
  if (!pos) return lane;
  const double* c = column(*pos, "C");
  const double* pn = column(*pos, "PN");
  const double* pe = column(*pos, "PE");
  const double* pd = column(*pos, "PD");
  if (!pn || !pe || !pd) return lane;
  const double* vn = column(*pos, "VN");
  const double* ve = column(*pos, "VE");
  const double* vd = column(*pos, "VD");
  std::vector<std::array<double, 3>> velocity;  // of the rows kept, as lane.v
  const EkfStatus status = ekfStatus(log, status_name, core);
  std::size_t k = 0;
  double north = 0.0, east = 0.0;  // [m] sum of the reset shifts so far
  for (std::size_t r : usableRows(*pos, c, static_cast<double>(core), dropped)) {
    const double t = seconds(pos->timestamp_us[r]);
    ++lane.rows;
    bool valid = true;
    if (!status.t.empty()) {
      // The status row written with this position (same TimeUS), else the latest before it.
      while (k + 1 < status.t.size() && status.t[k + 1] <= t) {
        ++k;
        if (!status.north.empty()) {
          const double dn = status.north[k] - status.north[k - 1], de = status.east[k] - status.east[k - 1];
          if ((dn != 0.0 || de != 0.0) && std::isfinite(status.north[k]) && std::isfinite(status.east[k])) {
            north += status.north[k];
            east += status.east[k];
            lane.largest = std::max(lane.largest, std::hypot(status.north[k], status.east[k]));
            ++lane.resets;
          }
        }
      }
      const std::uint32_t ss = status.solution[k];
      valid = status.t[k] <= t && (ss & kHorizPosRel) != 0 && (ss & kVertPos) != 0;
    }
    if (!valid) {
      ++lane.invalid;
      continue;
    }
    lane.t.push_back(t);
    lane.v.push_back({pn[r] - north, -(pe[r] - east), -pd[r]});
    if (vn && ve && vd) velocity.push_back({vn[r], -ve[r], -vd[r]});
  }
  takeOutUnloggedResets(lane, velocity, status.north.empty());
  return lane;
}

// ArduPilot's battery voltage ratio v over the log (MOTB rows, each kept where it is one), and the
// conventions line that says where it came from.
struct BatteryRatios {
  std::vector<std::int64_t> t;  // [µs] TimeUS of each usable MOTB row
  std::vector<double> v;        // [-] its voltage ratio
  std::string line;
};

// ArduPilot keeps v in [0.6, 1] (MOT_BAT_VOLT_MIN raised to 0.6 × MAX, the resting voltage
// clamped between them) or at 1 without compensation; a little slack for float rounding.
constexpr double kMinVoltageRatio = 0.55, kMaxVoltageRatio = 1.0 + 1e-4;

BatteryRatios batteryRatios(const DecodedLog& log, const ArdupilotThrustMap& map) {
  BatteryRatios out;
  const LogTopic* motb = log.find("MOTB");
  const double* bat_volt = motb ? column(*motb, "BatVolt") : nullptr;
  const double* lift_max = motb ? column(*motb, "LiftMax") : nullptr;
  if (!bat_volt && !lift_max) {
    out.line = "battery: voltage compensation not undone: the log has no MOTB (LOG_BITMASK bit 17, MOTBATT); the thrust fractions "
               "are as on a full battery, so a sagging battery reads as more thrust on every motor";
    return out;
  }
  std::size_t from_lift = 0, refused = 0, dropped = 0;
  for (std::size_t r : usableRows(*motb, nullptr, 0.0, dropped)) {
    double v = bat_volt ? bat_volt[r] : std::nan("");
    if (!(v >= kMinVoltageRatio && v <= kMaxVoltageRatio) && lift_max) {  // BatVolt missing or not a ratio: from LiftMax
      v = map.voltageRatioOfLiftMax(lift_max[r]);
      ++from_lift;
    }
    if (!(v >= kMinVoltageRatio && v <= kMaxVoltageRatio)) {
      ++refused;
      continue;
    }
    out.t.push_back(motb->timestamp_us[r]);
    out.v.push_back(std::min(v, 1.0));
  }
  if (out.v.empty()) {
    out.line = "battery: voltage compensation not undone: no MOTB row holds a voltage ratio in [0.55, 1] (" + std::to_string(refused) +
               " rows)";
    return out;
  }
  const auto [lo, hi] = std::minmax_element(out.v.begin(), out.v.end());
  if (*lo == 1.0) {
    out.line = "battery: MOTB shows no voltage compensation (v = 1 in its " + std::to_string(out.v.size()) +
               " rows: MOT_BAT_VOLT_MAX 0, or no voltage reading); the thrust fractions are as on a full battery";
    return out;
  }
  char buf[128];
  std::snprintf(buf, sizeof buf, "%.3f … %.3f", *lo, *hi);
  out.line = "battery: ArduPilot's voltage compensation undone: each throttle × v before the thrust curve, v = " + std::string(buf) +
             " (MOTB " + (from_lift == out.v.size() ? "LiftMax = v(1 − e) + e·v²" : from_lift > 0 ? "BatVolt, else LiftMax" : "BatVolt") +
             ": the 0.5 Hz filtered resting voltage over MOT_BAT_VOLT_MAX; " + std::to_string(out.v.size()) + " rows" +
             (refused > 0 ? ", " + std::to_string(refused) + " without a ratio in [0.55, 1] left out" : "") +
             "), so the thrust fractions are of a full battery's maximum";
  return out;
}

double usableVoltageRatio(double v) { return v > 0.0 && v <= 1.0 ? v : 1.0; }

// The root x ≥ 0 of e·x² + (1 − e)·x = y: ArduPilot's thrust curve inverted (the throttle of a
// thrust, apply_thrust_curve_and_volt_scaling), and the voltage ratio of a lift_max alike.
double curveRoot(double e, double y) {
  if (std::fabs(e) < 1e-9) return y;
  return ((e - 1.0) + std::sqrt(std::max(0.0, (1.0 - e) * (1.0 - e) + 4.0 * e * y))) / (2.0 * e);
}

}  // namespace

double ArdupilotThrustMap::thrustFraction(double pwm, double voltage_ratio) const {
  const double e = std::clamp(expo, -1.0, 1.0);
  if (!(pwm_max > pwm_min) || !(spin_max > spin_min) || !std::isfinite(pwm)) return 0.0;
  const double a = (pwm - pwm_min) / (pwm_max - pwm_min);
  const double x = std::clamp((a - spin_min) / (spin_max - spin_min), 0.0, 1.0) * usableVoltageRatio(voltage_ratio);
  return std::clamp((1.0 - e) * x + e * x * x, 0.0, 1.0);
}

double ArdupilotThrustMap::pwmFor(double thrust_fraction, double voltage_ratio) const {
  // thrust_fraction = lift_max · the controller's demand: apply_thrust_curve_and_volt_scaling's
  // root of e·x² + (1 − e)·x = lift_max·thrust, divided by the voltage ratio.
  const double x = curveRoot(std::clamp(expo, -1.0, 1.0), std::clamp(thrust_fraction, 0.0, 1.0));
  const double throttle = std::clamp(x / usableVoltageRatio(voltage_ratio), 0.0, 1.0);
  const double actuator = spin_min + (spin_max - spin_min) * throttle;  // thrust_to_actuator
  return pwm_min + (pwm_max - pwm_min) * actuator;                      // output_to_pwm
}

double ArdupilotThrustMap::voltageRatioOfLiftMax(double lift_max) const { return curveRoot(std::clamp(expo, -1.0, 1.0), lift_max); }

LogIssue extractArdupilotSignals(const DecodedLog& log, const ArdupilotSignalOptions& options, FlightSignals& out) {
  out = FlightSignals{};
  out.command_kind = CommandKind::kThrustFraction;

  // Frame: quad X only, where the log says.
  bool have = false;
  const double frame_class = param(log, "FRAME_CLASS", 1.0, &have);
  if (have && frame_class != 1.0)
    return LogIssue{LogStatus::kCorrupt, 0, "PARM", "FRAME_CLASS is " + shortNumber(frame_class) + ", not 1 (quad); only quad X is supported"};
  const double frame_type = param(log, "FRAME_TYPE", 1.0, &have);
  const int type = frame_type >= 0.0 && frame_type <= 255.0 && frame_type == std::floor(frame_type) ? static_cast<int>(frame_type) : -1;
  const ApQuadFrame* frame = quadFrame(type);
  if (!frame) return LogIssue{LogStatus::kCorrupt, 0, "PARM", "FRAME_TYPE is " + shortNumber(frame_type) + ": " + refusedQuadFrame(type)};
  std::string layout_text;
  const QuadLayout layout = apQuadLayout(*frame, layout_text);
  if (layout.status != QuadLayoutStatus::kOk)  // every frame of the table is an X or a plus (test ArdupilotSignals)
    return LogIssue{LogStatus::kCorrupt, 0, "PARM", "FRAME_TYPE " + std::to_string(type) + ": the frame table is not a quad"};
  out.conventions.push_back("frame: ArduPilot quad " + std::string(frame->name) + " (FRAME_CLASS 1, FRAME_TYPE " +
                            std::to_string(type) + (have ? ", from the log)" : ", assumed: not in the log)") +
                            bodyTurnNote(layout));
  out.numbering.name = "ArduPilot";
  out.numbering.autopilot_motor = layout.rotor_of_quadfdi_motor;
  out.numbering.body_turn = layout.turn;
  out.conventions.push_back("time: TimeUS [µs since boot] → t = TimeUS·1e-6 s");

  // Attitude.
  const LogTopic* att = log.find("ATT");
  if (!att) return missing("ATT", "no ATT message: the attitude (Roll, Pitch, Yaw) is needed; LOG_BITMASK bit ATTITUDE_FAST or ATTITUDE_MED");
  const double* roll = column(*att, "Roll");
  const double* pitch = column(*att, "Pitch");
  const double* yaw = column(*att, "Yaw");
  if (!roll || !pitch || !yaw) return missing("ATT", "ATT has no Roll, Pitch and Yaw fields");
  std::size_t dropped = 0;
  for (std::size_t r : usableRows(*att, nullptr, 0.0, dropped)) {
    out.attitude.t.push_back(seconds(att->timestamp_us[r]));
    out.attitude.v.push_back({roll[r] * kDegToRad, -pitch[r] * kDegToRad, wrapAngle(-yaw[r] * kDegToRad)});
  }
  out.attitude.source = {"ATT", "Roll,Pitch,Yaw", "deg → rad; NED/FRD → x north, y west, z up / FLU: roll = Roll, pitch = −Pitch, yaw = −Yaw"};
  out.conventions.push_back("attitude: ATT Roll, Pitch, Yaw [deg] (NED/FRD, pitch nose-up, yaw clockwise from north) → "
                            "roll = Roll, pitch = −Pitch, yaw = −Yaw wrapped to (−π, π] [rad] (world x north, y west, z up; body FLU)");

  // Body rates (optional): RATE R, P, Y, the gyro the rate controller flies on (AC_AttitudeControl
  // Write_Rate: degrees of ahrs.get_gyro_latest(), deg/s, FRD), logged with ATT. Where a log has
  // no RATE (LOG_BITMASK without ATTITUDE_FAST/MED), the first IMU's GyrX, GyrY, GyrZ
  // (AP_InertialSensor Write_IMU: rad/s, FRD; instance I = 0, the others' rows left out; older
  // logs name the second and third IMU2, IMU3), which is the gyro before the rate loop's filter.
  if (const LogTopic* rate = log.find("RATE")) {
    const double* p = column(*rate, "R");
    const double* q = column(*rate, "P");
    const double* r = column(*rate, "Y");
    if (p && q && r) {
      std::size_t rate_dropped = 0;
      for (std::size_t i : usableRows(*rate, nullptr, 0.0, rate_dropped)) {
        if (!std::isfinite(p[i]) || !std::isfinite(q[i]) || !std::isfinite(r[i])) continue;  // a sample the reader would drop
        out.rates.t.push_back(seconds(rate->timestamp_us[i]));
        out.rates.v.push_back({p[i] * kDegToRad, -q[i] * kDegToRad, -r[i] * kDegToRad});
      }
      out.rates.source = {"RATE", "R,P,Y", "deg/s → rad/s; FRD → FLU: (R, −P, −Y)"};
    }
  }
  if (out.rates.t.empty()) {
    if (const LogTopic* imu = coreTopic(log, "IMU", 0)) {
      const double* p = column(*imu, "GyrX");
      const double* q = column(*imu, "GyrY");
      const double* r = column(*imu, "GyrZ");
      if (p && q && r) {
        out.rates.v.clear();
        std::size_t imu_dropped = 0;
        for (std::size_t i : usableRows(*imu, column(*imu, "I"), 0.0, imu_dropped)) {
          if (!std::isfinite(p[i]) || !std::isfinite(q[i]) || !std::isfinite(r[i])) continue;
          out.rates.t.push_back(seconds(imu->timestamp_us[i]));
          out.rates.v.push_back({p[i], -q[i], -r[i]});
        }
        out.rates.source = {"IMU", "GyrX,GyrY,GyrZ (I = 0)", "rad/s; FRD → FLU: (GyrX, −GyrY, −GyrZ)"};
      }
    }
  }

  // Position.
  const char* pos_name = nullptr;
  for (const char* name : {"XKF1", "NKF1"}) {
    const LogTopic* t = coreTopic(log, name, std::max(options.ekf_core, 0));
    if (t && column(*t, "PN") && column(*t, "PE") && column(*t, "PD")) {
      pos_name = name;
      break;
    }
  }
  if (pos_name) {
    // The lane (EKF core) whose position is read: the one given, else the one ArduPilot flew on,
    // which its status messages name (PI) and which may change in flight (a lane switch).
    const std::string status_name = std::string(pos_name).substr(0, 3) + "4";
    std::vector<LaneSpan> lanes;
    std::string lane_note;
    if (options.ekf_core >= 0) {
      lanes.push_back({-std::numeric_limits<double>::infinity(), options.ekf_core});
      lane_note = "EKF core " + std::to_string(options.ekf_core) + ", as given";
    } else {
      lanes = primaryLanes(log, status_name);
      if (lanes.empty()) {
        lanes.push_back({-std::numeric_limits<double>::infinity(), 0});
        lane_note = "EKF core 0: the log has no " + status_name + " PI naming the primary core (--ekf-core chooses one)";
      } else {
        lane_note = "the EKF's primary core (" + status_name + " PI): core " + std::to_string(lanes[0].core);
        for (std::size_t i = 1; i < lanes.size(); ++i) {
          char at[32];
          std::snprintf(at, sizeof at, "%.3f", lanes[i].from);
          lane_note += ", core " + std::to_string(lanes[i].core) + " from " + at + " s";
        }
        if (lanes.size() > 1)
          lane_note += "; the cores' positions differ, so the flight is cut at each switch";
        else
          lane_note += " throughout";
      }
    }
    // Each lane's whole track once, then the stretch of it that was primary.
    std::map<int, LanePosition> tracks;
    std::size_t rows = 0, invalid = 0, resets = 0;
    double largest = 0.0;
    bool velocity_checked = false, horizontal_checked = false;
    std::size_t unlogged[2] = {0, 0};
    double unlogged_largest[2] = {0.0, 0.0}, unlogged_largest_t[2] = {0.0, 0.0}, unexplained_left[2] = {0.0, 0.0};
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      auto it = tracks.find(lanes[i].core);
      if (it == tracks.end()) {
        it = tracks.emplace(lanes[i].core, lanePosition(log, pos_name, status_name, lanes[i].core, dropped)).first;
        const LanePosition& lane = it->second;
        rows += lane.rows;
        invalid += lane.invalid;
        resets += lane.resets;
        largest = std::max(largest, lane.largest);
        velocity_checked = velocity_checked || lane.velocity_checked;
        horizontal_checked = horizontal_checked || lane.horizontal_checked;
        for (int a = 0; a < 2; ++a) {
          unlogged[a] += lane.unlogged[a];
          if (lane.unlogged_largest[a] > unlogged_largest[a]) {
            unlogged_largest[a] = lane.unlogged_largest[a];
            unlogged_largest_t[a] = lane.unlogged_largest_t[a];
          }
          unexplained_left[a] = std::max(unexplained_left[a], lane.unexplained_left[a]);
        }
      }
      const LanePosition& lane = it->second;
      const double until = i + 1 < lanes.size() ? lanes[i + 1].from : std::numeric_limits<double>::infinity();
      bool first = true;
      for (std::size_t r = 0; r < lane.t.size(); ++r) {
        if (lane.t[r] < lanes[i].from || lane.t[r] >= until) continue;
        if (!out.position.t.empty() && lane.t[r] <= out.position.t.back()) continue;
        if (first && i > 0 && !out.position.t.empty())
          out.breaks.push_back({lane.t[r], out.position.t.back(),
                                status_name + ": the EKF's primary core switched to core " + std::to_string(lanes[i].core)});
        first = false;
        out.position.t.push_back(lane.t[r]);
        out.position.v.push_back(lane.v[r]);
      }
    }
    std::string cores;
    for (const auto& [core, lane] : tracks) cores += (cores.empty() ? "" : ", ") + std::to_string(core);
    const std::string of_cores = std::string(tracks.size() == 1 ? "EKF core " : "EKF cores ") + cores;
    if (out.position.empty() && invalid > 0)
      return missing(pos_name, std::string(pos_name) + ": " + status_name + " SS flags no position estimate in all " +
                                   std::to_string(invalid) + " rows of " + of_cores +
                                   " (relative horizontal position and vertical position valid, bits 3 and 5): "
                                   "without GPS, optical flow or beacons the EKF holds PN and PE, it does not "
                                   "measure them, and the detector needs the vehicle's measured motion");
    if (out.position.empty()) return missing(pos_name, std::string(pos_name) + " has no rows of " + of_cores);
    if (invalid > 0)
      out.conventions.push_back("position: " + std::to_string(invalid) + " of " + std::to_string(rows) + " " + pos_name +
                                " rows skipped: " + status_name +
                                " SS flags no position estimate there; nothing is evaluated across the holes they leave");
    if (resets > 0) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "position: %zu horizontal position reset%s (largest %.3g m) taken out with %s OFN, OFE, "
                    "so the track is continuous", resets, resets == 1 ? "" : "s", largest, status_name.c_str());
      out.conventions.push_back(buf);
    }
    {
      // The resets ArduPilot does not log (EKF3 ResetHeight on a change of height source; a
      // horizontal reset in a log without usable OFN, OFE), found with the EKF's own velocity.
      char buf[400];
      const char* which = horizontal_checked ? "height or horizontal" : "height";
      if (!velocity_checked)
        std::snprintf(buf, sizeof buf, "position: not checked for resets ArduPilot does not log (height resets): %s has no VN, VE, VD",
                      pos_name);
      else if (unlogged[0] + unlogged[1] == 0)
        std::snprintf(buf, sizeof buf, "position: each %s row checked against the EKF's own velocity (VN, VE, VD): no %s reset "
                      "ArduPilot does not log (largest step the velocity does not explain %.2g m)",
                      pos_name, which, std::max(unexplained_left[0], unexplained_left[1]));
      else {
        std::string found;
        for (int a : {1, 0}) {
          if (unlogged[a] == 0) continue;
          char part[120];
          std::snprintf(part, sizeof part, "%zu %s step%s (largest %.3g m at %.3f s)", unlogged[a], a == 1 ? "height" : "horizontal",
                        unlogged[a] == 1 ? "" : "s", unlogged_largest[a], unlogged_largest_t[a]);
          found += (found.empty() ? "" : " and ") + std::string(part);
        }
        std::snprintf(buf, sizeof buf, "position: %s that the EKF's own velocity (VN, VE, VD) does not explain — resets ArduPilot "
                      "does not log — taken out, so the track is continuous", found.c_str());
      }
      out.conventions.push_back(buf);
    }
    out.position.source = {pos_name, "PN,PE,PD", "NED → x north, y west, z up: (PN, −PE, −PD), " + of_cores};
    out.conventions.push_back(std::string("position: ") + pos_name + " PN, PE, PD [m] (NED) of " + lane_note +
                              " → (x, y, z) = (PN, −PE, −PD)");
  } else if (const LogTopic* p = log.find("POS"); p && column(*p, "Lat") && column(*p, "Lng") && column(*p, "Alt")) {
    const double* lat = column(*p, "Lat");
    const double* lng = column(*p, "Lng");
    const double* alt = column(*p, "Alt");
    const std::vector<std::size_t> rows = usableRows(*p, nullptr, 0.0, dropped);
    if (rows.empty()) return missing("POS", "POS has no rows");
    const double lat0 = lat[rows[0]], lng0 = lng[rows[0]], alt0 = alt[rows[0]];
    const double coslat = std::cos(lat0 * kDegToRad);
    for (std::size_t r : rows) {
      const double north = (lat[r] - lat0) * kDegToRad * options.earth_radius;
      const double east = (lng[r] - lng0) * kDegToRad * options.earth_radius * coslat;
      out.position.t.push_back(seconds(p->timestamp_us[r]));
      out.position.v.push_back({north, -east, alt[r] - alt0});
    }
    out.position.source = {"POS", "Lat,Lng,Alt", "flat earth around the first fix → x north, y west, z up"};
    out.conventions.push_back("position: POS Lat, Lng [deg], Alt [m] on a flat earth around the first fix (no EKF XKF1/NKF1 "
                              "in the log) → x north, y west, z up from the first fix");
  } else {
    return missing("XKF1", "no XKF1 (EKF3), NKF1 (EKF2) or POS message: the position is needed; LOG_BITMASK bit NTUN/EKF");
  }

  // Commands.
  const LogTopic* rcou = log.find("RCOU");
  if (!rcou) return missing("RCOU", "no RCOU message: the motor outputs are needed; LOG_BITMASK bit RCOUT");
  std::array<int, kMotors> channel{};
  std::string channel_note;
  for (int k = 0; k < kMotors; ++k) {
    const int ap_motor = layout.rotor_of_quadfdi_motor[static_cast<std::size_t>(k)];
    int ch = ap_motor;  // default SERVOn_FUNCTION: output n = motor n
    for (int n = 1; n <= kRcouChannels; ++n) {
      bool found = false;
      const double f = param(log, ("SERVO" + std::to_string(n) + "_FUNCTION").c_str(), 0.0, &found);
      if (found && f == static_cast<double>(kServoFunctionMotor1 + ap_motor - 1)) {
        ch = n;
        break;
      }
    }
    channel[static_cast<std::size_t>(k)] = ch;
    channel_note += (k ? ", " : "") + std::string("quadfdi ") + std::to_string(k + 1) + " ← AP motor " +
                    std::to_string(ap_motor) + " (output " + std::to_string(ch) + ")";
  }
  // Output n is labelled Cn (Copter 3.6 on), Chn (3.3–3.5) or Chann (3.2 and before).
  std::array<const double*, kMotors> pwm{};
  std::string pwm_fields;
  for (int k = 0; k < kMotors; ++k) {
    const std::string n = std::to_string(channel[static_cast<std::size_t>(k)]);
    std::string label;
    for (const char* prefix : {"C", "Ch", "Chan"})
      if (!pwm[static_cast<std::size_t>(k)]) pwm[static_cast<std::size_t>(k)] = column(*rcou, (label = prefix + n).c_str());
    if (!pwm[static_cast<std::size_t>(k)]) return missing("RCOU", "RCOU has no field C" + n + " (nor Ch" + n + ", Chan" + n + ")");
    pwm_fields += (k ? "," : "") + label;
  }

  ArdupilotThrustMap map;
  bool pmin_found = false, pmax_found = false, rc_found = false;
  map.pwm_min = param(log, "MOT_PWM_MIN", options.pwm_min, &pmin_found);
  map.pwm_max = param(log, "MOT_PWM_MAX", options.pwm_max, &pmax_found);
  std::string pwm_source = pmin_found && pmax_found ? "MOT_PWM_MIN/MAX from the log" : "MOT_PWM_MIN/MAX defaults";
  if (map.pwm_min <= 0.0 || map.pwm_max <= 0.0) {  // older firmware: 0 = the throttle channel's range
    map.pwm_min = param(log, "RC3_MIN", options.rc3_min, &rc_found);
    map.pwm_max = param(log, "RC3_MAX", options.rc3_max);
    pwm_source = std::string("MOT_PWM_MIN/MAX are 0: RC3_MIN/MAX ") + (rc_found ? "from the log" : "defaults");
  }
  bool smin_found = false, smax_found = false, expo_found = false;
  map.spin_min = param(log, "MOT_SPIN_MIN", options.spin_min, &smin_found);
  map.spin_max = param(log, "MOT_SPIN_MAX", options.spin_max, &smax_found);
  map.expo = param(log, "MOT_THST_EXPO", options.thrust_expo, &expo_found);
  if (!(map.pwm_max > map.pwm_min) || !(map.spin_max > map.spin_min) || !std::isfinite(map.expo))
    return LogIssue{LogStatus::kCorrupt, 0, "PARM",
                    "motor output range unusable: PWM " + shortNumber(map.pwm_min) + ".." + shortNumber(map.pwm_max) + ", spin " +
                        shortNumber(map.spin_min) + ".." + shortNumber(map.spin_max) + ", expo " + shortNumber(map.expo)};
  // The battery's voltage ratio ArduPilot compensates its throttle for (MOTB; LOG_BITMASK bit 17):
  // each RCOU row's from the last MOTB row at or before it (the first before any).
  const BatteryRatios battery = batteryRatios(log, map);
  std::size_t motb_row = 0;
  for (std::size_t r : usableRows(*rcou, nullptr, 0.0, dropped)) {
    while (motb_row + 1 < battery.t.size() && battery.t[motb_row + 1] <= rcou->timestamp_us[r]) ++motb_row;
    const double v = battery.v.empty() ? 1.0 : battery.v[motb_row];
    std::array<double, kMotors> u{};
    for (std::size_t k = 0; k < u.size(); ++k) u[k] = map.thrustFraction(pwm[k][r], v);
    out.command.t.push_back(seconds(rcou->timestamp_us[r]));
    out.command.v.push_back(u);
  }
  out.command.source = {"RCOU", pwm_fields,
                        std::string("PWM → thrust fraction (MOT_THST_EXPO curve inverted") +
                            (battery.v.empty() ? "" : ", battery voltage compensation undone with MOTB") + "); AP quad-X order → quadfdi"};
  out.conventions.push_back("motors: ArduPilot quad " + std::string(frame->name) + " (" + layout_text +
                            ") → quadfdi (1 FR, 2 BR, 3 BL, 4 FL): " + channel_note);
  out.conventions.push_back("commands: RCOU PWM [µs] → a = (pwm − " + shortNumber(map.pwm_min) + ")/(" + shortNumber(map.pwm_max) + " − " +
                            shortNumber(map.pwm_min) + ") (" + pwm_source + "), x = (a − " + shortNumber(map.spin_min) + ")/(" +
                            shortNumber(map.spin_max) + " − " + shortNumber(map.spin_min) + ") in [0, 1] (MOT_SPIN_MIN/MAX " +
                            (smin_found && smax_found ? "from the log" : "defaults") + "), thrust fraction = (1 − e)x + e·x², e = " +
                            shortNumber(std::clamp(map.expo, -1.0, 1.0)) + " (MOT_THST_EXPO " + (expo_found ? "from the log" : "default") +
                            ")");
  out.conventions.push_back(battery.line);

  // Armed / landed states.
  struct Change {
    std::int64_t t;
    int kind;  // 0 armed, 1 disarmed, 2 landed, 3 not landed
  };
  std::vector<Change> changes;
  if (const LogTopic* ev = log.find("EV")) {
    if (const double* id = column(*ev, "Id")) {
      for (std::size_t r = 0; r < ev->rows(); ++r) {
        // Compared as doubles: a damaged FMT may make Id a float, NaN or huge.
        const double v = id[r];
        const int i = v >= 0.0 && v <= 255.0 ? static_cast<int>(v) : -1;
        const int kind = i == kEvArmed ? 0 : i == kEvDisarmed ? 1 : (i == kEvLandMaybe || i == kEvLandComplete) ? 2 : i == kEvNotLanded ? 3 : -1;
        if (kind >= 0) changes.push_back({ev->timestamp_us[r], kind});
      }
    }
  }
  if (const LogTopic* arm = log.find("ARM")) {
    if (const double* state = column(*arm, "ArmState"))
      for (std::size_t r = 0; r < arm->rows(); ++r) changes.push_back({arm->timestamp_us[r], state[r] != 0.0 ? 0 : 1});
  }
  std::stable_sort(changes.begin(), changes.end(), [](const Change& a, const Change& b) { return a.t < b.t; });
  bool armed = false, landed = true;
  for (const Change& c : changes) {
    const bool was_armed = armed, was_landed = landed;
    if (c.kind == 0) armed = true;
    if (c.kind == 1) armed = false;
    if (c.kind == 2) landed = true;
    if (c.kind == 3) landed = false;
    if (armed != was_armed || landed != was_landed) out.states.push_back({seconds(c.t), armed, landed});
  }
  if (!changes.empty())
    out.conventions.push_back("states: EV 10 ARMED, 11 DISARMED, 17/18 LAND_COMPLETE(_MAYBE) → landed, 28 NOT_LANDED, ARM ArmState; "
                              "disarmed and landed before the first event");
  if (dropped > 0) out.conventions.push_back("dropped " + std::to_string(dropped) + " rows whose TimeUS did not increase");
  return {};
}

}  // namespace quadfdi
