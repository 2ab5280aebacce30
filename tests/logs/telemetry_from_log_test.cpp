// The conventions layer (src/logs/telemetry_from_log.h): rates and refusals, the clock
// (interpolation, hold), thrust scaling and hover calibration, flight phases and margins, holes;
// then simulated missions written as PX4, ArduPilot and Crazyflie logs, detected through it and
// compared with the CSV path of the same flight; and the real logs' refusals.
#include "logs/telemetry_from_log.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "detection/session.h"
#include "io/model_file.h"
#include "io/telemetry_csv.h"
#include "io/telemetry_reader.h"
#include "logs/crazyflie_usd.h"
#include "logs/dataflash.h"
#include "logs/mission_writers.h"
#include "logs/px4_signals.h"
#include "logs/ulog.h"

namespace quadfdi {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The import report's convention lines, one a line.
std::string conventionsOf(const LogSampleSource& src) {
  std::string text;
  for (const std::string& c : src.report().conventions) text += c + "\n";
  return text;
}

// A synthetic flight: signals at the given periods, airborne (armed, not landed) from `takeoff`.
FlightSignals synthetic(double att_dt, double pos_dt, double cmd_dt, double span, CommandKind kind = CommandKind::kThrustNewton) {
  FlightSignals s;
  for (double t = 0.0; t <= span + 1e-9; t += att_dt) {
    s.attitude.t.push_back(t);
    s.attitude.v.push_back({0.01 * t, -0.02 * t, 0.1 * t});
  }
  for (double t = 0.0; t <= span + 1e-9; t += pos_dt) {
    s.position.t.push_back(t);
    s.position.v.push_back({0.5 * t, -0.25 * t, 1.0});
  }
  for (double t = 0.0; t <= span + 1e-9; t += cmd_dt) {
    s.command.t.push_back(t);
    const double c = kind == CommandKind::kThrustNewton ? 0.07 + 0.001 * t : 0.45 + 0.001 * t;
    s.command.v.push_back({c, c, c, c});
  }
  s.command_kind = kind;
  s.attitude.source = {"att_topic", "r,p,y", ""};
  s.position.source = {"pos_topic", "x,y,z", ""};
  s.command.source = {"cmd_topic", "m1..m4", ""};
  s.states = {{0.0, true, false}};  // airborne from the start
  return s;
}

std::vector<TelemetrySample> drain(LogSampleSource& src) {
  std::vector<TelemetrySample> out;
  TelemetrySample s;
  std::string problem;
  while (src.next(s, problem) == SampleSource::Next::kSample) out.push_back(s);
  return out;
}

TEST(TelemetryFromLog, RefusesACoarseSignalNamingTopicRateAndWhatToChange) {
  {
    LogSampleSource src;
    const ImportRefusal r = buildLogSampleSource(synthetic(0.004, 0.02, 0.1, 5.0), LogFormat::kUlog, ImportOptions{}, src);
    ASSERT_TRUE(r.refused());
    EXPECT_EQ(r.topic, "cmd_topic");
    EXPECT_TRUE(contains(r.message, "10.0 Hz")) << r.message;
    EXPECT_TRUE(contains(r.message, "SDLOG_PROFILE")) << r.message;
    EXPECT_TRUE(contains(r.message, "≥ 125 Hz")) << r.message;
  }
  {
    LogSampleSource src;
    const ImportRefusal r = buildLogSampleSource(synthetic(0.1, 0.02, 0.0025, 5.0), LogFormat::kDataflash, ImportOptions{}, src);
    EXPECT_EQ(r.topic, "att_topic");
    EXPECT_TRUE(contains(r.message, "LOG_BITMASK bit 0")) << r.message;
  }
  {
    LogSampleSource src;
    const ImportRefusal r = buildLogSampleSource(synthetic(0.002, 0.1, 0.002, 5.0), LogFormat::kCrazyflieUsd, ImportOptions{}, src);
    EXPECT_EQ(r.topic, "pos_topic");
    EXPECT_TRUE(contains(r.message, "≥ 20.0 Hz")) << r.message;
    EXPECT_TRUE(contains(r.message, "deck's logging frequency")) << r.message;
  }
  // 50 Hz position passes; lowering the attitude limit lets a 100 Hz attitude through, with a
  // warning that says what that costs (and none for the position, whose default it meets).
  ImportOptions o;
  o.min_rate_attitude = 90;
  LogSampleSource src;
  EXPECT_FALSE(buildLogSampleSource(synthetic(0.01, 0.02, 0.002, 5.0), LogFormat::kUlog, o, src).refused());
  const std::vector<std::string>& warnings = src.report().warnings;
  ASSERT_EQ(std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) { return contains(w, "below the default"); }), 1)
      << ::testing::PrintToString(warnings);
  const auto at = std::find_if(warnings.begin(), warnings.end(), [](const std::string& w) { return contains(w, "below the default"); });
  EXPECT_TRUE(contains(*at, "att_topic (attitude) is logged at 100 Hz, below the default 125 Hz, and read as --min-rate-attitude allows"))
      << *at;
  // At the default rate, no such warning.
  LogSampleSource full;
  ASSERT_FALSE(buildLogSampleSource(synthetic(0.002, 0.02, 0.002, 5.0), LogFormat::kUlog, ImportOptions{}, full).refused());
  for (const std::string& w : full.report().warnings) EXPECT_FALSE(contains(w, "below the default")) << w;
}

TEST(TelemetryFromLog, InterpolatesAttitudeAndPositionAndHoldsCommands) {
  FlightSignals s = synthetic(0.004, 0.04, 0.005, 3.0);
  // Yaw across the ±π seam: 0.02 rad per 4 ms step, the short way.
  for (std::size_t i = 0; i < s.attitude.t.size(); ++i) s.attitude.v[i][2] = std::remainder(kPi - 0.5 + 5.0 * s.attitude.t[i], 2 * kPi);
  const FlightSignals copy = s;
  LogSampleSource src;
  ASSERT_FALSE(buildLogSampleSource(s, LogFormat::kUlog, ImportOptions{}, src).refused());
  const std::vector<TelemetrySample> out = drain(src);
  ASSERT_EQ(out.size(), 1501u);  // 0 … 3 s every 2 ms, airborne from the log's start, no margin
  for (const TelemetrySample& x : out) {
    EXPECT_NEAR(x.y[0], 0.5 * x.t, 1e-9);
    EXPECT_NEAR(x.y[1], -0.25 * x.t, 1e-9);
    EXPECT_NEAR(x.y[3], 0.01 * x.t, 1e-9);
    EXPECT_NEAR(std::remainder(x.y[5] - (kPi - 0.5 + 5.0 * x.t), 2 * kPi), 0.0, 1e-9) << x.t;
    // Held: the command logged at or before t.
    const auto k = static_cast<std::size_t>(std::floor(x.t / 0.005 + 1e-9));
    EXPECT_EQ(x.u[0], copy.command.v[k][0]) << x.t;
  }
  EXPECT_EQ(src.report().signals.size(), 3u);
  EXPECT_NEAR(src.report().signals[0].rate_hz, 250.0, 1e-6);
  EXPECT_NEAR(src.report().signals[1].rate_hz, 25.0, 1e-6);
}

TEST(TelemetryFromLog, ThrustFractionsNeedAScaleAndCanBeCalibratedFromHover) {
  {
    LogSampleSource src;
    const ImportRefusal r = buildLogSampleSource(synthetic(0.002, 0.02, 0.002, 4.0, CommandKind::kThrustFraction),
                                                 LogFormat::kUlog, ImportOptions{}, src);
    ASSERT_TRUE(r.refused());
    EXPECT_TRUE(contains(r.message, "--max-thrust")) << r.message;
    EXPECT_TRUE(contains(r.message, "--mass")) << r.message;
  }
  {
    ImportOptions o;
    o.max_thrust = 0.2;
    LogSampleSource src;
    ASSERT_FALSE(buildLogSampleSource(synthetic(0.002, 0.02, 0.002, 4.0, CommandKind::kThrustFraction), LogFormat::kUlog, o, src).refused());
    EXPECT_NEAR(drain(src)[0].u[0], 0.45 * 0.2, 1e-12);
  }
  {
    // Level hover at constant height: mean command 0.45 + 0.001·t ≈ 0.452 ↔ m·g/4.
    FlightSignals s = synthetic(0.002, 0.02, 0.002, 4.0, CommandKind::kThrustFraction);
    for (auto& a : s.attitude.v) a = {0.0, 0.0, 0.3};
    for (auto& p : s.position.v) p[0] = p[1] = 0.0;
    ImportOptions o;
    o.mass = 0.03;
    LogSampleSource src;
    ASSERT_FALSE(buildLogSampleSource(s, LogFormat::kUlog, o, src).refused());
    EXPECT_TRUE(src.report().hover_calibrated);
    EXPECT_NEAR(src.report().thrust_factor, 0.03 * 9.81 / 4 / 0.452, 0.002);
    EXPECT_TRUE(contains(src.report().thrust, "calibrated from the log's steady hover")) << src.report().thrust;
  }
}

// Body rates are optional: a rate row beyond any gyro's range is left out and counted; rates
// coarser than the attitude needs are not read, with a warning, and the log reads as without them.
TEST(TelemetryFromLog, BodyRatesOutOfRangeRowsAreLeftOutAndCoarseRatesAreNotRead) {
  FlightSignals signals = synthetic(0.004, 0.01, 0.004, 3.0);
  for (double t = 0.0; t <= 3.0 + 1e-9; t += 0.004) {
    signals.rates.t.push_back(t);
    signals.rates.v.push_back({0.1, std::abs(t - 1.5) < 1e-6 ? 700.0 : 0.2, 0.3});  // one corrupt row
  }
  signals.rates.source = {"rate_topic", "p,q,r", ""};
  FlightSignals coarse = signals;
  LogSampleSource src;
  ImportOptions o;
  ASSERT_FALSE(buildLogSampleSource(std::move(signals), LogFormat::kUlog, o, src).refused());
  EXPECT_TRUE(src.carriesRates());
  bool noted = false;
  for (const std::string& c : src.report().conventions) noted = noted || c == "rate_topic: 1 body-rate rows not finite or beyond 100 rad/s (no gyro measures that) left out";
  EXPECT_TRUE(noted) << src.report().text();
  for (const TelemetrySample& s : drain(src)) {
    ASSERT_NEAR(s.rates[1], 0.2, 1e-12) << s.t;
    ASSERT_NEAR(s.rates[2], 0.3, 1e-12) << s.t;
  }
  for (std::size_t i = 0; i < coarse.rates.t.size(); ++i) coarse.rates.t[i] *= 3.0;  // 83 Hz, and longer than the flight
  LogSampleSource without;
  ASSERT_FALSE(buildLogSampleSource(std::move(coarse), LogFormat::kUlog, o, without).refused());
  EXPECT_FALSE(without.carriesRates());
  ASSERT_EQ(without.report().warnings.size(), 1u) << without.report().text();
  EXPECT_EQ(without.report().warnings[0],
            "rate_topic (body rates) is logged at 83.3 Hz, below the 125 Hz attitude needs: not read (a model on body rates refuses this log)");
}

TEST(TelemetryFromLog, APlusOrPropsOutFrameIsReadInItsTurnedAxes) {
  // The extractor numbered the motors in turned axes (numbering.body_turn); the attitude and body
  // rates are turned here, once, for every autopilot, and the report names where each motor sits.
  FlightSignals signals = synthetic(0.004, 0.01, 0.004, 2.0);
  for (double t = 0.0; t <= 2.0 + 1e-9; t += 0.004) {
    signals.rates.t.push_back(t);
    signals.rates.v.push_back({0.1 + t, 0.2, 0.3});
  }
  signals.rates.source = {"rate_topic", "p,q,r", ""};
  for (const BodyTurn turn : {BodyTurn{2}, BodyTurn{-1}}) {
    SCOPED_TRACE(turn.eighths);
    FlightSignals turned = signals;
    turned.numbering = {"PX4", {3, 1, 4, 2}, turn};
    LogSampleSource plain, src;
    ASSERT_FALSE(buildLogSampleSource(signals, LogFormat::kUlog, ImportOptions{}, plain).refused());
    ASSERT_FALSE(buildLogSampleSource(std::move(turned), LogFormat::kUlog, ImportOptions{}, src).refused());
    const std::vector<TelemetrySample> a = drain(plain), b = drain(src);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); i += 50) {
      const EulerZyx want = attitudeOfTurnedAxes({a[i].y[3], a[i].y[4], a[i].y[5]}, turn);
      EXPECT_NEAR(b[i].y[3], want.roll, 1e-9) << a[i].t;
      EXPECT_NEAR(b[i].y[4], want.pitch, 1e-9) << a[i].t;
      EXPECT_NEAR(std::remainder(b[i].y[5] - want.yaw, 2 * kPi), 0.0, 1e-9) << a[i].t;
      const std::array<double, 3> w = bodyVectorInTurnedAxes(a[i].rates, turn);
      for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(b[i].rates[k], w[k], 1e-12) << a[i].t;
      for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(b[i].y[k], a[i].y[k]);  // the world frame is the world frame
    }
    EXPECT_TRUE(contains(src.report().text(), turn.eighths == 2 ? "1: front-left, PX4 motor 3" : "1: right, PX4 motor 3"))
        << src.report().text();
  }
}

TEST(TelemetryFromLog, PhasesFromEventsSkipMarginsAndLeaveAGapBetweenFlights) {
  FlightSignals s = synthetic(0.002, 0.02, 0.002, 20.0);
  // Two flights: 2–8 s and 11–18 s.
  s.states = {{0.0, false, true}, {1.5, true, true}, {2.0, true, false}, {8.0, true, true},
              {11.0, true, false}, {18.0, true, true}, {19.0, false, true}};
  LogSampleSource src;
  ASSERT_FALSE(buildLogSampleSource(s, LogFormat::kUlog, ImportOptions{}, src).refused());
  const ImportReport& r = src.report();
  ASSERT_EQ(r.phases.size(), 2u);
  EXPECT_NEAR(r.phases[0].eval_begin, 3.0, 1e-9);
  EXPECT_NEAR(r.phases[0].eval_end, 7.5, 1e-9);
  EXPECT_NEAR(r.phases[1].eval_begin, 12.0, 1e-9);
  EXPECT_NEAR(r.phases[1].eval_end, 17.5, 1e-9);
  EXPECT_TRUE(contains(r.phasesLine(), "evaluated 2 of 2 airborne phases")) << r.phasesLine();
  const std::vector<TelemetrySample> out = drain(src);
  ASSERT_FALSE(out.empty());
  EXPECT_NEAR(out.front().t, 3.0, 1e-9);
  int jumps = 0;
  for (std::size_t i = 1; i < out.size(); ++i) {
    const double d = out[i].t - out[i - 1].t;
    if (d > 0.02) ++jumps;
    else EXPECT_NEAR(d, 0.002, 1e-9);
  }
  EXPECT_EQ(jumps, 1);  // the detector restarts between the flights
}

TEST(TelemetryFromLog, ACrashKeepsItsLastMomentsAndAHoleIsNotBridged) {
  FlightSignals s = synthetic(0.002, 0.02, 0.002, 10.0);
  s.states = {{0.0, true, true}, {1.0, true, false}, {9.0, true, true}};
  for (std::size_t i = 0; i < s.attitude.t.size(); ++i)
    if (s.attitude.t[i] > 8.8) s.attitude.v[i][0] = 1.4;  // flipped before "landing"
  // A 50 ms hole in the attitude at 5 s.
  for (std::size_t i = 0; i < s.attitude.t.size();)
    if (s.attitude.t[i] > 5.0 && s.attitude.t[i] < 5.05) {
      s.attitude.t.erase(s.attitude.t.begin() + static_cast<std::ptrdiff_t>(i));
      s.attitude.v.erase(s.attitude.v.begin() + static_cast<std::ptrdiff_t>(i));
    } else {
      ++i;
    }
  LogSampleSource src;
  ASSERT_FALSE(buildLogSampleSource(s, LogFormat::kUlog, ImportOptions{}, src).refused());
  const PhaseReport& p = src.report().phases.at(0);
  EXPECT_NEAR(p.eval_end, 9.0, 1e-9) << p.note;  // no landing margin: a crash
  EXPECT_TRUE(contains(p.note, "crash")) << p.note;
  EXPECT_TRUE(contains(p.note, "1 hole")) << p.note;
  EXPECT_EQ(src.stretchCount(), 2u);
}

// The motors given at times of their own (a merged export with a row per motor): the commands
// are as fast as the slowest motor, not as the four together, and a hole in one motor is a hole.
FlightSignals motorsApart(double motor_dt, double span) {
  FlightSignals s = synthetic(0.002, 0.02, 1.0, span);
  s.command = {};
  s.command.source = {"columns u1,u2,u3,u4", "", ""};
  s.command_times_per_motor.resize(4);
  for (double t0 = 0.0; t0 <= span + 1e-9; t0 += motor_dt)
    for (std::size_t m = 0; m < 4; ++m) {
      const double t = t0 + motor_dt * static_cast<double>(m) / 4.0;  // motor m + 1 a quarter period after motor m
      s.command_times_per_motor[m].push_back(t);
    }
  for (const std::vector<double>& times : s.command_times_per_motor)
    for (double t : times) s.command.t.push_back(t);
  std::sort(s.command.t.begin(), s.command.t.end());
  s.command.v.assign(s.command.t.size(), {0.07, 0.07, 0.07, 0.07});
  return s;
}

TEST(TelemetryFromLog, MotorsGivenApartAreAsFastAsTheSlowestAndEachOnesHolesCount) {
  {  // Each motor at 100 Hz, a quarter period apart: the four together change every 2.5 ms.
    LogSampleSource src;
    const FlightSignals s = motorsApart(0.01, 5.0);
    EXPECT_NEAR(1.0 / medianInterval(s.command.t), 400.0, 1.0);
    const ImportRefusal r = buildLogSampleSource(s, LogFormat::kMergedCsv, ImportOptions{}, src);
    ASSERT_TRUE(r.refused());
    EXPECT_TRUE(contains(r.topic, "column u")) << r.topic;
    EXPECT_TRUE(contains(r.message, "(commands) is logged at 100 Hz")) << r.message;
    // The way out, with where its cost was measured.
    EXPECT_TRUE(contains(r.message, "(or lower --min-rate-command, at a measured cost: docs/results/log-rates/README.md)")) << r.message;
  }
  {  // Each at 500 Hz: read; then a 50 ms hole in motor 3 alone cuts the flight there.
    FlightSignals s = motorsApart(0.002, 10.0);
    LogSampleSource whole;
    ASSERT_FALSE(buildLogSampleSource(s, LogFormat::kMergedCsv, ImportOptions{}, whole).refused());
    EXPECT_EQ(whole.stretchCount(), 1u);
    EXPECT_TRUE(contains(whole.report().signals.at(2).source.fields, "the slowest of u1..u4"));
    EXPECT_NEAR(whole.report().signals.at(2).rate_hz, 500.0, 1.0);
    std::vector<double>& m3 = s.command_times_per_motor[2];
    m3.erase(std::remove_if(m3.begin(), m3.end(), [](double t) { return t > 5.0 && t < 5.05; }), m3.end());
    LogSampleSource holed;
    ASSERT_FALSE(buildLogSampleSource(s, LogFormat::kMergedCsv, ImportOptions{}, holed).refused());
    EXPECT_EQ(holed.stretchCount(), 2u);
    EXPECT_TRUE(contains(holed.report().phases.at(0).note, "1 hole")) << holed.report().phases.at(0).note;
  }
}

TEST(TelemetryFromLog, AJumpTheLogDoesNotSizeIsCutNotBridged) {
  FlightSignals s = synthetic(0.002, 0.02, 0.002, 10.0);
  // The jump's last sample before it came 60 ms earlier (a slow signal): nothing after that is kept.
  s.breaks.push_back({5.0, 4.94, "pos_topic: 2 horizontal position resets whose shift the log does not hold"});
  s.breaks.push_back({30.0, 29.98, "after the log: cuts nothing"});
  LogSampleSource src;
  ASSERT_FALSE(buildLogSampleSource(s, LogFormat::kUlog, ImportOptions{}, src).refused());
  const PhaseReport& p = src.report().phases.at(0);
  EXPECT_TRUE(contains(p.note, "1 jump the log does not size (pos_topic: 2 horizontal position resets")) << p.note;
  EXPECT_EQ(src.stretchCount(), 2u);
  const std::vector<TelemetrySample> out = drain(src);
  int jumps = 0;
  for (std::size_t i = 1; i < out.size(); ++i) {
    const double d = out[i].t - out[i - 1].t;
    if (d > 0.002 + 1e-9) {
      ++jumps;
      EXPECT_LE(out[i - 1].t, 4.94 + 1e-9);  // nothing interpolated toward the jump
      EXPECT_GE(out[i].t, 5.0 + 0.02 - 1e-9);
    }
  }
  EXPECT_EQ(jumps, 1);
}

TEST(TelemetryFromLog, NoFlightIsRefused) {
  FlightSignals s = synthetic(0.002, 0.02, 0.002, 5.0);
  s.states = {{0.0, false, true}, {1.0, true, true}, {4.0, false, true}};  // armed, never airborne
  LogSampleSource src;
  const ImportRefusal r = buildLogSampleSource(s, LogFormat::kUlog, ImportOptions{}, src);
  ASSERT_TRUE(r.refused());
  EXPECT_EQ(r.message.rfind("no flight found", 0), 0u) << r.message;
  // No events: the rule finds nothing either on a log that stays at one height with no thrust.
  FlightSignals g = synthetic(0.002, 0.02, 0.002, 5.0);
  g.states.clear();
  for (auto& c : g.command.v) c = {0, 0, 0, 0};
  LogSampleSource src2;
  const ImportRefusal r2 = buildLogSampleSource(g, LogFormat::kCrazyflieUsd, ImportOptions{}, src2);
  EXPECT_EQ(r2.message.rfind("no flight found", 0), 0u) << r2.message;
}

// ---------- simulated missions through each autopilot's log ----------

class LogDetection : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    model_ = std::make_unique<TrainedModel>(readModelFile(QUADFDI_SOURCE_DIR "/models/lstm-model-free.qfdw"));
  }
  static void TearDownTestSuite() { model_.reset(); }

  struct Result {
    DetectorSummary summary;
    long outputs = 0;
    float lowest = 1.0f;  // lowest Θ̂ of any motor over the flight
  };
  class CountingSink : public DetectionSink {
   public:
    void output(const DetectorOutput& d) override {
      ++outputs;
      for (float t : d.theta) lowest = std::min(lowest, t);
    }
    void warning(const std::string&) override {}
    long outputs = 0;
    float lowest = 1.0f;
  };
  static Result detect(SampleSource& source) {
    DetectorConfig c;
    c.symmetry = model_->metadata.symmetry;
    c.resampler.dt = model_->metadata.dt;
    Detector d(c, *model_);
    CountingSink sink;
    const SessionResult r = runDetection(d, source, sink, SessionConfig{});
    EXPECT_EQ(r.status, SessionStatus::kDone);
    return {d.summary(), sink.outputs, sink.lowest};
  }
  // The CSV path: the flight's own 500 Hz samples from `from` on, written and read as CSV.
  static Result detectCsv(const test::Mission& m, double from) {
    std::stringstream csv;
    writeTelemetryCsvHeader(csv);
    for (const TelemetrySample& s : m.samples)
      if (s.t >= from - 1e-9) writeTelemetryCsvRow(csv, s);
    TelemetryReader reader(csv, "flight.csv");
    return detect(reader);
  }
  static ImportOptions options() {
    ImportOptions o;
    o.dt = model_->metadata.dt;
    o.max_thrust = test::kMissionMaxThrust;
    return o;
  }
  static ImportRefusal fromBytes(const std::vector<std::uint8_t>& bytes, const ImportOptions& o, LogSampleSource& src) {
    const ByteSpan span{bytes.data(), bytes.size()};
    DecodedLog log;
    FlightSignals signals;
    LogIssue issue;
    if (looksLikeUlog(span)) {
      issue = readUlog(span, log);
      if (issue.ok()) issue = extractPx4Signals(log, Px4SignalOptions{}, signals);
    } else if (looksLikeDataflash(span)) {
      issue = readDataflash(span, log);
      if (issue.ok()) issue = extractArdupilotSignals(log, ArdupilotSignalOptions{}, signals);
    } else {
      issue = readCrazyflieUsd(span, log);
      if (issue.ok()) issue = extractCrazyflieSignals(log, CrazyflieSignalOptions{}, signals);
    }
    EXPECT_TRUE(issue.ok()) << issue.message;
    return buildLogSampleSource(std::move(signals), log.format, o, src);
  }
  static void expectSameAlarmAsCsv(const std::vector<std::uint8_t>& bytes, const test::Mission& m, int motor) {
    LogSampleSource src;
    const ImportRefusal r = fromBytes(bytes, options(), src);
    ASSERT_FALSE(r.refused()) << r.message;
    const ImportReport& rep = src.report();
    ASSERT_EQ(rep.phases.size(), 1u) << rep.text();
    ASSERT_TRUE(rep.phases[0].evaluated) << rep.text();
    EXPECT_LT(rep.phases[0].eval_begin, m.fault_at - 0.5) << rep.text();
    const Result log = detect(src);
    const Result csv = detectCsv(m, rep.phases[0].eval_begin);
    ASSERT_GE(csv.summary.alarms_raised, 1);
    EXPECT_EQ(csv.summary.first_alarm_motor, motor);
    ASSERT_GE(log.summary.alarms_raised, 1) << rep.text();
    EXPECT_EQ(log.summary.first_alarm_motor, csv.summary.first_alarm_motor) << rep.text();
    EXPECT_GT(log.summary.first_alarm_t, m.fault_at);
    EXPECT_NEAR(log.summary.first_alarm_t, csv.summary.first_alarm_t, 0.016) << rep.text();
    std::printf("[ measured ] %s, motor %d failing at %.3f s: first alarm via the log %.3f s (motor %d), via CSV %.3f s (motor %d)\n",
                rep.format.c_str(), motor, m.fault_at, log.summary.first_alarm_t, log.summary.first_alarm_motor,
                csv.summary.first_alarm_t, csv.summary.first_alarm_motor);
  }
  static void expectQuietLanding(const std::vector<std::uint8_t>& bytes, const test::Mission& m, const char* rule) {
    LogSampleSource src;
    const ImportRefusal r = fromBytes(bytes, options(), src);
    ASSERT_FALSE(r.refused()) << r.message;
    const ImportReport& rep = src.report();
    const Result log = detect(src);
    EXPECT_EQ(log.summary.alarms_raised, 0) << rep.text();
    ASSERT_EQ(rep.phases.size(), 1u) << rep.text();
    EXPECT_TRUE(contains(rep.phasesLine(), "evaluated 1 of 1 airborne phase")) << rep.phasesLine();
    EXPECT_TRUE(contains(rep.phase_rule, rule)) << rep.phase_rule;
    EXPECT_GT(rep.phases[0].eval_begin, m.takeoff_at + 1.0);
    EXPECT_LT(rep.phases[0].eval_end, m.landed_at);
    EXPECT_GT(rep.phases[0].eval_end - rep.phases[0].eval_begin, 5.0) << rep.text();
    EXPECT_GT(log.outputs, 2000);
    std::printf("[ measured ] %s, healthy: %s; lowest Θ̂ %.2f, %ld alarms\n", rep.format.c_str(), rep.phasesLine().c_str(),
                static_cast<double>(log.lowest), log.summary.alarms_raised);
  }
  static std::unique_ptr<TrainedModel> model_;
};
std::unique_ptr<TrainedModel> LogDetection::model_;

TEST_F(LogDetection, Px4MotorFailureGivesTheCsvPathsAlarmAndMotor) {
  for (int motor : {1, 3}) {
    SCOPED_TRACE(motor);
    const test::Mission m = test::simulateMission(motor, 0.0, 4.0);
    expectSameAlarmAsCsv(test::writePx4Mission(m), m, motor);
  }
}

TEST_F(LogDetection, ArdupilotMotorFailureGivesTheCsvPathsAlarmAndMotor) {
  for (int motor : {2, 4}) {
    SCOPED_TRACE(motor);
    const test::Mission m = test::simulateMission(motor, 0.0, 4.0);
    expectSameAlarmAsCsv(test::writeArdupilotMission(m), m, motor);
  }
}

// A battery draining from v = 1 to 0.75 while ArduPilot compensates (every throttle ÷ v): with
// MOTB logged the extractor multiplies it back, and the log gives the CSV path's alarm; without
// MOTB the PWM reads as up to ≈ 50 % more thrust on every motor, and the report says it was not undone.
TEST_F(LogDetection, ArdupilotBatteryCompensationIsUndoneWithMotb) {
  const test::Mission m = test::simulateMission(2, 0.0, 4.0);
  expectSameAlarmAsCsv(test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kNone, test::kApX, {}, {1.0, 0.75, true}), m, 2);
  LogSampleSource src;
  ASSERT_FALSE(fromBytes(test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kNone, test::kApX, {}, {1.0, 0.75, false}),
                         options(), src)
                   .refused());
  EXPECT_TRUE(contains(src.report().text(), "battery: voltage compensation not undone: the log has no MOTB")) << src.report().text();
  const Result unlogged = detect(src);
  const Result csv = detectCsv(m, src.report().phases[0].eval_begin);
  std::printf("[ measured ] ArduPilot, battery 1 → 0.75 without MOTB: first alarm %.3f s (motor %d), lowest Θ̂ %.2f; CSV path %.3f s (motor %d)\n",
              unlogged.summary.first_alarm_t, unlogged.summary.first_alarm_motor, static_cast<double>(unlogged.lowest),
              csv.summary.first_alarm_t, csv.summary.first_alarm_motor);
  // A healthy flight: the lowest Θ̂ with the compensation undone is the unsagged log's.
  const test::Mission healthy = test::simulateMission(0, 1.0, -1.0);
  double lowest[3] = {};
  const test::ApBattery batteries[3] = {{}, {1.0, 0.75, true}, {1.0, 0.75, false}};
  for (int b = 0; b < 3; ++b) {
    LogSampleSource h;
    ASSERT_FALSE(fromBytes(test::writeArdupilotMission(healthy, 400.0, 25.0, test::ApRates::kNone, test::kApX, {}, batteries[b]),
                           options(), h)
                     .refused());
    const Result r = detect(h);
    EXPECT_EQ(r.summary.alarms_raised, 0) << b;
    lowest[b] = static_cast<double>(r.lowest);
  }
  EXPECT_NEAR(lowest[1], lowest[0], 0.02);
  std::printf("[ measured ] ArduPilot, healthy: lowest Θ̂ %.3f with a full battery, %.3f draining with MOTB, %.3f draining without\n",
              lowest[0], lowest[1], lowest[2]);
}

// Each reader's motor order, checked against the physics: a manoeuvring flight logged as PX4,
// ArduPilot (X, H and PLUS frames) and the Crazyflie write it, read back, turns the vehicle as
// the reader numbers its motors (detection/numbering_check.h). An ArduPilot log whose FRAME_TYPE
// says Betaflight's order while its outputs are in the X's is caught.
TEST_F(LogDetection, EachAutopilotsMotorOutputsTurnTheVehicleAsItsReaderNumbersThem) {
  const test::Mission m = test::simulateManoeuvringMission();
  auto check = [](const std::vector<std::uint8_t>& bytes) {
    LogSampleSource src;
    EXPECT_FALSE(fromBytes(bytes, options(), src).refused());
    DetectorConfig c;
    c.symmetry = model_->metadata.symmetry;
    c.resampler.dt = model_->metadata.dt;
    Detector d(c, *model_);
    CountingSink sink;
    return runDetection(d, src, sink, SessionConfig{}).numbering;
  };
  struct Case {
    const char* name;
    std::vector<std::uint8_t> bytes;
  };
  const Case cases[] = {{"PX4", test::writePx4Mission(m)},
                        {"ArduPilot X", test::writeArdupilotMission(m)},
                        {"ArduPilot H", test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kNone, test::kApH)},
                        {"ArduPilot PLUS", test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kRate, test::kApPlus)},
                        {"Crazyflie", test::writeCrazyflieMission(m)}};
  for (const Case& c : cases) {
    const NumberingCheckResult r = check(c.bytes);
    std::printf("[ measured ] %s: %s\n", c.name, r.text().c_str());
    EXPECT_EQ(r.verdict, NumberingVerdict::kConsistent) << c.name << ": " << r.text();
    EXPECT_GT(r.seconds, 8.0) << c.name;
  }
  // FRAME_TYPE 12 (Betaflight's order: ArduPilot motor 1 back-right, 2 front-right, 3 back-left,
  // 4 front-left) on outputs wired as the X's: the reader puts them on the wrong rotors.
  const test::ApFrame lying{12, 0, test::kApX.motor};
  const NumberingCheckResult r = check(test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kNone, lying));
  EXPECT_EQ(r.verdict, NumberingVerdict::kOtherNumbering) << r.text();
}

TEST_F(LogDetection, ArdupilotPropsOutAndPlusFramesGiveTheXsAlarmOnTheMotorWhereItSits) {
  // One flight of the standard X, logged as an H (props-out) and as a PLUS frame would log it: each
  // airframe's own attitude and motor numbers. Read back in the turned axes, the alarm is the X's,
  // and the report names the motor where it sits on that airframe.
  const test::Mission m = test::simulateMission(2, 0.0, 4.0);
  LogSampleSource x_source;
  ASSERT_FALSE(fromBytes(test::writeArdupilotMission(m), options(), x_source).refused());
  const std::vector<TelemetrySample> x = drain(x_source);
  struct Frame {
    const test::ApFrame* frame;
    const char* motor2;  // quadfdi motor 2 (the X's back-right) on this airframe
  };
  for (const Frame& f : {Frame{&test::kApH, "2: front-right, ArduPilot motor 1"}, Frame{&test::kApPlus, "2: back, ArduPilot motor 4"}}) {
    SCOPED_TRACE(f.frame->frame_type);
    const std::vector<std::uint8_t> bytes = test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kNone, *f.frame);
    expectSameAlarmAsCsv(bytes, m, 2);
    LogSampleSource src;
    ASSERT_FALSE(fromBytes(bytes, options(), src).refused());
    EXPECT_TRUE(contains(src.report().text(), f.motor2)) << src.report().text();
    EXPECT_EQ(src.report().numbering.body_turn.eighths, f.frame->eighths);
    // The samples are the X's: the attitude to ATT's centidegrees, the commands exactly.
    const std::vector<TelemetrySample> turned = drain(src);
    ASSERT_EQ(turned.size(), x.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      worst = std::max(worst, rotationAngleBetween({x[i].y[3], x[i].y[4], x[i].y[5]}, {turned[i].y[3], turned[i].y[4], turned[i].y[5]}));
      for (std::size_t k = 0; k < 4; ++k) ASSERT_EQ(turned[i].u[k], x[i].u[k]) << x[i].t;
    }
    EXPECT_LT(worst, 4e-4);  // rad: two roundings to 0.01°, each axis
  }
}

// An EKF heading reset ArduPilot does not log with its shift (EKF3's in-flight yaw alignment after
// the first climb, a compass switch): ATT's yaw steps by 10° mid-hover, the gyro (RATE) does not.
// Found with the gyro and taken out, the samples are the reset-free log's (to ATT's centidegrees),
// and so are the detector's Θ̂ and alarm; without RATE it cannot be told from a turn: left in, and
// the report says the check was not made.
TEST_F(LogDetection, ArdupilotHeadingResetIsFoundWithTheGyroAndTakenOut) {
  test::ApResets reset;
  reset.heading_at = 3.0;
  reset.heading_degrees = 10.0;
  for (int motor : {0, 2}) {
    SCOPED_TRACE(motor);
    const test::Mission m = motor == 0 ? test::simulateMission(0, 1.0, -1.0) : test::simulateMission(motor, 0.0, 4.0);
    LogSampleSource plain_source;
    ASSERT_FALSE(fromBytes(test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kRate), options(), plain_source).refused());
    const std::vector<TelemetrySample> plain = drain(plain_source);
    const std::vector<std::uint8_t> bytes = test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kRate, test::kApX, reset);
    LogSampleSource src;
    ASSERT_FALSE(fromBytes(bytes, options(), src).refused());
    std::string conventions = conventionsOf(src);
    EXPECT_TRUE(contains(conventions, "heading: 1 yaw step that the gyro (RATE) does not show")) << conventions;
    EXPECT_TRUE(contains(conventions, "largest 10° at 3.000 s")) << conventions;
    const std::vector<TelemetrySample> read = drain(src);
    ASSERT_EQ(read.size(), plain.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < read.size(); ++i) {
      worst = std::max(worst, rotationAngleBetween({plain[i].y[3], plain[i].y[4], plain[i].y[5]}, {read[i].y[3], read[i].y[4], read[i].y[5]}));
      for (std::size_t k = 0; k < 3; ++k) ASSERT_EQ(read[i].y[k], plain[i].y[k]) << read[i].t;
      for (std::size_t k = 0; k < 4; ++k) ASSERT_EQ(read[i].u[k], plain[i].u[k]) << read[i].t;
    }
    EXPECT_LT(worst, 4e-4);  // rad: ATT's rounding to 0.01°, and the step measured through it
    LogSampleSource again, plain_again;
    ASSERT_FALSE(fromBytes(bytes, options(), again).refused());
    ASSERT_FALSE(fromBytes(test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kRate), options(), plain_again).refused());
    const Result with_reset = detect(again), without = detect(plain_again);
    EXPECT_EQ(with_reset.summary.alarms_raised, without.summary.alarms_raised);
    EXPECT_EQ(with_reset.summary.first_alarm_motor, without.summary.first_alarm_motor);
    EXPECT_NEAR(with_reset.summary.first_alarm_t, without.summary.first_alarm_t, 1e-9);
    EXPECT_NEAR(with_reset.lowest, without.lowest, 0.02);
    if (motor != 0) expectSameAlarmAsCsv(bytes, m, motor);

    // Without body rates: not checked, and the step stays in the yaw.
    const std::vector<std::uint8_t> blind_bytes = test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kNone, test::kApX, reset);
    LogSampleSource blind;
    ASSERT_FALSE(fromBytes(blind_bytes, options(), blind).refused());
    conventions = conventionsOf(blind);
    EXPECT_TRUE(contains(conventions, "heading: not checked for estimator resets the log does not record: the log has no body rates"))
        << conventions;
    const std::vector<TelemetrySample> left = drain(blind);
    ASSERT_EQ(left.size(), plain.size());
    EXPECT_NEAR(std::abs(wrapAngle(left.back().y[5] - plain.back().y[5])), 10.0 * kPi / 180.0, 4e-4);
    LogSampleSource blind_again;
    ASSERT_FALSE(fromBytes(blind_bytes, options(), blind_again).refused());
    const Result left_in = detect(blind_again);
    std::printf("[ measured ] ArduPilot, %s, a 10° heading reset at 3 s: taken out, lowest Θ̂ %.2f and %ld alarm(s) "
                "(no reset: %.2f, %ld); left in (no RATE), %.2f and %ld\n",
                motor == 0 ? "healthy" : "motor 2 failing at 4 s", static_cast<double>(with_reset.lowest),
                with_reset.summary.alarms_raised, static_cast<double>(without.lowest), without.summary.alarms_raised,
                static_cast<double>(left_in.lowest), left_in.summary.alarms_raised);
  }
}

// A height reset ArduPilot does not log (EKF3 ResetHeight: a change of height source, a baro
// glitch): XKF1's PD steps by 0.8 m mid-hover, its VD does not; and a 0.5 m horizontal one, in a
// log without XKF4's OFN, OFE to say so (older firmware). Found with the EKF's own velocity and
// taken out, the samples are the reset-free log's, and so is the detection.
TEST_F(LogDetection, ArdupilotPositionResetsAreFoundWithTheEkfVelocityAndTakenOut) {
  test::ApResets reset;
  reset.height_at = 3.0;
  reset.height_metres = 0.8;
  reset.north_at = 3.5;
  reset.north_metres = 0.5;
  for (int motor : {0, 2}) {
    SCOPED_TRACE(motor);
    const test::Mission m = motor == 0 ? test::simulateMission(0, 1.0, -1.0) : test::simulateMission(motor, 0.0, 4.0);
    const std::vector<std::uint8_t> plain_bytes = test::writeArdupilotMission(m);
    LogSampleSource plain_source;
    ASSERT_FALSE(fromBytes(plain_bytes, options(), plain_source).refused());
    std::string conventions = conventionsOf(plain_source);
    // The healthy mission lands by setting the vehicle on the ground from its last 0.12 m hover
    // (sim_flights.h): a step the velocity does not show, found too, after the evaluated phase.
    char touchdown[96];
    std::snprintf(touchdown, sizeof touchdown, "1 height step (largest 0.124 m at %.3f s)",
                  std::ceil(m.landed_at * 25.0 - 1e-9) / 25.0);  // the first 25 Hz XKF1 row after touchdown
    EXPECT_TRUE(motor == 0 ? contains(conventions, touchdown)
                           : contains(conventions, "position: each XKF1 row checked against the EKF's own velocity (VN, VE, "
                                                   "VD): no height or horizontal reset ArduPilot does not log")) << conventions;
    const std::vector<TelemetrySample> plain = drain(plain_source);
    const std::vector<std::uint8_t> bytes = test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kNone, test::kApX, reset);
    LogSampleSource src;
    ASSERT_FALSE(fromBytes(bytes, options(), src).refused());
    conventions = conventionsOf(src);
    EXPECT_TRUE(contains(conventions, std::string(motor == 0 ? "position: 2 height steps" : "position: 1 height step") +
                                          " (largest 0.8 m at 3.000 s) and 1 horizontal step (largest 0.5 m at 3.520 s) that "
                                          "the EKF's own velocity (VN, VE, VD) does not explain")) << conventions;
    const std::vector<TelemetrySample> read = drain(src);
    ASSERT_EQ(read.size(), plain.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < read.size(); ++i)
      for (std::size_t k = 0; k < 3; ++k) worst = std::max(worst, std::abs(read[i].y[k] - plain[i].y[k]));
    EXPECT_LT(worst, 1e-4);  // m: the step measured against the velocity, through XKF1's floats
    LogSampleSource again, plain_again;
    ASSERT_FALSE(fromBytes(bytes, options(), again).refused());
    ASSERT_FALSE(fromBytes(plain_bytes, options(), plain_again).refused());
    const Result with_reset = detect(again), without = detect(plain_again);
    EXPECT_EQ(with_reset.summary.alarms_raised, without.summary.alarms_raised);
    EXPECT_EQ(with_reset.summary.first_alarm_motor, without.summary.first_alarm_motor);
    EXPECT_NEAR(with_reset.summary.first_alarm_t, without.summary.first_alarm_t, 1e-9);
    std::printf("[ measured ] ArduPilot, %s, 0.8 m height and 0.5 m horizontal resets taken out: position within %.2g m of the reset-free log's, "
                "lowest Θ̂ %.2f (no reset %.2f)\n", motor == 0 ? "healthy" : "motor 2 failing at 4 s", worst,
                static_cast<double>(with_reset.lowest), static_cast<double>(without.lowest));
  }
}

TEST_F(LogDetection, CrazyflieMotorFailureGivesTheCsvPathsAlarmAndMotor) {
  for (int motor : {1, 4}) {
    SCOPED_TRACE(motor);
    const test::Mission m = test::simulateMission(motor, 0.0, 4.0);
    expectSameAlarmAsCsv(test::writeCrazyflieMission(m), m, motor);
  }
}

TEST_F(LogDetection, CrazyflieCompressedStateGivesTheCsvPathsAlarmAndMotor) {
  // stateEstimateZ: the attitude to 9 bits a component (about 0.16°) and the position to 1 mm.
  const test::Mission m = test::simulateMission(2, 0.0, 4.0);
  expectSameAlarmAsCsv(test::writeCrazyflieMission(m, 10, true), m, 2);
}

TEST_F(LogDetection, HealthyTakeOffFlightAndLandingRaiseNoAlarmInAnyFormat) {
  const test::Mission m = test::simulateMission(0, 1.0, -1.0);
  ASSERT_GT(m.landed_at, 0.0);
  {
    SCOPED_TRACE("PX4");
    expectQuietLanding(test::writePx4Mission(m), m, "armed/landed events");
  }
  {
    SCOPED_TRACE("ArduPilot");
    expectQuietLanding(test::writeArdupilotMission(m), m, "armed/landed events");
  }
  {
    SCOPED_TRACE("Crazyflie");
    expectQuietLanding(test::writeCrazyflieMission(m), m, "no armed/landed events");
  }
  {
    SCOPED_TRACE("Crazyflie, stateEstimateZ");
    expectQuietLanding(test::writeCrazyflieMission(m, 10, true), m, "no armed/landed events");
  }
}

// A healthy flight through an EKF2 reset (3.6 m of position, 0.5 m of height, 20° of heading) half-way.
TEST_F(LogDetection, Px4EstimatorResetInAHealthyFlightRaisesNoAlarm) {
  const test::Mission m = test::simulateMission(0, 1.0, -1.0);
  ASSERT_GT(m.landed_at, 0.0);
  test::Px4LogOptions o;
  o.reset_at = 0.5 * (m.takeoff_at + m.landed_at);
  const std::vector<std::uint8_t> bytes = test::writePx4Mission(m, o);
  expectQuietLanding(bytes, m, "armed/landed events");
  LogSampleSource src;
  ASSERT_FALSE(fromBytes(bytes, options(), src).refused());
  std::string conventions = conventionsOf(src);
  EXPECT_TRUE(contains(conventions, "1 horizontal position reset (largest 3.61 m) and 1 height reset (largest 0.5 m)")) << conventions;
  EXPECT_TRUE(contains(conventions, "1 attitude reset (largest 20.1°)")) << conventions;
  // The same jumps without their logged shifts.
  o.log_reset_shifts = false;
  LogSampleSource raw;
  ASSERT_FALSE(fromBytes(test::writePx4Mission(m, o), options(), raw).refused());
  const Result r = detect(raw);
  std::printf("[ measured ] PX4, healthy, the reset's jumps not taken out: lowest Θ̂ %.2f, %ld alarms\n",
              static_cast<double>(r.lowest), r.summary.alarms_raised);
}

TEST_F(LogDetection, HoverCalibrationRecoversTheMotorsMaximumThrust) {
  const test::Mission m = test::simulateMission(0, 1.0, -1.0);
  ImportOptions o = options();
  o.max_thrust = 0.0;
  o.mass = nominalParams().mass;
  LogSampleSource src;
  const ImportRefusal r = fromBytes(test::writePx4Mission(m), o, src);
  ASSERT_FALSE(r.refused()) << r.message;
  EXPECT_TRUE(src.report().hover_calibrated);
  EXPECT_NEAR(src.report().thrust_factor, test::kMissionMaxThrust, 0.03 * test::kMissionMaxThrust) << src.report().thrust;
}

TEST_F(LogDetection, ALogThatNeverLeavesTheGroundIsRefused) {
  test::Mission m = test::simulateMission(0, 1.0, -1.0);
  m.samples.resize(400);  // 0.8 s on the ground
  m.takeoff_at = 100.0;
  m.landed_at = -1.0;
  for (const auto& bytes : {test::writePx4Mission(m), test::writeCrazyflieMission(m)}) {
    LogSampleSource src;
    const ImportRefusal r = fromBytes(bytes, options(), src);
    ASSERT_TRUE(r.refused());
    EXPECT_EQ(r.message.rfind("no flight found", 0), 0u) << r.message;
  }
}

// ---------- the real logs ----------

const std::string kReal = QUADFDI_SOURCE_DIR "/../shared/logs/";

// Body rates in each autopilot's log (PX4 vehicle_angular_velocity [rad/s, FRD], ArduPilot RATE
// [deg/s, FRD] or, without RATE, the first IMU's gyro [rad/s, FRD], Crazyflie gyro [deg/s, FLU]) come out on the clock in quadfdi's FLU body frame:
// the flight's true rates, through a motor failure's tumble (several rad/s) as in hover. A log
// without them carries none, and is read as before.
TEST_F(LogDetection, BodyRatesComeThroughEachAutopilotsLogInQuadfdisFrame) {
  const test::Mission m = test::simulateMission(2, 0.0, 4.0);
  test::Px4LogOptions px4;
  px4.with_rates = true;
  px4.attitude_every = 1;
  struct Case {
    std::vector<std::uint8_t> bytes;
    const char* topic;
    // [rad/s] largest and RMS error. ArduPilot's 400 Hz rows are the 500 Hz flight interpolated,
    // read back interpolated: at the failure the angular acceleration jumps by ~500 rad/s², and
    // two linear interpolations 2.5 ms apart differ there by up to a quarter of 500 × 2.5 ms.
    double worst, rms;
  };
  const Case cases[] = {{test::writePx4Mission(m, px4), "vehicle_angular_velocity", 1e-5, 1e-6},
                        {test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kRate), "RATE", 0.35, 0.02},
                        {test::writeArdupilotMission(m, 400.0, 25.0, test::ApRates::kImu), "IMU", 0.35, 0.02},
                        {test::writeCrazyflieMission(m, 10, false, true), "fixedFrequency", 1e-5, 1e-6}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.topic);
    LogSampleSource src;
    const ImportRefusal r = fromBytes(c.bytes, options(), src);
    ASSERT_FALSE(r.refused()) << r.message;
    ASSERT_TRUE(src.carriesRates()) << src.report().text();
    EXPECT_TRUE(contains(src.report().text(), std::string("body rates: ") + c.topic)) << src.report().text();
    double worst = 0.0, squares = 0.0, largest = 0.0;
    long compared = 0;
    for (const TelemetrySample& s : drain(src)) {
      const TelemetrySample truth = test::missionAt(m, s.t);
      for (std::size_t i = 0; i < 3; ++i) {
        const double e = s.rates[i] - truth.rates[i];
        worst = std::max(worst, std::abs(e));
        squares += e * e;
        largest = std::max(largest, std::abs(truth.rates[i]));
      }
      ++compared;
    }
    EXPECT_GT(compared, 1000);
    EXPECT_GT(largest, 3.0);  // the tumble after the failure: every sign convention shows
    EXPECT_LT(worst, c.worst);
    EXPECT_LT(std::sqrt(squares / (3.0 * static_cast<double>(compared))), c.rms);
  }
  LogSampleSource without;
  ASSERT_FALSE(fromBytes(test::writeCrazyflieMission(m), options(), without).refused());
  EXPECT_FALSE(without.carriesRates());
  // Not read (a model without rates): the same samples as the log without them, bit for bit.
  ImportOptions unread = options();
  unread.read_rates = false;
  LogSampleSource left_out;
  ASSERT_FALSE(fromBytes(test::writeCrazyflieMission(m, 10, false, true), unread, left_out).refused());
  EXPECT_FALSE(left_out.carriesRates());
  const std::vector<TelemetrySample> a = drain(left_out), b = drain(without);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].t, b[i].t);
    ASSERT_EQ(a[i].y, b[i].y);
    ASSERT_EQ(a[i].u, b[i].u);
  }
}

bool readFile(const std::string& path, std::vector<std::uint8_t>& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  bytes.assign(s.begin(), s.end());
  return true;
}

TEST(TelemetryFromLogReal, Px4SampleLogsAreRefusedForTheirTenHertzActuatorOutputs) {
  for (const char* name : {"px4/sample_log_small.ulg", "px4/sample_logging_tagged_and_default_params.ulg"}) {
    SCOPED_TRACE(name);
    std::vector<std::uint8_t> bytes;
    if (!readFile(kReal + name, bytes)) GTEST_SKIP() << "no real logs in " << kReal;
    DecodedLog log;
    ASSERT_TRUE(readUlog(ByteSpan{bytes.data(), bytes.size()}, log).ok());
    // Both were flown (or sat) without horizontal aiding: refused for that first; with the
    // position flagged valid, the commands' rate is what remains.
    FlightSignals s;
    const LogIssue invalid = extractPx4Signals(log, Px4SignalOptions{}, s);
    EXPECT_EQ(invalid.topic, "vehicle_local_position");
    EXPECT_TRUE(contains(invalid.message, "xy_valid is false in all")) << invalid.message;
    for (LogTopic& t : log.topics)
      if (t.name == "vehicle_local_position") {
        auto& flag = t.columns[static_cast<std::size_t>(t.fieldIndex("xy_valid"))];
        std::fill(flag.begin(), flag.end(), 1.0);
      }
    s = FlightSignals{};
    ASSERT_TRUE(extractPx4Signals(log, Px4SignalOptions{}, s).ok());
    ImportOptions o;
    o.max_thrust = 10.0;
    LogSampleSource src;
    const ImportRefusal r = buildLogSampleSource(std::move(s), log.format, o, src);
    ASSERT_TRUE(r.refused());
    EXPECT_EQ(r.topic, "actuator_outputs");
    EXPECT_TRUE(contains(r.message, "SDLOG_PROFILE")) << r.message;
    const std::size_t at = r.message.find("logged at ");
    ASSERT_NE(at, std::string::npos) << r.message;
    const double hz = std::stod(r.message.substr(at + 10));
    EXPECT_GT(hz, 5.0) << r.message;
    EXPECT_LT(hz, 15.0) << r.message;
  }
}

TEST(TelemetryFromLogReal, CrazyflieMotorLogIsTooCoarseBesidesMissingItsPitch) {
  std::vector<std::uint8_t> bytes;
  if (!readFile(kReal + "crazyflie-usd/motor_normal_flight_E8_log00", bytes)) GTEST_SKIP() << "no real logs in " << kReal;
  DecodedLog log;
  ASSERT_TRUE(readCrazyflieUsd(ByteSpan{bytes.data(), bytes.size()}, log).ok());
  FlightSignals s;
  const LogIssue i = extractCrazyflieSignals(log, CrazyflieSignalOptions{}, s);
  EXPECT_EQ(i.status, LogStatus::kMissingSignal);
  EXPECT_EQ(i.topic, "stateEstimate.pitch");
  const std::string note = coarseTopicsNote(log, ImportOptions{});
  EXPECT_TRUE(contains(note, "fixedFrequency")) << note;
  EXPECT_TRUE(contains(note, "below the 125 Hz")) << note;
  const std::size_t at = note.find("logged at ");
  ASSERT_NE(at, std::string::npos) << note;
  EXPECT_NEAR(std::stod(note.substr(at + 10)), 100.0, 5.0) << note;
}

}  // namespace
}  // namespace quadfdi
