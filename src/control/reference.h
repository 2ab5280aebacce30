// What a controller tracks (a Reference, one per step) and the manoeuvres that produce one
// (TrajectorySpec → referenceAt, a pure function of time). docs/control.md, "References".
#pragma once

#include <cstdint>
#include <string>

#include "model/state.h"

namespace quadfdi {

// Desired flat outputs at one instant; all in the world frame (z up).
struct Reference {
  Vec3 position = Vec3::Zero();      // [m]
  Vec3 velocity = Vec3::Zero();      // [m/s]
  Vec3 acceleration = Vec3::Zero();  // [m/s²] feed-forward
  double yaw = 0.0;                  // [rad] heading, ZYX yaw
  double yaw_rate = 0.0;             // [rad/s]
};

// Hover at `position` with yaw 0 (what Controller::setGoal means).
inline Reference hoverReference(const Vec3& position) {
  Reference r;
  r.position = position;
  return r;
}

enum class TrajectoryKind : std::uint8_t { kHover, kPointToPoint, kCircle, kFigureEight };
const char* toString(TrajectoryKind k);
// "hover" | "point-to-point" | "circle" | "figure-eight"; false for anything else.
bool parseTrajectoryKind(const std::string& text, TrajectoryKind& kind);

enum class YawMode : std::uint8_t {
  kFixed,           // yaw = TrajectorySpec::yaw throughout
  kFacingVelocity,  // nose along the horizontal reference velocity (multicopter "yaw along path")
};

// A manoeuvre, as plain data. Before start_time the reference holds the manoeuvre's first point
// at rest; from start_time on it moves. Speeds of 0.5–3 m/s are typical of small vehicles
// (Crazyflie demos, indoor flight), up to about 5 m/s for larger ones (PX4's default
// MPC_XY_CRUISE is 5 m/s); docs/control.md.
struct TrajectorySpec {
  TrajectoryKind kind = TrajectoryKind::kHover;
  Vec3 start = Vec3::Zero();  // [m] hover point; point-to-point start; circle / figure-eight centre
  Vec3 goal = Vec3::Zero();   // [m] point-to-point end (other kinds ignore it)
  double radius = 1.0;        // [m] circle radius; figure-eight half-length along x (half-width a/2 along y)
  double speed = 1.0;         // [m/s] point-to-point peak speed; circle speed; figure-eight peak speed
  YawMode yaw_mode = YawMode::kFixed;
  double yaw = 0.0;           // [rad] the fixed yaw (kFixed; also hover)
  double start_time = 0.0;    // [s] when the manoeuvre begins
  // A heading sweep added to either yaw mode from start_time on: A·sin(2π·τ/P), a pilot panning
  // the nose or a camera operator's slow yaw (docs/control.md, "References"). 0: none.
  double yaw_sweep_amplitude = 0.0;  // [rad] A
  double yaw_sweep_period = 1.0;     // [s] P
  // kFacingVelocity on a circle: the nose turns at most this fast, as an autopilot slews the yaw
  // setpoint of its mission modes (PX4 MPC_YAWRAUTO_MAX, default 45 °/s; ArduPilot ATC_SLEW_YAW,
  // default 6000 cdeg/s = 60 °/s). Where the path turns faster (speed / radius above it) the nose
  // keeps turning the path's way at this rate and falls behind it. 0: no limit. A figure-eight's
  // heading is not slewed (validate refuses the pair); a point-to-point path does not turn.
  double facing_yaw_rate_max = 0.0;  // [rad/s]
};

// Empty when valid, else a one-line description of the first problem (non-finite values,
// radius <= 0, speed <= 0, start time < 0, a sweep's amplitude < 0 or period <= 0, a yaw-rate limit
// < 0 or on a figure-eight flown nose first). Whether the vehicle can fly it (v²/r against its
// thrust-to-weight) is the caller's business.
std::string validate(const TrajectorySpec& spec);

// The reference at time t [s] (any t; before start_time the first point at rest). Pure.
// Point-to-point: minimum-jerk quintic s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ over T = 15·D/(8·speed), so the
// peak speed is `speed`. Circle: counter-clockwise from start + (radius, 0, 0) at constant speed,
// centripetal acceleration speed²/radius. Figure-eight: the 1:2 Lissajous curve
// x = a·sin ωt, y = (a/2)·sin 2ωt, with peak speed √2·a·ω = `speed` at the centre crossings.
Reference referenceAt(const TrajectorySpec& spec, double t);

// Duration of the moving part [s]: point-to-point T; one lap of the circle or figure-eight; 0 for hover.
double manoeuvreDuration(const TrajectorySpec& spec);

}  // namespace quadfdi
