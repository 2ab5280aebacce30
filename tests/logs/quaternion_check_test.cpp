// An attitude quaternion's reading against the flight (src/logs/quaternion_check.h): written in any
// of the four readings, the columns are named for the one they were written in, from the tilt
// alone and from the rates; in NED with a body turn too; a short flight checks nothing.
#include "logs/quaternion_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

namespace quadfdi {
namespace {

constexpr double kGravity = 9.81;  // [m/s²]

// 20 s at 250 Hz of a multirotor: its body turning at ω(t) (body FLU; its heading once round unless
// not `turning`), the attitude integrated
// from it, and the position accelerated where the thrust leans (g·tilt holds its height), with
// 2 mrad of noise on the logged angles and 2 mm on the position.
struct Flight {
  std::vector<double> t;
  std::vector<Quaternion> attitude;  // body → world, quadfdi's frames
  SignalSeries<3> position, rates;
};
Flight leaningFlight(double yaw0, bool turning = true) {
  Flight f;
  Quaternion q = quaternionOfEuler({0.05, -0.03, yaw0});
  const double yaw_rate = turning ? 1.0 : 0.0;
  const auto omega = [yaw_rate](double t) {
    return std::array<double, 3>{0.4 * std::sin(3 * t), 0.3 * std::cos(2.1 * t), yaw_rate * (0.3 + 0.25 * std::sin(0.7 * t))};
  };
  const double dt = 0.004;
  std::array<double, 2> p{}, v{};
  for (int k = 0; k <= 5000; ++k) {
    const double t = k * dt;
    f.t.push_back(t);
    f.attitude.push_back(q);
    f.position.t.push_back(t);
    f.position.v.push_back({p[0], p[1], 1.0});
    f.rates.t.push_back(t);
    f.rates.v.push_back(omega(t));
    const double up = 1.0 - 2.0 * (q.x * q.x + q.y * q.y);
    const std::array<double, 2> tilt{2.0 * (q.x * q.z + q.w * q.y) / up, 2.0 * (q.y * q.z - q.w * q.x) / up};
    for (std::size_t b = 0; b < 2; ++b) {
      v[b] += kGravity * tilt[b] * dt;
      p[b] += v[b] * dt;
    }
    for (int s = 0; s < 20; ++s) {
      const std::array<double, 3> w = omega(t + (s + 0.5) * dt / 20);
      q = q * quaternionOfRotationVector({w[0] * dt / 20, w[1] * dt / 20, w[2] * dt / 20});
    }
  }
  return f;
}

// The attitude a reader makes of `flight` written with `writer` and read with `reader` (its frame
// and body turn undone as TelemetryReader does), with angle noise.
SignalSeries<3> readAttitude(const Flight& flight, const QuaternionReading& writer, bool ned = false, BodyTurn turn = {},
                             const QuaternionReading& reader = {}) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.002);
  SignalSeries<3> out;
  out.t = flight.t;
  const Quaternion unturn = quaternionOfRotationVector({0.0, 0.0, -turn.radians()});
  for (const Quaternion& truth : flight.attitude) {
    Quaternion file = truth * unturn;  // in the airframe's own axes, as the file holds it
    if (ned) file = turnedAboutX(file);
    const Quaternion q = quaternionOfColumns(columnsOfQuaternion(file, writer), reader);
    EulerZyx e = eulerZyxFromUnitQuaternion(q.w, q.x, q.y, q.z);
    if (ned) e = turnedAboutX(e);
    e = attitudeOfTurnedAxes(e, turn);
    out.v.push_back({e.roll + noise(rng), e.pitch + noise(rng), e.yaw + noise(rng)});
  }
  return out;
}

TEST(QuaternionCheck, ReadingsTurnColumnsIntoTheirRotationAndBack) {
  const std::array<double, 4> c{0.5, -0.1, 0.7, std::sqrt(1.0 - 0.25 - 0.01 - 0.49)};
  for (const QuaternionReading& r : kQuaternionReadings) {
    SCOPED_TRACE(r.name());
    EXPECT_EQ(columnsOfQuaternion(quaternionOfColumns(c, r), r), c);
    EXPECT_EQ(kQuaternionReadings[indexOf(r)], r);
  }
  // x,y,z,w: the scalar is the last column; world → body: the inverse rotation.
  const Quaternion last = quaternionOfColumns(c, {true, false});
  EXPECT_EQ(last.w, c[3]);
  EXPECT_EQ(last.x, c[0]);
  const Quaternion inverse = quaternionOfColumns(c, {false, true});
  EXPECT_EQ(inverse.w, c[0]);
  EXPECT_EQ(inverse.x, -c[1]);
  EXPECT_EQ(QuaternionReading{}.name(), "w,x,y,z body → world");
  EXPECT_EQ((QuaternionReading{true, true}.options()), "--csv-quaternion xyzw-world-to-body");
  EXPECT_EQ((QuaternionReading{false, true}.options()), "--csv-quaternion wxyz-world-to-body");
}

TEST(QuaternionCheck, EachReadingIsNamedFromTheTiltAndFromTheRates) {
  const Flight f = leaningFlight(2.0);  // heading turning: the inverse's tilt (the body's) is not the world's
  const SignalSeries<3> none;
  for (const QuaternionReading& writer : kQuaternionReadings) {
    SCOPED_TRACE(writer.name());
    const SignalSeries<3> attitude = readAttitude(f, writer);
    for (const SignalSeries<3>* rates : {&none, &f.rates}) {
      const QuaternionCheck c = checkQuaternionReading(f.position, attitude, *rates, QuaternionReading{}, false, {});
      EXPECT_EQ(c.verdict, writer == QuaternionReading{} ? QuaternionVerdict::kAgrees : QuaternionVerdict::kOtherReading) << c.text();
      EXPECT_EQ(c.best, writer) << c.text();
      EXPECT_EQ(c.rates_compared, !rates->empty());
      EXPECT_GT(std::abs(c.tilt_fit[indexOf(writer)]), 0.9) << c.text();
      if (!rates->empty()) {
        EXPECT_TRUE(c.rates_in_order[indexOf(writer)]) << c.text();
      }
    }
  }
  const QuaternionCheck c = checkQuaternionReading(f.position, readAttitude(f, {true, false}), f.rates, QuaternionReading{}, false, {});
  EXPECT_EQ(c.text().rfind("attitude quaternion: the columns qw,qx,qy,qz fit the flight read as x,y,z,w body → world, not as w,x,y,z "
                           "body → world (its horizontal acceleration on the tilt over ", 0),
            0u)
      << c.text();
  EXPECT_NE(c.text().find("): read them with --csv-quaternion xyzw"), std::string::npos) << c.text();
}

// A file in NED and in a plus frame's own axes: the columns are found again through the reader's
// frame flip and body turn, and the rates (FRD, turned alike) still follow the written reading.
TEST(QuaternionCheck, TheColumnsAreFoundThroughTheFrameAndTheBodyTurn) {
  const Flight f = leaningFlight(-1.0);
  const BodyTurn turn{2};  // a plus frame read as an X: 90°
  // The reader gives position, attitude and rates in quadfdi's frames and the X's axes: the truth's.
  const SignalSeries<3>& position = f.position;
  const SignalSeries<3>& rates = f.rates;
  for (const QuaternionReading& writer : kQuaternionReadings) {
    SCOPED_TRACE(writer.name());
    const SignalSeries<3> attitude = readAttitude(f, writer, true, turn);
    const QuaternionCheck c = checkQuaternionReading(position, attitude, rates, QuaternionReading{}, true, turn);
    EXPECT_EQ(c.best, writer) << c.text();
    EXPECT_TRUE(c.rates_in_order[indexOf(writer)]) << c.text();
  }
  // Read already as written: agrees.
  const QuaternionReading last{true, true};
  const QuaternionCheck c = checkQuaternionReading(position, readAttitude(f, last, true, turn, last), rates, last, true, turn);
  EXPECT_EQ(c.verdict, QuaternionVerdict::kAgrees) << c.text();
}

// Without rates, at a steady heading near north the inverse's tilt fits as the right one's does:
// nothing is named either way.
TEST(QuaternionCheck, TheInverseAtASteadyNorthHeadingIsLeftOpenWithoutRates) {
  const Flight f = leaningFlight(0.0, false);
  for (const QuaternionReading& writer : {QuaternionReading{}, QuaternionReading{false, true}}) {
    SCOPED_TRACE(writer.name());
    const QuaternionCheck c = checkQuaternionReading(f.position, readAttitude(f, writer), {}, QuaternionReading{}, false, {});
    EXPECT_EQ(c.verdict, QuaternionVerdict::kUnclear) << c.text();
    EXPECT_TRUE(c.alike[indexOf({false, true})]) << c.text();  // the inverse of the reading used, whichever was written
    EXPECT_NE(c.text().find("(the inverse's tilt is the body's, which a steady heading near north or south cannot tell from the world's): p,q,r columns would tell"), std::string::npos) << c.text();
  }
}

// A clock that jumps by an hour mid-file (a logger's restart): two pieces, each checked, the hole
// stepped over rather than walked node by node.
TEST(QuaternionCheck, AnHoursHoleIsSteppedOver) {
  Flight f = leaningFlight(1.0);
  for (SignalSeries<3>* s : {&f.position, &f.rates})
    for (std::size_t i = 2500; i < s->t.size(); ++i) s->t[i] += 3600.0;
  for (std::size_t i = 2500; i < f.t.size(); ++i) f.t[i] += 3600.0;
  const QuaternionCheck c = checkQuaternionReading(f.position, readAttitude(f, {}), {}, QuaternionReading{}, false, {});
  EXPECT_EQ(c.verdict, QuaternionVerdict::kAgrees) << c.text();
  // Each 10-s piece loses its first and last 0.5 s (the second difference's span) and the filters' 2 s.
  EXPECT_NEAR(c.seconds, 2 * (10.0 - 0.5 - 2.0 - 0.5), 0.1) << c.text();
}

TEST(QuaternionCheck, AShortFlightChecksNothing) {
  Flight f = leaningFlight(1.0);
  for (SignalSeries<3>* s : {&f.position, &f.rates}) {
    s->t.resize(1000);  // 4 s
    s->v.resize(1000);
  }
  f.t.resize(1000);
  f.attitude.resize(1000);
  const QuaternionCheck c = checkQuaternionReading(f.position, readAttitude(f, {}), {}, QuaternionReading{}, false, {});
  EXPECT_EQ(c.verdict, QuaternionVerdict::kNotChecked) << c.text();
  EXPECT_EQ(c.text(), "attitude quaternion: not checked (under 5 s of flight without holes, and no body rates to compare)");
}

}  // namespace
}  // namespace quadfdi
