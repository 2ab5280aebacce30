// PX4 extractor: synthetic logs written with the test writer (known values in → quadfdi
// conventions out: frames, Euler signs, motor order, PWM and thrust model, states) and the real
// sample log.
#include "logs/px4_signals.h"
#include "logs/quaternion_check.h"
#include "logs/rate_agreement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/frames.h"
#include "logs/ulog.h"
#include "logs/ulog_writer.h"

namespace quadfdi {
namespace {

using testing::UlogPayload;
using testing::UlogWriter;

using Quat = Quaternion;
// PX4's FRD→NED attitude from its ZYX Euler angles: Rz(ψ)·Ry(θ)·Rx(φ).
Quat px4Quaternion(double roll, double pitch, double yaw) {
  const Quat qz{std::cos(yaw / 2), 0, 0, std::sin(yaw / 2)};
  const Quat qy{std::cos(pitch / 2), 0, std::sin(pitch / 2), 0};
  const Quat qx{std::cos(roll / 2), std::sin(roll / 2), 0, 0};
  return qz * qy * qx;
}

struct Px4Flight {
  std::vector<std::array<double, 3>> ned;    // position per sample [m]
  std::vector<Quat> attitude;                // per sample
  std::vector<std::array<float, 4>> motors;  // actuator_motors.control[0..3], PX4 order
  bool with_motors = true;
  bool with_position = true;
  std::vector<std::array<float, 4>> pwm;     // actuator_outputs.output[0..3]
  std::vector<float> battery_scale;          // battery_status.scale per sample (none: no battery_status), connected
};

std::vector<std::uint8_t> writeFlight(const Px4Flight& f, UlogWriter w = UlogWriter()) {
  testing::formatPx4Estimates(w, false);
  w.format("actuator_motors:uint64_t timestamp;uint64_t timestamp_sample;uint16_t reversible_flags;float[12] control;");
  w.format("actuator_outputs:uint64_t timestamp;uint32_t noutputs;float[16] output;");
  w.format("vehicle_status:uint64_t timestamp;uint8_t arming_state;");
  w.format("vehicle_land_detected:uint64_t timestamp;bool maybe_landed;bool landed;");
  w.format("battery_status:uint64_t timestamp;float voltage_v;float scale;bool connected;");
  if (f.with_position) w.subscribe(0, 0, "vehicle_local_position");
  w.subscribe(0, 1, "vehicle_attitude");
  if (f.with_motors) w.subscribe(0, 2, "actuator_motors");
  w.subscribe(0, 3, "actuator_outputs");
  w.subscribe(0, 4, "vehicle_status");
  w.subscribe(0, 5, "vehicle_land_detected");
  if (!f.battery_scale.empty()) w.subscribe(0, 6, "battery_status");
  for (std::size_t i = 0; i < f.attitude.size(); ++i) {
    const std::uint64_t t = 1000000 + i * 10000;
    if (i < f.battery_scale.size()) w.data(6, UlogPayload().put(t).put(16.0f).put(f.battery_scale[i]).put(true));
    if (f.with_position)
      w.data(0, UlogPayload()
                    .put(t)
                    .put(static_cast<float>(f.ned[i][0]))
                    .put(static_cast<float>(f.ned[i][1]))
                    .put(static_cast<float>(f.ned[i][2]))
                    .put(true));
    const Quat& q = f.attitude[i];
    w.data(1, UlogPayload().put(t + 1).put(static_cast<float>(q.w)).put(static_cast<float>(q.x)).put(static_cast<float>(q.y)).put(static_cast<float>(q.z)));
    if (f.with_motors && i < f.motors.size()) {
      UlogPayload p;
      p.put(t + 2).put(t).put<std::uint16_t>(0);
      for (int k = 0; k < 12; ++k) p.put(k < 4 ? f.motors[i][static_cast<std::size_t>(k)] : NAN);
      w.data(2, p);
    }
    if (i < f.pwm.size()) {
      UlogPayload p;
      p.put(t + 3).put<std::uint32_t>(4);
      for (int k = 0; k < 16; ++k) p.put(k < 4 ? f.pwm[i][static_cast<std::size_t>(k)] : 0.0f);
      w.data(3, p);
    }
  }
  return w.bytes();
}

// The conventions line that starts with `prefix` ("battery: "), or "".
std::string conventionLine(const FlightSignals& s, const std::string& prefix) {
  for (const std::string& c : s.conventions)
    if (c.rfind(prefix, 0) == 0) return c;
  return {};
}

FlightSignals extract(const std::vector<std::uint8_t>& bytes, LogIssue& issue, const Px4SignalOptions& o = {}) {
  DecodedLog log;
  const LogIssue read = readUlog(ByteSpan{bytes.data(), bytes.size()}, log);
  EXPECT_TRUE(read.ok()) << read.message;
  FlightSignals s;
  issue = extractPx4Signals(log, o, s);
  return s;
}

TEST(Px4Signals, FramesEulerSignsAndPosition) {
  Px4Flight f;
  // 0: level; 1: nose down 0.3 rad (negative PX4 pitch); 2: right turn 0.5 rad (positive PX4
  // yaw); 3: right side down 0.2 rad; 4: all three.
  const double px4_euler[5][3] = {{0, 0, 0}, {0, -0.3, 0}, {0, 0, 0.5}, {0.2, 0, 0}, {0.1, 0.2, 0.3}};
  for (const auto& e : px4_euler) {
    f.attitude.push_back(px4Quaternion(e[0], e[1], e[2]));
    f.ned.push_back({1.0, 2.0, -3.0});  // 1 m north, 2 m east, 3 m up
    f.motors.push_back({0.5f, 0.5f, 0.5f, 0.5f});
  }
  LogIssue issue;
  const FlightSignals s = extract(writeFlight(f), issue);
  ASSERT_TRUE(issue.ok()) << issue.message;
  ASSERT_EQ(s.attitude.v.size(), 5u);
  const double tol = 1e-6;
  EXPECT_NEAR(s.attitude.v[1][1], 0.3, tol);   // nose down: positive quadfdi pitch (README)
  EXPECT_NEAR(s.attitude.v[1][0], 0.0, tol);
  EXPECT_NEAR(s.attitude.v[2][2], -0.5, tol);  // turning right (clockwise from above) in z-up: negative yaw
  EXPECT_NEAR(s.attitude.v[3][0], 0.2, tol);   // right side down: positive roll
  EXPECT_NEAR(s.attitude.v[4][0], 0.1, tol);
  EXPECT_NEAR(s.attitude.v[4][1], -0.2, tol);
  EXPECT_NEAR(s.attitude.v[4][2], -0.3, tol);
  ASSERT_EQ(s.position.v.size(), 5u);
  EXPECT_NEAR(s.position.v[0][0], 1.0, tol);   // north
  EXPECT_NEAR(s.position.v[0][1], -2.0, tol);  // west = −east
  EXPECT_NEAR(s.position.v[0][2], 3.0, tol);   // up
  EXPECT_DOUBLE_EQ(s.position.t[0], 1.0);
  EXPECT_DOUBLE_EQ(s.attitude.t[1], 1.010001);
  EXPECT_FALSE(s.conventions.empty());
}

TEST(Px4Signals, ActuatorMotorsInQuadfdiOrder) {
  Px4Flight f;
  f.attitude.assign(2, px4Quaternion(0, 0, 0));
  f.ned = {{0, 0, 0}, {0, 0, 0}};
  // PX4 motors 1 FR, 2 BL, 3 FL, 4 BR.
  f.motors = {{0.1f, 0.2f, 0.3f, 0.4f}, {NAN, 1.5f, -0.2f, 0.5f}};
  LogIssue issue;
  const FlightSignals s = extract(writeFlight(f), issue);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_EQ(s.command_kind, CommandKind::kThrustFraction);
  EXPECT_EQ(s.command.source.topic, "actuator_motors");
  ASSERT_EQ(s.command.v.size(), 2u);
  // quadfdi 1 FR, 2 BR, 3 BL, 4 FL.
  EXPECT_FLOAT_EQ(static_cast<float>(s.command.v[0][0]), 0.1f);
  EXPECT_FLOAT_EQ(static_cast<float>(s.command.v[0][1]), 0.4f);
  EXPECT_FLOAT_EQ(static_cast<float>(s.command.v[0][2]), 0.2f);
  EXPECT_FLOAT_EQ(static_cast<float>(s.command.v[0][3]), 0.3f);
  EXPECT_EQ(s.command.v[1][0], 0.0);  // NaN = disarmed
  EXPECT_EQ(s.command.v[1][2], 1.0);  // clamped
  EXPECT_EQ(s.command.v[1][3], 0.0);  // negative (reverse) clamped
}

// With MC_BAT_SCALE_EN, PX4 multiplies its setpoints by battery_status.scale so that a draining
// battery gives the same thrust: each command is divided back by the scale in force at its time.
// Without the parameter set (PX4's default) the commands stay as logged.
TEST(Px4Signals, BatteryScalingIsUndoneWhereEnabled) {
  Px4Flight f;
  const std::array<float, 4> thrust{0.30f, 0.35f, 0.40f, 0.45f};  // PX4 order, of a full battery's maximum
  for (int i = 0; i < 20; ++i) {
    f.attitude.push_back(px4Quaternion(0, 0, 0));
    f.ned.push_back({0, 0, -1});
    const float scale = 1.0f + 0.01f * static_cast<float>(i);  // the battery draining: 1 → 1.19
    std::array<float, 4> command{};
    for (std::size_t m = 0; m < 4; ++m) command[m] = thrust[m] * scale;
    f.motors.push_back(command);
    if (i % 5 == 0) f.battery_scale.push_back(scale);  // logged now and then: held in between
    else f.battery_scale.push_back(std::nanf(""));     // a row PX4 would not use (NaN scale)
  }
  const auto lineOf = [](const FlightSignals& signals) { return conventionLine(signals, "battery: "); };
  LogIssue issue;
  UlogWriter enabled;
  enabled.paramInt("MC_BAT_SCALE_EN", 1);
  const FlightSignals s = extract(writeFlight(f, enabled), issue);
  ASSERT_TRUE(issue.ok()) << issue.message;
  ASSERT_EQ(s.command.v.size(), 20u);
  const int px4_of_quadfdi[4] = {0, 3, 1, 2};  // quadfdi 1 FR, 2 BR, 3 BL, 4 FL = PX4 1, 4, 2, 3
  for (std::size_t i = 0; i < 20; ++i) {
    // The scale in force: the last one logged at or before the command (commands 2 µs after it).
    const double in_force = 1.0 + 0.01 * static_cast<double>(i - i % 5);
    const double own = 1.0 + 0.01 * static_cast<double>(i);
    for (std::size_t k = 0; k < 4; ++k) {
      const double logged = static_cast<double>(thrust[static_cast<std::size_t>(px4_of_quadfdi[k])] * static_cast<float>(own));
      EXPECT_NEAR(s.command.v[i][k], logged / in_force, 1e-6) << i << " " << k;
    }
  }
  EXPECT_EQ(lineOf(s), "battery: PX4's battery scaling undone (MC_BAT_SCALE_EN 1): each command ÷ battery_status.scale, 1.000 … "
                       "1.150 (4 rows), so the thrust fractions are of a full battery's maximum");
  UlogWriter disabled;
  disabled.paramInt("MC_BAT_SCALE_EN", 0);
  const FlightSignals off = extract(writeFlight(f, disabled), issue);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_FLOAT_EQ(static_cast<float>(off.command.v[19][0]), thrust[0] * 1.19f);
  EXPECT_EQ(lineOf(off), "battery: PX4 does not scale its commands for the battery (MC_BAT_SCALE_EN 0); commands as logged");
  const FlightSignals unknown = extract(writeFlight(f), issue);
  EXPECT_EQ(unknown.command.v[19], off.command.v[19]);
  EXPECT_NE(lineOf(unknown).find("MC_BAT_SCALE_EN not in the log"), std::string::npos);
}

// The control allocation's geometry as PX4 ≥ 1.13 logs it: rotor i at (px, py) [m, FRD], km > 0
// counter-clockwise.
struct Rotor {
  float px, py, km;
};
UlogWriter withGeometry(const std::vector<Rotor>& rotors, int airframe = 0) {
  UlogWriter w;
  w.paramInt("CA_AIRFRAME", airframe);
  w.paramInt("CA_ROTOR_COUNT", static_cast<std::int32_t>(rotors.size()));
  for (std::size_t i = 0; i < rotors.size(); ++i) {
    const std::string r = "CA_ROTOR" + std::to_string(i) + "_";
    w.paramFloat(r + "PX", rotors[i].px).paramFloat(r + "PY", rotors[i].py).paramFloat(r + "KM", rotors[i].km);
  }
  return w;
}

Px4Flight twoLevelSamples() {
  Px4Flight f;
  f.attitude.assign(2, px4Quaternion(0, 0, 0));
  f.ned = {{0, 0, 0}, {0, 0, 0}};
  f.motors = {{0.1f, 0.2f, 0.3f, 0.4f}, {0.1f, 0.2f, 0.3f, 0.4f}};
  return f;
}

TEST(Px4Signals, MotorTableFromTheLogsRotorGeometry) {
  // PX4's own quad X (the gz_x500 airframe's numbers): the same table as the default.
  {
    LogIssue issue;
    const FlightSignals s = extract(
        writeFlight(twoLevelSamples(), withGeometry({{0.13f, 0.22f, 0.05f}, {-0.13f, -0.20f, 0.05f}, {0.13f, -0.22f, -0.05f}, {-0.13f, 0.20f, -0.05f}})),
        issue);
    ASSERT_TRUE(issue.ok()) << issue.message;
    EXPECT_EQ(s.numbering.name, "PX4");
    EXPECT_EQ(s.numbering.autopilot_motor, (std::array<int, 4>{1, 4, 2, 3}));
    EXPECT_FLOAT_EQ(static_cast<float>(s.command.v[0][1]), 0.4f);  // back-right = PX4 motor 4
  }
  // A custom airframe numbered clockwise from the front right: motor i + 1 is quadfdi's i + 1.
  {
    LogIssue issue;
    const FlightSignals s = extract(
        writeFlight(twoLevelSamples(), withGeometry({{0.1f, 0.1f, 0.05f}, {-0.1f, 0.1f, -0.05f}, {-0.1f, -0.1f, 0.05f}, {0.1f, -0.1f, -0.05f}})),
        issue);
    ASSERT_TRUE(issue.ok()) << issue.message;
    EXPECT_EQ(s.numbering.autopilot_motor, (std::array<int, 4>{1, 2, 3, 4}));
    for (std::size_t k = 0; k < 4; ++k) EXPECT_FLOAT_EQ(static_cast<float>(s.command.v[0][k]), 0.1f * static_cast<float>(k + 1));
    bool noted = false;
    for (const std::string& c : s.conventions) noted = noted || c.find("CA_ROTORn_PX/PY") != std::string::npos;
    EXPECT_TRUE(noted);
  }
  // No geometry in the log (PX4 before 1.13): PX4's quad-X table, said so.
  {
    LogIssue issue;
    const FlightSignals s = extract(writeFlight(twoLevelSamples()), issue);
    ASSERT_TRUE(issue.ok()) << issue.message;
    EXPECT_EQ(s.numbering.autopilot_motor, (std::array<int, 4>{1, 4, 2, 3}));
    bool noted = false;
    for (const std::string& c : s.conventions) noted = noted || c.find("PX4's quad-X numbering: the log has no CA_ROTOR_COUNT") != std::string::npos;
    EXPECT_TRUE(noted);
  }
}

TEST(Px4Signals, PropsOutAndPlusFramesAreReadInTurnedAxes) {
  const std::vector<Rotor> x = {{0.13f, 0.22f, 0.05f}, {-0.13f, -0.20f, 0.05f}, {0.13f, -0.22f, -0.05f}, {-0.13f, 0.20f, -0.05f}};
  std::vector<Rotor> props_out = x;
  for (Rotor& r : props_out) r.km = -r.km;
  // A plus frame, front and back counter-clockwise.
  const std::vector<Rotor> plus = {{0.25f, 0.0f, 0.05f}, {-0.25f, 0.0f, 0.05f}, {0.0f, 0.25f, -0.05f}, {0.0f, -0.25f, -0.05f}};
  struct Case {
    const std::vector<Rotor>* rotors;
    int eighths;
    std::array<int, 4> px4_motor_at;  // PX4 motor at quadfdi motor 1..4
    const char* first_position;       // where PX4 motor 1 sits
  };
  const Case cases[] = {{&props_out, 2, {3, 1, 4, 2}, "front-right"}, {&plus, 1, {1, 3, 2, 4}, "front"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.eighths);
    LogIssue issue;
    const FlightSignals s = extract(writeFlight(twoLevelSamples(), withGeometry(*c.rotors)), issue);
    ASSERT_TRUE(issue.ok()) << issue.message;
    EXPECT_EQ(s.numbering.body_turn.eighths, c.eighths);
    EXPECT_EQ(s.numbering.autopilot_motor, c.px4_motor_at);
    for (std::size_t k = 0; k < 4; ++k)  // PX4 motor m's command is 0.1·m
      EXPECT_FLOAT_EQ(static_cast<float>(s.command.v[0][k]), 0.1f * static_cast<float>(c.px4_motor_at[k]));
    int q1 = 0;
    for (int q = 1; q <= 4; ++q) q1 = s.numbering.autopilot_motor[static_cast<std::size_t>(q - 1)] == 1 ? q : q1;
    EXPECT_STREQ(motorPosition(s.numbering, q1), c.first_position);
    bool noted = false;
    for (const std::string& line : s.conventions) noted = noted || line.find("read as the standard quad X in body axes turned") != std::string::npos;
    EXPECT_TRUE(noted);
  }
  // A plus frame whose spins the log does not give: which way to turn is unknown.
  std::vector<Rotor> unknown = plus;
  for (Rotor& r : unknown) r.km = 0.0f;
  LogIssue issue;
  extract(writeFlight(twoLevelSamples(), withGeometry(unknown)), issue);
  EXPECT_NE(issue.message.find("a plus frame with a CA_ROTORn_KM of 0"), std::string::npos) << issue.message;
}

TEST(Px4Signals, FramesTheModelDoesNotDescribeAreRefusedByTheirParameters) {
  const std::vector<Rotor> x = {{0.13f, 0.22f, 0.05f}, {-0.13f, -0.20f, 0.05f}, {0.13f, -0.22f, -0.05f}, {-0.13f, 0.20f, -0.05f}};
  struct Case {
    UlogWriter writer;
    const char* expect;
  };
  std::vector<Rotor> hexa = x;
  hexa.push_back({0.0f, 0.25f, 0.05f});
  hexa.push_back({0.0f, -0.25f, -0.05f});
  std::vector<Rotor> twice = x;
  twice[3] = {0.13f, 0.22f, -0.05f};  // a second front-right rotor
  std::vector<Rotor> half_plus = x;
  half_plus[0] = {0.25f, 0.0f, 0.05f};
  std::vector<Rotor> spin = x;
  spin[2].km = -spin[2].km;  // the front-left rotor spins as its diagonal neighbour does not
  const Case cases[] = {
      {withGeometry(hexa), "CA_ROTOR_COUNT is 6"},
      {withGeometry(x, 2), "CA_AIRFRAME is 2"},
      {withGeometry(half_plus), "PX4 motor 1 (CA_ROTOR0_PX 0.25, CA_ROTOR0_PY 0) is on a body axis and PX4 motor 2"},
      {withGeometry(twice), "and PX4 motor 4 (CA_ROTOR3_PX 0.13"},
      {withGeometry(spin), "PX4 motors 4 and 3 spin clockwise and counter-clockwise"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.expect);
    LogIssue issue;
    extract(writeFlight(twoLevelSamples(), c.writer), issue);
    EXPECT_EQ(issue.status, LogStatus::kCorrupt);
    EXPECT_EQ(issue.topic, "parameters");
    EXPECT_NE(issue.message.find(c.expect), std::string::npos) << issue.message;
  }
  // Asked not to read the geometry: the configured table, whatever the parameters say.
  Px4SignalOptions o;
  o.motor_table_from_parameters = false;
  LogIssue issue;
  const FlightSignals s = extract(writeFlight(twoLevelSamples(), withGeometry(hexa)), issue, o);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_EQ(s.numbering.autopilot_motor, (std::array<int, 4>{1, 4, 2, 3}));
}

TEST(Px4Signals, ActuatorOutputsPwmAndThrustModel) {
  Px4Flight f;
  f.with_motors = false;
  f.attitude.assign(2, px4Quaternion(0, 0, 0));
  f.ned = {{0, 0, 0}, {0, 0, 0}};
  f.pwm = {{1500, 1000, 2000, 1250}, {900, 1100, 1100, 1100}};
  UlogWriter w;
  w.paramFloat("THR_MDL_FAC", 0.5f);
  w.paramInt("PWM_MAIN_MIN", 1000);
  w.paramInt("PWM_MAIN_MAX", 2000);
  w.paramInt("PWM_MAIN_MIN3", 1100);  // per channel (PX4 motor 3 = quadfdi 4) wins
  LogIssue issue;
  const FlightSignals s = extract(writeFlight(f, w), issue);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_EQ(s.command.source.topic, "actuator_outputs");
  ASSERT_EQ(s.command.v.size(), 2u);
  auto thrust = [](double x) { return 0.5 * x + 0.5 * x * x; };
  EXPECT_NEAR(s.command.v[0][0], thrust(0.5), 1e-9);   // PX4 1: 1500 µs
  EXPECT_NEAR(s.command.v[0][1], thrust(0.25), 1e-9);  // PX4 4: 1250 µs
  EXPECT_NEAR(s.command.v[0][2], 0.0, 1e-9);           // PX4 2: 1000 µs
  EXPECT_NEAR(s.command.v[0][3], 1.0, 1e-9);           // PX4 3: 2000 µs
  EXPECT_NEAR(s.command.v[1][0], 0.0, 1e-9);           // disarmed PWM below min: 0
  EXPECT_NEAR(s.command.v[1][3], 0.0, 1e-9);           // 1100 on a 1100–2000 channel
  EXPECT_NEAR(s.command.v[1][1], thrust(0.1), 1e-9);
}

TEST(Px4Signals, ArmedAndLandedStates) {
  Px4Flight f;
  f.attitude.assign(1, px4Quaternion(0, 0, 0));
  f.ned = {{0, 0, 0}};
  f.motors = {{0, 0, 0, 0}};
  std::vector<std::uint8_t> bytes = writeFlight(f);
  UlogWriter tail;
  tail.data(4, UlogPayload().put<std::uint64_t>(100).put<std::uint8_t>(1));
  tail.data(5, UlogPayload().put<std::uint64_t>(100).put(false).put(true));
  tail.data(4, UlogPayload().put<std::uint64_t>(200).put<std::uint8_t>(2));  // armed
  tail.data(5, UlogPayload().put<std::uint64_t>(300).put(true).put(false));  // maybe landed: still landed
  tail.data(5, UlogPayload().put<std::uint64_t>(400).put(false).put(false)); // airborne
  tail.data(5, UlogPayload().put<std::uint64_t>(500).put(false).put(true));  // landed
  tail.data(4, UlogPayload().put<std::uint64_t>(600).put<std::uint8_t>(1));  // disarmed
  bytes.insert(bytes.end(), tail.bytes().begin() + 16, tail.bytes().end());
  LogIssue issue;
  const FlightSignals s = extract(bytes, issue);
  ASSERT_TRUE(issue.ok()) << issue.message;
  ASSERT_EQ(s.states.size(), 5u);
  EXPECT_FALSE(s.states[0].armed);
  EXPECT_TRUE(s.states[0].landed);
  EXPECT_TRUE(s.states[1].armed);
  EXPECT_DOUBLE_EQ(s.states[1].t, 200e-6);
  EXPECT_FALSE(s.states[2].landed);
  EXPECT_DOUBLE_EQ(s.states[2].t, 400e-6);
  EXPECT_TRUE(s.states[3].landed);
  EXPECT_FALSE(s.states[4].armed);
}

TEST(Px4Signals, MissingTopicIsNamed) {
  Px4Flight f;
  f.with_position = false;
  f.attitude.assign(1, px4Quaternion(0, 0, 0));
  f.motors = {{0, 0, 0, 0}};
  LogIssue issue;
  extract(writeFlight(f), issue);
  EXPECT_FALSE(issue.ok());
  EXPECT_EQ(issue.topic, "vehicle_local_position");
  EXPECT_NE(issue.message.find("vehicle_local_position"), std::string::npos);

  f.with_position = true;
  f.with_motors = false;  // and no actuator_outputs rows either
  f.ned = {{0, 0, 0}};
  extract(writeFlight(f), issue);
  EXPECT_FALSE(issue.ok());
  EXPECT_EQ(issue.topic, "actuator_motors");
}

// A 1 s flight at 100 Hz whose estimator resets: its position jumps by a logged shift at row 30
// (x, y) and row 40 (z), by an unlogged one at row 60 (the counter steps by 2), its attitude by a
// logged yaw rotation at row 50 (the counter wraps 255 → 0); rows 80–84 are flagged xy-invalid,
// 85–86 z-invalid. The
// counters start nonzero, with stale shifts from before the log that must not be applied.
struct ResetFlight {
  static constexpr int kRows = 100;
  static double time(int i) { return 1.0 + 0.01 * i; }
  static std::array<double, 3> trueNed(int i) { return {0.5 * time(i), 0.2 * time(i), -2.0}; }
  static double trueYaw(int i) { return 0.1 + 0.2 * time(i); }  // [rad] PX4's (NED) heading
  static constexpr double kYawReset = 0.3;                        // [rad] the attitude reset's rotation
  bool all_invalid = false;

  std::vector<std::uint8_t> write() const {
    UlogWriter w;
    testing::formatPx4Estimates(w, true);
    w.format("actuator_motors:uint64_t timestamp;uint64_t timestamp_sample;uint16_t reversible_flags;float[12] control;");
    w.subscribe(0, 0, "vehicle_local_position");
    w.subscribe(0, 1, "vehicle_attitude");
    w.subscribe(0, 2, "actuator_motors");
    const Quat yaw_reset{std::cos(kYawReset / 2), 0, 0, std::sin(kYawReset / 2)};
    for (int i = 0; i < kRows; ++i) {
      const std::uint64_t t = static_cast<std::uint64_t>(std::llround(time(i) * 1e6));
      std::array<double, 3> p = trueNed(i);
      float dx = 9.0f, dy = 9.0f, dz = 9.0f;  // stale until the first reset in the log
      std::uint8_t xy_counter = 3, z_counter = 0;
      if (i >= 30) {
        p[0] += 3.0;
        p[1] -= 1.0;
        dx = 3.0f;
        dy = -1.0f;
        xy_counter = 4;
      }
      if (i >= 40) {
        p[2] += 0.4;
        dz = 0.4f;
        z_counter = 1;
      }
      if (i >= 60) {  // two resets: the log holds only the last one's shift
        p[0] += 5.0;
        p[1] += 5.0;
        dx = 1.0f;
        dy = 1.0f;
        xy_counter = 6;
      }
      const bool valid = !all_invalid && (i < 80 || i >= 85);
      w.data(0, UlogPayload()
                    .put(t)
                    .put(static_cast<float>(p[0]))
                    .put(static_cast<float>(p[1]))
                    .put(static_cast<float>(p[2]))
                    .put(dx)
                    .put(dy)
                    .put(dz)
                    .put(valid)
                    .put(i != 85 && i != 86)  // z_valid
                    .put(xy_counter)
                    .put(z_counter));
      Quat q = px4Quaternion(0.05, -0.02, trueYaw(i));
      Quat d{0.5, 0.5, 0.5, 0.5};  // stale
      std::uint8_t q_counter = 255;
      if (i >= 50) {
        q = yaw_reset * q;
        d = yaw_reset;
        q_counter = 0;
      }
      UlogPayload a;
      a.put(t + 1);
      for (double v : {q.w, q.x, q.y, q.z, d.w, d.x, d.y, d.z}) a.put(static_cast<float>(v));
      w.data(1, a.put(q_counter));
      UlogPayload m;
      m.put(t + 2).put(t).put<std::uint16_t>(0);
      for (int k = 0; k < 12; ++k) m.put(k < 4 ? 0.5f : NAN);
      w.data(2, m);
    }
    return w.bytes();
  }
};

bool anyContains(const std::vector<std::string>& lines, const std::string& part) {
  for (const std::string& l : lines)
    if (l.find(part) != std::string::npos) return true;
  return false;
}

TEST(Px4Signals, EstimatorResetsAreTakenOutAndInvalidPositionsSkipped) {
  LogIssue issue;
  const FlightSignals s = extract(ResetFlight().write(), issue);
  ASSERT_TRUE(issue.ok()) << issue.message;
  // Position: the true track (north, west, up) until the unlogged reset at row 60, then still
  // continuous from row to row; rows 80–86 absent.
  ASSERT_EQ(s.position.t.size(), static_cast<std::size_t>(ResetFlight::kRows - 7));
  for (std::size_t j = 0; j < s.position.t.size(); ++j) {
    const int i = static_cast<int>(std::lround((s.position.t[j] - 1.0) / 0.01));
    ASSERT_FALSE(i >= 80 && i < 87) << i;
    const std::array<double, 3> ned = ResetFlight::trueNed(i);
    if (i < 60) {
      EXPECT_NEAR(s.position.v[j][0], ned[0], 1e-5) << i;
      EXPECT_NEAR(s.position.v[j][1], -ned[1], 1e-5) << i;
      EXPECT_NEAR(s.position.v[j][2], -ned[2], 1e-5) << i;
    } else if (j > 0 && i != 60 && i != 87) {
      EXPECT_NEAR(s.position.v[j][0] - s.position.v[j - 1][0], 0.005, 1e-5) << i;
      EXPECT_NEAR(s.position.v[j][1] - s.position.v[j - 1][1], -0.002, 1e-5) << i;
    }
  }
  ASSERT_EQ(s.breaks.size(), 1u);
  EXPECT_NEAR(s.breaks[0].t, ResetFlight::time(60), 1e-9);
  EXPECT_NEAR(s.breaks[0].last_before, ResetFlight::time(59), 1e-9);
  EXPECT_TRUE(s.breaks[0].why.find("2 horizontal position resets") != std::string::npos) << s.breaks[0].why;
  // Attitude: PX4's heading without the reset (quadfdi yaw = −ψ), across the counter's wrap.
  ASSERT_EQ(s.attitude.t.size(), static_cast<std::size_t>(ResetFlight::kRows));
  for (int i = 0; i < ResetFlight::kRows; ++i) {
    EXPECT_NEAR(s.attitude.v[static_cast<std::size_t>(i)][2], -ResetFlight::trueYaw(i), 1e-5) << i;
    EXPECT_NEAR(s.attitude.v[static_cast<std::size_t>(i)][0], 0.05, 1e-5) << i;
    EXPECT_NEAR(s.attitude.v[static_cast<std::size_t>(i)][1], 0.02, 1e-5) << i;
  }
  EXPECT_TRUE(anyContains(s.conventions, "1 horizontal position reset (largest 3.16 m) and 1 height reset (largest 0.4 m)"));
  EXPECT_TRUE(anyContains(s.conventions, "1 attitude reset (largest 17.2°)"));
  EXPECT_TRUE(anyContains(s.conventions, "7 of 100 rows skipped: the estimator flagged its position invalid (5 xy_valid false, 2 z_valid false)"));
  EXPECT_TRUE(anyContains(s.conventions, "1 reset counter steps without their shift"));
}

TEST(Px4Signals, APositionNeverValidIsRefusedByItsFlag) {
  ResetFlight f;
  f.all_invalid = true;
  LogIssue issue;
  extract(f.write(), issue);
  EXPECT_EQ(issue.status, LogStatus::kMissingSignal);
  EXPECT_EQ(issue.topic, "vehicle_local_position");
  EXPECT_TRUE(issue.message.find("xy_valid is false in all 100 rows") != std::string::npos) << issue.message;
}

// The real sample log with its position flagged valid: what the rest of the extractor reads.
void flagPositionValid(DecodedLog& log) {
  for (LogTopic& t : log.topics)
    if (t.name == "vehicle_local_position")
      for (const char* flag : {"xy_valid", "z_valid"})
        if (const int i = t.fieldIndex(flag); i >= 0) std::fill(t.columns[static_cast<std::size_t>(i)].begin(), t.columns[static_cast<std::size_t>(i)].end(), 1.0);
}

// A PX4 sample log from ../shared/logs/px4, decoded, with its position flagged valid; false when absent.
bool readRealLog(const std::string& name, DecodedLog& log) {
  std::ifstream in(std::string(QUADFDI_SOURCE_DIR) + "/../shared/logs/px4/" + name, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) return false;
  const LogIssue issue = readUlog(ByteSpan{bytes.data(), bytes.size()}, log);
  EXPECT_TRUE(issue.ok()) << name << ": " << issue.message;
  flagPositionValid(log);
  return issue.ok();
}

TEST(Px4Signals, RealSampleLog) {
  std::ifstream in(std::string(QUADFDI_SOURCE_DIR) + "/../shared/logs/px4/sample_log_small.ulg", std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) GTEST_SKIP() << "../shared/logs/px4/sample_log_small.ulg not found";
  // Flown without horizontal aiding: EKF2 held x, y at 0 and flagged them invalid.
  LogIssue issue;
  extract(bytes, issue);
  EXPECT_EQ(issue.topic, "vehicle_local_position");
  EXPECT_TRUE(issue.message.find("xy_valid is false in all 636 rows") != std::string::npos) << issue.message;
  DecodedLog log;
  ASSERT_TRUE(readUlog(ByteSpan{bytes.data(), bytes.size()}, log).ok());
  flagPositionValid(log);
  FlightSignals s;
  issue = extractPx4Signals(log, Px4SignalOptions{}, s);
  ASSERT_TRUE(issue.ok()) << issue.topic << ": " << issue.message;
  EXPECT_GT(s.position.v.size(), 500u);
  EXPECT_GT(s.attitude.v.size(), 1000u) << s.position.t.back() - s.position.t.front();
  EXPECT_EQ(s.command.source.topic, "actuator_outputs");  // this PX4 predates actuator_motors
  EXPECT_NEAR(static_cast<double>(s.command.t.size() - 1) / (s.command.t.back() - s.command.t.front()), 10.0, 5.0);
  for (const auto& u : s.command.v)
    for (double x : u) ASSERT_TRUE(x >= 0.0 && x <= 1.0);
  bool armed = false;
  for (const FlightStateEvent& e : s.states) armed = armed || e.armed;
  EXPECT_TRUE(armed);
  for (const auto& a : s.attitude.v) {
    ASSERT_LE(std::abs(a[0]), M_PI);
    ASSERT_LE(std::abs(a[1]), M_PI / 2);
  }
}


// The body rates of a real flight (vehicle_angular_velocity, FRD) read into FLU agree with the
// rates the attitude's own change gives through the ZYX kinematics (p = φ̇ − sin θ·ψ̇, q = cos φ·θ̇ +
// sin φ cos θ·ψ̇, r = −sin φ·θ̇ + cos φ cos θ·ψ̇): a sign or frame slip would turn the fit around.
TEST(Px4Signals, RealSampleLogBodyRatesAgreeWithTheAttitudesChange) {
  DecodedLog log;
  if (!readRealLog("sample_log_small.ulg", log)) GTEST_SKIP() << "../shared/logs/px4/sample_log_small.ulg not found";
  FlightSignals s;
  ASSERT_TRUE(extractPx4Signals(log, Px4SignalOptions{}, s).ok());
  ASSERT_EQ(s.rates.source.topic, "vehicle_angular_velocity");
  ASSERT_GT(s.rates.t.size(), 1000u);
  // Per axis, over 50 ms steps of the attitude (a single step's difference is mostly noise): the
  // rate the step gives against the mean measured rate over it.
  std::array<double, 3> cross{}, derived_sq{}, measured_sq{};
  std::size_t j = 0;
  const auto& a = s.attitude;
  for (std::size_t i0 = 0, i = 1; i < a.t.size(); ++i) {
    const double dt = a.t[i] - a.t[i0];
    if (dt < 0.05) continue;
    const std::size_t from = i0;
    i0 = i;
    if (dt > 0.1) continue;  // a hole
    while (j < s.rates.t.size() && s.rates.t[j] < a.t[from]) ++j;
    std::array<double, 3> mean{};
    int n = 0;
    for (std::size_t r = j; r < s.rates.t.size() && s.rates.t[r] <= a.t[i]; ++r, ++n)
      for (std::size_t k = 0; k < 3; ++k) mean[k] += s.rates.v[r][k];
    if (n < 3) continue;
    const double phi = 0.5 * (a.v[i][0] + a.v[from][0]), theta = 0.5 * (a.v[i][1] + a.v[from][1]);
    const double dphi = (a.v[i][0] - a.v[from][0]) / dt, dtheta = (a.v[i][1] - a.v[from][1]) / dt,
                 dpsi = std::remainder(a.v[i][2] - a.v[from][2], 2.0 * M_PI) / dt;
    const std::array<double, 3> derived = {dphi - std::sin(theta) * dpsi,
                                           std::cos(phi) * dtheta + std::sin(phi) * std::cos(theta) * dpsi,
                                           -std::sin(phi) * dtheta + std::cos(phi) * std::cos(theta) * dpsi};
    for (std::size_t k = 0; k < 3; ++k) {
      const double measured = mean[k] / n;
      cross[k] += measured * derived[k];
      derived_sq[k] += derived[k] * derived[k];
      measured_sq[k] += measured * measured;
    }
  }
  for (std::size_t k = 0; k < 3; ++k) {
    const double correlation = cross[k] / std::sqrt(derived_sq[k] * measured_sq[k]);
    std::printf("[ measured ] axis %zu: correlation %.3f, gain %.3f\n", k, correlation, cross[k] / derived_sq[k]);
    EXPECT_GT(correlation, 0.8) << "axis " << k;
  }
}

// PX4 SITL on the ground: EKF2 reset its heading twice (t = 1.244 s and 8.856 s, by 4.1 and 1.2 mrad),
// and vehicle_attitude jumps there by as much: read, the attitude is continuous.
// The rate-agreement check (logs/rate_agreement.h) on real flights, two still hovers (the gyro
// moving 0.006–0.008 rad/s): the gyro as the extractor reads it is the order that fits the
// attitude EKF2 logs, and no warning is given; turned into FRD, that is the order that fits, named.
TEST(Px4Signals, RealLogsRatesFitTheirAttitudeByTheRateCheck) {
  for (const char* name : {"sample_log_small.ulg", "sample_logging_tagged_and_default_params.ulg"}) {
    DecodedLog log;
    if (!readRealLog(name, log)) GTEST_SKIP() << "../shared/logs/px4/" << name << " not found";
    FlightSignals s;
    ASSERT_TRUE(extractPx4Signals(log, Px4SignalOptions{}, s).ok());
    const RateAgreement a = checkRateAgreement(s.attitude, s.rates);
    std::printf("[ real log ] %s: %s\n", name, a.text().c_str());
    EXPECT_NE(a.verdict, RateAgreementVerdict::kDiffers) << a.text();
    EXPECT_EQ(a.axis, (std::array<int, 3>{0, 1, 2})) << a.text();
    EXPECT_EQ(a.sign, (std::array<int, 3>{1, 1, 1})) << a.text();
    for (auto& w : s.rates.v) w = {w[0], -w[1], -w[2]};
    const RateAgreement frd = checkRateAgreement(s.attitude, s.rates);
    std::printf("[ real log ] %s, its rates turned into FRD: %s\n", name, frd.text().c_str());
    EXPECT_EQ(frd.sign, (std::array<int, 3>{1, -1, -1})) << frd.text();
    EXPECT_EQ(frd.verdict, RateAgreementVerdict::kDiffers) << frd.text();
  }
}

// The real logs' attitude read as PX4 writes it (w, x, y, z, body → world) fits their flight, and
// written in each other reading, that reading is named or nothing is (a hover turns little).
TEST(Px4Signals, RealLogsQuaternionFitsTheirFlightInItsReading) {
  for (const char* name : {"sample_log_small.ulg", "sample_logging_tagged_and_default_params.ulg"}) {
    DecodedLog log;
    if (!readRealLog(name, log)) GTEST_SKIP() << "../shared/logs/px4/" << name << " not found";
    FlightSignals s;
    ASSERT_TRUE(extractPx4Signals(log, Px4SignalOptions{}, s).ok());
    for (const QuaternionReading& writer : kQuaternionReadings) {
      SignalSeries<3> attitude = s.attitude;
      for (auto& e : attitude.v) {
        const Quaternion q = quaternionOfColumns(columnsOfQuaternion(quaternionOfEuler({e[0], e[1], e[2]}), writer), QuaternionReading{});
        const EulerZyx read = eulerZyxFromUnitQuaternion(q.w, q.x, q.y, q.z);
        e = {read.roll, read.pitch, read.yaw};
      }
      const QuaternionCheck c = checkQuaternionReading(s.position, attitude, s.rates, QuaternionReading{}, false, {});
      std::printf("[ real log ] %s written %s: %s\n", name, writer.name().c_str(), c.text().c_str());
      if (writer == QuaternionReading{}) {
        EXPECT_EQ(c.verdict, QuaternionVerdict::kAgrees) << c.text();
      } else {
        EXPECT_NE(c.verdict, QuaternionVerdict::kAgrees) << c.text();
        if (c.verdict == QuaternionVerdict::kOtherReading) {
          EXPECT_EQ(c.best, writer) << c.text();
        }
      }
    }
  }
}

// The real logs say what their battery scaling is: their parameter and their battery_status.
TEST(Px4Signals, RealLogsSayWhetherPx4ScaledForTheBattery) {
  for (const char* name : {"sample_log_small.ulg", "sample_logging_tagged_and_default_params.ulg"}) {
    DecodedLog log;
    if (!readRealLog(name, log)) GTEST_SKIP() << "../shared/logs/px4/" << name << " not found";
    FlightSignals s;
    const LogIssue issue = extractPx4Signals(log, Px4SignalOptions{}, s);
    ASSERT_TRUE(issue.ok()) << issue.topic << ": " << issue.message;
    const auto lineOf = [](const FlightSignals& f) { return conventionLine(f, "battery: "); };
    // Both flew with PX4's default: no scaling, so the commands are as logged.
    EXPECT_EQ(lineOf(s), "battery: PX4 does not scale its commands for the battery (MC_BAT_SCALE_EN 0); commands as logged") << name;
    // Their battery_status.scale, read as if scaling had been on: within PX4's own bounds [1, 1.3],
    // and the commands divided by it.
    log.parameters["MC_BAT_SCALE_EN"] = 1.0;
    FlightSignals scaled;
    ASSERT_TRUE(extractPx4Signals(log, Px4SignalOptions{}, scaled).ok());
    const std::string line = lineOf(scaled);
    std::printf("[ real log ] %s read as if MC_BAT_SCALE_EN were 1: %s\n", name, line.c_str());
    double lo = 0.0, hi = 0.0;
    ASSERT_EQ(std::sscanf(line.c_str(), "battery: PX4's battery scaling undone (MC_BAT_SCALE_EN 1): each command ÷ battery_status.scale, %lf … %lf", &lo, &hi), 2) << line;
    EXPECT_GE(lo, 1.0);
    EXPECT_LE(hi, 1.3);
    ASSERT_EQ(scaled.command.v.size(), s.command.v.size());
    for (std::size_t k = 0; k < s.command.v.size(); ++k)
      for (std::size_t m = 0; m < 4; ++m) ASSERT_LE(scaled.command.v[k][m], s.command.v[k][m] + 1e-12);
  }
}

TEST(Px4Signals, RealLogsHeadingResetsAreTakenOut) {
  DecodedLog log;
  if (!readRealLog("sample_logging_tagged_and_default_params.ulg", log))
    GTEST_SKIP() << "../shared/logs/px4/sample_logging_tagged_and_default_params.ulg not found";
  FlightSignals s;
  const LogIssue issue = extractPx4Signals(log, Px4SignalOptions{}, s);
  ASSERT_TRUE(issue.ok()) << issue.topic << ": " << issue.message;
  EXPECT_TRUE(anyContains(s.conventions, "vehicle_attitude: 2 attitude resets")) << s.conventions.size();
  EXPECT_TRUE(s.breaks.empty());
  // Each reset row's yaw step, raw and as read.
  const LogTopic* att = log.find("vehicle_attitude");
  ASSERT_NE(att, nullptr);
  const std::vector<double>& counter = att->columns[static_cast<std::size_t>(att->fieldIndex("quat_reset_counter"))];
  const std::size_t q0 = static_cast<std::size_t>(att->fieldIndex("q[0]"));
  auto rawYaw = [&](std::size_t r) {
    EulerZyx e;
    EXPECT_TRUE(eulerZyxFromQuaternion(att->columns[q0][r], att->columns[q0 + 1][r], att->columns[q0 + 2][r],
                                       att->columns[q0 + 3][r], e));
    return -e.yaw;
  };
  int resets = 0;
  for (std::size_t r = 1; r < att->rows(); ++r) {
    if (counter[r] == counter[r - 1]) continue;
    ++resets;
    const double t0 = static_cast<double>(att->timestamp_us[r - 1]) * 1e-6, t1 = static_cast<double>(att->timestamp_us[r]) * 1e-6;
    const auto at = [&](double t) { return std::lower_bound(s.attitude.t.begin(), s.attitude.t.end(), t) - s.attitude.t.begin(); };
    const std::size_t j0 = static_cast<std::size_t>(at(t0)), j1 = static_cast<std::size_t>(at(t1));
    ASSERT_LT(j1, s.attitude.t.size());
    const double raw_step = std::abs(wrapAngle(rawYaw(r) - rawYaw(r - 1)));
    const double read_step = std::abs(wrapAngle(s.attitude.v[j1][2] - s.attitude.v[j0][2]));
    // Measured: raw steps of 4.2 and 1.4 mrad, read as 0.015 and 0.039 mrad (the vehicle's own motion);
    // the opposite sign convention would double the step instead.
    EXPECT_GT(raw_step, 1e-3) << t1;
    EXPECT_LT(read_step, 0.1 * raw_step) << t1;
  }
  EXPECT_EQ(resets, 2);
}

}  // namespace
}  // namespace quadfdi
