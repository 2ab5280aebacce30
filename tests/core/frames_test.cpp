// The shared frame conventions (core/frames.h): the one angle wrap, the quaternion → ZYX Euler
// conversion every reader uses, and the NED/FRD ↔ z-up/FLU turn.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/frames.h"

using namespace quadfdi;

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST(Frames, WrapAngleGivesOneValuePerHeadingInMinusPiToPi) {
  EXPECT_NEAR(wrapAngle(3.0 * kPi / 2), -kPi / 2, 1e-15);
  EXPECT_NEAR(wrapAngle(-3.0 * kPi / 2), kPi / 2, 1e-15);
  EXPECT_DOUBLE_EQ(wrapAngle(0.3), 0.3);
  EXPECT_DOUBLE_EQ(wrapAngle(-0.3), -0.3);
  // The seam: −π and +π are one heading, written +π; so are odd multiples of π either side.
  EXPECT_EQ(wrapAngle(-kPi), kPi);
  EXPECT_EQ(wrapAngle(kPi), kPi);
  EXPECT_EQ(wrapAngle(3.0 * kPi), kPi);
  EXPECT_EQ(wrapAngle(-3.0 * kPi), kPi);
  // Many turns away: exact (std::remainder does not lose the fraction).
  EXPECT_NEAR(wrapAngle(0.25 + 200.0 * kPi), 0.25, 1e-12);
  for (double a = -20.0; a <= 20.0; a += 0.37) {
    const double w = wrapAngle(a);
    EXPECT_GT(w, -kPi);
    EXPECT_LE(w, kPi);
    EXPECT_NEAR(std::cos(w), std::cos(a), 1e-12);
    EXPECT_NEAR(std::sin(w), std::sin(a), 1e-12);
  }
}

TEST(Frames, QuaternionToEulerKnownRotations) {
  const double h = std::sqrt(0.5);
  EulerZyx e = eulerZyxFromUnitQuaternion(1, 0, 0, 0);
  EXPECT_EQ(e.roll, 0.0);
  EXPECT_EQ(e.pitch, 0.0);
  EXPECT_EQ(e.yaw, 0.0);
  e = eulerZyxFromUnitQuaternion(h, h, 0, 0);  // 90° about body x: right side down
  EXPECT_NEAR(e.roll, kPi / 2, 1e-12);
  e = eulerZyxFromUnitQuaternion(h, 0, h, 0);  // 90° about body y (left): nose down
  EXPECT_NEAR(e.pitch, kPi / 2, 1e-7);
  e = eulerZyxFromUnitQuaternion(h, 0, 0, h);  // 90° about z (up): counter-clockwise from above
  EXPECT_NEAR(e.yaw, kPi / 2, 1e-12);
  // q and −q are the same rotation.
  const EulerZyx a = eulerZyxFromUnitQuaternion(0.9, 0.1, -0.3, std::sqrt(1 - 0.81 - 0.01 - 0.09));
  const EulerZyx b = eulerZyxFromUnitQuaternion(-0.9, -0.1, 0.3, -std::sqrt(1 - 0.81 - 0.01 - 0.09));
  EXPECT_NEAR(a.roll, b.roll, 1e-15);
  EXPECT_NEAR(a.pitch, b.pitch, 1e-15);
  EXPECT_NEAR(a.yaw, b.yaw, 1e-15);
  EXPECT_NEAR(rotationAngleBetween(a, b), 0.0, 1e-7);
}

TEST(Frames, TurningAboutXTwiceIsTheIdentity) {
  const EulerZyx e{0.1, -0.2, 2.5};
  const EulerZyx t = turnedAboutX(e);
  EXPECT_EQ(t.roll, 0.1);
  EXPECT_EQ(t.pitch, 0.2);
  EXPECT_EQ(t.yaw, -2.5);
  const EulerZyx back = turnedAboutX(t);
  EXPECT_EQ(back.pitch, e.pitch);
  EXPECT_EQ(back.yaw, e.yaw);
}

// The product composes rotations (qz·qy·qx is the ZYX attitude), the conjugate undoes one, and
// rotationAngle agrees with the Euler-side rotationAngleBetween.
TEST(Frames, QuaternionProductComposesAndConjugateUndoes) {
  const double roll = 0.3, pitch = -0.4, yaw = 2.0;
  const Quaternion qz{std::cos(yaw / 2), 0, 0, std::sin(yaw / 2)};
  const Quaternion qy{std::cos(pitch / 2), 0, std::sin(pitch / 2), 0};
  const Quaternion qx{std::cos(roll / 2), std::sin(roll / 2), 0, 0};
  const Quaternion q = qz * qy * qx;
  const EulerZyx e = eulerZyxFromUnitQuaternion(q.w, q.x, q.y, q.z);
  EXPECT_NEAR(e.roll, roll, 1e-12);
  EXPECT_NEAR(e.pitch, pitch, 1e-12);
  EXPECT_NEAR(e.yaw, yaw, 1e-12);
  const Quaternion one = conjugate(q) * q;
  EXPECT_NEAR(one.w, 1.0, 1e-12);
  EXPECT_NEAR(std::abs(one.x) + std::abs(one.y) + std::abs(one.z), 0.0, 1e-12);
  // A yaw step applied on the world side (an estimator heading reset) and taken out again.
  const Quaternion step{std::cos(0.15), 0, 0, std::sin(0.15)};
  EXPECT_NEAR(rotationAngle(step), 0.3, 1e-12);
  const Quaternion reset = step * q;
  const EulerZyx r = eulerZyxFromUnitQuaternion(reset.w, reset.x, reset.y, reset.z);
  EXPECT_NEAR(r.yaw, yaw + 0.3, 1e-12);
  EXPECT_NEAR(r.roll, roll, 1e-12);
  EXPECT_NEAR(rotationAngleBetween(e, r), 0.3, 1e-9);
  const Quaternion undone = conjugate(step) * reset;
  EXPECT_NEAR(undone.w, q.w, 1e-12);
  EXPECT_NEAR(undone.z, q.z, 1e-12);
}

// The rotation vector of a quaternion undoes quaternionOfRotationVector: tiny turns (the series),
// ordinary ones, and turns near π, where q and −q are one rotation and the shorter way is taken.
TEST(Frames, RotationVectorOfAQuaternionUndoesItsQuaternion) {
  for (const std::array<double, 3>& v : {std::array<double, 3>{1e-9, -2e-9, 3e-9}, std::array<double, 3>{2e-5, 0.0, -1e-5},
                                         std::array<double, 3>{0.3, -0.2, 0.1}, std::array<double, 3>{0.0, 0.0, 3.1},
                                         std::array<double, 3>{-1.5, 1.5, 2.0}}) {
    const Quaternion q = quaternionOfRotationVector(v);
    for (const double sign : {1.0, -1.0}) {  // −q is the same rotation
      const std::array<double, 3> back = rotationVectorOfQuaternion({sign * q.w, sign * q.x, sign * q.y, sign * q.z});
      const double angle = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      // Beyond π the shorter turn is the other way round the same axis.
      const double k = angle > kPi ? (angle - 2.0 * kPi) / angle : 1.0;
      for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(back[i], k * v[i], 1e-12 * std::max(1.0, angle)) << i << " of " << angle;
    }
  }
  const std::array<double, 3> none = rotationVectorOfQuaternion(Quaternion{});
  EXPECT_EQ(none[0] * none[0] + none[1] * none[1] + none[2] * none[2], 0.0);
  // The body-axes turn between two attitudes: a yaw of 0.2 rad after a roll of 0.5 is a turn about
  // the body's own tilted z.
  const Quaternion a = quaternionOfEuler({0.5, 0.0, 0.0}), b = quaternionOfEuler({0.5, 0.0, 0.2});
  const std::array<double, 3> turn = rotationVectorOfQuaternion(conjugate(a) * b);
  EXPECT_NEAR(turn[0], 0.0, 1e-12);
  EXPECT_NEAR(turn[1], 0.2 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(turn[2], 0.2 * std::cos(0.5), 1e-12);
}

namespace {
// R = Rz(ψ)·Ry(θ)·Rx(φ), row-major.
std::array<double, 9> rotation(const EulerZyx& e) {
  const double cf = std::cos(e.roll), sf = std::sin(e.roll), ct = std::cos(e.pitch), st = std::sin(e.pitch),
               cp = std::cos(e.yaw), sp = std::sin(e.yaw);
  return {cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf,
          sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf,
          -st,     ct * sf,                ct * cf};
}
std::array<double, 3> times(const std::array<double, 9>& r, const std::array<double, 3>& v) {
  return {r[0] * v[0] + r[1] * v[1] + r[2] * v[2], r[3] * v[0] + r[4] * v[1] + r[5] * v[2], r[6] * v[0] + r[7] * v[1] + r[8] * v[2]};
}
}  // namespace

TEST(Frames, TurnedBodyAxesDescribeTheSameRotationAndTheSameVectors) {
  // A body vector given in the turned axes and turned back is the same vector in the world:
  // R·v = R'·v' for R' the attitude of the turned axes and v' the vector in them.
  const EulerZyx attitudes[] = {{0.0, 0.0, 0.0}, {0.3, -0.2, 2.9}, {-1.1, 0.7, -3.0}, {2.5, 1.2, 0.4}};
  const std::array<double, 3> v = {0.4, -1.3, 2.2};
  for (int eighths = -3; eighths <= 4; ++eighths) {
    const BodyTurn turn{eighths};
    for (const EulerZyx& e : attitudes) {
      SCOPED_TRACE(testing::Message() << "turn " << 45 * eighths << "°, attitude " << e.roll << ", " << e.pitch << ", " << e.yaw);
      const EulerZyx t = attitudeOfTurnedAxes(e, turn);
      const std::array<double, 3> world = times(rotation(e), v);
      const std::array<double, 3> world_turned = times(rotation(t), bodyVectorInTurnedAxes(v, turn));
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(world_turned[static_cast<std::size_t>(k)], world[static_cast<std::size_t>(k)], 1e-12);
      // Turning back gives the attitude again, and the turned axes share the body z axis.
      EXPECT_NEAR(rotationAngleBetween(attitudeOfTurnedAxes(t, BodyTurn{-eighths}), e), 0.0, 1e-7);
      EXPECT_NEAR(rotation(t)[8], rotation(e)[8], 1e-12);
    }
  }
  // Level flight: a turn of the body axes is a turn of the heading, nothing else.
  const EulerZyx level = attitudeOfTurnedAxes({0.0, 0.0, 0.5}, BodyTurn{2});
  EXPECT_NEAR(level.roll, 0.0, 1e-15);
  EXPECT_NEAR(level.pitch, 0.0, 1e-15);
  EXPECT_NEAR(level.yaw, 0.5 + kPi / 2, 1e-15);
  // A roll of the airframe is a pitch of axes turned 90° counter-clockwise (their x is its left).
  const EulerZyx rolled = attitudeOfTurnedAxes({0.2, 0.0, 0.0}, BodyTurn{2});
  EXPECT_NEAR(rolled.pitch, -0.2, 1e-12);
  EXPECT_NEAR(rotationAngleBetween(rolled, {0.0, -0.2, kPi / 2}), 0.0, 1e-7);
}
