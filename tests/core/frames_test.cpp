// The shared frame conventions (core/frames.h): the one angle wrap, the quaternion → ZYX Euler
// conversion every reader uses, and the NED/FRD ↔ z-up/FLU turn.
#include <gtest/gtest.h>

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
