#include <gtest/gtest.h>

#include <array>
#include <sstream>
#include <string>

#include "io/key_value.h"
#include "io/telemetry_csv.h"
#include "io/telemetry_reader.h"

namespace quadfdi {
namespace {

TEST(TelemetryCsv, HeaderRowsAndExactRoundTrip) {
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
  writeTelemetryCsvHeader(px4, MotorNumbering{"PX4 quad X", {1, 4, 2, 3}});
  EXPECT_EQ(px4.str(), "# motor_numbering: PX4 quad X = 1 4 2 3\nt,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n");
  const TelemetryReader reader(px4, "px4.csv");
  ASSERT_TRUE(reader.numbering());
  EXPECT_EQ(reader.numbering()->name, "PX4 quad X");
  EXPECT_EQ(reader.numbering()->autopilot_motor, (std::array<int, 4>{1, 4, 2, 3}));
  // Only before the header; other comments are ignored.
  std::stringstream late("# a note\nt,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n# motor_numbering: PX4 = 1 4 2 3\n");
  EXPECT_FALSE(TelemetryReader(late, "late.csv").numbering());
}

TEST(TelemetryCsv, AMalformedNumberingCommentNamesItsLine) {
  for (const char* value : {"PX4 = 1 4 2", "PX4 = 1 4 2 2", "PX4 = 1 4 2 5", "= 1 2 3 4", "PX4 1 4 2 3", "PX4 = 1 4 2 3 1", "PX4 = a b c d"}) {
    SCOPED_TRACE(value);
    std::stringstream in(std::string("# exported\n# motor_numbering: ") + value + "\nt,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n");
    try {
      TelemetryReader reader(in, "bad.csv");
      ADD_FAILURE() << "accepted";
    } catch (const TelemetryError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("bad.csv:2: '# motor_numbering: NAME = A B C D' expects", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace quadfdi
