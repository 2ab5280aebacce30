// Heading resets found with the gyro (src/logs/heading_resets.h): a step about the vertical that
// the gyro does not show is taken out, and nothing else is — not a gyro's lag, bias or noise, not
// a simulator's white attitude noise, not a tumbling crash seen through the estimator model, not
// the real PX4 logs (whose own resets PX4 records).
#include "logs/heading_resets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/frames.h"
#include "logs/mission_writers.h"
#include "logs/px4_signals.h"
#include "logs/ulog.h"
#include "simulation/rng.h"
#include "simulation/sensor_model.h"

namespace quadfdi {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

std::array<double, 3> ratesAt(double t) { return {2.0 * std::sin(3.0 * t), 1.5 * std::cos(2.0 * t), 0.8 * std::sin(t)}; }

// A vehicle turning about all three axes (rates of up to 2 rad/s) for `seconds`: attitude rows every
// `dt` from the body rates integrated finely, and the rates at the same rows.
void turningFlight(double dt, double seconds, SignalSeries<3>& attitude, SignalSeries<3>& rates) {
  Quaternion q = quaternionOfEuler({0.1, -0.2, 0.3});
  const int fine = 20;
  for (long k = 0; static_cast<double>(k) * dt <= seconds + 1e-9; ++k) {
    const double t = static_cast<double>(k) * dt;
    if (k > 0)
      for (int i = 0; i < fine; ++i) {
        const double h = dt / fine, mid = t - dt + (i + 0.5) * h;
        const std::array<double, 3> w = ratesAt(mid);
        q = q * quaternionOfRotationVector({w[0] * h, w[1] * h, w[2] * h});
      }
    const EulerZyx e = eulerZyxFromUnitQuaternion(q.w, q.x, q.y, q.z);
    attitude.t.push_back(t);
    attitude.v.push_back({e.roll, e.pitch, e.yaw});
    rates.t.push_back(t);
    rates.v.push_back(ratesAt(t));
  }
  rates.source.topic = "RATE";
}

// The estimator's heading moved by `step` [rad] from row `from` on (R' = Rz(step)·R: yaw + step).
void resetHeading(SignalSeries<3>& attitude, std::size_t from, double step) {
  for (std::size_t k = from; k < attitude.v.size(); ++k) attitude.v[k][2] = wrapAngle(attitude.v[k][2] + step);
}

TEST(HeadingResets, AStepTheGyroDoesNotShowIsTakenOutAndNothingElse) {
  SignalSeries<3> clean, rates;
  turningFlight(0.0025, 4.0, clean, rates);  // ArduPilot's ATT and RATE at 400 Hz

  SignalSeries<3> same = clean;
  const HeadingResets none = takeOutHeadingResets(same, rates);
  EXPECT_TRUE(none.checked);
  EXPECT_EQ(none.steps, clean.t.size() - 1);
  EXPECT_EQ(none.count, 0u);
  EXPECT_EQ(same.v, clean.v);  // untouched
  EXPECT_LT(none.largest_left, 1e-6);
  EXPECT_NE(headingResetsLine(none, rates).find("no estimator reset the log does not record"), std::string::npos);

  SignalSeries<3> reset = clean;
  resetHeading(reset, 400, 2.0 * kDeg);
  resetHeading(reset, 1000, -5.0 * kDeg);
  const HeadingResets found = takeOutHeadingResets(reset, rates);
  EXPECT_EQ(found.count, 2u);
  EXPECT_NEAR(found.largest, 5.0 * kDeg, 1e-6);
  EXPECT_DOUBLE_EQ(found.largest_t, clean.t[1000]);
  double worst = 0.0;
  for (std::size_t k = 0; k < clean.v.size(); ++k) {
    EXPECT_EQ(reset.v[k][0], clean.v[k][0]);
    EXPECT_EQ(reset.v[k][1], clean.v[k][1]);
    worst = std::max(worst, std::abs(wrapAngle(reset.v[k][2] - clean.v[k][2])));
  }
  EXPECT_LT(worst, 1e-6);
  const std::string line = headingResetsLine(found, rates);
  EXPECT_NE(line.find("2 yaw steps that the gyro (RATE) does not show"), std::string::npos) << line;
  EXPECT_NE(line.find("largest 5° at 2.500 s"), std::string::npos) << line;
}

// A rate topic that lags the attitude by 10 ms, with a 0.02 rad/s bias and 0.05 rad/s of white
// noise, and 5 mrad of white noise on every attitude angle (the randomisation's largest): the gyro
// explains each row less well, smoothly (lag, bias) or by noise, and none of it is a reset. A step
// that stands out of that noise still is.
TEST(HeadingResets, GyroLagBiasAndNoiseAreNotResets) {
  SignalSeries<3> clean, exact;
  turningFlight(0.0025, 4.0, clean, exact);
  SignalSeries<3> rates = exact;
  Rng rng(7, 0);
  for (std::size_t k = 0; k < rates.t.size(); ++k) {
    const std::array<double, 3> w = ratesAt(rates.t[k] - 0.010);
    for (std::size_t c = 0; c < 3; ++c) rates.v[k][c] = w[c] + 0.02 + 0.05 * standardNormal(rng);
  }
  SignalSeries<3> lagged = clean;
  const HeadingResets smooth = takeOutHeadingResets(lagged, rates);
  EXPECT_EQ(smooth.count, 0u);
  EXPECT_EQ(lagged.v, clean.v);
  std::printf("[ measured ] lag 10 ms, bias, gyro noise: largest step beyond its neighbours %.3f°, noise σ %.4f°\n",
              smooth.largest_left / kDeg, smooth.noise / kDeg);

  SignalSeries<3> noisy = clean;
  for (auto& a : noisy.v)
    for (double& angle : a) angle += 0.005 * standardNormal(rng);
  const SignalSeries<3> noisy_before = noisy;
  const HeadingResets white = takeOutHeadingResets(noisy, rates);
  EXPECT_EQ(white.count, 0u);
  EXPECT_EQ(noisy.v, noisy_before.v);
  EXPECT_GT(white.threshold, 0.5 * kDeg);  // raised by the noise
  std::printf("[ measured ] + 5 mrad white attitude noise: largest %.3f°, noise σ %.3f°, threshold %.2f°\n",
              white.largest_left / kDeg, white.noise / kDeg, white.threshold / kDeg);

  resetHeading(noisy, 800, 2.0 * white.threshold);
  const HeadingResets found = takeOutHeadingResets(noisy, rates);
  EXPECT_EQ(found.count, 1u);
  EXPECT_NEAR(found.largest, 2.0 * white.threshold, 0.3 * white.threshold);
}

// The simulated Crazyflie losing motor 2 and tumbling (rates of tens of rad/s), seen through the
// estimator model at the randomisation's harshest settings (attitude noise 5 mrad, 10 ms attitude
// lag, gyro noise 0.05 rad/s behind a 20 Hz low-pass, both 10 ms late): no reset found, in hover
// or in the tumble.
TEST(HeadingResets, ACrashThroughTheEstimatorModelHasNone) {
  for (int motor : {0, 2}) {
    const test::Mission m = test::simulateMission(motor, 0.0, 4.0);
    SensorModelConfig config;
    config.attitude_std = 0.005;
    config.rate_std = 0.05;
    config.attitude_filter_tau = 0.01;
    config.rate_filter_tau = 0.008;
    config.delay_steps = 5;
    SensorModel sensors(config, m.dt);
    Rng rng(11, 0);
    auto state = [](const TelemetrySample& s) {
      State x = State::Zero();
      for (int i = 0; i < 3; ++i) {
        x(idx::kPos + i) = s.y[static_cast<std::size_t>(i)];
        x(idx::kAtt + i) = s.y[static_cast<std::size_t>(3 + i)];
        x(idx::kRate + i) = s.rates[static_cast<std::size_t>(i)];
      }
      return x;
    };
    sensors.reset(state(m.samples.front()));
    SignalSeries<3> attitude, rates;
    double fastest = 0.0;
    for (const TelemetrySample& s : m.samples) {
      const State& e = sensors.measure(state(s), rng);
      attitude.t.push_back(s.t);
      attitude.v.push_back({e(idx::kRoll), e(idx::kPitch), e(idx::kYaw)});
      rates.t.push_back(s.t);
      rates.v.push_back({e(idx::kP), e(idx::kQ), e(idx::kR)});
      fastest = std::max(fastest, std::hypot(s.rates[0], s.rates[1], s.rates[2]));
    }
    const SignalSeries<3> before = attitude;
    const HeadingResets found = takeOutHeadingResets(attitude, rates);
    std::printf("[ measured ] %s, fastest %.1f rad/s: largest step beyond its neighbours %.3f°, noise σ %.3f°, threshold %.2f°\n",
                motor == 0 ? "healthy mission" : "motor 2 lost, tumbling", fastest, found.largest_left / kDeg,
                found.noise / kDeg, found.threshold / kDeg);
    EXPECT_TRUE(found.checked);
    EXPECT_EQ(found.count, 0u) << "largest " << found.largest / kDeg << "° at " << found.largest_t << " s";
    EXPECT_EQ(attitude.v, before.v);
  }
}

// A PX4 sample log from ../shared/logs/px4, decoded, its position flagged valid (both were flown
// without horizontal aiding; the attitude is what counts here); false when absent.
bool readRealPx4Log(const std::string& name, DecodedLog& log) {
  std::ifstream in(std::string(QUADFDI_SOURCE_DIR) + "/../shared/logs/px4/" + name, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) return false;
  EXPECT_TRUE(readUlog(ByteSpan{bytes.data(), bytes.size()}, log).ok()) << name;
  for (LogTopic& t : log.topics)
    if (t.name == "vehicle_local_position")
      for (const char* flag : {"xy_valid", "z_valid"})
        if (const int f = t.fieldIndex(flag); f >= 0)
          for (double& v : t.columns[static_cast<std::size_t>(f)]) v = 1.0;
  return true;
}

// The real PX4 logs (vehicle_attitude ~200 Hz, vehicle_angular_velocity): PX4 records its resets
// and its extractor takes them out, so nothing is left to find; how well the gyro explains a real
// estimator's attitude is what the default threshold stands on.
TEST(HeadingResets, RealPx4LogsHaveNoneLeft) {
  for (const char* name : {"sample_log_small.ulg", "sample_logging_tagged_and_default_params.ulg"}) {
    DecodedLog log;
    if (!readRealPx4Log(name, log)) GTEST_SKIP() << "../shared/logs/px4/" << name << " not found";
    FlightSignals s;
    const LogIssue issue = extractPx4Signals(log, Px4SignalOptions{}, s);
    ASSERT_TRUE(issue.ok()) << name << ": " << issue.message;
    ASSERT_FALSE(s.rates.empty()) << name;
    const SignalSeries<3> before = s.attitude;
    const HeadingResets found = takeOutHeadingResets(s.attitude, s.rates);
    std::printf("[ measured ] %s: %zu steps, largest beyond its neighbours %.3f°, noise σ %.4f°\n", name, found.steps,
                found.largest_left / kDeg, found.noise / kDeg);
    EXPECT_GT(found.steps, 1000u);
    EXPECT_EQ(found.count, 0u) << name << ": largest " << found.largest / kDeg << "° at " << found.largest_t << " s";
    EXPECT_EQ(s.attitude.v, before.v);
  }
}

// The same SITL log whose two heading resets PX4 recorded (t = 1.244 s by 4.1 mrad, 8.856 s by
// 1.2 mrad; Px4Signals.RealLogsHeadingResetsAreTakenOut), with that record erased: the gyro finds
// the first by itself, its size to within the attitude's noise; the second, 0.07°, is below
// min_step and stays.
TEST(HeadingResets, RealPx4ResetIsFoundWithoutItsRecord) {
  const char* name = "sample_logging_tagged_and_default_params.ulg";
  DecodedLog log;
  if (!readRealPx4Log(name, log)) GTEST_SKIP() << "../shared/logs/px4/" << name << " not found";
  for (LogTopic& t : log.topics)
    if (t.name == "vehicle_attitude")
      if (const int f = t.fieldIndex("quat_reset_counter"); f >= 0)
        for (double& v : t.columns[static_cast<std::size_t>(f)]) v = 0.0;
  FlightSignals s;
  ASSERT_TRUE(extractPx4Signals(log, Px4SignalOptions{}, s).ok());
  const HeadingResets found = takeOutHeadingResets(s.attitude, s.rates);
  std::printf("[ measured ] the record erased: %zu reset(s), largest %.2f mrad at %.3f s; largest left %.2f mrad\n",
              found.count, found.largest * 1e3, found.largest_t, found.largest_left * 1e3);
  EXPECT_EQ(found.count, 1u);
  EXPECT_NEAR(found.largest_t, 1.244, 0.01);
  EXPECT_NEAR(found.largest, 4.1e-3, 0.3e-3);
}

TEST(HeadingResets, WithoutBodyRatesNothingIsChecked) {
  SignalSeries<3> attitude, rates;
  turningFlight(0.0025, 1.0, attitude, rates);
  const SignalSeries<3> before = attitude;
  const HeadingResets found = takeOutHeadingResets(attitude, SignalSeries<3>{});
  EXPECT_FALSE(found.checked);
  EXPECT_EQ(attitude.v, before.v);
  EXPECT_EQ(headingResetsLine(found, SignalSeries<3>{}),
            "heading: not checked for estimator resets the log does not record: the log has no body rates");
  // A gyro that stops half-way covers only the first half.
  rates.t.resize(rates.t.size() / 2);
  rates.v.resize(rates.t.size());
  const HeadingResets half = takeOutHeadingResets(attitude, rates);
  EXPECT_TRUE(half.checked);
  EXPECT_EQ(half.steps, rates.t.size() - 1);
}

}  // namespace
}  // namespace quadfdi
