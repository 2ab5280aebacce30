// Body rates against the attitude's own turn (src/logs/rate_agreement.h): the columns as read
// agree; in FRD, in degrees per second, or with two axes swapped they are named for what they hold.
#include "logs/rate_agreement.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "core/frames.h"

namespace quadfdi {
namespace {

// 6 s at 250 Hz of a body turning at ω(t) = (0.5 sin 3t, 0.4 cos 2t, 0.3 sin t) rad/s (body FLU),
// its attitude integrated from it (20 sub-steps a row), with `noise` [rad] of white noise on the
// logged angles.
struct Flight {
  SignalSeries<3> attitude, rates;
};
Flight turningBody(double noise = 0.0) {
  Flight f;
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, noise);
  Quaternion q = quaternionOfEuler({0.1, -0.05, 2.0});
  const auto omega = [](double t) { return std::array<double, 3>{0.5 * std::sin(3 * t), 0.4 * std::cos(2 * t), 0.3 * std::sin(t)}; };
  const double dt = 0.004;
  for (int k = 0; k <= 1500; ++k) {
    const double t = k * dt;
    EulerZyx e;
    EXPECT_TRUE(eulerZyxFromQuaternion(q.w, q.x, q.y, q.z, e));
    f.attitude.t.push_back(t);
    f.attitude.v.push_back({e.roll + (noise > 0 ? n(rng) : 0.0), e.pitch + (noise > 0 ? n(rng) : 0.0), e.yaw + (noise > 0 ? n(rng) : 0.0)});
    f.rates.t.push_back(t);
    f.rates.v.push_back(omega(t));
    for (int s = 0; s < 20; ++s) {
      const std::array<double, 3> w = omega(t + (s + 0.5) * dt / 20);
      q = q * quaternionOfRotationVector({w[0] * dt / 20, w[1] * dt / 20, w[2] * dt / 20});
    }
  }
  return f;
}

TEST(RateAgreement, RatesAsReadAgreeWithTheAttitudesTurn) {
  for (double noise : {0.0, 0.002}) {
    SCOPED_TRACE(noise);
    const Flight f = turningBody(noise);
    const RateAgreement a = checkRateAgreement(f.attitude, f.rates);
    EXPECT_EQ(a.verdict, RateAgreementVerdict::kAgrees) << a.text();
    EXPECT_EQ(a.windows, 300u);  // 6 s in 20 ms windows
    EXPECT_NEAR(a.scale, 1.0, noise > 0 ? 0.2 : 0.002) << a.text();  // the spreads' ratio: 2 mrad of angle noise swells the turn's
    for (double c : a.axis_correlation) EXPECT_GT(c, noise > 0 ? 0.8 : 0.999) << a.text();
    EXPECT_EQ(a.text().rfind("body rates: p,q,r agree with the attitude's own turn over 300 windows", 0), 0u) << a.text();
  }
}

TEST(RateAgreement, AnotherFrameUnitOrOrderIsNamed) {
  const Flight f = turningBody(0.002);
  Flight frd = f, deg = f, swapped = f;
  for (auto& w : frd.rates.v) w = {w[0], -w[1], -w[2]};
  for (auto& w : deg.rates.v)
    for (double& c : w) c *= 180.0 / M_PI;
  for (auto& w : swapped.rates.v) w = {w[1], w[0], w[2]};
  const RateAgreement a = checkRateAgreement(frd.attitude, frd.rates);
  EXPECT_EQ(a.verdict, RateAgreementVerdict::kDiffers);
  EXPECT_EQ(a.axis, (std::array<int, 3>{0, 1, 2}));
  EXPECT_EQ(a.sign, (std::array<int, 3>{1, -1, -1}));
  EXPECT_LT(a.score_as_read, 1.0);
  EXPECT_NE(a.text().find("the attitude turns as (p, −q, −r) would, not as p,q,r read"), std::string::npos) << a.text();
  EXPECT_NE(a.text().find("FRD rates (PX4, ArduPilot, Gazebo) beside attitude in quadfdi's frames?"), std::string::npos) << a.text();

  const RateAgreement d = checkRateAgreement(deg.attitude, deg.rates);
  EXPECT_EQ(d.verdict, RateAgreementVerdict::kDiffers);
  EXPECT_NEAR(d.scale, M_PI / 180.0, 0.2 * M_PI / 180.0);
  EXPECT_NE(d.text().find("p,q,r look like degrees per second read as radians (--csv-rate-unit deg/s"), std::string::npos) << d.text();

  const RateAgreement s = checkRateAgreement(swapped.attitude, swapped.rates);
  EXPECT_EQ(s.verdict, RateAgreementVerdict::kDiffers);
  EXPECT_EQ(s.axis, (std::array<int, 3>{1, 0, 2}));
  EXPECT_NE(s.text().find("the attitude turns as (q, p, r) would"), std::string::npos) << s.text();
}

TEST(RateAgreement, TooLittleFlightOrRatesOfSomethingElseDecideNothing) {
  Flight f = turningBody();
  Flight short_flight;
  for (std::size_t k = 0; k < 400; ++k) {  // 1.6 s
    short_flight.attitude.t.push_back(f.attitude.t[k]);
    short_flight.attitude.v.push_back(f.attitude.v[k]);
  }
  short_flight.rates = f.rates;
  EXPECT_EQ(checkRateAgreement(short_flight.attitude, short_flight.rates).verdict, RateAgreementVerdict::kNotChecked);
  Flight still = f;
  for (auto& w : still.rates.v) w = {0.001, 0.0, 0.0};
  EXPECT_EQ(checkRateAgreement(still.attitude, still.rates).verdict, RateAgreementVerdict::kNotChecked);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.5);
  Flight unrelated = f;
  for (auto& w : unrelated.rates.v) w = {n(rng), n(rng), n(rng)};
  const RateAgreement u = checkRateAgreement(unrelated.attitude, unrelated.rates);
  EXPECT_EQ(u.verdict, RateAgreementVerdict::kUnclear) << u.text();
  EXPECT_NE(u.text().find("no order, sign and scale of p,q,r fits the attitude's turn clearly"), std::string::npos) << u.text();
}

}  // namespace
}  // namespace quadfdi
