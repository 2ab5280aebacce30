#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "io/key_value.h"
#include "io/telemetry_csv.h"
#include "io/telemetry_reader.h"

namespace quadfdi {
namespace {

// Three logged steps of distinct states and a command whose text must read back exactly.
FlightLog threeStepLog() {
  FlightLog log;
  for (int k = 0; k < 3; ++k) {
    State x = State::LinSpaced(0.1 * k, 1.0 / 3.0 + k);
    log.states.push_back(x);
    log.outputs.push_back(outputOf(x, OutputKind::kPositionEuler));
    ControlStep c;
    c.u_cmd = Input(0.07, 0.071, 1.0 / 7.0, 0.0015);
    log.controls.push_back(c);
    log.applied.push_back(c.u_cmd);
  }
  return log;
}

TEST(TelemetryCsv, HeaderRowsAndExactRoundTrip) {
  FlightLog log = threeStepLog();
  std::ostringstream out;
  writeTelemetryCsv(out, log, TelemetryCsvOptions{});
  std::istringstream in(out.str());
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4");
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(std::getline(in, line));
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) {
      double d = 0;
      ASSERT_TRUE(parseFiniteNumber(cell, d)) << cell;
      v.push_back(d);
    }
    ASSERT_EQ(v.size(), 11u);
    EXPECT_EQ(v[0], k * 0.002);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(v[1 + static_cast<std::size_t>(i)], log.outputs[static_cast<std::size_t>(k)](i));
    EXPECT_EQ(v[9], 1.0 / 7.0);  // shortest round-trip text reads back exactly
  }
  EXPECT_FALSE(std::getline(in, line));
  std::ostringstream full;
  TelemetryCsvOptions o;
  o.full_state = true;
  writeTelemetryCsv(full, log, o);
  EXPECT_EQ(full.str().substr(0, full.str().find('\n')),
            "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,vx,vy,vz,p,q,r,f1,f2,f3,f4,status");
}

TEST(TelemetryCsv, SampleRowsReadBackExactlyThroughTheReader) {
  TelemetrySample a;
  a.t = 12.3456789;
  a.y = {0.1, -1.0 / 3.0, 1.25, 3.14159, -0.002, 1e-9};
  a.u = {0.07, 0.071, 1.0 / 7.0, 0.0015};
  std::stringstream csv;
  writeTelemetryCsvHeader(csv);
  writeTelemetryCsvRow(csv, a);
  TelemetryReader reader(csv, "rows.csv");
  TelemetrySample b;
  std::string problem;
  ASSERT_EQ(reader.next(b, problem), SampleSource::Next::kSample) << problem;
  EXPECT_EQ(b.t, a.t);
  EXPECT_EQ(b.y, a.y);
  EXPECT_EQ(b.u, a.u);
  EXPECT_EQ(reader.next(b, problem), SampleSource::Next::kEnd);
}

// A converted log keeps its autopilot's motor numbers in a comment before the header, which the
// reader gives back; quadfdi's own numbering writes none.
TEST(TelemetryCsv, TheMotorNumberingCommentRoundTrips) {
  std::stringstream plain;
  writeTelemetryCsvHeader(plain);
  EXPECT_EQ(plain.str(), "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n");
  EXPECT_FALSE(TelemetryReader(plain, "plain.csv").numbering());
  std::stringstream px4;
  writeTelemetryCsvHeader(px4, MotorNumbering{"PX4 quad X", {1, 4, 2, 3}, BodyTurn{}});
  EXPECT_EQ(px4.str(), "# motor_numbering: PX4 quad X = 1 4 2 3\nt,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n");
  const TelemetryReader reader(px4, "px4.csv");
  ASSERT_TRUE(reader.numbering());
  EXPECT_EQ(reader.numbering()->name, "PX4 quad X");
  EXPECT_EQ(reader.numbering()->autopilot_motor, (std::array<int, 4>{1, 4, 2, 3}));
  // A plus or props-out frame's turned axes come back with it.
  std::stringstream plus;
  writeTelemetryCsvHeader(plus, MotorNumbering{"ArduPilot", {1, 4, 2, 3}, BodyTurn{-1}});
  EXPECT_EQ(plus.str(), "# motor_numbering: ArduPilot = 1 4 2 3 turned -45\nt,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n");
  const TelemetryReader plus_reader(plus, "plus.csv");
  ASSERT_TRUE(plus_reader.numbering());
  EXPECT_EQ(plus_reader.numbering()->body_turn.eighths, -1);
  EXPECT_STREQ(motorPosition(*plus_reader.numbering(), 1), "right");
  // Only before the header; other comments are ignored.
  std::stringstream late("# a note\nt,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n# motor_numbering: PX4 = 1 4 2 3\n");
  EXPECT_FALSE(TelemetryReader(late, "late.csv").numbering());
}

TEST(TelemetryCsv, AMalformedNumberingCommentNamesItsLine) {
  for (const char* value : {"PX4 = 1 4 2", "PX4 = 1 4 2 2", "PX4 = 1 4 2 5", "= 1 2 3 4", "PX4 1 4 2 3", "PX4 = 1 4 2 3 1", "PX4 = a b c d",
                            "PX4 = 1 4 2 3 turned 30", "PX4 = 1 4 2 3 turned", "PX4 = 1 4 2 3 rotated 90", "PX4 = 1 4 2 3 turned 90 x"}) {
    SCOPED_TRACE(value);
    std::stringstream in(std::string("# exported\n# motor_numbering: ") + value + "\nt,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n");
    try {
      TelemetryReader reader(in, "bad.csv");
      ADD_FAILURE() << "accepted";
    } catch (const TelemetryError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("bad.csv:2: '# motor_numbering: NAME = A B C D [turned DEG]' expects", 0), 0u) << e.what();
    }
  }
}

// Hamilton quaternion (w, x, y, z) of Rz(ψ)·Ry(θ)·Rx(φ), composed from the three axis rotations
// (independent of the reader's formula).
std::array<double, 4> quaternionOfZyx(double roll, double pitch, double yaw) {
  const auto mul = [](const std::array<double, 4>& a, const std::array<double, 4>& b) {
    return std::array<double, 4>{a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3], a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                                 a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1], a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
  };
  const std::array<double, 4> qx{std::cos(roll / 2), std::sin(roll / 2), 0, 0}, qy{std::cos(pitch / 2), 0, std::sin(pitch / 2), 0},
      qz{std::cos(yaw / 2), 0, 0, std::sin(yaw / 2)};
  return mul(qz, mul(qy, qx));
}

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

TelemetrySample readOne(const std::string& csv, const TelemetryReaderOptions& options = {}) {
  std::istringstream in(csv);
  TelemetryReader reader(in, "one.csv", options);
  TelemetrySample s;
  std::string problem;
  EXPECT_EQ(reader.next(s, problem), SampleSource::Next::kSample) << problem;
  return s;
}

// The reader's error on `csv` (header and every row read), or "accepted".
std::string firstRefusal(const std::string& csv, const std::string& name, const TelemetryReaderOptions& options = {}) {
  std::istringstream in(csv);
  try {
    TelemetryReader reader(in, name, options);
    TelemetrySample s;
    std::string problem;
    while (reader.next(s, problem) != SampleSource::Next::kEnd) {
    }
  } catch (const TelemetryError& e) {
    return e.what();
  }
  return "accepted";
}

// A simulator that logs orientation as a quaternion needs no converter: qw,qx,qy,qz stand in for
// roll,pitch,yaw and give the same ZYX angles, near gimbal lock and across yaw = ±π too.
// A hexacopter's or octocopter's telemetry (u5, u6 …) is refused naming the column, not read as a
// quad's first four motors; columns that only look alike (u0, u10 of nothing, "u5x") are extra columns.
TEST(TelemetryCsv, AMotorBeyondTheFourthIsRefused) {
  const std::string row = "0,0,0,1,0,0,0,1,1,1,1,1,1\n";
  EXPECT_EQ(firstRefusal("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,u5,u6\n" + row, "hexa.csv"),
            "hexa.csv:1: column 'u5': a motor beyond the fourth — quadfdi detects faults on quadrotors, whose four motors are "
            "u1..u4; a hexacopter's or octocopter's telemetry is not read as a quad's");
  EXPECT_EQ(firstRefusal("# exported\nt\tx\ty\tz\troll\tpitch\tyaw\tu1\tu2\tu3\tu4\tu8 [N]\n0\t0\t0\t1\t0\t0\t0\t1\t1\t1\t1\t1\n", "octo.tsv")
                .rfind("octo.tsv:2: column 'u8 [N]': a motor beyond the fourth", 0),
            0u);
  for (const char* extra : {"u0", "u5x", "u05", "battery"})
    EXPECT_EQ(firstRefusal(std::string("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,") + extra + ",u40x\n" + row, "quad.csv"), "accepted") << extra;
}

// A line past the reader's bound (1 MiB) is no telemetry: a device or a binary file read as CSV
// would otherwise be read into memory without end. Lines up to it read; the last needs no newline.
TEST(TelemetryCsv, ALineLongerThanTheBoundIsRefusedNamingIt) {
  const std::string header = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4";
  const std::string row = "0,0,0,0,0,0,0,0.1,0.1,0.1,0.1";
  EXPECT_EQ(firstRefusal(header + "\n" + row, "last.csv"), "accepted");
  const std::string padded = header + std::string((std::size_t{1} << 20) - header.size(), ' ');  // the bound, exactly
  EXPECT_EQ(firstRefusal(padded + "\n" + row + "\n", "padded.csv"), "accepted");
  EXPECT_EQ(firstRefusal(header + "\n" + row + "\n" + std::string((std::size_t{1} << 20) + 1, '0'), "zeros.csv"),
            "zeros.csv:3: a line longer than 1048576 bytes: not CSV telemetry");
}

// A flight log read as CSV (on standard input, where its format is not sniffed) is named by its
// magic; other binary is refused as binary; a header in UTF-8 (°) is text; a text DataFlash log is named.
TEST(TelemetryCsv, BinaryInputIsRefusedAndAFlightLogNamed) {
  EXPECT_EQ(firstRefusal(std::string("ULog\x01\x12\x35\x01\0\0\0\0\0\0\0\0", 16), "log.csv"),
            "log.csv:1: binary, not CSV telemetry (the ulog magic: a flight log; read it with --format ulog)");
  EXPECT_EQ(firstRefusal(std::string("t,x\0y\n", 6), "nul.csv"),
            "nul.csv:1: binary, not CSV telemetry (a flight log? name its format: --format ulog, dataflash or crazyflie)");
  EXPECT_EQ(firstRefusal("t,x,y,z,roll [°],pitch [°],yaw [°],u1,u2,u3,u4\r\n0,0,0,0,0,0,0,0.1,0.1,0.1,0.1\r\n", "utf8.csv"), "accepted");
  // ArduPilot's DataFlash as text (Mission Planner writes it beside the .BIN) is text, and no CSV
  // telemetry: where it is read as CSV (standard input without --format), the flag is named.
  for (const char* first_line : {"FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns\r\n", "FMT,129,23,PARM,QNf,TimeUS,Name,Value\n"})
    EXPECT_EQ(firstRefusal(std::string(first_line) + "FMT, 130, 23, PARM, QNf, TimeUS,Name,Value\r\n", "00000012.log"),
              "00000012.log:1: an ArduPilot DataFlash log as text (Mission Planner's .log), not CSV telemetry: read it with --format "
              "dataflash");
}

TEST(TelemetryCsv, AQuaternionAttitudeReadsAsItsEulerAngles) {
  const double kAngles[][3] = {{0.0, 0.0, 0.0}, {0.3, -0.2, 1.0}, {-2.9, 1.2, -3.1}, {3.1, -1.5, 3.14}, {0.01, 1.5707, -0.5}};
  for (const auto& a : kAngles) {
    SCOPED_TRACE(std::to_string(a[0]) + " " + std::to_string(a[1]) + " " + std::to_string(a[2]));
    const std::array<double, 4> q = quaternionOfZyx(a[0], a[1], a[2]);
    // Any column order, extra columns ignored; the sign of q does not matter.
    for (double sign : {1.0, -1.0}) {
      const TelemetrySample s = readOne("u1,qx,t,qz,x,y,z,qy,note,qw,u2,u3,u4\n0.1," + number(sign * q[1]) + ",2.5," +
                                        number(sign * q[3]) + ",1,2,3," + number(sign * q[2]) + ",7," + number(sign * q[0]) + ",0.2,0.3,0.4\n");
      EXPECT_EQ(s.t, 2.5);
      EXPECT_EQ(s.y[0], 1.0);
      EXPECT_EQ(s.y[2], 3.0);
      EXPECT_NEAR(s.y[3], a[0], 1e-6);  // asin near ±π/2 loses digits
      EXPECT_NEAR(s.y[4], a[1], 1e-6);
      EXPECT_NEAR(s.y[5], a[2], 1e-6);
      EXPECT_EQ(s.u, (std::array<double, 4>{0.1, 0.2, 0.3, 0.4}));
    }
  }
  // Where both are given, roll, pitch, yaw win and the quaternion is an ignored extra column.
  const TelemetrySample both = readOne("t,x,y,z,roll,pitch,yaw,qw,qx,qy,qz,u1,u2,u3,u4\n0,0,0,0,0.1,0.2,0.3,1,0,0,0,1,1,1,1\n");
  EXPECT_EQ(both.y[3], 0.1);
  EXPECT_EQ(both.y[5], 0.3);
}

// NED/FRD, as PX4, ArduPilot and AirSim write it, turns into quadfdi's frames: a vehicle 3 m up
// heading east, nose 10° up and right wing 20° down is, in (north, west, up) with an FLU body,
// at z = +3, yaw −90°, pitch −10° (FLU's pitch is about the left axis) and roll +20°; the same
// from Euler columns and from a quaternion.
TEST(TelemetryCsv, NedFramesTurnIntoQuadfdis) {
  const double roll = 20 * M_PI / 180, pitch = 10 * M_PI / 180, yaw = M_PI / 2;  // NED/FRD
  const std::array<double, 4> q = quaternionOfZyx(roll, pitch, yaw);
  const std::string euler = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,1,2,-3," + number(roll) + "," + number(pitch) + "," + number(yaw) + ",1,2,3,4\n";
  const std::string quaternion = "t,x,y,z,qw,qx,qy,qz,u1,u2,u3,u4\n0,1,2,-3," + number(q[0]) + "," + number(q[1]) + "," + number(q[2]) + "," +
                                 number(q[3]) + ",1,2,3,4\n";
  for (const std::string& csv : {euler, quaternion}) {
    TelemetryReaderOptions ned;
    ned.frame = TelemetryFrame::kNed;
    const TelemetrySample s = readOne(csv, ned);
    EXPECT_EQ(s.y[0], 1.0);
    EXPECT_EQ(s.y[1], -2.0);
    EXPECT_EQ(s.y[2], 3.0);
    EXPECT_NEAR(s.y[3], roll, 1e-12);
    EXPECT_NEAR(s.y[4], -pitch, 1e-12);
    EXPECT_NEAR(s.y[5], -M_PI / 2, 1e-12);
    EXPECT_EQ(s.u, (std::array<double, 4>{1, 2, 3, 4}));
  }
}

// Rotor speeds are read as their squares (thrust up to k_f), in any unit: RPM far past the 500 N
// bound on thrust, and a signed speed (a clockwise rotor's, in some simulators) alike.
TEST(TelemetryCsv, RotorSpeedsAreReadAsTheirSquares) {
  const std::string csv = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,0,0,0,0,20000,-0.5,3,0\n";
  TelemetryReaderOptions speeds;
  speeds.commands = CommandQuantity::kRotorSpeed;
  EXPECT_EQ(readOne(csv, speeds).u, (std::array<double, 4>{4e8, 0.25, 9, 0}));
  const std::string thrust = firstRefusal(csv, "thrust.csv");
  EXPECT_EQ(thrust.rfind("thrust.csv:2: column 'u1' = 20000 is no thrust in newtons", 0), 0u) << thrust;
}

// Throttles and PWM pulses go through the vehicle's thrust curve f = max·((1 − k)c + k c²):
// max 10 N, k = 0.5 here, so c = 0.5 (or 1500 µs in 1000–2000) gives 10·(0.25 + 0.125) = 3.75 N.
// A throttle a little outside [0, 1] is clamped; one far outside, or a pulse past the range by
// its width, is another quantity and refused naming the line and column.
TEST(TelemetryCsv, ThrottleAndPwmCommandsGoThroughTheVehiclesThrustCurve) {
  TelemetryReaderOptions throttle;
  throttle.commands = CommandQuantity::kThrottle;
  throttle.curve.max_thrust = 10.0;
  throttle.curve.model_factor = 0.5;
  EXPECT_EQ(readOne("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,0,0,0,0,0.5,1,0,-0.01\n", throttle).u,
            (std::array<double, 4>{3.75, 10.0, 0.0, 0.0}));
  EXPECT_NEAR(readOne("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,0,0,0,0,1.04,0.2,0,0\n", throttle).u[1],
              10.0 * (0.5 * 0.2 + 0.5 * 0.04), 1e-15);
  EXPECT_EQ(firstRefusal("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,0,0,0,0,0.5,0.5,1500,0.5\n", "throttle.csv", throttle),
            "throttle.csv:2: column 'u3' = 1500 is no throttle in [0, 1] (--csv-commands throttle): a PWM pulse "
            "(--csv-commands pwm) or a thrust in newtons (--csv-commands thrust)?");

  TelemetryReaderOptions pwm = throttle;
  pwm.commands = CommandQuantity::kPwm;
  EXPECT_EQ(readOne("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,0,0,0,0,1500,2000,1000,0\n", pwm).u,
            (std::array<double, 4>{3.75, 10.0, 0.0, 0.0}));  // 0 µs: an output switched off
  pwm.curve.pwm_min = 1100;
  pwm.curve.pwm_max = 1900;
  EXPECT_EQ(readOne("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,0,0,0,0,1500,1950,1050,2700\n", pwm).u,
            (std::array<double, 4>{3.75, 10.0, 0.0, 10.0}));
  EXPECT_EQ(firstRefusal("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,0,0,0,0,1500,1500,1500,32768\n", "pwm.csv", pwm),
            "pwm.csv:2: column 'u4' = 32768 is no PWM pulse in µs between 1100 and 1900 (--csv-commands pwm; the range: "
            "--csv-pwm-min, --csv-pwm-max)");
  // Read as thrust, a pulse says what it may be.
  const std::string thrust = firstRefusal("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,0,0,0,0,1500,1500,1500,1500\n", "t.csv");
  EXPECT_NE(thrust.find("PWM or a throttle? read it with --csv-commands pwm or throttle"), std::string::npos) << thrust;
  // A curve that maps nothing is a programming error.
  TelemetryReaderOptions no_curve;
  no_curve.commands = CommandQuantity::kThrottle;
  std::istringstream header("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n");
  EXPECT_THROW(TelemetryReader(header, "x.csv", no_curve), std::invalid_argument);
}

// A date and time in t (ISO 8601, as pandas, spreadsheets and ROS tools write it) is seconds since
// 1970 UTC: the zone's offset taken out, a leap day and the fraction kept; a malformed one is named.
TEST(TelemetryCsv, DateAndTimeStampsAreSecondsSince1970) {
  const std::string header = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n";
  auto at = [&](const std::string& stamp) { return readOne(header + stamp + ",0,0,0,0,0,0,1,1,1,1\n").t; };
  // 2026-12-01 00:00 UTC is day 20 788 since 1970-01-01 (56 years of 365 days + 14 leap days + 334).
  EXPECT_EQ(at("2026-12-01T00:00:00Z"), 20788.0 * 86400.0);
  EXPECT_EQ(at("2026-12-01 21:00:00.25"), 20788.0 * 86400.0 + 21 * 3600 + 0.25);
  EXPECT_EQ(at("2026-12-01T22:30:00.25+01:30"), 20788.0 * 86400.0 + 21 * 3600 + 0.25);
  EXPECT_EQ(at("2026-12-01T19:00:00.25-0200"), 20788.0 * 86400.0 + 21 * 3600 + 0.25);
  EXPECT_EQ(at("1970-01-01T00:00:00Z"), 0.0);
  EXPECT_EQ(at("2000-03-01T00:00:00Z") - at("2000-02-28T00:00:00Z"), 2 * 86400.0);  // 2000 is a leap year
  EXPECT_EQ(at("2100-03-01T00:00:00Z") - at("2100-02-28T00:00:00Z"), 86400.0);      // 2100 is not
  EXPECT_NEAR(at("2026-12-01T21:00:00.002Z") - at("2026-12-01T21:00:00Z"), 0.002, 1e-6);
  for (const std::string bad : {"2026-13-01T00:00:00", "2026-02-29 00:00:00", "2026-12-01T24:00:00", "2026-12-01",
                                "2026-12-01T00:00:00.", "2026-12-01T00:00:00+1", "2026-12-01T00:00:00 UTC"})
    EXPECT_EQ(firstRefusal(header + bad + ",0,0,0,0,0,0,1,1,1,1\n", "dates.csv"),
              "dates.csv:2: t = '" + bad + "' is no date and time (YYYY-MM-DD hh:mm:ss[.fraction][Z or ±hh:mm]) nor a number")
        << bad;
}

// Units in the header ("t [ms]", "roll (deg)", as spreadsheets and MATLAB tables name columns) are
// read as the matching options; units quadfdi does not read, or that contradict each other or the
// options, are refused naming the column.
TEST(TelemetryCsv, UnitsInTheHeaderAreReadOrRefused) {
  const std::string row = "2,0.5,0,1,10,-5,180,0.1,0.1,0.1,0.1\n";
  TelemetryReaderOptions told;
  told.time_unit = 1e-3;
  told.angles_in_degrees = true;
  const TelemetrySample expected = readOne("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n" + row, told);
  const TelemetrySample got =
      readOne("t [ms],x [m],y [m],z [m],roll (deg),pitch (deg),yaw (\u00b0),u1 [N],u2 [N],u3 [N],u4 [N]\n" + row);
  EXPECT_EQ(got.t, expected.t);
  EXPECT_EQ(got.t, 0.002);
  EXPECT_EQ(got.y, expected.y);
  EXPECT_EQ(got.u, expected.u);
  // The same unit given twice, header and option, is no contradiction; and a column named with a
  // unit is named so in messages.
  std::istringstream empty_cell("t [ms],x [m],y,z,roll,pitch,yaw,u1,u2,u3,u4\n2,,0,1,0,0,0,1,1,1,1\n");
  TelemetryReaderOptions ms;
  ms.time_unit = 1e-3;
  TelemetryReader reader(empty_cell, "named.csv", ms);
  TelemetrySample s;
  std::string problem;
  EXPECT_EQ(reader.next(s, problem), SampleSource::Next::kSkipped);
  EXPECT_EQ(problem, "named.csv:2: column 'x [m]' is empty; row skipped");
  const std::string rest = ",x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n";
  EXPECT_EQ(firstRefusal("t [min]" + rest, "u.csv"), "u.csv:1: column 't [min]': the unit 'min' is no time unit read here (s, ms, us or ns)");
  EXPECT_EQ(firstRefusal("t [s]" + rest, "u.csv", ms), "u.csv:1: column 't [s]': the header says s, --csv-time-unit another unit");
  EXPECT_EQ(firstRefusal("t,x [mm],y,z,roll,pitch,yaw,u1,u2,u3,u4\n", "u.csv"),
            "u.csv:1: column 'x [mm]': the unit 'mm' is not read here: positions are in metres (m)");
  EXPECT_EQ(firstRefusal("t,x,y,z,roll [deg],pitch [rad],yaw,u1,u2,u3,u4\n", "u.csv"),
            "u.csv:1: column 'pitch [rad]': the header says rad here and another unit for another angle");
  EXPECT_EQ(firstRefusal("t,x,y,z,roll [rad],pitch,yaw,u1,u2,u3,u4\n", "u.csv", told),
            "u.csv:1: column 'roll [rad]': the header says rad, --csv-angle-unit deg");
  EXPECT_EQ(firstRefusal("t,x,y,z,roll,pitch,yaw,u1 [rpm],u2,u3,u4\n", "u.csv"),
            "u.csv:1: column 'u1 [rpm]': the unit 'rpm' does not fit the commands read (thrust in N; rotor speeds, "
            "throttle or PWM pulses: --csv-commands rotor-speed, throttle or pwm)");
  TelemetryReaderOptions rotor;
  rotor.commands = CommandQuantity::kRotorSpeed;
  EXPECT_EQ(firstRefusal("t,x,y,z,roll,pitch,yaw,u1 [rpm],u2 [rpm],u3 [rpm],u4 [rpm]\n", "u.csv", rotor), "accepted");
  EXPECT_EQ(firstRefusal("t,x,y,z,qw [rad],qx,qy,qz,u1,u2,u3,u4\n", "u.csv"),
            "u.csv:1: column 'qw [rad]': a quaternion has no unit, the header says 'rad'");
  // A column named with its unit and again without is named twice, as two plain ones are.
  EXPECT_EQ(firstRefusal("t,x [m],y,z,roll,pitch,yaw,u1,u2,u3,u4,x\n", "u.csv"), "u.csv:1: column 'x' appears twice in the header");
  // A unit on a column quadfdi does not read is none of its business; one on a name it does not
  // know leaves the column unnamed.
  EXPECT_EQ(firstRefusal("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,battery [V]\n", "u.csv"), "accepted");
  EXPECT_EQ(firstRefusal("time [s],x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n", "u.csv").substr(0, 40),
            "u.csv:1: the header lacks column 't' (ne");
}

// Tab-, semicolon- and blank-separated tables (spreadsheets, pandas with sep='\t', MATLAB and
// gnuplot data files) read as the comma-separated file they copy, cell for cell; the separator is
// the header's, and a decimal comma is named, not misread.
TEST(TelemetryCsv, TabSemicolonAndBlankSeparatedFilesReadAsCommaSeparated) {
  std::ostringstream comma;
  writeTelemetryCsvHeader(comma);
  for (int k = 0; k < 3; ++k) {
    TelemetrySample a;
    a.t = 0.002 * k;
    a.y = {0.1 * k, -1.0 / 3.0, 1.25, 0.01 * k, -0.002, 1e-9};
    a.u = {0.07, 0.071, 1.0 / 7.0, 0.0015 * k};
    writeTelemetryCsvRow(comma, a);
  }
  auto readAll = [](const std::string& text, const std::string& name) {
    std::istringstream in(text);
    TelemetryReader reader(in, name);
    std::vector<TelemetrySample> samples;
    TelemetrySample s;
    std::string problem;
    for (SampleSource::Next n; (n = reader.next(s, problem)) != SampleSource::Next::kEnd;) {
      EXPECT_EQ(n, SampleSource::Next::kSample) << problem;
      samples.push_back(s);
    }
    return samples;
  };
  const std::vector<TelemetrySample> expected = readAll(comma.str(), "comma.csv");
  ASSERT_EQ(expected.size(), 3u);
  auto replaced = [&](const std::string& by, bool pad) {
    std::string out = pad ? "  " : "";
    for (char c : comma.str()) {
      if (c == ',') out += by;
      else if (c == '\n' && pad) out += "  \r\n  ";
      else out += c;
    }
    return out;
  };
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"tabs.tsv", replaced("\t", false)}, {"semicolons.csv", replaced(";", false)},
           {"blanks.txt", replaced(" \t  ", true)}}) {
    const std::vector<TelemetrySample> got = readAll(text, name);
    ASSERT_EQ(got.size(), expected.size()) << name;
    for (std::size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].t, expected[k].t) << name;
      EXPECT_EQ(got[k].y, expected[k].y) << name;
      EXPECT_EQ(got[k].u, expected[k].u) << name;
    }
  }
  // Tabs separate exactly: two tabs are an empty cell, as two commas are.
  std::istringstream gap("t\tx\ty\tz\troll\tpitch\tyaw\tu1\tu2\tu3\tu4\n0\t\t0\t1\t0\t0\t0\t1\t1\t1\t1\n");
  TelemetryReader tabs(gap, "gap.tsv");
  TelemetrySample s;
  std::string problem;
  EXPECT_EQ(tabs.next(s, problem), SampleSource::Next::kSkipped);
  EXPECT_EQ(problem, "gap.tsv:2: column 'x' is empty; row skipped");
  // A row with another number of cells than the header is refused as in a comma-separated file.
  EXPECT_EQ(firstRefusal("t x y z roll pitch yaw u1 u2 u3 u4\n0 0 0 1 0 0 0 1 1 1\n", "short.txt"),
            "short.txt:2: 10 cells, the header has 11");
  EXPECT_EQ(firstRefusal("t;x;y;z;roll;pitch;yaw;u1;u2;u3;u4\n0;0,5;0;1;0;0;0;1;1;1;1\n", "excel.csv"),
            "excel.csv:2: column 'x': '0,5' is not a number (a decimal comma? numbers are read with a decimal point)");
}

// t may be an absolute clock: seconds since 1970 read exactly (the network never sees t). Micro-
// or nanoseconds since 1970 are refused with their unit named; other columns keep their bound.
TEST(TelemetryCsv, AnAbsoluteClockIsReadAndANanosecondOneRefused) {
  EXPECT_EQ(readOne("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n1764370000.002,0,0,0,0,0,0,1,1,1,1\n").t, 1764370000.002);
  EXPECT_EQ(firstRefusal("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n1764370000002000000,0,0,0,0,0,0,1,1,1,1\n", "ns.csv"),
            "ns.csv:2: t = 1764370000002000000 is no time in seconds (over 1e13 s): microseconds or nanoseconds since 1970? "
            "detect reads seconds (--csv-time-unit us or ns)");
  TelemetrySample s;
  std::string problem;
  std::istringstream big("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,2e9,0,0,0,0,0,1,1,1,1\n");
  TelemetryReader position(big, "big.csv");
  EXPECT_EQ(position.next(s, problem), SampleSource::Next::kSkipped);
  EXPECT_EQ(problem, "big.csv:2: column 'x' = 2e9 is out of range; row skipped");
}

// An export names its columns its own way (PlotJuggler: the topic path) and stamps rows in
// nanoseconds (ROS): the header names and the time unit are options; messages use the file's names.
TEST(TelemetryCsv, ColumnsNamedOtherwiseAndATimeUnitAreRead) {
  TelemetryReaderOptions o;
  o.header_names = {{"t", "__time"}, {"x", "/pose/position/x"}, {"u2", "/motors/1"}};
  o.time_unit = 1e-9;
  std::istringstream in("__time,/pose/position/x,y,z,roll,pitch,yaw,u1,/motors/1,u3,u4,x,u2\n"
                        "1764370000002000000,0.5,0,1,0,0,0,1,2,3,4,9,9\n"
                        "1764370000004000000,,0,1,0,0,0,1,2,3,4,9,9\n");
  TelemetryReader reader(in, "export.csv", o);
  TelemetrySample s;
  std::string problem;
  ASSERT_EQ(reader.next(s, problem), SampleSource::Next::kSample) << problem;
  EXPECT_NEAR(s.t, 1764370000.002, 1e-6);  // ns since 1970 in a double: 256 ns apart
  EXPECT_EQ(s.y[0], 0.5);  // not the file's own column 'x' (9)
  EXPECT_EQ(s.u[1], 2.0);
  ASSERT_EQ(reader.next(s, problem), SampleSource::Next::kSkipped);
  EXPECT_EQ(problem, "export.csv:3: column '/pose/position/x' is empty; row skipped");
  // A name the header lacks is named with the column it was given for.
  std::istringstream lacking("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n");
  TelemetryReaderOptions absent;
  absent.header_names = {{"x", "/pose/x"}};
  try {
    TelemetryReader r(lacking, "lacking.csv", absent);
    ADD_FAILURE() << "accepted";
  } catch (const TelemetryError& e) {
    EXPECT_STREQ(e.what(), "lacking.csv:1: the header lacks column '/pose/x' (read as x, --csv-columns)");
  }
  // A name for no column, or one column named twice, is a programming error (the CLI checks first).
  for (const auto& bad : std::vector<std::vector<std::pair<std::string, std::string>>>{{{"vx", "a"}}, {{"x", "a"}, {"x", "b"}}}) {
    std::istringstream header("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n");
    TelemetryReaderOptions wrong;
    wrong.header_names = bad;
    EXPECT_THROW(TelemetryReader(header, "x.csv", wrong), std::invalid_argument);
  }
}

// Angles in degrees, when the options say so: the same sample as in radians, and bounds in degrees.
TEST(TelemetryCsv, AnglesInDegreesAreReadWhenSaid) {
  TelemetryReaderOptions deg;
  deg.angles_in_degrees = true;
  std::istringstream in("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,1,30,-45,170,1,1,1,1\n0.002,0,0,1,30,-95,0,1,1,1,1\n");
  TelemetryReader reader(in, "deg.csv", deg);
  TelemetrySample s;
  std::string problem;
  ASSERT_EQ(reader.next(s, problem), SampleSource::Next::kSample) << problem;
  EXPECT_NEAR(s.y[3], M_PI / 6, 1e-15);
  EXPECT_NEAR(s.y[4], -M_PI / 4, 1e-15);
  EXPECT_NEAR(s.y[5], 170 * M_PI / 180, 1e-15);
  try {
    reader.next(s, problem);
    ADD_FAILURE() << "accepted";
  } catch (const TelemetryError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("deg.csv:3: pitch = -95 is outside ±90°: roll, pitch, yaw are ZYX Euler angles (read in degrees", 0), 0u)
        << e.what();
  }
}

TEST(TelemetryCsv, QuaternionColumnsAreCheckedAndNamed) {
  auto refusal = [](const std::string& csv) { return firstRefusal(csv, "q.csv"); };
  // A quaternion missing a column, and no attitude at all.
  EXPECT_EQ(refusal("t,x,y,z,qw,qx,qy,u1,u2,u3,u4\n"),
            "q.csv:1: the header lacks column 'qz' (needs t,x,y,z,qw,qx,qy,qz,u1,u2,u3,u4; others are ignored; --csv-columns "
            "reads a column named otherwise)");
  EXPECT_EQ(refusal("t,x,y,z,u1,u2,u3,u4\n"),
            "q.csv:1: the header lacks column 'roll' (needs t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4, or qw,qx,qy,qz for the attitude; "
            "others are ignored; --csv-columns reads a column named otherwise)");
  // Euler angles named in part are Euler angles, whatever quaternion is there.
  EXPECT_EQ(refusal("t,x,y,z,roll,pitch,qw,qx,qy,qz,u1,u2,u3,u4\n"),
            "q.csv:1: the header lacks column 'yaw' (needs t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4, or qw,qx,qy,qz for the attitude; "
            "others are ignored; --csv-columns reads a column named otherwise)");
  EXPECT_EQ(refusal("t,x,y,z,qw,qx,qy,qz,qw,u1,u2,u3,u4\n"), "q.csv:1: column 'qw' appears twice in the header");
  // Rounded to four digits is a unit quaternion; 2 % off is not one.
  EXPECT_EQ(refusal("t,x,y,z,qw,qx,qy,qz,u1,u2,u3,u4\n0,0,0,0,0.7071,0,0,0.7071,1,1,1,1\n"), "accepted");
  const std::string off = refusal("t,x,y,z,qw,qx,qy,qz,u1,u2,u3,u4\n0,0,0,0,0.7071,0,0,0.7071,1,1,1,1\n0.002,0,0,0,1.02,0,0,0,1,1,1,1\n");
  EXPECT_EQ(off.rfind("q.csv:3: qw,qx,qy,qz = 1.02,0,0,0 is no unit quaternion (norm 1.02", 0), 0u) << off;
  // An all-zero quaternion (before an estimator's first attitude) drops its row, naming it.
  std::istringstream zero("t,x,y,z,qw,qx,qy,qz,u1,u2,u3,u4\n0,0,0,0,0,0,0,0,1,1,1,1\n0.002,0,0,0,1,0,0,0,1,1,1,1\n");
  TelemetryReader reader(zero, "zero.csv");
  EXPECT_TRUE(reader.quaternionAttitude());
  TelemetrySample s;
  std::string problem;
  EXPECT_EQ(reader.next(s, problem), SampleSource::Next::kSkipped);
  EXPECT_EQ(problem, "zero.csv:2: the quaternion qw,qx,qy,qz is zero; row skipped");
  EXPECT_EQ(reader.next(s, problem), SampleSource::Next::kSample);
  EXPECT_EQ(s.t, 0.002);
}

// Body rates: optional columns p, q, r, written by import for a log that records them and read
// back bit for bit; without them the source says it carries none (a rates model then refuses it).
TEST(TelemetryCsv, BodyRatesRoundTripAndAreOptional) {
  TelemetrySample a;
  a.t = 0.25;
  a.y = {0.1, -0.2, 1.5, 0.01, -0.02, 3.0};
  a.u = {0.07, 0.071, 1.0 / 7.0, 0.0015};
  a.rates = {0.5, -1.0 / 3.0, 2.25};
  std::stringstream csv;
  writeTelemetryCsvHeader(csv, {}, true);
  writeTelemetryCsvRow(csv, a, true);
  EXPECT_EQ(csv.str().substr(0, csv.str().find('\n')), "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,p,q,r");
  TelemetryReader reader(csv, "rates.csv");
  EXPECT_TRUE(reader.carriesRates());
  TelemetrySample b;
  std::string problem;
  ASSERT_EQ(reader.next(b, problem), SampleSource::Next::kSample) << problem;
  EXPECT_EQ(b.rates, a.rates);
  EXPECT_EQ(b.y, a.y);
  std::istringstream plain("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,0,0,0,0,1,1,1,1\n");
  TelemetryReader without(plain, "plain.csv");
  EXPECT_FALSE(without.carriesRates());
  ASSERT_EQ(without.next(b, problem), SampleSource::Next::kSample);
  EXPECT_EQ(b.rates, (std::array<double, 3>{0, 0, 0}));
}

// A flight's logged rates (gyro noise and all), written alone or with the full state, read back
// exactly; a log without logged rates writes the true ones.
TEST(TelemetryCsv, AFlightsLoggedRatesAreWrittenAndReadBack) {
  FlightLog log = threeStepLog();
  for (const bool full_state : {false, true}) {
    TelemetryCsvOptions o;
    o.rates = !full_state;
    o.full_state = full_state;
    for (const bool logged : {false, true}) {
      log.rates.clear();
      if (logged) {
        for (int k = 0; k < 3; ++k) log.rates.push_back(Vec3(0.5 + k, -1.0 / 3.0, 0.125 * k));
      }
      std::stringstream csv;
      writeTelemetryCsv(csv, log, o);
      if (!full_state) {
        EXPECT_EQ(csv.str().substr(0, csv.str().find('\n')), "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,p,q,r");
      }
      TelemetryReader reader(csv, "flight.csv");
      ASSERT_TRUE(reader.carriesRates());
      TelemetrySample b;
      std::string problem;
      for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_EQ(reader.next(b, problem), SampleSource::Next::kSample) << problem;
        const Vec3 want = logged ? log.rates[k] : Vec3(log.states[k].segment<3>(idx::kRate));
        for (int i = 0; i < 3; ++i) EXPECT_EQ(b.rates[static_cast<std::size_t>(i)], want(i)) << full_state << logged << k;
      }
    }
  }
}

// FRD body rates (PX4, ArduPilot, Gazebo) turn into FLU ones as the body does (180° about x: p,
// −q, −r); degrees per second from the header or the option; mixed units, a partial set and a rate
// beyond any gyro's range are refused, naming the line.
TEST(TelemetryCsv, BodyRatesInNedAndDegreesAndTheirRefusals) {
  const std::string head = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,";
  const std::string row = "0,0,0,0,0,0,0,1,1,1,1,0.1,0.2,-0.3\n";
  TelemetryReaderOptions ned;
  ned.frame = TelemetryFrame::kNed;
  const TelemetrySample frd = readOne(head + "p,q,r\n" + row, ned);
  EXPECT_EQ(frd.rates, (std::array<double, 3>{0.1, -0.2, 0.3}));
  const TelemetrySample deg = readOne(head + "p [deg/s],q [deg/s],r [deg/s]\n" + row);
  TelemetryReaderOptions told;
  told.rates_in_degrees = true;
  const TelemetrySample deg_told = readOne(head + "p,q,r\n" + row, told);
  EXPECT_EQ(deg.rates, deg_told.rates);
  EXPECT_NEAR(deg.rates[1], 0.2 * M_PI / 180.0, 1e-15);
  EXPECT_EQ(firstRefusal(head + "p [deg/s],q [rad/s],r\n", "u.csv"),
            "u.csv:1: column 'q [rad/s]': the header says rad/s here and another unit for another rate");
  EXPECT_EQ(firstRefusal(head + "p [rpm],q,r\n", "u.csv"),
            "u.csv:1: column 'p [rpm]': the unit 'rpm' is no angular rate unit read here (rad/s or deg/s)");
  EXPECT_EQ(firstRefusal(head + "p,q\n", "u.csv"),
            "u.csv:1: the header has body rates and lacks column 'r' (p, q, r [rad/s] come together, or not at all)");
  EXPECT_EQ(firstRefusal(head + "p,q,r\n0,0,0,0,0,0,0,1,1,1,1,0,0,0\n0.002,0,0,0,0,0,0,1,1,1,1,0,150,0\n", "u.csv"),
            "u.csv:3: q = 150 is no body rate in rad/s (over 100 rad/s): degrees per second? --csv-rate-unit deg/s");
  // For a model that does not read them (read_rates false) they are extra columns, whatever they hold.
  TelemetryReaderOptions unread;
  unread.read_rates = false;
  EXPECT_EQ(firstRefusal(head + "p,q,r\n0,0,0,0,0,0,0,1,1,1,1,0,150,\n", "u.csv", unread), "accepted");
  EXPECT_EQ(firstRefusal(head + "p [rpm],q\n0,0,0,0,0,0,0,1,1,1,1,0,150\n", "u.csv", unread), "accepted");
  // An empty rate cell drops its row, as any read cell's does.
  std::istringstream hole(head + "p,q,r\n0,0,0,0,0,0,0,1,1,1,1,0,,0\n");
  TelemetryReader reader(hole, "hole.csv");
  TelemetrySample s;
  std::string problem;
  EXPECT_EQ(reader.next(s, problem), SampleSource::Next::kSkipped);
  EXPECT_EQ(problem, "hole.csv:2: column 'q' is empty; row skipped");
}

}  // namespace
}  // namespace quadfdi
