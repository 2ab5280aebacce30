#include "control/geometric.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "model/dynamics.h"

namespace quadfdi {
namespace {

bool positiveFinite(double v) { return std::isfinite(v) && v > 0.0; }

// (S)^∨ of a skew-symmetric S: the vector s with S·y = s × y.
Vec3 vee(const Mat3& s) { return Vec3(s(2, 1), s(0, 2), s(1, 0)); }

}  // namespace

std::string validate(const GeometricConfig& c) {
  if (c.position_divisor < 1) return "geometric position_divisor must be >= 1";
  for (double g : {c.position_frequency_xy, c.position_damping_xy, c.position_frequency_z, c.position_damping_z,
                   c.attitude_frequency_rp, c.attitude_damping_rp, c.attitude_frequency_yaw, c.attitude_damping_yaw})
    if (!positiveFinite(g)) return "geometric frequencies and damping ratios must be finite and > 0";
  for (double g : {c.position_integral, c.position_integral_limit_xy, c.position_integral_limit_z, c.attitude_integral_rp,
                   c.attitude_integral_yaw})
    if (!(std::isfinite(g) && g >= 0.0)) return "geometric integral gain and limits must be finite and >= 0";
  if (!(c.attitude_integral_band > 0.0 && c.attitude_integral_band <= 1.0))
    return "geometric attitude_integral_band must lie in (0, 1]";
  if (!(c.attitude_integral_limit >= 0.0 && c.attitude_integral_limit <= 1.0))
    return "geometric attitude_integral_limit must lie in [0, 1]";
  if (!(c.max_tilt > 0.0 && c.max_tilt < 1.5)) return "geometric max_tilt must lie in (0, 1.5) rad";
  if (!(c.min_thrust_fraction > 0.0 && c.min_thrust_fraction < 1.0))
    return "geometric min_thrust_fraction must lie in (0, 1)";
  return {};
}

GeometricConfig scaledGeometric(GeometricConfig c, double s) {
  for (double* w : {&c.position_frequency_xy, &c.position_frequency_z, &c.attitude_frequency_rp, &c.attitude_frequency_yaw})
    *w *= s;
  for (double* k : {&c.position_integral, &c.attitude_integral_rp, &c.attitude_integral_yaw}) *k *= s * s * s;  // gains on ∫e
  return c;
}

GeometricController::GeometricController(const VehicleParams& params, const GeometricConfig& config, double dt)
    : config_(config),
      dt_(dt),
      mass_(params.mass),
      gravity_(params.gravity),
      inertia_(params.inertia_xx, params.inertia_yy, params.inertia_zz),
      min_thrust_(params.min_thrust),
      max_thrust_(params.max_thrust),
      inverse_mix_(mixMatrixOf(RigidBodyModel::fromParams(params)).inverse()) {
  const Vec3 w(config.position_frequency_xy, config.position_frequency_xy, config.position_frequency_z);
  const Vec3 z(config.position_damping_xy, config.position_damping_xy, config.position_damping_z);
  kp_ = w.cwiseProduct(w);
  kv_ = 2.0 * z.cwiseProduct(w);
  ki_ = Vec3::Constant(config.position_integral);
  integral_limit_ = Vec3(config.position_integral_limit_xy, config.position_integral_limit_xy, config.position_integral_limit_z);
  const Vec3 wa(config.attitude_frequency_rp, config.attitude_frequency_rp, config.attitude_frequency_yaw);
  const Vec3 za(config.attitude_damping_rp, config.attitude_damping_rp, config.attitude_damping_yaw);
  kr_ = wa.cwiseProduct(wa);
  kw_ = 2.0 * za.cwiseProduct(wa);
  kri_ = Vec3(config.attitude_integral_rp, config.attitude_integral_rp, config.attitude_integral_yaw);
  // |J·K_I·∫e_R| ≤ limit · largest torque about the axis.
  const Vec3 max_torque = MotorAllocator(RigidBodyModel::fromParams(params), params.min_thrust, params.max_thrust).maxTorque();
  for (int a = 0; a < 3; ++a)
    attitude_integral_limit_(a) = kri_(a) > 0.0 ? config.attitude_integral_limit * max_torque(a) / (inertia_(a) * kri_(a)) : 0.0;
  reset();
}

void GeometricController::reset() {
  step_ = 0;
  integral_.setZero();
  attitude_integral_.setZero();
  saturated_ = false;
  force_ = Vec3(0.0, 0.0, mass_ * gravity_);
  desired_.setIdentity();
  torque_.setZero();
}

void GeometricController::positionLoop(const Vec3& p, const Vec3& v) {
  const Reference& ref = reference_;
  const Vec3 position_error = ref.position - p;
  integral_ = (integral_ + position_error * (dt_ * config_.position_divisor)).cwiseMax(-integral_limit_).cwiseMin(integral_limit_);
  const Vec3 acceleration = ref.acceleration + kp_.cwiseProduct(position_error) + kv_.cwiseProduct(ref.velocity - v) +
                            ki_.cwiseProduct(integral_);
  Vec3 force = mass_ * (acceleration + Vec3(0.0, 0.0, gravity_));
  // Lee's law has no limits; a flown one needs two: the force must point up, and not too far
  // from vertical (otherwise a large position error commands a flip).
  limitThrustVector(force, std::max(4.0 * min_thrust_, config_.min_thrust_fraction * 4.0 * max_thrust_), config_.max_tilt);
  force_ = force;
  // Desired axes: b₃ along F, b₁ the heading's projection (Lee et al., eq. 12–13).
  const Vec3 b3 = force / force.norm();
  const Vec3 heading(std::cos(ref.yaw), std::sin(ref.yaw), 0.0);
  const Vec3 b2 = b3.cross(heading).normalized();
  desired_.col(0) = b2.cross(b3);
  desired_.col(1) = b2;
  desired_.col(2) = b3;
}

bool GeometricController::allocate(double collective, Input& f, Input& unconstrained) const {
  Eigen::Matrix<double, kInputDim, 1> wrench;
  wrench << collective, torque_;
  unconstrained = inverse_mix_ * wrench;
  f = unconstrained;
  bool changed = false;
  const double excess = f.maxCoeff() - max_thrust_;
  if (excess > 0.0) {
    f.array() -= excess;
    changed = true;
  }
  const Input clipped = f.cwiseMax(min_thrust_).cwiseMin(max_thrust_);
  if ((clipped.array() != f.array()).any()) changed = true;
  f = clipped;
  return changed;
}

void GeometricController::compute(const State& x, ControlStep& out) {
  const Mat3 r = rotationBodyToWorld(x(idx::kRoll), x(idx::kPitch), x(idx::kYaw));
  if (step_ % config_.position_divisor == 0) positionLoop(x.segment<3>(idx::kPos), r * x.segment<3>(idx::kVel));
  ++step_;
  const Vec3 omega = x.segment<3>(idx::kRate);
  // e_R = ½ (R_dᵀR − RᵀR_d)^∨ and e_Ω = Ω − RᵀR_d Ω_d, with Ω_d the reference's yaw rate about
  // world z seen in the desired body frame (the jerk terms of Mellinger's Ω_d are left out).
  const Mat3 rt_rd = r.transpose() * desired_;
  const Vec3 e_r = 0.5 * vee(rt_rd.transpose() - rt_rd);
  const Vec3 omega_d = desired_.transpose().col(2) * reference_.yaw_rate;
  const Vec3 e_w = omega - rt_rd * omega_d;
  const Vec3 j_omega = inertia_.cwiseProduct(omega);
  // Anti-windup: stand still while the motors saturate (as the PID's rate integrators), and integrate
  // only an axis whose error is inside the band (integral separation): a large slew is the PD's,
  // a steady offset the integral's.
  if (!saturated_)
    for (int a = 0; a < 3; ++a)
      if (std::abs(e_r(a)) < config_.attitude_integral_band)
        attitude_integral_(a) = std::clamp(attitude_integral_(a) + e_r(a) * dt_, -attitude_integral_limit_(a), attitude_integral_limit_(a));
  torque_ = -inertia_.cwiseProduct(kr_.cwiseProduct(e_r) + kw_.cwiseProduct(e_w) + kri_.cwiseProduct(attitude_integral_)) +
            omega.cross(j_omega);
  const double collective = std::clamp(force_.dot(r.col(2)), 4.0 * min_thrust_, 4.0 * max_thrust_);
  saturated_ = allocate(collective, out.u_cmd, out.u_nominal);
  out.status = saturated_ ? ControlStatus::kSaturated : ControlStatus::kOk;
  out.active_constraints = saturated_ ? kMotorBoundActive : 0;
}

}  // namespace quadfdi
