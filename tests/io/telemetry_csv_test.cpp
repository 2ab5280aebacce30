#include <gtest/gtest.h>

#include <sstream>

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

}  // namespace
}  // namespace quadfdi
