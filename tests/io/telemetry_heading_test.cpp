// Heading resets in a telemetry CSV (src/io/telemetry_heading.h): found by reading the whole file
// with its own p,q,r, then taken out of the yaw of every row from the reset on as the rows stream.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "io/telemetry_heading.h"
#include "io/telemetry_reader.h"

namespace quadfdi {
namespace {

constexpr double kDeg = M_PI / 180.0;

// 2 s at 250 Hz of a vehicle yawing at 0.5 rad/s with a constant 0.2 rad roll and −0.1 rad pitch
// (so each body rate is non-zero), its heading crossing ±π near t = 0.28 s; yaw stepped by
// `steps` = {t, rad} from each t on, the gyro unchanged. `ned`: written as a NED/FRD simulator
// writes it (y, z, pitch, yaw, q, r change sign).
std::string turningFlight(const std::vector<std::pair<double, double>>& steps, bool ned = false) {
  const double roll = 0.2, pitch = -0.1, w = 0.5;
  // Body rates of a constant-roll, constant-pitch turn at yaw rate w (ZYX Euler kinematics).
  const double p = -w * std::sin(pitch), q = w * std::cos(pitch) * std::sin(roll), r = w * std::cos(pitch) * std::cos(roll);
  const double s = ned ? -1.0 : 1.0;
  std::string text = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,p,q,r\n";
  for (int k = 0; k < 500; ++k) {
    const double t = 0.004 * k;
    double yaw = 3.0 + w * t;
    for (const auto& [at, by] : steps)
      if (t >= at - 1e-9) yaw += by;
    yaw = std::remainder(yaw, 2.0 * M_PI);
    char row[320];
    std::snprintf(row, sizeof row, "%.3f,0.1,%.17g,%.17g,%.17g,%.17g,%.17g,0.07,0.07,0.07,0.07,%.17g,%.17g,%.17g\n", t, s * 0.2,
                  s * 1.0, roll, s * pitch, s * yaw, p, s * q, s * r);
    text += row;
  }
  return text;
}

HeadingResets find(const std::string& text, const TelemetryReaderOptions& options = {}) {
  std::istringstream in(text);
  return checkTelemetryFile(in, "flight.csv", options).heading;
}

// Every sample of `text` as the detector reads it: through the reader, and through a
// HeadingCorrectedSource with `resets` where any are given.
std::vector<TelemetrySample> samples(const std::string& text, const std::vector<HeadingShift>& resets,
                                     const TelemetryReaderOptions& options = {}) {
  std::istringstream in(text);
  TelemetryReader reader(in, "flight.csv", options);
  HeadingCorrectedSource corrected(reader, resets);
  SampleSource& source = resets.empty() ? static_cast<SampleSource&>(reader) : corrected;
  std::vector<TelemetrySample> out;
  TelemetrySample s;
  std::string problem;
  for (SampleSource::Next row; (row = source.next(s, problem)) != SampleSource::Next::kEnd;)
    if (row == SampleSource::Next::kSample) out.push_back(s);
  return out;
}

// The largest |yaw difference| (modulo 2π) between two runs of samples, and that the rest is equal.
double largestYawDifference(const std::vector<TelemetrySample>& a, const std::vector<TelemetrySample>& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    for (int c = 0; c < 5; ++c) EXPECT_EQ(a[i].y[static_cast<std::size_t>(c)], b[i].y[static_cast<std::size_t>(c)]) << i;
    EXPECT_EQ(a[i].t, b[i].t);
    EXPECT_EQ(a[i].u, b[i].u);
    worst = std::max(worst, std::abs(std::remainder(a[i].y[5] - b[i].y[5], 2.0 * M_PI)));
  }
  return worst;
}

TEST(TelemetryHeading, ResetsTheGyroDoesNotShowAreFoundAndTakenOutAsTheRowsStream) {
  const std::string clean = turningFlight({}), stepped = turningFlight({{1.2, 5.0 * kDeg}, {1.6, -3.0 * kDeg}});
  const HeadingResets none = find(clean);
  EXPECT_TRUE(none.checked);
  EXPECT_EQ(none.steps, 499u);
  EXPECT_EQ(none.count, 0u);
  EXPECT_TRUE(none.resets.empty());
  EXPECT_LT(none.largest_left, 1e-9);  // the gyro explains a turn through ±π exactly

  const HeadingResets found = find(stepped);
  ASSERT_EQ(found.count, 2u);
  ASSERT_EQ(found.resets.size(), 2u);
  EXPECT_DOUBLE_EQ(found.resets[0].t, 1.2);
  EXPECT_NEAR(found.resets[0].shift, 5.0 * kDeg, 1e-9);
  EXPECT_DOUBLE_EQ(found.resets[1].t, 1.6);
  EXPECT_NEAR(found.resets[1].shift, -3.0 * kDeg, 1e-9);
  EXPECT_NEAR(found.largest, 5.0 * kDeg, 1e-9);
  EXPECT_DOUBLE_EQ(found.largest_t, 1.2);

  // Streamed with them taken out: the reset-free file's samples, yaw to round-off, all else bit for bit.
  EXPECT_LT(largestYawDifference(samples(stepped, found.resets), samples(clean, {})), 1e-12);
  // Left in, the yaw differs by the steps.
  EXPECT_NEAR(largestYawDifference(samples(stepped, {}), samples(clean, {})), 5.0 * kDeg, 1e-9);
}

TEST(TelemetryHeading, TheFileIsCheckedInTheFramesItIsReadIn) {
  // A NED/FRD file's −5° heading step (its yaw turns the other way) is a +5° one in quadfdi's z-up
  // frames, which the detector reads and the check works in.
  TelemetryReaderOptions ned;
  ned.frame = TelemetryFrame::kNed;
  const std::string stepped = turningFlight({{1.2, 5.0 * kDeg}}, true);
  const HeadingResets found = find(stepped, ned);
  ASSERT_EQ(found.count, 1u);
  EXPECT_NEAR(found.resets[0].shift, 5.0 * kDeg, 1e-9);
  EXPECT_LT(largestYawDifference(samples(stepped, found.resets, ned), samples(turningFlight({}, true), {}, ned)), 1e-12);
  // Read as z-up, its attitude and body rates are the same motion seen in axes turned 180° about x:
  // the gyro still explains every step, so the frames' mix-up is no reset (the numbering check's to see).
  const HeadingResets misread = find(turningFlight({}, true));
  EXPECT_EQ(misread.count, 0u);
  EXPECT_LT(misread.largest_left, 1e-9);
}

TEST(TelemetryHeading, RatesAreReadForTheCheckEvenWhereTheModelDoesNot) {
  TelemetryReaderOptions no_rates;
  no_rates.read_rates = false;  // a model that does not read p,q,r
  EXPECT_EQ(find(turningFlight({{1.2, 5.0 * kDeg}}), no_rates).count, 1u);
}

TEST(TelemetryHeading, AFileWithoutBodyRatesIsNotChecked) {
  const HeadingResets found = find("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,1,0,0,0,1,1,1,1\n0.004,0,0,1,0,0,0.5,1,1,1,1\n");
  EXPECT_FALSE(found.checked);
  EXPECT_EQ(found.count, 0u);
  EXPECT_EQ(headingResetsLine(found, "the gyro (columns p,q,r)", "the file has no p,q,r"),
            "heading: not checked for estimator resets the log does not record: the file has no p,q,r");
}

TEST(TelemetryHeading, AnUnreadableRowIsRefusedByFileAndLine) {
  std::string text = turningFlight({});
  std::size_t line5 = 0;  // the fourth row after the header
  for (int i = 0; i < 4; ++i) line5 = text.find('\n', line5) + 1;
  const std::size_t end = text.find('\n', line5), r_cell = text.rfind(',', end) + 1;
  text.replace(r_cell, end - r_cell, "abc");
  try {
    find(text);
    FAIL() << "a rate cell of text was read";
  } catch (const TelemetryError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("flight.csv:5: ", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace quadfdi
