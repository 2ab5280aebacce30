#include "control/reference.h"

#include <cmath>

#include "core/frames.h"

namespace quadfdi {
namespace {

bool finite(const Vec3& v) { return v.allFinite(); }

// Yaw facing the horizontal velocity (vx, vy) and its rate, from the acceleration.
void faceVelocity(double vx, double vy, double ax, double ay, Reference& r) {
  const double speed2 = vx * vx + vy * vy;
  r.yaw = std::atan2(vy, vx);
  r.yaw_rate = speed2 > 0.0 ? (vx * ay - vy * ax) / speed2 : 0.0;
}

}  // namespace

const char* toString(TrajectoryKind k) {
  switch (k) {
    case TrajectoryKind::kHover: return "hover";
    case TrajectoryKind::kPointToPoint: return "point-to-point";
    case TrajectoryKind::kCircle: return "circle";
    case TrajectoryKind::kFigureEight: return "figure-eight";
  }
  return "?";
}

bool parseTrajectoryKind(const std::string& text, TrajectoryKind& kind) {
  if (text == "hover") kind = TrajectoryKind::kHover;
  else if (text == "point-to-point") kind = TrajectoryKind::kPointToPoint;
  else if (text == "circle") kind = TrajectoryKind::kCircle;
  else if (text == "figure-eight") kind = TrajectoryKind::kFigureEight;
  else return false;
  return true;
}

std::string validate(const TrajectorySpec& s) {
  if (!finite(s.start) || !finite(s.goal)) return "trajectory points must be finite";
  if (!std::isfinite(s.yaw)) return "trajectory yaw must be finite";
  if (!(std::isfinite(s.start_time) && s.start_time >= 0.0)) return "trajectory start time must be finite and >= 0";
  if (!(std::isfinite(s.yaw_sweep_amplitude) && s.yaw_sweep_amplitude >= 0.0))
    return "trajectory yaw sweep amplitude must be finite and >= 0";
  if (!(std::isfinite(s.yaw_sweep_period) && s.yaw_sweep_period > 0.0)) return "trajectory yaw sweep period must be finite and > 0";
  if (!(std::isfinite(s.facing_yaw_rate_max) && s.facing_yaw_rate_max >= 0.0))
    return "trajectory facing yaw-rate limit must be finite and >= 0";
  if (s.facing_yaw_rate_max > 0.0 && s.kind == TrajectoryKind::kFigureEight && s.yaw_mode == YawMode::kFacingVelocity)
    return "trajectory facing yaw-rate limit is for circles: a figure-eight's heading along the path is not slewed";
  if (s.kind == TrajectoryKind::kHover) return {};
  if (!(std::isfinite(s.speed) && s.speed > 0.0)) return "trajectory speed must be finite and > 0";
  if ((s.kind == TrajectoryKind::kCircle || s.kind == TrajectoryKind::kFigureEight) &&
      !(std::isfinite(s.radius) && s.radius > 0.0))
    return "trajectory radius must be finite and > 0";
  return {};
}

double manoeuvreDuration(const TrajectorySpec& s) {
  switch (s.kind) {
    case TrajectoryKind::kHover: return 0.0;
    case TrajectoryKind::kPointToPoint: return 15.0 * (s.goal - s.start).norm() / (8.0 * s.speed);
    case TrajectoryKind::kCircle: return 2.0 * M_PI * s.radius / s.speed;
    case TrajectoryKind::kFigureEight: return 2.0 * M_PI * std::sqrt(2.0) * s.radius / s.speed;
  }
  return 0.0;
}

Reference referenceAt(const TrajectorySpec& s, double t) {
  Reference r;
  r.yaw = s.yaw;
  const double tau = std::max(0.0, t - s.start_time);  // time into the manoeuvre [s]
  const bool face = s.yaw_mode == YawMode::kFacingVelocity;
  switch (s.kind) {
    case TrajectoryKind::kHover:
      r.position = s.start;
      break;
    case TrajectoryKind::kPointToPoint: {
      const Vec3 d = s.goal - s.start;
      const double duration = manoeuvreDuration(s);
      if (!(duration > 0.0)) {
        r.position = s.start;
        break;
      }
      const double x = std::min(tau / duration, 1.0);  // normalised time τ/T
      const double x2 = x * x, x3 = x2 * x;
      const double pos = x3 * (10.0 + x * (-15.0 + 6.0 * x));
      const double vel = x2 * (30.0 + x * (-60.0 + 30.0 * x)) / duration;
      const double acc = x * (60.0 + x * (-180.0 + 120.0 * x)) / (duration * duration);
      r.position = s.start + pos * d;
      r.velocity = vel * d;
      r.acceleration = acc * d;
      // The path is a straight line: face along it for its whole length (at rest too).
      if (face && (d.x() != 0.0 || d.y() != 0.0)) r.yaw = std::atan2(d.y(), d.x());
      break;
    }
    case TrajectoryKind::kCircle: {
      const double w = s.speed / s.radius;  // [rad/s]
      const double phase = w * tau;
      const double c = std::cos(phase), sn = std::sin(phase);
      r.position = s.start + Vec3(s.radius * c, s.radius * sn, 0.0);
      if (tau > 0.0) {
        r.velocity = Vec3(-s.speed * sn, s.speed * c, 0.0);
        r.acceleration = Vec3(-s.speed * w * c, -s.speed * w * sn, 0.0);
      }
      if (face) {
        // Slewed: the nose starts along the path and turns at most facing_yaw_rate_max.
        const double yaw_rate = s.facing_yaw_rate_max > 0.0 ? std::min(w, s.facing_yaw_rate_max) : w;
        r.yaw = wrapAngle(yaw_rate * tau + 0.5 * M_PI);
        r.yaw_rate = tau > 0.0 ? yaw_rate : 0.0;
      }
      break;
    }
    case TrajectoryKind::kFigureEight: {
      const double a = s.radius;
      const double w = s.speed / (std::sqrt(2.0) * a);  // peak speed √2·a·ω at the crossings
      const double phase = w * tau;
      const double s1 = std::sin(phase), c1 = std::cos(phase);
      const double s2 = std::sin(2.0 * phase), c2 = std::cos(2.0 * phase);
      r.position = s.start + Vec3(a * s1, 0.5 * a * s2, 0.0);
      const double vx = a * w * c1, vy = a * w * c2;
      const double ax = -a * w * w * s1, ay = -2.0 * a * w * w * s2;
      if (tau > 0.0) {
        r.velocity = Vec3(vx, vy, 0.0);
        r.acceleration = Vec3(ax, ay, 0.0);
      }
      if (face) {
        faceVelocity(vx, vy, ax, ay, r);  // the speed never vanishes on this curve
        if (!(tau > 0.0)) r.yaw_rate = 0.0;
      }
      break;
    }
  }
  if (s.yaw_sweep_amplitude > 0.0 && tau > 0.0) {
    const double w = 2.0 * M_PI / s.yaw_sweep_period;  // [rad/s]
    r.yaw = wrapAngle(r.yaw + s.yaw_sweep_amplitude * std::sin(w * tau));
    r.yaw_rate += s.yaw_sweep_amplitude * w * std::cos(w * tau);
  }
  return r;
}

}  // namespace quadfdi
