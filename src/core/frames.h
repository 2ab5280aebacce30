// Frame conventions of telemetry (docs/conventions.md): quadfdi's world is z up and its body
// FLU (x forward, y left, z up), attitude as ZYX Euler angles. Autopilots and many simulators
// write NED (x north, y east, z down) with an FRD body (PX4, ArduPilot, AirSim, PX4's Gazebo
// bridge) and attitude as a quaternion. Turning both frames 180° about x maps one onto the other:
// with T = diag(1, −1, −1), p' = T·p and R' = T·R·T, so (φ, θ, ψ) → (φ, −θ, −ψ).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace quadfdi {

enum class TelemetryFrame {
  kZUp,  // quadfdi's: world z up, body FLU
  kNed,  // world NED, body FRD
};

// An angle wrapped to (−π, π]: −π maps to +π, so one heading has one value. Every wrap of an
// absolute angle or of a difference ("the short way round") in quadfdi is this one.
inline double wrapAngle(double angle) {
  constexpr double kPi = 3.14159265358979323846;
  const double a = std::remainder(angle, 2.0 * kPi);  // [−π, π], exact
  return a <= -kPi ? a + 2.0 * kPi : a;
}

struct EulerZyx {
  double roll = 0.0;   // [rad] φ, in [−π, π]
  double pitch = 0.0;  // [rad] θ, in [−π/2, π/2]
  double yaw = 0.0;    // [rad] ψ, in [−π, π]
};

// A Hamilton quaternion (w, x, y, z), for composing the rotations logs hold (estimator resets).
struct Quaternion {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
};
// a·b: the rotation b, then a.
inline Quaternion operator*(const Quaternion& a, const Quaternion& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
// The inverse of a unit quaternion.
inline Quaternion conjugate(const Quaternion& q) { return {q.w, -q.x, -q.y, -q.z}; }
// The angle [rad, 0..π] of the rotation a unit quaternion stands for.
inline double rotationAngle(const Quaternion& q) { return 2.0 * std::acos(std::min(1.0, std::abs(q.w))); }

// ZYX Euler angles of the rotation body → world given by the Hamilton quaternion (w, x, y, z),
// which must be of unit norm: R = Rz(ψ)·Ry(θ)·Rx(φ).
inline EulerZyx eulerZyxFromUnitQuaternion(double w, double x, double y, double z) {
  const double r11 = 1.0 - 2.0 * (y * y + z * z);
  const double r21 = 2.0 * (x * y + w * z);
  const double r31 = 2.0 * (x * z - w * y);
  const double r32 = 2.0 * (y * z + w * x);
  const double r33 = 1.0 - 2.0 * (x * x + y * y);
  return {std::atan2(r32, r33), std::asin(std::clamp(-r31, -1.0, 1.0)), std::atan2(r21, r11)};
}

// The same for any quaternion a log holds, normalised first; false for a zero or non-finite one
// (written before the estimator's first attitude), whose row the readers skip.
inline bool eulerZyxFromQuaternion(double w, double x, double y, double z, EulerZyx& out) {
  constexpr double kMinNorm = 1e-6;  // [-] below it the direction is round-off, not an attitude
  const double norm = std::sqrt(w * w + x * x + y * y + z * z);
  if (!(norm > kMinNorm) || !std::isfinite(norm)) return false;
  out = eulerZyxFromUnitQuaternion(w / norm, x / norm, y / norm, z / norm);
  return true;
}

// The unit quaternion of a ZYX attitude: qz(ψ)·qy(θ)·qx(φ).
inline Quaternion quaternionOfEuler(const EulerZyx& e) {
  const double cr = std::cos(0.5 * e.roll), sr = std::sin(0.5 * e.roll), cp = std::cos(0.5 * e.pitch),
               sp = std::sin(0.5 * e.pitch), cy = std::cos(0.5 * e.yaw), sy = std::sin(0.5 * e.yaw);
  return {cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
          cr * cp * sy - sr * sp * cy};
}

// The unit quaternion of the rotation by |v| [rad] about v (a rotation vector; ω·Δt for a body
// rate held over Δt).
inline Quaternion quaternionOfRotationVector(const std::array<double, 3>& v) {
  const double angle = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  // sin(a/2)/a to round-off below 1e-4 rad, where the series' next term (a⁴/3840) is below 1e-19.
  const double k = angle < 1e-4 ? 0.5 - angle * angle / 48.0 : std::sin(0.5 * angle) / angle;
  return {std::cos(0.5 * angle), k * v[0], k * v[1], k * v[2]};
}

// Its inverse: the rotation vector [rad] (axis × angle, the angle in [0, π]) of a unit quaternion;
// of R_aᵀ·R_b, the turn from attitude a to b in a's body axes.
inline std::array<double, 3> rotationVectorOfQuaternion(const Quaternion& q) {
  const double s = q.w < 0.0 ? -1.0 : 1.0;  // q and −q are one rotation: take the one turning ≤ π
  const double v = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
  const double angle = 2.0 * std::atan2(v, s * q.w);
  // angle / sin(angle/2) → 2 as v → 0 (series 2 + angle²/12 below 1e-4 rad, to round-off).
  const double k = v < 1e-12 ? 2.0 : (angle < 1e-4 ? 2.0 + angle * angle / 12.0 : angle / v);
  return {s * k * q.x, s * k * q.y, s * k * q.z};
}

// The angle [rad, 0..π] of the rotation from attitude a to attitude b: the geodesic distance, which
// Euler differences are not (they wrap, and roll and yaw swing by π through pitch ±π/2).
inline double rotationAngleBetween(const EulerZyx& a, const EulerZyx& b) {
  const Quaternion qa = quaternionOfEuler(a), qb = quaternionOfEuler(b);
  const double dot = std::abs(qa.w * qb.w + qa.x * qb.x + qa.y * qb.y + qa.z * qb.z);
  return 2.0 * std::acos(std::min(1.0, dot));
}

// The same attitude with both frames turned 180° about x: NED/FRD angles → quadfdi's, and back.
inline EulerZyx turnedAboutX(const EulerZyx& e) { return {e.roll, -e.pitch, -e.yaw}; }
// The same for a unit quaternion of the body → world rotation.
inline Quaternion turnedAboutX(const Quaternion& q) { return {q.w, q.x, -q.y, -q.z}; }

// [-] Where the rotors push: the body z axis (R·e3) of a unit quaternion, its horizontal part
// (world x, y) over its vertical one — what g·tilt accelerates at constant height. Past ~78° of
// tilt (a vertical part below 0.2) the ratio means nothing, and the vertical part is held there.
inline std::array<double, 2> thrustTilt(const Quaternion& q) {
  const double up = 1.0 - 2.0 * (q.x * q.x + q.y * q.y);
  const double lean = std::max(up, 0.2);
  return {2.0 * (q.x * q.z + q.w * q.y) / lean, 2.0 * (q.y * q.z - q.w * q.x) / lean};
}

// The axes quadfdi reads an airframe in: the airframe's own body axes turned about body z by
// `eighths` × 45°, counter-clockwise seen from above. A plus frame is an X seen from axes turned
// ±45°, and a props-out X (every propeller spinning the other way) a standard X seen from axes
// turned 90°, so both are read as the standard X the model and networks know
// (docs/vehicles.md#plus-and-props-out-frames). Rigid-body dynamics do not depend on which body
// axes describe them: only the attitude and the body rates change, and the motors' numbers.
struct BodyTurn {
  int eighths = 0;  // [45°] −3 … 4
  double radians() const { return eighths * 0.78539816339744830962; }  // π/4 per eighth
  bool none() const { return eighths % 8 == 0; }
  // An odd number of quarter turns (±90°): the body x and y axes trade places.
  bool swapsXY() const { return eighths % 4 == 2 || eighths % 4 == -2; }
};

// The attitude of the turned axes: R' = R·Rz(α), α the turn.
inline EulerZyx attitudeOfTurnedAxes(const EulerZyx& e, BodyTurn turn) {
  if (turn.none()) return e;
  const double cf = std::cos(e.roll), sf = std::sin(e.roll), ct = std::cos(e.pitch), st = std::sin(e.pitch),
               cp = std::cos(e.yaw), sp = std::sin(e.yaw), ca = std::cos(turn.radians()), sa = std::sin(turn.radians());
  // R = Rz(ψ)·Ry(θ)·Rx(φ): its first two columns (the body x and y axes in the world) and third row.
  const double r11 = cp * ct, r21 = sp * ct, r31 = -st;
  const double r12 = cp * st * sf - sp * cf, r22 = sp * st * sf + cp * cf, r32 = ct * sf;
  const double r33 = ct * cf;
  // The turned x axis is ca·x + sa·y; its y axis −sa·x + ca·y; z is unchanged.
  const double n11 = ca * r11 + sa * r12, n21 = ca * r21 + sa * r22, n31 = ca * r31 + sa * r32;
  const double n32 = -sa * r31 + ca * r32;
  return {std::atan2(n32, r33), std::asin(std::clamp(-n31, -1.0, 1.0)), std::atan2(n21, n11)};
}

// A body vector (the body rates) in the turned axes: Rz(−α)·v.
inline std::array<double, 3> bodyVectorInTurnedAxes(const std::array<double, 3>& v, BodyTurn turn) {
  if (turn.none()) return v;
  const double ca = std::cos(turn.radians()), sa = std::sin(turn.radians());
  return {ca * v[0] + sa * v[1], -sa * v[0] + ca * v[1], v[2]};
}

}  // namespace quadfdi
