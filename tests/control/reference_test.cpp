// Reference trajectories (src/control/reference.*): continuity, velocity and acceleration are
// the derivatives of position (central differences), the stated speeds, validation messages.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "control/lqr.h"
#include "control/reference.h"
#include "core/frames.h"

namespace quadfdi {
namespace {

TrajectorySpec make(TrajectoryKind kind, YawMode yaw_mode) {
  TrajectorySpec s;
  s.kind = kind;
  s.start = Vec3(0.5, -0.5, 1.0);
  s.goal = Vec3(2.5, 0.5, 1.8);
  s.radius = 1.2;
  s.speed = 1.5;
  s.yaw_mode = yaw_mode;
  s.yaw = 0.4;
  s.start_time = 0.5;
  return s;
}

TEST(Reference, DerivativesMatchFiniteDifferences) {
  const double h = 1e-5;
  for (const auto kind : {TrajectoryKind::kHover, TrajectoryKind::kPointToPoint, TrajectoryKind::kCircle,
                          TrajectoryKind::kFigureEight}) {
    for (const auto mode : {YawMode::kFixed, YawMode::kFacingVelocity}) {
      const TrajectorySpec s = make(kind, mode);
      ASSERT_EQ(validate(s), "");
      // Smooth inside the manoeuvre (the start of a circle or figure-eight is a velocity step).
      for (double t = 0.6; t < 0.5 + manoeuvreDuration(s) + 0.3; t += 0.037) {
        const Reference r = referenceAt(s, t), a = referenceAt(s, t - h), b = referenceAt(s, t + h);
        const Vec3 v_fd = (b.position - a.position) / (2 * h);
        const Vec3 a_fd = (b.velocity - a.velocity) / (2 * h);
        EXPECT_LT((v_fd - r.velocity).norm(), 1e-6) << toString(kind) << " t=" << t;
        EXPECT_LT((a_fd - r.acceleration).norm(), 1e-5) << toString(kind) << " t=" << t;
        EXPECT_NEAR(wrapAngle(b.yaw - a.yaw) / (2 * h), r.yaw_rate, 1e-5) << toString(kind) << " t=" << t;
      }
    }
  }
}

TEST(Reference, PositionIsContinuousAndRestsBeforeTheStart) {
  for (const auto kind : {TrajectoryKind::kPointToPoint, TrajectoryKind::kCircle, TrajectoryKind::kFigureEight}) {
    const TrajectorySpec s = make(kind, YawMode::kFacingVelocity);
    const Reference first = referenceAt(s, 0.0);
    EXPECT_EQ(first.velocity, Vec3::Zero());
    EXPECT_EQ(referenceAt(s, 0.4).position, first.position);
    double jump = 0.0;
    for (double t = 0.0; t < 10.0; t += 1e-4)
      jump = std::max(jump, (referenceAt(s, t + 1e-4).position - referenceAt(s, t).position).norm());
    EXPECT_LT(jump, 1e-4 * s.speed * 1.0001) << toString(kind);  // never faster than the stated speed
  }
}

TEST(Reference, SpeedsAndShapesAreTheStatedOnes) {
  TrajectorySpec p2p = make(TrajectoryKind::kPointToPoint, YawMode::kFixed);
  const double duration = manoeuvreDuration(p2p);
  EXPECT_NEAR(referenceAt(p2p, 0.5 + duration / 2).velocity.norm(), p2p.speed, 1e-12);  // peak mid-way
  EXPECT_EQ(referenceAt(p2p, 0.5 + duration).position, p2p.goal);
  EXPECT_EQ(referenceAt(p2p, 0.5 + duration + 3.0).velocity, Vec3::Zero());
  EXPECT_EQ(referenceAt(p2p, 2.0).yaw, 0.4);

  const TrajectorySpec circle = make(TrajectoryKind::kCircle, YawMode::kFacingVelocity);
  for (double t = 0.7; t < 8.0; t += 0.31) {
    const Reference r = referenceAt(circle, t);
    EXPECT_NEAR((r.position - circle.start).norm(), circle.radius, 1e-12);
    EXPECT_NEAR(r.velocity.norm(), circle.speed, 1e-12);
    EXPECT_NEAR(r.acceleration.norm(), circle.speed * circle.speed / circle.radius, 1e-12);
    EXPECT_NEAR(wrapAngle(r.yaw - std::atan2(r.velocity.y(), r.velocity.x())), 0.0, 1e-12);
  }
  const TrajectorySpec eight = make(TrajectoryKind::kFigureEight, YawMode::kFixed);
  double peak = 0.0;
  for (double t = 0.5; t < 0.5 + manoeuvreDuration(eight); t += 0.001) peak = std::max(peak, referenceAt(eight, t).velocity.norm());
  EXPECT_LE(peak, eight.speed * (1 + 1e-12));
  EXPECT_NEAR(referenceAt(eight, 0.5 + manoeuvreDuration(eight) / 2).velocity.norm(), eight.speed, 1e-12);  // centre crossing
  EXPECT_LT((referenceAt(eight, 0.5 + manoeuvreDuration(eight)).position - eight.start).norm(), 1e-12);  // closed
}

// A heading sweep rides on either yaw mode: the yaw is the path's plus A·sin(2π·τ/P), its rate the
// derivative, and nothing moves before the start or off the yaw.
TEST(Reference, AYawSweepAddsItsSineToEveryManoeuvresYaw) {
  const double h = 1e-5;
  for (const auto kind : {TrajectoryKind::kHover, TrajectoryKind::kPointToPoint, TrajectoryKind::kCircle,
                          TrajectoryKind::kFigureEight}) {
    for (const auto mode : {YawMode::kFixed, YawMode::kFacingVelocity}) {
      const TrajectorySpec plain = make(kind, mode);
      TrajectorySpec swept = plain;
      swept.yaw_sweep_amplitude = 0.7;
      swept.yaw_sweep_period = 2.5;
      ASSERT_EQ(validate(swept), "");
      EXPECT_EQ(referenceAt(swept, 0.3).yaw, referenceAt(plain, 0.3).yaw);  // at rest before the start
      EXPECT_EQ(referenceAt(swept, 0.3).yaw_rate, 0.0);
      for (double t = 0.6; t < 6.0; t += 0.113) {
        const Reference r = referenceAt(swept, t), p = referenceAt(plain, t);
        const double tau = t - swept.start_time, w = 2.0 * M_PI / 2.5;
        EXPECT_NEAR(wrapAngle(r.yaw - p.yaw - 0.7 * std::sin(w * tau)), 0.0, 1e-12) << toString(kind) << " t=" << t;
        EXPECT_NEAR(r.yaw_rate - p.yaw_rate, 0.7 * w * std::cos(w * tau), 1e-12);
        const Reference a = referenceAt(swept, t - h), b = referenceAt(swept, t + h);
        EXPECT_NEAR(wrapAngle(b.yaw - a.yaw) / (2 * h), r.yaw_rate, 1e-5) << toString(kind) << " t=" << t;
        EXPECT_EQ(r.position, p.position);
        EXPECT_EQ(r.acceleration, p.acceleration);
      }
    }
  }
}

// An autopilot slews its mission yaw setpoint (PX4 MPC_YAWRAUTO_MAX, ArduPilot ATC_SLEW_YAW): on a
// circle that turns faster than the limit the nose starts along the path and turns at the limit,
// falling behind; a limit the path never reaches changes nothing, bit for bit; the path is the same.
TEST(Reference, ASlewedNoseTurnsAtItsLimitAndFallsBehindTheCircle) {
  const TrajectorySpec free = make(TrajectoryKind::kCircle, YawMode::kFacingVelocity);  // ω = 1.5 / 1.2 = 1.25 rad/s
  TrajectorySpec slewed = free;
  slewed.facing_yaw_rate_max = 0.5;
  ASSERT_EQ(validate(slewed), "");
  TrajectorySpec loose = free;
  loose.facing_yaw_rate_max = 1.3;
  const double h = 1e-5;
  EXPECT_EQ(referenceAt(slewed, 0.3).yaw_rate, 0.0);  // at rest before the start, nose along the path
  EXPECT_EQ(referenceAt(slewed, 0.3).yaw, referenceAt(free, 0.3).yaw);
  for (double t = 0.6; t < 8.0; t += 0.137) {
    const Reference r = referenceAt(slewed, t), f = referenceAt(free, t), l = referenceAt(loose, t);
    const double tau = t - slewed.start_time;
    EXPECT_EQ(r.yaw_rate, 0.5);
    EXPECT_NEAR(wrapAngle(r.yaw - 0.5 * M_PI - 0.5 * tau), 0.0, 1e-12) << "t=" << t;
    EXPECT_NEAR(wrapAngle(f.yaw - r.yaw), wrapAngle(0.75 * tau), 1e-12) << "t=" << t;  // the lag grows at ω − limit
    const Reference a = referenceAt(slewed, t - h), b = referenceAt(slewed, t + h);
    EXPECT_NEAR(wrapAngle(b.yaw - a.yaw) / (2 * h), r.yaw_rate, 1e-6);
    EXPECT_EQ(r.position, f.position);
    EXPECT_EQ(r.velocity, f.velocity);
    EXPECT_EQ(r.acceleration, f.acceleration);
    EXPECT_EQ(l.yaw, f.yaw);
    EXPECT_EQ(l.yaw_rate, f.yaw_rate);
  }
  // Other kinds: a point-to-point path does not turn, a fixed yaw is not the path's.
  for (const auto& [kind, mode] : {std::pair{TrajectoryKind::kPointToPoint, YawMode::kFacingVelocity},
                                  std::pair{TrajectoryKind::kCircle, YawMode::kFixed},
                                  std::pair{TrajectoryKind::kFigureEight, YawMode::kFixed}}) {
    TrajectorySpec limited = make(kind, mode);
    limited.facing_yaw_rate_max = 0.5;
    ASSERT_EQ(validate(limited), "");
    for (double t = 0.6; t < 6.0; t += 0.29) {
      EXPECT_EQ(referenceAt(limited, t).yaw, referenceAt(make(kind, mode), t).yaw);
      EXPECT_EQ(referenceAt(limited, t).yaw_rate, referenceAt(make(kind, mode), t).yaw_rate);
    }
  }
}

TEST(Reference, ValidateNamesTheProblem) {
  TrajectorySpec s = make(TrajectoryKind::kCircle, YawMode::kFixed);
  s.radius = 0.0;
  EXPECT_EQ(validate(s), "trajectory radius must be finite and > 0");
  s = make(TrajectoryKind::kFigureEight, YawMode::kFixed);
  s.speed = -1.0;
  EXPECT_EQ(validate(s), "trajectory speed must be finite and > 0");
  s.kind = TrajectoryKind::kHover;
  EXPECT_EQ(validate(s), "");  // hover ignores speed
  s.start_time = -1.0;
  EXPECT_EQ(validate(s), "trajectory start time must be finite and >= 0");
  s.start_time = 0.0;
  s.yaw_sweep_amplitude = -0.1;
  EXPECT_EQ(validate(s), "trajectory yaw sweep amplitude must be finite and >= 0");
  s.yaw_sweep_amplitude = 0.5;
  s.yaw_sweep_period = 0.0;
  EXPECT_EQ(validate(s), "trajectory yaw sweep period must be finite and > 0");
  s = make(TrajectoryKind::kCircle, YawMode::kFacingVelocity);
  s.facing_yaw_rate_max = -0.1;
  EXPECT_EQ(validate(s), "trajectory facing yaw-rate limit must be finite and >= 0");
  s.kind = TrajectoryKind::kFigureEight;
  s.facing_yaw_rate_max = 1.0;
  EXPECT_EQ(validate(s), "trajectory facing yaw-rate limit is for circles: a figure-eight's heading along the path is not slewed");
  TrajectoryKind k;
  EXPECT_TRUE(parseTrajectoryKind("figure-eight", k));
  EXPECT_EQ(k, TrajectoryKind::kFigureEight);
  EXPECT_FALSE(parseTrajectoryKind("square", k));
}

}  // namespace
}  // namespace quadfdi
