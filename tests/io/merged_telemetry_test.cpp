// A merged export (each row holds some of the signals) read into FlightSignals: every signal from
// the rows that hold it whole, converted as a whole row is, and bad rows named by line.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "io/merged_telemetry.h"
#include "io/telemetry_reader.h"

namespace quadfdi {
namespace {

FlightSignals readMerged(const std::string& text, MergedTelemetryCounts* counts = nullptr,
                         const TelemetryReaderOptions& options = {}) {
  std::istringstream in(text);
  TelemetryReader reader(in, "merged.csv", options);
  FlightSignals s;
  const MergedTelemetryCounts c = readMergedTelemetry(reader, s);
  if (counts) *counts = c;
  return s;
}

std::string errorOf(const std::string& text) {
  try {
    readMerged(text);
  } catch (const TelemetryError& e) {
    return e.what();
  }
  return "";
}

TEST(MergedTelemetry, EachSignalComesFromTheRowsThatHoldItWhole) {
  const std::string text =
      "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,battery\n"
      "0.000,1,2,3,,,,,,,,\n"             // position
      "0.000,,,,0.1,0.2,0.3,,,,,\n"       // attitude, same time
      "0.002,,,,,,,0.5,0.6,0.7,0.8,\n"    // commands
      "0.003,,,,,,,,,,,12.1\n"            // another topic's column only
      ",4,5,6,,,,,,,,\n"                  // no time: skipped
      "0.004,4,,6,0.4,0.5,0.6,,,,,\n"     // position lacks y: left out; attitude kept
      "0.006,7,8,9,,,,0.9,1.0,1.1,1.2,\n";
  MergedTelemetryCounts c;
  const FlightSignals s = readMerged(text, &c);
  EXPECT_EQ(c.rows, 7u);
  EXPECT_EQ(c.without_time, 1u);
  EXPECT_EQ(c.without_signal, 1u);
  EXPECT_EQ(c.partial, 1u);
  EXPECT_EQ(c.first_problem, "merged.csv:6: column 't' is empty; row skipped");
  ASSERT_EQ(s.position.t, (std::vector<double>{0.0, 0.006}));
  EXPECT_EQ(s.position.v[1], (std::array<double, 3>{7, 8, 9}));
  ASSERT_EQ(s.attitude.t, (std::vector<double>{0.0, 0.004}));
  EXPECT_EQ(s.attitude.v[1], (std::array<double, 3>{0.4, 0.5, 0.6}));
  ASSERT_EQ(s.command.t, (std::vector<double>{0.002, 0.006}));
  EXPECT_EQ(s.command.v[0], (std::array<double, 4>{0.5, 0.6, 0.7, 0.8}));
  EXPECT_EQ(s.command_kind, CommandKind::kThrustNewton);
  // The file is the flight: one "airborne" event at its first row.
  ASSERT_EQ(s.states.size(), 1u);
  EXPECT_EQ(s.states[0].t, 0.0);
  EXPECT_TRUE(s.states[0].armed);
  EXPECT_FALSE(s.states[0].landed);
  EXPECT_EQ(s.position.source.topic, "columns x,y,z");
  EXPECT_TRUE(s.numbering.isQuadfdis());
}

// Body rates on rows of their own (a ROS bag's IMU topic) are a signal like the others: read, not
// skipped as rows without a signal (they were, until 2026-12-06).
TEST(MergedTelemetry, BodyRatesOnRowsOfTheirOwnAreRead) {
  const std::string text =
      "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,p,q,r\n"
      "0.000,1,2,3,,,,,,,,,,\n"
      "0.001,,,,,,,,,,,0.1,0.2,0.3\n"
      "0.002,,,,0.1,0.2,0.3,,,,,,,\n"
      "0.003,,,,,,,,,,,0.4,0.5,0.6\n"
      "0.004,,,,,,,0.5,0.6,0.7,0.8,,,\n";
  MergedTelemetryCounts c;
  const FlightSignals s = readMerged(text, &c);
  EXPECT_EQ(c.without_signal, 0u);
  ASSERT_EQ(s.rates.t, (std::vector<double>{0.001, 0.003}));
  EXPECT_EQ(s.rates.v[1], (std::array<double, 3>{0.4, 0.5, 0.6}));
  EXPECT_EQ(s.rates.source.topic, "columns p,q,r");
}

// A row of every signal is read as the plain reader reads it, frames and quantities included.
TEST(MergedTelemetry, WholeRowsReadAsThePlainReaderReadsThem) {
  const std::string text =
      "# motor_numbering: PX4 = 1 4 2 3\n"
      "t,x,y,z,qw,qx,qy,qz,u1,u2,u3,u4\n"
      "1.000,1,2,-3,0.5,0.5,-0.5,0.5,1200,1400,1500,1600\n"
      "1.002,1.1,2.1,-3.1,0.8,0.2,-0.4,0.4,1250,1450,1550,1650\n";
  TelemetryReaderOptions o;
  o.frame = TelemetryFrame::kNed;
  o.commands = CommandQuantity::kPwm;
  o.curve.max_thrust = 8.0;
  o.curve.model_factor = 0.5;
  std::istringstream plain_in(text);
  TelemetryReader plain(plain_in, "merged.csv", o);
  const FlightSignals s = readMerged(text, nullptr, o);
  ASSERT_EQ(s.attitude.t.size(), 2u);
  ASSERT_EQ(s.command.t.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    TelemetrySample row;
    std::string problem;
    ASSERT_EQ(plain.next(row, problem), SampleSource::Next::kSample) << problem;
    EXPECT_EQ(s.position.t[k], row.t);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(s.position.v[k][i], row.y[i]);
      EXPECT_EQ(s.attitude.v[k][i], row.y[3 + i]);
    }
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(s.command.v[k][i], row.u[i]);
  }
  EXPECT_EQ(s.position.v[0][2], 3.0);  // NED down −3 is up +3
  EXPECT_EQ(s.numbering.name, "PX4");
  EXPECT_EQ(s.numbering.autopilot_motor, (std::array<int, 4>{1, 4, 2, 3}));
}

// One topic per motor (a simulator publishing each rotor's command on its own): each motor read
// from the rows that give it, all four held to every time one of them is given, from the first
// time all four have been.
TEST(MergedTelemetry, MotorsOnRowsOfTheirOwnAreEachHeldToTheOthersTimes) {
  MergedTelemetryCounts c;
  const FlightSignals s = readMerged(
      "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n"
      "0.000,,,,,,,1,,,\n"
      "0.000,,,,,,,,2,,\n"
      "0.001,,,,,,,,,3,\n"
      "0.001,0,0,1,,,,,,,\n"     // position between the motors' rows
      "0.002,,,,,,,,,,4\n"       // all four given: the commands start here
      "0.003,,,,,,,5,,,\n"
      "0.004,,,,,,,,6,7,\n"      // two motors on one row
      "0.006,,,,,,,8,9,10,11\n", // and all four on one
      &c);
  EXPECT_EQ(c.split_commands, 6u);
  EXPECT_EQ(c.partial, 0u);  // a motor alone is no partial signal
  ASSERT_EQ(s.command.t, (std::vector<double>{0.002, 0.003, 0.004, 0.006}));
  EXPECT_EQ(s.command.v[0], (std::array<double, 4>{1, 2, 3, 4}));
  EXPECT_EQ(s.command.v[1], (std::array<double, 4>{5, 2, 3, 4}));
  EXPECT_EQ(s.command.v[2], (std::array<double, 4>{5, 6, 7, 4}));
  EXPECT_EQ(s.command.v[3], (std::array<double, 4>{8, 9, 10, 11}));
  ASSERT_EQ(s.command_times_per_motor.size(), 4u);
  EXPECT_EQ(s.command_times_per_motor[0], (std::vector<double>{0.0, 0.003, 0.006}));
  EXPECT_EQ(s.command_times_per_motor[3], (std::vector<double>{0.002, 0.006}));
  EXPECT_EQ(s.command.source.note, "each motor held from its own rows to the others' times");
  bool said = false;
  for (const std::string& line : s.conventions) said = said || line.find("6 rows with some of u1..u4 and not all") == 0;
  EXPECT_TRUE(said);
  // A NaN command is no command of that motor, and said; the others on its row are read.
  MergedTelemetryCounts nan_counts;
  const FlightSignals nan = readMerged("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,,,,,,,1,2,3,4\n0.002,,,,,,,5,6,nan,8\n", &nan_counts);
  EXPECT_EQ(nan_counts.partial, 1u);
  EXPECT_EQ(nan_counts.first_problem, "merged.csv:3: column 'u3' is nan; that signal left out of the row");
  ASSERT_EQ(nan.command.t.size(), 2u);
  EXPECT_EQ(nan.command.v[1], (std::array<double, 4>{5, 6, 3, 8}));
  // Read in a vehicle's numbering (--csv-numbering vehicle): quadfdi motor k + 1 from the file's u_m, m = file_motor[k].
  TelemetryReaderOptions px4;
  px4.file_motor = {1, 4, 2, 3};
  const FlightSignals reordered = readMerged("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,,,,,,,1,2,,\n0,,,,,,,,,3,4\n", nullptr, px4);
  ASSERT_EQ(reordered.command.t.size(), 1u);
  EXPECT_EQ(reordered.command.v[0], (std::array<double, 4>{1, 4, 2, 3}));
  px4.file_motor = {1, 1, 2, 3};
  EXPECT_THROW(readMerged("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n", nullptr, px4), std::invalid_argument);
  // A motor never given: no commands at all (the conventions layer refuses that, naming the column).
  const FlightSignals none = readMerged("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,,,,,,,1,2,3,\n0.002,,,,,,,1,2,3,\n");
  EXPECT_TRUE(none.command.empty());
  EXPECT_TRUE(none.command_times_per_motor.at(3).empty());
  // Whole rows only: the motors are not split, and the series is the rows' own.
  const FlightSignals whole = readMerged("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,,,,,,,1,2,3,4\n0.002,,,,,,,5,6,7,8\n");
  EXPECT_TRUE(whole.command_times_per_motor.empty());
  EXPECT_EQ(whole.command.t, (std::vector<double>{0.0, 0.002}));
}

TEST(MergedTelemetry, ASignalGivenTwiceAtOneTimeKeepsTheLaterRow) {
  MergedTelemetryCounts c;
  const FlightSignals s = readMerged(
      "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n"
      "0,,,,,,,1,1,1,1\n"
      "0,,,,,,,2,2,2,2\n"
      "0.002,,,,,,,3,3,3,3\n",
      &c);
  EXPECT_EQ(c.repeated, 1u);
  ASSERT_EQ(s.command.t, (std::vector<double>{0.0, 0.002}));
  EXPECT_EQ(s.command.v[0][0], 2.0);
}

TEST(MergedTelemetry, BadRowsAreNamedByLine) {
  const std::string header = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n";
  EXPECT_EQ(errorOf(header + "0.002,1,2,3,,,,,,,\n0.001,,,,,,,1,1,1,1\n"),
            "merged.csv:3: time goes backwards (t = 0.001000 s after 0.002000 s): a merged export's rows must be in time order");
  EXPECT_EQ(errorOf(header + "0,,,,,,,1,one,1,1\n"), "merged.csv:2: column 'u2': 'one' is not a number");
  EXPECT_EQ(errorOf(header + "0,,,,,,,,,,\n0,1,2\n"), "merged.csv:3: 3 cells, the header has 11");
  EXPECT_NE(errorOf(header + "0,,,,30,10,0,,,,\n").find("merged.csv:2: pitch = 10 is outside ±π/2"), std::string::npos);
  EXPECT_NE(errorOf(header + "0,,,,,,,1500,1500,1500,1500\n").find("merged.csv:2: column 'u1' = 1500 is no thrust in newtons"),
            std::string::npos);
}

}  // namespace
}  // namespace quadfdi
