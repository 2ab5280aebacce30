#include "control/pid.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace quadfdi {
namespace {

// w ≥ 0 picks one of the two quaternions of a rotation (w = 0 exactly: either).
Eigen::Quaterniond canonical(const Eigen::Quaterniond& q) {
  return q.w() < 0.0 ? Eigen::Quaterniond(-q.w(), -q.x(), -q.y(), -q.z()) : q;
}

// Quaternion of R = Rz(ψ)·Ry(θ)·Rx(φ), the state's ZYX Euler angles.
Eigen::Quaterniond quaternionFromEuler(double roll, double pitch, double yaw) {
  const double cr = std::cos(0.5 * roll), sr = std::sin(0.5 * roll);
  const double cp = std::cos(0.5 * pitch), sp = std::sin(0.5 * pitch);
  const double cy = std::cos(0.5 * yaw), sy = std::sin(0.5 * yaw);
  return Eigen::Quaterniond(cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
                            cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy);
}

Vec3 clampSymmetric(const Vec3& v, const Vec3& limit) { return v.cwiseMax(-limit).cwiseMin(limit); }

// Share of the thrust range the yaw may borrow from the collective: PX4's
// ControlAllocationSequentialDesaturation::mixYaw raises the upper bound by 0.15 for the yaw step.
constexpr double kYawHeadroom = 0.15;

bool finiteNonNegative(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

std::string validate(const PidConfig& c) {
  if (c.position_divisor < 1 || c.attitude_divisor < 1 || c.rate_divisor < 1) return "PID loop divisors must be >= 1";
  for (double g : {c.position_gain_xy, c.position_gain_z, c.velocity_gain_xy, c.velocity_integral_xy,
                   c.velocity_derivative_xy, c.velocity_gain_z, c.velocity_integral_z, c.velocity_derivative_z, c.velocity_derivative_cutoff,
                   c.velocity_integral_limit, c.attitude_gain_rp, c.attitude_gain_yaw, c.rate_gain_rp,
                   c.rate_integral_rp, c.rate_derivative_rp, c.rate_gain_yaw, c.rate_integral_yaw})
    if (!finiteNonNegative(g)) return "PID gains and limits must be finite and >= 0";
  if (!(c.max_tilt > 0.0 && c.max_tilt < 1.5)) return "PID max_tilt must lie in (0, 1.5) rad";
  if (!(c.yaw_weight > 0.0 && c.yaw_weight <= 1.0)) return "PID yaw_weight must lie in (0, 1]";
  if (!(std::isfinite(c.max_rate_rp) && c.max_rate_rp > 0.0 && std::isfinite(c.max_rate_yaw) && c.max_rate_yaw > 0.0))
    return "PID rate limits must be finite and > 0";
  if (!(c.min_thrust_fraction > 0.0 && c.min_thrust_fraction < 1.0)) return "PID min_thrust_fraction must lie in (0, 1)";
  if (!(c.rate_integral_limit >= 0.0 && c.rate_integral_limit <= 1.0)) return "PID rate_integral_limit must lie in [0, 1]";
  return {};
}

PidConfig scaledPid(PidConfig c, double s) {
  for (double* g : {&c.position_gain_xy, &c.position_gain_z, &c.velocity_gain_xy, &c.velocity_gain_z, &c.attitude_gain_rp,
                    &c.attitude_gain_yaw, &c.rate_gain_rp, &c.rate_gain_yaw})
    *g *= s;
  for (double* g : {&c.velocity_integral_xy, &c.velocity_integral_z, &c.rate_integral_rp, &c.rate_integral_yaw}) *g *= s * s;
  return c;
}

bool limitThrustVector(Vec3& force, double min_vertical, double max_tilt) {
  bool limited = false;
  if (force.z() < min_vertical) {
    force.z() = min_vertical;
    limited = true;
  }
  const double horizontal = std::hypot(force.x(), force.y());
  const double max_horizontal = force.z() * std::tan(max_tilt);
  if (horizontal > max_horizontal) {
    force.head<2>() *= max_horizontal / horizontal;
    limited = true;
  }
  return limited;
}

MotorAllocator::Matrix mixMatrixOf(const RigidBodyModel& m) {
  MotorAllocator::Matrix mix;
  for (int j = 0; j < kInputDim; ++j) {
    mix(0, j) = 1.0;
    mix(1, j) = m.roll_lever * kRollSign[j];
    mix(2, j) = m.pitch_lever * kPitchSign[j];
    mix(3, j) = m.yaw_coeff * kYawSign[j];
  }
  return mix;
}

MotorAllocator::MotorAllocator(const RigidBodyModel& model, double min_thrust, double max_thrust)
    : mix_(mixMatrixOf(model)), inverse_(mix_.inverse()), min_thrust_(min_thrust), max_thrust_(max_thrust) {
  const double half_range = 0.5 * (max_thrust - min_thrust);
  for (int a = 0; a < 3; ++a) max_torque_(a) = mix_.row(a + 1).cwiseAbs().sum() * half_range;
}

bool MotorAllocator::allocate(double collective, const Vec3& torque, Input& f, Input& unconstrained) const {
  const Input base = inverse_.col(0) * collective;
  Input tilt = inverse_.col(1) * torque.x() + inverse_.col(2) * torque.y();  // roll and pitch
  const Input yaw = inverse_.col(3) * torque.z();
  unconstrained = base + tilt + yaw;
  bool changed = false;

  // 1. Roll and pitch first: scaled down only if their spread alone exceeds the thrust range.
  const double range = max_thrust_ - min_thrust_;
  const double spread = tilt.maxCoeff() - tilt.minCoeff();
  if (spread > range) {
    tilt *= range / spread;
    changed = true;
  }
  f = base + tilt;
  // 2. Shift the collective by the least amount that brings every motor inside the bounds.
  const double raise = min_thrust_ - f.minCoeff();  // > 0: some motor below the minimum
  const double lower = max_thrust_ - f.maxCoeff();  // < 0: some motor above the maximum
  const double shift = raise > 0.0 ? raise : (lower < 0.0 ? std::max(lower, raise) : 0.0);
  if (shift != 0.0) {
    f.array() += shift;
    changed = true;
  }
  // 3. Yaw last: the largest share λ ∈ [0, 1] of it that fits at this collective, with the upper
  //    bound raised by 15 % of the range (PX4's mixYaw: some yaw response at full thrust) ...
  const double yaw_ceiling = max_thrust_ + kYawHeadroom * range;
  double share = 1.0;
  for (int i = 0; i < kInputDim; ++i) {
    if (yaw(i) > 0.0) share = std::min(share, (yaw_ceiling - f(i)) / yaw(i));
    else if (yaw(i) < 0.0) share = std::min(share, (min_thrust_ - f(i)) / yaw(i));
  }
  share = std::max(share, 0.0);
  if (share < 1.0) changed = true;
  f += share * yaw;
  //    ... paid for by lowering the collective (never raising it, which would lift the lowest
  //    motor off its bound only to push the vehicle up).
  const double excess = f.maxCoeff() - max_thrust_;
  if (excess > 0.0) {
    f.array() -= excess;
    changed = true;
  }
  // 4. Clip what round-off left outside.
  const Input clipped = f.cwiseMax(min_thrust_).cwiseMin(max_thrust_);
  if ((clipped.array() != f.array()).any()) changed = true;
  f = clipped;
  return changed;
}

PidController::PidController(const VehicleParams& params, const PidConfig& config, double dt)
    : config_(config),
      dt_(dt),
      mass_(params.mass),
      gravity_(params.gravity),
      inertia_(params.inertia_xx, params.inertia_yy, params.inertia_zz),
      min_collective_(std::max(4.0 * params.min_thrust, config.min_thrust_fraction * 4.0 * params.max_thrust)),
      max_collective_(4.0 * params.max_thrust),
      allocator_(RigidBodyModel::fromParams(params), params.min_thrust, params.max_thrust) {
  rate_integral_limit_ = config_.rate_integral_limit * allocator_.maxTorque().cwiseQuotient(inertia_);
  if (config_.velocity_derivative_cutoff > 0.0)
    velocity_derivative_alpha_ = 1.0 - std::exp(-2.0 * M_PI * config_.velocity_derivative_cutoff * dt_ * config_.position_divisor);
  reset();
}

void PidController::reset() {
  step_ = 0;
  velocity_integral_.setZero();
  previous_velocity_.setZero();
  have_previous_velocity_ = false;
  velocity_derivative_.setZero();
  thrust_limited_ = false;
  rate_integral_.setZero();
  previous_rate_.setZero();
  have_previous_rate_ = false;
  allocation_saturated_ = false;
  thrust_vector_ = Vec3(0.0, 0.0, mass_ * gravity_);
  attitude_setpoint_.setIdentity();
  yaw_rate_feedforward_ = 0.0;
  collective_ = mass_ * gravity_;
  rate_setpoint_.setZero();
  torque_.setZero();
  thrusts_.setConstant(0.25 * mass_ * gravity_);
  unconstrained_ = thrusts_;
}

void PidController::positionLoop(const Vec3& p, const Vec3& v) {
  const Reference& ref = reference_;
  const double period = dt_ * config_.position_divisor;
  const Vec3 kp(config_.position_gain_xy, config_.position_gain_xy, config_.position_gain_z);
  const Vec3 kv(config_.velocity_gain_xy, config_.velocity_gain_xy, config_.velocity_gain_z);
  const Vec3 ki(config_.velocity_integral_xy, config_.velocity_integral_xy, config_.velocity_integral_z);
  const Vec3 kd(config_.velocity_derivative_xy, config_.velocity_derivative_xy, config_.velocity_derivative_z);

  const Vec3 velocity_setpoint = ref.velocity + kp.cwiseProduct(ref.position - p);
  const Vec3 velocity_error = velocity_setpoint - v;
  const Vec3 dvdt = have_previous_velocity_ ? Vec3((v - previous_velocity_) / period) : Vec3::Zero();
  previous_velocity_ = v;
  have_previous_velocity_ = true;
  velocity_derivative_ += velocity_derivative_alpha_ * (dvdt - velocity_derivative_);
  const Vec3 acceleration =
      ref.acceleration + kv.cwiseProduct(velocity_error) + velocity_integral_ - kd.cwiseProduct(velocity_derivative_);

  // Thrust vector F = m·(a + g·e₃), limited like PX4's PositionControl: vertical component at
  // least the minimum collective, tilt at most max_tilt (horizontal part scaled), magnitude at
  // most the maximum collective keeping the vertical part first.
  Vec3 force = mass_ * (acceleration + Vec3(0.0, 0.0, gravity_));
  bool limited = limitThrustVector(force, min_collective_, config_.max_tilt);
  if (force.norm() > max_collective_) {
    if (force.z() >= max_collective_) {
      force = Vec3(0.0, 0.0, max_collective_);
    } else {
      const double room = std::sqrt(max_collective_ * max_collective_ - force.z() * force.z());
      force.head<2>() *= room / std::hypot(force.x(), force.y());
    }
    limited = true;
  }
  thrust_limited_ = limited;
  // Anti-windup: integrate only while neither the thrust vector nor the motors are limited.
  if (!limited && !allocation_saturated_)
    velocity_integral_ = clampSymmetric(velocity_integral_ + ki.cwiseProduct(velocity_error) * period,
                                        Vec3::Constant(config_.velocity_integral_limit));

  thrust_vector_ = force;
  collective_ = force.norm();
  // Desired attitude: body z along F, heading ψ_ref (body x in the plane of e_z(ψ) ⟂ body y).
  const Vec3 body_z = force / collective_;
  const Vec3 heading_y(-std::sin(ref.yaw), std::cos(ref.yaw), 0.0);
  const Vec3 body_x = heading_y.cross(body_z).normalized();
  const Vec3 body_y = body_z.cross(body_x);
  Mat3 desired;
  desired.col(0) = body_x;
  desired.col(1) = body_y;
  desired.col(2) = body_z;
  attitude_setpoint_ = Eigen::Quaterniond(desired);
  yaw_rate_feedforward_ = ref.yaw_rate;
}

void PidController::attitudeLoop(const Eigen::Quaterniond& q) {
  // Tilt-prioritised attitude control (PX4 mc_att_control): first the shortest rotation that
  // brings body z onto the desired one, then only a share yaw_weight of the remaining yaw.
  const Eigen::Quaterniond& qd = attitude_setpoint_;
  const Vec3 e_z = q * Vec3::UnitZ();
  const Vec3 e_z_d = qd * Vec3::UnitZ();
  const double c = e_z.dot(e_z_d);
  Eigen::Quaterniond reduced;
  if (1.0 + c < 1e-10) {
    reduced = qd;  // upside down: no unique shortest rotation, take the full setpoint
  } else {
    const Vec3 axis = e_z.cross(e_z_d);
    reduced = (Eigen::Quaterniond(1.0 + c, axis.x(), axis.y(), axis.z()).normalized() * q).normalized();
  }
  Eigen::Quaterniond mix = canonical(reduced.inverse() * qd);  // a rotation about body z
  const double w = std::clamp(mix.w(), -1.0, 1.0), z = std::clamp(mix.z(), -1.0, 1.0);
  const double yw = config_.yaw_weight;
  const Eigen::Quaterniond target = reduced * Eigen::Quaterniond(std::cos(yw * std::acos(w)), 0.0, 0.0,
                                                                  std::sin(yw * std::asin(z)));
  const Eigen::Quaterniond error = canonical(q.inverse() * target);
  // The yaw gain is divided by the weight so that a pure yaw error is corrected at attitude_gain_yaw.
  const Vec3 gain(config_.attitude_gain_rp, config_.attitude_gain_rp, config_.attitude_gain_yaw / yw);
  Vec3 rates = 2.0 * gain.cwiseProduct(error.vec());
  // Yaw-rate feed-forward about world z, expressed in the body frame.
  rates += (q.inverse() * Vec3::UnitZ()) * yaw_rate_feedforward_;
  rate_setpoint_ = clampSymmetric(rates, Vec3(config_.max_rate_rp, config_.max_rate_rp, config_.max_rate_yaw));
}

void PidController::rateLoop(const Vec3& w) {
  const double period = dt_ * config_.rate_divisor;
  const Vec3 kp(config_.rate_gain_rp, config_.rate_gain_rp, config_.rate_gain_yaw);
  const Vec3 ki(config_.rate_integral_rp, config_.rate_integral_rp, config_.rate_integral_yaw);
  const Vec3 kd(config_.rate_derivative_rp, config_.rate_derivative_rp, 0.0);
  const Vec3 error = rate_setpoint_ - w;
  const Vec3 dwdt = have_previous_rate_ ? Vec3((w - previous_rate_) / period) : Vec3::Zero();
  previous_rate_ = w;
  have_previous_rate_ = true;
  const Vec3 angular_acceleration = kp.cwiseProduct(error) + rate_integral_ - kd.cwiseProduct(dwdt);
  torque_ = inertia_.cwiseProduct(angular_acceleration);
  allocation_saturated_ = allocator_.allocate(collective_, torque_, thrusts_, unconstrained_);
  // Anti-windup: the integrators stand still while the motors saturate, and stay bounded.
  if (!allocation_saturated_)
    rate_integral_ = clampSymmetric(rate_integral_ + ki.cwiseProduct(error) * period, rate_integral_limit_);
}

void PidController::compute(const State& x, ControlStep& out) {
  const double roll = x(idx::kRoll), pitch = x(idx::kPitch), yaw = x(idx::kYaw);
  if (step_ % config_.position_divisor == 0) {
    const Vec3 v_world = rotationBodyToWorld(roll, pitch, yaw) * x.segment<3>(idx::kVel);
    positionLoop(x.segment<3>(idx::kPos), v_world);
  }
  if (step_ % config_.attitude_divisor == 0) attitudeLoop(quaternionFromEuler(roll, pitch, yaw));
  if (step_ % config_.rate_divisor == 0) rateLoop(x.segment<3>(idx::kRate));
  ++step_;
  out.u_cmd = thrusts_;
  out.u_nominal = unconstrained_;
  out.status = allocation_saturated_ ? ControlStatus::kSaturated : ControlStatus::kOk;
  out.active_constraints = allocation_saturated_ ? kMotorBoundActive : 0;
}

}  // namespace quadfdi
