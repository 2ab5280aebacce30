#include "control/cbf_qp.h"

#include <cmath>

namespace quadfdi {

BarrierValues barrierValues(const State& x, const CbfConfig& config) {
  return {x(idx::kPz) - config.min_altitude,
          std::cos(x(idx::kRoll)) * std::cos(x(idx::kPitch)) - std::cos(config.max_tilt)};
}

void computeCbfRows(const RigidBodyModel& model, const CbfConfig& config, const State& x, CbfRows& rows) {
  const double sf = std::sin(x(idx::kRoll)), cf = std::cos(x(idx::kRoll));
  const double st = std::sin(x(idx::kPitch)), ct = std::cos(x(idx::kPitch));
  const Vec3 v = x.segment<3>(idx::kVel), w = x.segment<3>(idx::kRate);
  const Vec3 r3(-st, ct * sf, ct * cf);  // third row of R: world z of the body axes
  int n = 0;

  if (config.altitude_floor_enabled) {
    // h = z − z_min;  ḣ = ż = r3·v;  ḧ = world vertical acceleration
    //   = −g + r3·(T/m e3 − (c/m) v) = −g + r3₃ T/m − (c/m) ḣ: affine in u.
    const double a1 = config.altitude_alpha1, a2 = config.altitude_alpha2;
    const double h = x(idx::kPz) - config.min_altitude;
    const double hdot = r3.dot(v);
    const double drift = -model.gravity - model.linear_drag_per_mass * hdot;
    rows.a.row(n).setConstant(r3.z() * model.inv_mass);
    rows.b(n) = -(drift + (a1 + a2) * hdot + a1 * a2 * h);
    rows.bits[n] = kAltitudeFloorActive;
    rows.h(n) = h;
    rows.hdot(n) = hdot;
    rows.drift(n) = drift;
    ++n;
  }
  if (config.tilt_limit_enabled) {
    // h = r3₃ − cos β.  Ṙ = R[ω]×  ⇒  ṙ3 = r3 × ω,  ḣ = (r3 × ω)₃ = r3·(ω × e3).
    // ḧ = (ṙ3 × ω + r3 × ω̇)₃ with ω̇ = J⁻¹(τ(u) − ω × Jω − c_r ω): affine in u.
    const double a1 = config.tilt_alpha1, a2 = config.tilt_alpha2;
    const double h = r3.z() - std::cos(config.max_tilt);
    const Vec3 r3dot = r3.cross(w);
    const double hdot = r3dot.z();
    const Vec3 jw = model.inertia.cwiseProduct(w);
    const Vec3 wdot_drift =
        (-w.cross(jw) - model.rotational_drag * w).cwiseProduct(model.inv_inertia);
    // (r3 × a)₃ = r3ₓ a_y − r3_y aₓ
    const double drift = r3dot.cross(w).z() + r3.x() * wdot_drift.y() - r3.y() * wdot_drift.x();
    for (int j = 0; j < kInputDim; ++j) {
      const double dwx = model.roll_lever * kRollSign[j] * model.inv_inertia.x();
      const double dwy = model.pitch_lever * kPitchSign[j] * model.inv_inertia.y();
      rows.a(n, j) = r3.x() * dwy - r3.y() * dwx;
    }
    rows.b(n) = -(drift + (a1 + a2) * hdot + a1 * a2 * h);
    rows.bits[n] = kTiltLimitActive;
    rows.h(n) = h;
    rows.hdot(n) = hdot;
    rows.drift(n) = drift;
    ++n;
  }
  rows.count = n;
}

CbfQpController::CbfQpController(const VehicleParams& params, const GainMatrix& lqr_gain,
                                 const CbfConfig& config)
    : lqr_(params, lqr_gain),
      model_(RigidBodyModel::fromParams(params)),
      config_(config),
      min_thrust_(params.min_thrust),
      max_thrust_(params.max_thrust) {
  // min ‖u − u_lqr‖² ⇔ min ½uᵀu − u_lqrᵀu.
  qp_.H.setIdentity();
  qp_.g.setZero();
  qp_.A.setZero();
  qp_.b.setZero();
  qp_.num_rows = 0;
  qp_.lower.setConstant(min_thrust_);
  qp_.upper.setConstant(max_thrust_);
}

void CbfQpController::compute(const State& x, ControlStep& out) {
  lqr_.compute(x, out);  // u_nominal, and the clipped command used as fallback
  const Input fallback = out.u_cmd;

  computeCbfRows(model_, config_, x, rows_);
  for (int r = 0; r < rows_.count; ++r) {
    qp_.A.row(r) = rows_.a.row(r);
    qp_.b(r) = rows_.b(r);
  }
  qp_.num_rows = rows_.count;
  qp_.g = -out.u_nominal;

  const QpStatus status = solver_.solve(qp_, solution_);
  if (status != QpStatus::kSolved) {
    out.u_cmd = fallback;
    out.status = status == QpStatus::kInfeasible ? ControlStatus::kQpInfeasible : ControlStatus::kQpFailed;
    return;
  }
  out.u_cmd = solution_.x.cwiseMax(min_thrust_).cwiseMin(max_thrust_);  // remove round-off overshoot
  std::uint8_t active = 0;
  const double tol = config_.active_tolerance;
  auto tight = [&](int r) {
    return qp_.A.row(r).dot(solution_.x) - qp_.b(r) <= tol * (1.0 + std::abs(qp_.b(r)));
  };
  for (int r = 0; r < rows_.count; ++r)
    if (tight(r)) active |= rows_.bits[r];
  for (int j = 0; j < kInputDim; ++j)
    if (solution_.x(j) <= min_thrust_ + tol || solution_.x(j) >= max_thrust_ - tol) active |= kMotorBoundActive;
  out.active_constraints = active;
  const bool changed = (active & (kAltitudeFloorActive | kTiltLimitActive)) != 0;
  out.status = changed ? ControlStatus::kFiltered
                       : ((active & kMotorBoundActive) ? ControlStatus::kSaturated : ControlStatus::kOk);
}

}  // namespace quadfdi
