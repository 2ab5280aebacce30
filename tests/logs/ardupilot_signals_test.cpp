// The ArduPilot extractor (src/logs/ardupilot_signals.h) on synthetic DataFlash logs: known
// NED/FRD trajectories and motor outputs in, quadfdi signals out.
#include "logs/ardupilot_signals.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "logs/dataflash.h"
#include "logs/dataflash_writer.h"

using namespace quadfdi;
using quadfdi::test::centi;
using quadfdi::test::DataflashWriter;
using quadfdi::test::DfValue;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

using Mat = std::array<std::array<double, 3>, 3>;

Mat mul(const Mat& a, const Mat& b) {
  Mat c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}
Mat rx(double a) { return {{{1, 0, 0}, {0, std::cos(a), -std::sin(a)}, {0, std::sin(a), std::cos(a)}}}; }
Mat ry(double a) { return {{{std::cos(a), 0, std::sin(a)}, {0, 1, 0}, {-std::sin(a), 0, std::cos(a)}}}; }
Mat rz(double a) { return {{{std::cos(a), -std::sin(a), 0}, {std::sin(a), std::cos(a), 0}, {0, 0, 1}}}; }
// ZYX Euler: body → world, the same formula in NED/FRD (ArduPilot) and in quadfdi's frames.
Mat zyx(double roll, double pitch, double yaw) { return mul(rz(yaw), mul(ry(pitch), rx(roll))); }

// ArduPilot's message layouts (LogStructure.h of Copter 4.x; only the fields read matter).
constexpr std::uint8_t kAtt = 30, kXkf1 = 31, kRcou = 32, kEv = 33, kArm = 34;

DataflashWriter apLog(bool with_fmtu = true) {
  DataflashWriter w;
  w.fmt(kAtt, "ATT", "QccccCCCCB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
  w.fmt(kXkf1, "XKF1", "QBccCfffffffccce", "TimeUS,C,Roll,Pitch,Yaw,VN,VE,VD,dPD,PN,PE,PD,GX,GY,GZ,OH");
  w.fmt(kRcou, "RCOU", "QHHHHHHHHHHHHHH", "TimeUS,C1,C2,C3,C4,C5,C6,C7,C8,C9,C10,C11,C12,C13,C14");
  w.fmt(kEv, "EV", "QB", "TimeUS,Id");
  w.fmt(kArm, "ARM", "QBIBB", "TimeUS,ArmState,ArmChecks,Forced,Method");
  if (with_fmtu) {
    w.unit(0, '#', "instance");
    w.fmtu(0, kXkf1, "s#ddhnnnnmmmkkkm", "F-BBB0000000BBBB");
  }
  return w;
}

void att(DataflashWriter& w, std::uint64_t t, double roll_deg, double pitch_deg, double yaw_deg) {
  w.write(kAtt, {t, 0, centi(roll_deg), 0, centi(pitch_deg), 0, centi(yaw_deg), 0, 0, 3});
}
void xkf1(DataflashWriter& w, std::uint64_t t, unsigned core, double pn, double pe, double pd) {
  w.write(kXkf1, {t, core, 0, 0, 0, 0.0, 0.0, 0.0, 0.0, pn, pe, pd, 0, 0, 0, 0});
}
void rcou(DataflashWriter& w, std::uint64_t t, const std::array<int, 4>& c) {
  w.write(kRcou, {t, c[0], c[1], c[2], c[3], 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
}

LogIssue extract(const DataflashWriter& w, FlightSignals& s, const ArdupilotSignalOptions& o = {}) {
  DecodedLog log;
  const LogIssue read = readDataflash(ByteSpan{w.bytes.data(), w.bytes.size()}, log);
  EXPECT_TRUE(read.ok()) << read.message;
  EXPECT_TRUE(log.warnings.empty());
  return extractArdupilotSignals(log, o, s);
}

// A minimal complete log: one row of each.
DataflashWriter completeLog() {
  DataflashWriter w = apLog();
  att(w, 1000, 0, 0, 0);
  xkf1(w, 1000, 0, 0, 0, 0);
  rcou(w, 1000, {1000, 1000, 1000, 1000});
  return w;
}

}  // namespace

TEST(ArdupilotSignals, AttitudeIsTheSamePhysicalRotation) {
  const double angles[][3] = {{0, 0, 0},      {10, 0, 0},     {0, 10, 0},     {0, 0, 30},    {25, -15, 120},
                              {-40, 30, 250}, {5, 60, 359.5}, {170, -5, 10}, {-90, 45, 180}, {33.33, -12.5, 0.01}};
  DataflashWriter w = apLog();
  std::uint64_t t = 1000;
  for (const auto& a : angles) {
    att(w, t, a[0], a[1], a[2]);
    xkf1(w, t, 0, 0, 0, 0);
    rcou(w, t, {1000, 1000, 1000, 1000});
    t += 2500;
  }
  FlightSignals s;
  ASSERT_TRUE(extract(w, s).ok());
  ASSERT_EQ(s.attitude.v.size(), std::size(angles));
  // T maps NED to (north, west, up) and FRD to FLU: the same physical rotation is T·R_NED·T.
  const Mat T = {{{1, 0, 0}, {0, -1, 0}, {0, 0, -1}}};
  for (std::size_t k = 0; k < std::size(angles); ++k) {
    SCOPED_TRACE(k);
    const double roll = static_cast<double>(centi(angles[k][0])) * 0.01 * kDeg;
    const double pitch = static_cast<double>(centi(angles[k][1])) * 0.01 * kDeg;
    const double yaw = static_cast<double>(centi(angles[k][2])) * 0.01 * kDeg;
    const Mat expected = mul(T, mul(zyx(roll, pitch, yaw), T));
    const auto& q = s.attitude.v[k];
    const Mat got = zyx(q[0], q[1], q[2]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(got[i][j], expected[i][j], 1e-12) << i << "," << j;
    EXPECT_GT(q[2], -kPi - 1e-12);
    EXPECT_LE(q[2], kPi + 1e-12);
  }
  // The physical meaning, spelled out: nose up 10° in ArduPilot is the nose above the horizon
  // (world z up), i.e. quadfdi pitch −10° (positive = nose down).
  EXPECT_NEAR(s.attitude.v[2][1], -10 * kDeg, 1e-12);
  EXPECT_GT(zyx(s.attitude.v[2][0], s.attitude.v[2][1], s.attitude.v[2][2])[2][0], 0.0);
  // Right side down 10°: quadfdi roll +10°; the body's left axis (y) points up.
  EXPECT_NEAR(s.attitude.v[1][0], 10 * kDeg, 1e-12);
  EXPECT_GT(zyx(s.attitude.v[1][0], s.attitude.v[1][1], s.attitude.v[1][2])[2][1], 0.0);
  // Yaw 30° clockwise from north (towards east): the nose points to −y (west is +y).
  EXPECT_NEAR(s.attitude.v[3][2], -30 * kDeg, 1e-12);
  EXPECT_LT(zyx(s.attitude.v[3][0], s.attitude.v[3][1], s.attitude.v[3][2])[1][0], 0.0);
  EXPECT_EQ(s.attitude.source.topic, "ATT");
}

TEST(ArdupilotSignals, TrajectoryMotorOrderAndThrust) {
  DataflashWriter w = apLog();
  w.parm(0, "FRAME_CLASS", 1);
  w.parm(0, "FRAME_TYPE", 1);
  w.parm(0, "MOT_PWM_MIN", 1100);
  w.parm(0, "MOT_PWM_MAX", 1940);
  w.parm(0, "MOT_SPIN_MIN", 0.12);
  w.parm(0, "MOT_SPIN_MAX", 0.9);
  w.parm(0, "MOT_THST_EXPO", 0.55);
  ArdupilotThrustMap map;
  map.pwm_min = 1100;
  map.pwm_max = 1940;
  map.spin_min = static_cast<double>(0.12f);  // PARM values are floats
  map.spin_max = static_cast<double>(0.9f);
  map.expo = static_cast<double>(0.55f);
  const int n = 50;
  std::vector<std::array<double, 4>> ap_thrust(n);
  for (int k = 0; k < n; ++k) {
    const std::uint64_t t = 1000000 + 2500 * static_cast<std::uint64_t>(k);  // 400 Hz from 1 s
    const double ts = static_cast<double>(t) * 1e-6;
    att(w, t, 0, 0, 0);
    // Core 1 interleaved with core 0: only core 0 is used.
    xkf1(w, t, 0, ts, 2 * ts, -3 - ts);
    xkf1(w, t + 1, 1, 99, 99, 99);
    // ArduPilot motor m (1..4) at thrust 0.1·m + 0.1 + small ramp; output m = motor m.
    std::array<int, 4> pwm{};
    for (int m = 0; m < 4; ++m) {
      ap_thrust[static_cast<std::size_t>(k)][static_cast<std::size_t>(m)] = 0.1 * (m + 1) + 0.1 + 0.002 * k;
      pwm[static_cast<std::size_t>(m)] = static_cast<int>(std::lround(map.pwmFor(ap_thrust[static_cast<std::size_t>(k)][static_cast<std::size_t>(m)])));
    }
    rcou(w, t, pwm);
  }
  FlightSignals s;
  const LogIssue issue = extract(w, s);
  ASSERT_TRUE(issue.ok()) << issue.message;
  ASSERT_EQ(s.position.t.size(), static_cast<std::size_t>(n));
  ASSERT_EQ(s.command.t.size(), static_cast<std::size_t>(n));
  EXPECT_EQ(s.command_kind, CommandKind::kThrustFraction);
  for (int k = 0; k < n; ++k) {
    const std::size_t r = static_cast<std::size_t>(k);
    const double ts = 1.0 + 0.0025 * k;
    EXPECT_NEAR(s.position.t[r], ts, 1e-12);
    // NED (t, 2t, −3 − t) → north, west, up: (t, −2t, 3 + t).
    EXPECT_NEAR(s.position.v[r][0], ts, 1e-6);
    EXPECT_NEAR(s.position.v[r][1], -2 * ts, 1e-6);
    EXPECT_NEAR(s.position.v[r][2], 3 + ts, 1e-6);
    // quadfdi 1 FR, 2 BR, 3 BL, 4 FL ← ArduPilot motors 1, 4, 2, 3 (1 µs PWM quantisation).
    const auto& ap = ap_thrust[r];
    const std::array<double, 4> expected = {ap[0], ap[3], ap[1], ap[2]};
    for (std::size_t m = 0; m < 4; ++m) EXPECT_NEAR(s.command.v[r][m], expected[m], 3e-3) << k << " motor " << m + 1;
  }
  EXPECT_FALSE(s.conventions.empty());
  bool motor_line = false;
  for (const std::string& c : s.conventions) motor_line |= c.find("quadfdi 2 ← AP motor 4 (output 4)") != std::string::npos;
  EXPECT_TRUE(motor_line);
}

TEST(ArdupilotSignals, ThrustMapInvertsArdupilotsCurve) {
  // By hand from AP_MotorsMulticopter: PWM 1500 in 1000..2000 → a = 0.5, x = (0.5 − 0.15)/0.8
  // = 0.4375, thrust = 0.35·0.4375 + 0.65·0.4375² = 0.27753906…
  ArdupilotThrustMap map;
  EXPECT_NEAR(map.thrustFraction(1500), 0.35 * 0.4375 + 0.65 * 0.4375 * 0.4375, 1e-15);
  EXPECT_EQ(map.thrustFraction(1000), 0.0);
  EXPECT_EQ(map.thrustFraction(1100), 0.0);  // below MOT_SPIN_MIN: no thrust in ArduPilot's model
  EXPECT_EQ(map.thrustFraction(2000), 1.0);
  EXPECT_EQ(map.thrustFraction(0), 0.0);     // output off
  for (double expo : {-0.5, 0.0, 0.3, 0.65, 1.0}) {
    map.expo = expo;
    double previous = -1.0;
    for (int k = 0; k <= 100; ++k) {
      const double t = k / 100.0;
      EXPECT_NEAR(map.thrustFraction(map.pwmFor(t)), t, 1e-12) << expo << " " << t;
      const double pwm = 1000 + 10 * k;
      EXPECT_GE(map.thrustFraction(pwm), previous);
      previous = map.thrustFraction(pwm);
    }
  }
}

// ArduPilot divides each throttle by its battery voltage ratio v (MOTB BatVolt) so that a sagging
// battery gives the same thrust: the extractor multiplies it back, from BatVolt or, in a log
// without it, from LiftMax; without MOTB the PWM reads as more thrust and the report says so.
TEST(ArdupilotSignals, BatteryVoltageCompensationIsUndoneWithMotb) {
  const ArdupilotThrustMap map;
  EXPECT_NEAR(map.thrustFraction(map.pwmFor(0.3, 0.8), 0.8), 0.3, 1e-12);
  EXPECT_GT(map.pwmFor(0.3, 0.8), map.pwmFor(0.3));      // a weaker battery needs a higher throttle
  EXPECT_DOUBLE_EQ(map.pwmFor(0.95, 0.6), map.pwm_min + map.spin_max * (map.pwm_max - map.pwm_min));  // saturated
  const double e = map.expo;
  for (double v : {0.6, 0.8, 1.0}) EXPECT_NEAR(map.voltageRatioOfLiftMax(v * (1.0 - e) + e * v * v), v, 1e-12);

  constexpr std::uint8_t kMotb = 35, kMotbOld = 36;
  constexpr int kRows = 200;
  const auto ratio = [](int k) { return 1.0 - 0.25 * (k / 10) / 19.0; };  // 1 → 0.75, held over each 10 rows (MOTB at 10 Hz)
  const auto thrust = [](int k, int m) { return 0.25 + 0.1 * std::sin(0.05 * k + m); };
  enum class Battery { kBatVolt, kLiftMaxOnly, kNone };
  const auto logWith = [&](Battery battery) {
    DataflashWriter w = apLog();
    w.fmt(kMotb, "MOTB", "QffffB", "TimeUS,LiftMax,BatVolt,ThLimit,ThrAvMx,FailFlags");  // Copter 4.x
    w.fmt(kMotbOld, "MOTB", "Qf", "TimeUS,LiftMax");  // a layout without BatVolt (only one is written)
    att(w, 1000, 0, 0, 0);
    xkf1(w, 1000, 0, 0, 0, 0);
    for (int k = 0; k < kRows; ++k) {
      const std::uint64_t t = 1000 + 2500 * static_cast<std::uint64_t>(k);
      const double v = ratio(k), lift = v * (1.0 - e) + e * v * v;
      if (k % 10 == 0 && battery == Battery::kBatVolt) w.write(kMotb, {t, lift, v, 1.0, 0.5, 0u});
      if (k % 10 == 0 && battery == Battery::kLiftMaxOnly) w.write(kMotbOld, {t, lift});
      std::array<int, 4> pwm{};
      for (int m = 0; m < 4; ++m) pwm[static_cast<std::size_t>(m)] = static_cast<int>(std::lround(map.pwmFor(thrust(k, m), v)));
      rcou(w, t, pwm);
    }
    return w;
  };
  // The X: quadfdi motor k is AP motor (1, 4, 2, 3)[k] on that output.
  const int ap_of_quadfdi[4] = {1, 4, 2, 3};
  const auto largestError = [&](const FlightSignals& s) {
    EXPECT_EQ(s.command.v.size(), static_cast<std::size_t>(kRows));
    double worst = 0.0;
    for (std::size_t k = 0; k < s.command.v.size(); ++k)
      for (int q = 0; q < 4; ++q)
        worst = std::max(worst, std::abs(s.command.v[k][static_cast<std::size_t>(q)] - thrust(static_cast<int>(k), ap_of_quadfdi[q] - 1)));
    return worst;
  };
  const auto lineOf = [](const FlightSignals& s) {
    for (const std::string& c : s.conventions)
      if (c.rfind("battery: ", 0) == 0) return c;
    return std::string();
  };
  FlightSignals with, lift_only, without;
  ASSERT_TRUE(extract(logWith(Battery::kBatVolt), with).ok());
  ASSERT_TRUE(extract(logWith(Battery::kLiftMaxOnly), lift_only).ok());
  ASSERT_TRUE(extract(logWith(Battery::kNone), without).ok());
  EXPECT_LT(largestError(with), 1.1e-3);  // the PWM's 1 µs steps
  EXPECT_LT(largestError(lift_only), 1.1e-3);
  EXPECT_GT(largestError(without), 0.08);  // at v = 0.75 a thrust of 0.15–0.35 reads 49–55 % high
  EXPECT_EQ(lineOf(with).rfind("battery: ArduPilot's voltage compensation undone: each throttle × v before the thrust curve, "
                               "v = 0.750 … 1.000 (MOTB BatVolt:", 0),
            0u)
      << lineOf(with);
  EXPECT_NE(lineOf(lift_only).find("(MOTB LiftMax = v(1 − e) + e·v²:"), std::string::npos) << lineOf(lift_only);
  EXPECT_EQ(lineOf(without).rfind("battery: voltage compensation not undone: the log has no MOTB (LOG_BITMASK bit 17", 0), 0u)
      << lineOf(without);
}

TEST(ArdupilotSignals, ServoFunctionsAndOldPwmDefaults) {
  DataflashWriter w = apLog();
  // Outputs reversed: SERVO1 drives motor 4 … SERVO4 motor 1 (SERVOn_FUNCTION 33 + m − 1).
  for (int n = 1; n <= 4; ++n) w.parm(0, "SERVO" + std::to_string(n) + "_FUNCTION", 33 + (4 - n));
  w.parm(0, "MOT_PWM_MIN", 0);  // older firmware: use RC3_MIN/MAX
  w.parm(0, "MOT_PWM_MAX", 0);
  w.parm(0, "RC3_MIN", 982);
  w.parm(0, "RC3_MAX", 2006);
  w.parm(0, "MOT_THST_EXPO", 0);
  w.parm(0, "MOT_SPIN_MIN", 0);
  w.parm(0, "MOT_SPIN_MAX", 1);
  att(w, 1000, 0, 0, 0);
  xkf1(w, 1000, 0, 0, 0, 0);
  // C1 = motor 4, C2 = motor 3, C3 = motor 2, C4 = motor 1.
  rcou(w, 1000, {982 + 400, 982 + 300, 982 + 200, 982 + 100});
  FlightSignals s;
  const LogIssue issue = extract(w, s);
  ASSERT_TRUE(issue.ok()) << issue.message;
  ASSERT_EQ(s.command.v.size(), 1u);
  // AP motors 1..4 at 100..400 µs over 1024: quadfdi order AP 1, 4, 2, 3.
  const double span = 2006 - 982;
  EXPECT_NEAR(s.command.v[0][0], 100 / span, 1e-12);
  EXPECT_NEAR(s.command.v[0][1], 400 / span, 1e-12);
  EXPECT_NEAR(s.command.v[0][2], 200 / span, 1e-12);
  EXPECT_NEAR(s.command.v[0][3], 300 / span, 1e-12);
  EXPECT_EQ(s.command.source.fields, "C4,C1,C3,C2");
}

// Older Copters label the outputs Chn (3.3–3.5: "TimeUS,Ch1,…,Ch12") or Chann (3.2: "TimeMS,Chan1,…"):
// read as Cn is.
TEST(ArdupilotSignals, OlderOutputLabelsReadAsTheCurrentOnes) {
  const std::array<int, 4> pulses = {1100, 1400, 1200, 1300};
  FlightSignals current;
  {
    DataflashWriter w = apLog();
    att(w, 1000, 0, 0, 0);
    xkf1(w, 1000, 0, 0, 0, 0);
    rcou(w, 1000, pulses);
    ASSERT_TRUE(extract(w, current).ok());
  }
  const struct {
    const char *format, *labels, *fields;
  } older[] = {{"Qhhhhhhhhhhhh", "TimeUS,Ch1,Ch2,Ch3,Ch4,Ch5,Ch6,Ch7,Ch8,Ch9,Ch10,Ch11,Ch12", "Ch1,Ch4,Ch2,Ch3"},
               {"Ihhhhhhhh", "TimeMS,Chan1,Chan2,Chan3,Chan4,Chan5,Chan6,Chan7,Chan8", "Chan1,Chan4,Chan2,Chan3"}};
  for (const auto& o : older) {
    SCOPED_TRACE(o.labels);
    DataflashWriter w;
    w.fmt(kAtt, "ATT", "QccccCCCCB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
    w.fmt(kXkf1, "XKF1", "QBccCfffffffccce", "TimeUS,C,Roll,Pitch,Yaw,VN,VE,VD,dPD,PN,PE,PD,GX,GY,GZ,OH");
    w.fmt(kRcou, "RCOU", o.format, o.labels);
    att(w, 1000, 0, 0, 0);
    xkf1(w, 1000, 0, 0, 0, 0);
    std::vector<DfValue> row = {o.format[0] == 'Q' ? DfValue(1000ull) : DfValue(1u)};
    for (std::size_t k = 1; k < std::string(o.format).size(); ++k) row.emplace_back(k <= 4 ? pulses[k - 1] : 0);
    w.write(kRcou, row);
    FlightSignals s;
    const LogIssue issue = extract(w, s);
    ASSERT_TRUE(issue.ok()) << issue.message;
    ASSERT_EQ(s.command.v.size(), 1u);
    EXPECT_EQ(s.command.v[0], current.command.v[0]);
    EXPECT_EQ(s.command.source.fields, o.fields);
  }
  // None of the three: named.
  DataflashWriter w;
  w.fmt(kAtt, "ATT", "QccccCCCCB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
  w.fmt(kXkf1, "XKF1", "QBccCfffffffccce", "TimeUS,C,Roll,Pitch,Yaw,VN,VE,VD,dPD,PN,PE,PD,GX,GY,GZ,OH");
  w.fmt(kRcou, "RCOU", "QHHHH", "TimeUS,Out1,Out2,Out3,Out4");
  att(w, 1000, 0, 0, 0);
  xkf1(w, 1000, 0, 0, 0, 0);
  w.write(kRcou, {1000ull, 1100, 1400, 1200, 1300});
  FlightSignals s;
  const LogIssue issue = extract(w, s);
  EXPECT_EQ(issue.status, LogStatus::kMissingSignal);
  EXPECT_EQ(issue.message, "RCOU has no field C1 (nor Ch1, Chan1)");
}

TEST(ArdupilotSignals, ArmedAndLandedStates) {
  DataflashWriter w = completeLog();
  w.write(kEv, {1000000ull, 10});                  // ARMED
  w.write(kArm, {1000000ull, 1, 0u, 0, 0});        // the same arming, from ARM: no new event
  w.write(kEv, {2000000ull, 28});                  // NOT_LANDED
  w.write(kEv, {3000000ull, 25});                  // SET_HOME: ignored
  w.write(kEv, {8000000ull, 18});                  // LAND_COMPLETE
  w.write(kArm, {9000000ull, 0, 0u, 0, 0});        // disarmed (ARM only)
  FlightSignals s;
  ASSERT_TRUE(extract(w, s).ok());
  ASSERT_EQ(s.states.size(), 4u);
  EXPECT_EQ(s.states[0].t, 1.0);
  EXPECT_TRUE(s.states[0].armed);
  EXPECT_TRUE(s.states[0].landed);
  EXPECT_EQ(s.states[1].t, 2.0);
  EXPECT_FALSE(s.states[1].landed);
  EXPECT_EQ(s.states[2].t, 8.0);
  EXPECT_TRUE(s.states[2].landed);
  EXPECT_TRUE(s.states[2].armed);
  EXPECT_EQ(s.states[3].t, 9.0);
  EXPECT_FALSE(s.states[3].armed);
}

TEST(ArdupilotSignals, PositionWithoutFmtuIsFilteredByCore) {
  DataflashWriter w = apLog(false);
  att(w, 1000, 0, 0, 0);
  rcou(w, 1000, {1000, 1000, 1000, 1000});
  xkf1(w, 1000, 0, 1, 2, 3);
  xkf1(w, 1001, 1, 10, 20, 30);
  xkf1(w, 2000, 0, 4, 5, 6);
  xkf1(w, 2001, 1, 40, 50, 60);
  FlightSignals s;
  ASSERT_TRUE(extract(w, s).ok());
  ASSERT_EQ(s.position.v.size(), 2u);
  EXPECT_EQ(s.position.v[1][0], 4.0);
  EXPECT_EQ(s.position.v[1][1], -5.0);
  EXPECT_EQ(s.position.v[1][2], -6.0);
  ArdupilotSignalOptions core1;
  core1.ekf_core = 1;
  ASSERT_TRUE(extract(w, s, core1).ok());
  ASSERT_EQ(s.position.v.size(), 2u);
  EXPECT_EQ(s.position.v[0][0], 10.0);
}

// XKF4 of EKF3 (LogStructure.h: "QBcccccfffHBIHb"), written with the same TimeUS as XKF1.
constexpr std::uint8_t kXkf4 = 35;
constexpr unsigned kSolutionPosition = 1 | 2 | 4 | 8 | 32;  // attitude, velocities, horiz_pos_rel, vert_pos
constexpr unsigned kSolutionConstPos = 1 | 4 | 32 | 128;    // constant-position mode: no horiz_pos_rel

TEST(ArdupilotSignals, EkfStatusSkipsHeldPositionsAndResetShiftsAreTakenOut) {
  DataflashWriter w = apLog(false);
  w.fmt(kXkf4, "XKF4", "QBcccccfffHBIHb", "TimeUS,C,SV,SP,SH,SM,SVT,errRP,OFN,OFE,FS,TS,SS,GPS,PI");
  rcou(w, 1000, {1000, 1000, 1000, 1000});
  att(w, 1000, 0, 0, 0);
  // True track: PN = t, PE = −t [m, t in s] at 25 Hz. Rows 0–4 in constant-position mode; at
  // row 20 the EKF resets its position by (+4, +2) m; core 1's status must not be used for core 0.
  double ofn = 0.5, ofe = -0.5;  // a reset from before the log: not applied
  for (int i = 0; i < 40; ++i) {
    const std::uint64_t t = 1000000 + static_cast<std::uint64_t>(i) * 40000;
    const double tt = static_cast<double>(t) * 1e-6;
    double pn = tt, pe = -tt;
    if (i >= 20) {
      pn += 4.0;
      pe += 2.0;
      ofn = 4.0;
      ofe = 2.0;
    }
    const unsigned ss = i < 5 ? kSolutionConstPos : kSolutionPosition;
    xkf1(w, t, 0, pn, pe, 1.0);
    w.write(kXkf4, {t, 0u, 0, 0, 0, 0, 0, 0.0, ofn, ofe, 0u, 0u, ss, 0u, 0});
    w.write(kXkf4, {t + 1, 1u, 0, 0, 0, 0, 0, 0.0, 7.0 * i, 0.0, 0u, 0u, kSolutionConstPos, 0u, 0});
  }
  FlightSignals s;
  const LogIssue issue = extract(w, s);
  ASSERT_TRUE(issue.ok()) << issue.message;
  ASSERT_EQ(s.position.v.size(), 35u);
  for (std::size_t j = 0; j < s.position.v.size(); ++j) {
    EXPECT_NEAR(s.position.v[j][0], s.position.t[j], 1e-5) << j;   // north
    EXPECT_NEAR(s.position.v[j][1], s.position.t[j], 1e-5) << j;   // west = −PE
    EXPECT_NEAR(s.position.v[j][2], -1.0, 1e-9) << j;
  }
  auto has = [&](const std::string& part) {
    for (const std::string& c : s.conventions)
      if (c.find(part) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(has("5 of 40 XKF1 rows skipped: XKF4 SS flags no position estimate"));
  EXPECT_TRUE(has("1 horizontal position reset (largest 4.47 m) taken out with XKF4 OFN, OFE"));

  // Core 1 never had a position: refused by its flag, naming both messages.
  ArdupilotSignalOptions core1;
  core1.ekf_core = 1;
  DataflashWriter w1 = apLog(false);
  w1.fmt(kXkf4, "XKF4", "QBcccccfffHBIHb", "TimeUS,C,SV,SP,SH,SM,SVT,errRP,OFN,OFE,FS,TS,SS,GPS,PI");
  rcou(w1, 1000, {1000, 1000, 1000, 1000});
  att(w1, 1000, 0, 0, 0);
  for (int i = 0; i < 5; ++i) {
    const std::uint64_t t = 1000000 + static_cast<std::uint64_t>(i) * 40000;
    xkf1(w1, t, 1, 0.0, 0.0, 0.0);
    w1.write(kXkf4, {t, 1u, 0, 0, 0, 0, 0, 0.0, 0.0, 0.0, 0u, 0u, kSolutionConstPos, 0u, 0});
  }
  const LogIssue refused = extract(w1, s, core1);
  EXPECT_EQ(refused.status, LogStatus::kMissingSignal);
  EXPECT_EQ(refused.topic, "XKF1");
  EXPECT_TRUE(refused.message.find("XKF4 SS flags no position estimate in all 5 rows of EKF core 1") != std::string::npos)
      << refused.message;
}

// Two lanes whose positions differ by 10 m north; XKF4 PI names core 0 primary, then core 1 from
// row 20 (a lane switch). By default the position follows the primary, cut at the switch.
TEST(ArdupilotSignals, PositionFollowsThePrimaryCoreAndALaneSwitchIsCut) {
  DataflashWriter w = apLog(false);
  w.fmt(kXkf4, "XKF4", "QBcccccfffHBIHb", "TimeUS,C,SV,SP,SH,SM,SVT,errRP,OFN,OFE,FS,TS,SS,GPS,PI");
  rcou(w, 1000, {1000, 1000, 1000, 1000});
  att(w, 1000, 0, 0, 0);
  auto time = [](int i) { return 1000000 + static_cast<std::uint64_t>(i) * 40000; };
  for (int i = 0; i < 40; ++i) {
    const double tt = static_cast<double>(time(i)) * 1e-6;
    const int primary = i < 20 ? 0 : 1;
    for (unsigned core = 0; core < 2; ++core) {
      xkf1(w, time(i), core, tt + 10.0 * core, 0.0, -1.0);
      w.write(kXkf4, {time(i), core, 0, 0, 0, 0, 0, 0.0, 0.0, 0.0, 0u, 0u, kSolutionPosition, 0u, primary});
    }
  }
  FlightSignals s;
  const LogIssue issue = extract(w, s);
  ASSERT_TRUE(issue.ok()) << issue.message;
  ASSERT_EQ(s.position.v.size(), 40u);
  for (std::size_t j = 0; j < 40; ++j) EXPECT_NEAR(s.position.v[j][0], s.position.t[j] + (j < 20 ? 0.0 : 10.0), 1e-5) << j;
  ASSERT_EQ(s.breaks.size(), 1u);
  EXPECT_NEAR(s.breaks[0].t, static_cast<double>(time(20)) * 1e-6, 1e-9);
  EXPECT_NEAR(s.breaks[0].last_before, static_cast<double>(time(19)) * 1e-6, 1e-9);
  EXPECT_TRUE(s.breaks[0].why.find("switched to core 1") != std::string::npos) << s.breaks[0].why;
  bool named = false;
  for (const std::string& c : s.conventions)
    named = named || c.find("the EKF's primary core (XKF4 PI): core 0, core 1 from 1.800 s") != std::string::npos;
  EXPECT_TRUE(named);
  // A core given is read throughout, without a cut.
  ArdupilotSignalOptions core0;
  core0.ekf_core = 0;
  ASSERT_TRUE(extract(w, s, core0).ok());
  ASSERT_EQ(s.position.v.size(), 40u);
  EXPECT_NEAR(s.position.v[39][0], s.position.t[39], 1e-5);
  EXPECT_TRUE(s.breaks.empty());
}

TEST(ArdupilotSignals, MissingMessagesAreNamed) {
  {
    DataflashWriter w = apLog();
    xkf1(w, 1000, 0, 0, 0, 0);
    rcou(w, 1000, {1000, 1000, 1000, 1000});
    FlightSignals s;
    const LogIssue issue = extract(w, s);
    EXPECT_EQ(issue.status, LogStatus::kMissingSignal);
    EXPECT_EQ(issue.topic, "ATT");
  }
  {
    DataflashWriter w = apLog();
    att(w, 1000, 0, 0, 0);
    rcou(w, 1000, {1000, 1000, 1000, 1000});
    FlightSignals s;
    const LogIssue issue = extract(w, s);
    EXPECT_EQ(issue.topic, "XKF1");
  }
  {
    DataflashWriter w = apLog();
    att(w, 1000, 0, 0, 0);
    xkf1(w, 1000, 0, 0, 0, 0);
    FlightSignals s;
    const LogIssue issue = extract(w, s);
    EXPECT_EQ(issue.topic, "RCOU");
  }
}

TEST(ArdupilotSignals, EveryXNumberingPutsEachMotorInItsQuadrant) {
  // The same physical X numbered four ways (AP_MotorsMatrix::setup_quad_matrix): the output of the
  // motor at each quadrant carries that quadrant's PWM, and each must land on quadfdi's motor there.
  struct Frame {
    int type;
    std::array<int, 4> ap_motor_of;  // ArduPilot motor at quadfdi 1 FR, 2 BR, 3 BL, 4 FL
  };
  const Frame frames[] = {{1, {1, 4, 2, 3}}, {12, {2, 1, 3, 4}}, {13, {1, 4, 3, 2}}, {14, {1, 2, 3, 4}}};
  const std::array<int, 4> quadrant_pwm = {1300, 1400, 1500, 1600};  // FR, BR, BL, FL
  ArdupilotThrustMap map;  // the defaults: the log has no MOT_* parameters
  for (const Frame& f : frames) {
    SCOPED_TRACE(f.type);
    DataflashWriter w = apLog();
    w.parm(0, "FRAME_CLASS", 1);
    w.parm(0, "FRAME_TYPE", f.type);
    std::array<int, 4> outputs{};  // C1..C4 = motors 1..4 (default SERVOn_FUNCTION)
    for (std::size_t q = 0; q < 4; ++q) outputs[static_cast<std::size_t>(f.ap_motor_of[q] - 1)] = quadrant_pwm[q];
    att(w, 1000, 0, 0, 0);
    xkf1(w, 1000, 0, 0, 0, 0);
    rcou(w, 1000, outputs);
    FlightSignals s;
    const LogIssue issue = extract(w, s);
    ASSERT_TRUE(issue.ok()) << issue.message;
    for (std::size_t q = 0; q < 4; ++q) EXPECT_DOUBLE_EQ(s.command.v[0][q], map.thrustFraction(quadrant_pwm[q])) << "quadfdi motor " << q + 1;
    EXPECT_EQ(s.numbering.name, "ArduPilot");
    EXPECT_EQ(s.numbering.autopilot_motor, f.ap_motor_of);
  }
}

TEST(ArdupilotSignals, PropsOutAndPlusFramesAreReadInTurnedAxes) {
  // Each output carries its motor's number; each frame's motor at each quadfdi motor, and where it sits.
  struct Frame {
    int type;
    int eighths;
    std::array<int, 4> ap_motor_of;  // ArduPilot motor at quadfdi motor 1..4 in the turned axes
    const char* motor1_at;
  };
  const Frame frames[] = {{3, 2, {3, 1, 4, 2}, "front-right"},  // H: the X's positions, every spin reversed
                          {18, 2, {4, 2, 1, 3}, "back-right"},  // BF_X_REV
                          {0, -1, {1, 4, 2, 3}, "right"},        // PLUS
                          {6, 1, {3, 1, 4, 2}, "right"}};        // PLUSREV
  for (const Frame& f : frames) {
    SCOPED_TRACE(f.type);
    DataflashWriter w = apLog();
    w.parm(0, "FRAME_CLASS", 1);
    w.parm(0, "FRAME_TYPE", f.type);
    att(w, 1000, 0, 0, 0);
    xkf1(w, 1000, 0, 0, 0, 0);
    rcou(w, 1000, {1100, 1200, 1300, 1400});
    FlightSignals s;
    const LogIssue issue = extract(w, s);
    ASSERT_TRUE(issue.ok()) << issue.message;
    EXPECT_EQ(s.numbering.body_turn.eighths, f.eighths);
    EXPECT_EQ(s.numbering.autopilot_motor, f.ap_motor_of);
    ArdupilotThrustMap map;
    for (std::size_t q = 0; q < 4; ++q) EXPECT_DOUBLE_EQ(s.command.v[0][q], map.thrustFraction(1000 + 100 * f.ap_motor_of[q]));
    int q1 = 0;
    for (int q = 1; q <= 4; ++q) q1 = f.ap_motor_of[static_cast<std::size_t>(q - 1)] == 1 ? q : q1;
    EXPECT_STREQ(motorPosition(s.numbering, q1), f.motor1_at);
  }
}

TEST(ArdupilotSignals, FramesTheModelDoesNotDescribeAreRefused) {
  const std::pair<int, const char*> cases[] = {{16, "NYT_PLUS"}, {17, "NYT_X"}, {19, "Y4"}, {2, "V, V-tail"}, {7, "not a quad frame"}};
  for (const auto& [type, expect] : cases) {
    SCOPED_TRACE(type);
    DataflashWriter w = completeLog();
    w.parm(0, "FRAME_TYPE", type);
    FlightSignals s;
    const LogIssue issue = extract(w, s);
    EXPECT_EQ(issue.status, LogStatus::kCorrupt);
    EXPECT_EQ(issue.topic, "PARM");
    EXPECT_NE(issue.message.find("FRAME_TYPE is " + std::to_string(type) + ": "), std::string::npos) << issue.message;
    EXPECT_NE(issue.message.find(expect), std::string::npos) << issue.message;
  }
  DataflashWriter w = completeLog();
  w.parm(0, "FRAME_CLASS", 2);  // hexa
  FlightSignals s;
  EXPECT_NE(extract(w, s).message.find("FRAME_CLASS is 2"), std::string::npos);
}

TEST(ArdupilotSignals, NonIncreasingTimesAreDropped) {
  DataflashWriter w = completeLog();
  att(w, 1000, 1, 0, 0);  // same time as the first ATT
  att(w, 900, 2, 0, 0);   // back in time
  att(w, 2000, 3, 0, 0);
  FlightSignals s;
  ASSERT_TRUE(extract(w, s).ok());
  ASSERT_EQ(s.attitude.v.size(), 2u);
  EXPECT_NEAR(s.attitude.v[1][0], 3 * kDeg, 1e-12);
  EXPECT_NE(s.conventions.back().find("dropped 2 rows"), std::string::npos);
}

TEST(ArdupilotSignals, HugeTimestampsStayStrictlyIncreasingInSeconds) {
  // Beyond 2^53 µs, consecutive TimeUS round to the same double (found by dataflash_fuzz).
  DataflashWriter w = apLog();
  const std::uint64_t base = 1ull << 60;
  for (std::uint64_t k = 0; k < 4; ++k) {
    att(w, base + k, 0, 0, 0);
    xkf1(w, base + k, 0, 0, 0, 0);
    rcou(w, base + k, {1000, 1000, 1000, 1000});
  }
  FlightSignals s;
  ASSERT_TRUE(extract(w, s).ok());
  ASSERT_FALSE(s.attitude.t.empty());
  for (std::size_t k = 1; k < s.attitude.t.size(); ++k) EXPECT_GT(s.attitude.t[k], s.attitude.t[k - 1]);
  EXPECT_LT(s.attitude.t.size(), 4u);
}
