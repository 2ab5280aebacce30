// Newton–Euler rigid-body dynamics of a quadrotor with the Crazyflie mixer (docs/model.md).
// Header-only inline so the integrator and the batched rollouts can inline it.
#pragma once

#include <cmath>

#include "model/state.h"
#include "model/vehicle_params.h"

namespace quadfdi {

// Mixer rows: thrust-to-wrench map with Crazyflie numbering, rotors at (±a, ±b)
// (1 front-right +a−b, 2 back-right −a−b, 3 back-left −a+b, 4 front-left +a+b).
//   T  = f1 + f2 + f3 + f4
//   τx = ℓx(−f1 − f2 + f3 + f4),  τy = ℓy(−f1 + f2 + f3 − f4),  τz = κ(−f1 + f2 − f3 + f4)
// with the roll lever ℓx = b = |y| and the pitch lever ℓy = a = |x| (the seed: ℓx = ℓy = √2·d).
inline constexpr double kRollSign[4] = {-1.0, -1.0, 1.0, 1.0};
inline constexpr double kPitchSign[4] = {-1.0, 1.0, 1.0, -1.0};
inline constexpr double kYawSign[4] = {-1.0, 1.0, -1.0, 1.0};

// Everything the derivative needs, precomputed once from VehicleParams (setup),
// so that evaluating it divides by nothing.
struct RigidBodyModel {
  double inv_mass = 0.0;         // [1/kg]
  Vec3 inertia = Vec3::Zero();   // [kg·m²] diagonal of J
  Vec3 inv_inertia = Vec3::Zero();  // [1/(kg·m²)]
  double roll_lever = 0.0;       // [m] |y| of every rotor (seed: √2·d); thrust differences → τx
  double pitch_lever = 0.0;      // [m] |x| of every rotor (seed: √2·d); thrust differences → τy
  double yaw_coeff = 0.0;        // [m] κ, yaw moment per newton of thrust (seed: C_D/C_T)
  double gravity = 0.0;          // [m/s²]
  double linear_drag_per_mass = 0.0;  // [1/s] c/m
  double rotational_drag = 0.0;  // [N·m·s/rad]

  static RigidBodyModel fromParams(const VehicleParams& p) {
    RigidBodyModel m;
    m.inv_mass = 1.0 / p.mass;
    m.inertia = Vec3(p.inertia_xx, p.inertia_yy, p.inertia_zz);
    m.inv_inertia = m.inertia.cwiseInverse();
    m.roll_lever = p.rollLever();
    m.pitch_lever = p.pitchLever();
    m.yaw_coeff = p.yawCoeff();
    m.gravity = p.gravity;
    m.linear_drag_per_mass = p.linear_drag / p.mass;
    m.rotational_drag = p.rotational_drag;
    return m;
  }
};

// Collective thrust [N] and body torques [N·m] produced by per-motor thrusts.
struct Wrench {
  double thrust;
  Vec3 torque;
};

inline Wrench mix(const RigidBodyModel& m, const Input& f) {
  Wrench w;
  w.thrust = (f(0) + f(1)) + (f(2) + f(3));
  w.torque.x() = m.roll_lever * ((f(2) + f(3)) - (f(0) + f(1)));
  w.torque.y() = m.pitch_lever * ((f(1) + f(2)) - (f(0) + f(3)));
  w.torque.z() = m.yaw_coeff * ((f(1) + f(3)) - (f(0) + f(2)));
  return w;
}

// Body-to-world rotation R = Rz(ψ) Ry(θ) Rx(φ).
inline Mat3 rotationBodyToWorld(double roll, double pitch, double yaw) {
  const double sf = std::sin(roll), cf = std::cos(roll);
  const double st = std::sin(pitch), ct = std::cos(pitch);
  const double ss = std::sin(yaw), cs = std::cos(yaw);
  Mat3 r;
  r << cs * ct, cs * st * sf - ss * cf, cs * st * cf + ss * sf,  //
      ss * ct, ss * st * sf + cs * cf, ss * st * cf - cs * sf,   //
      -st, ct * sf, ct * cf;
  return r;
}

// ẋ = f(x, u) for the 12-state model of state.h, thrusts f [N] as applied to the rotors. With
// kWindy, the linear drag acts on the velocity relative to the air, v − Rᵀw, w = `wind_world`
// [m/s] (rotor drag, docs/model.md#wind; no effect without drag). A template parameter rather
// than a run-time test so that the still-air derivative, the generator's hot loop, is the one it
// always was (a run-time test cost 5–25 % per RK4 step in a throwaway loop on this VM, 2026-11-25).
template <bool kWindy>
inline void stateDerivativeIn(const RigidBodyModel& m, const State& x, const Input& f, const Vec3& wind_world, State& dx) {
  const double roll = x(idx::kRoll), pitch = x(idx::kPitch), yaw = x(idx::kYaw);
  const double sf = std::sin(roll), cf = std::cos(roll);
  const double st = std::sin(pitch), ct = std::cos(pitch);
  const double ss = std::sin(yaw), cs = std::cos(yaw);
  const double u = x(idx::kVx), v = x(idx::kVy), w = x(idx::kVz);
  const double p = x(idx::kP), q = x(idx::kQ), r = x(idx::kR);
  const Wrench wr = mix(m, f);

  // ṗ = R v
  dx(idx::kPx) = cs * ct * u + (cs * st * sf - ss * cf) * v + (cs * st * cf + ss * sf) * w;
  dx(idx::kPy) = ss * ct * u + (ss * st * sf + cs * cf) * v + (ss * st * cf - cs * sf) * w;
  dx(idx::kPz) = -st * u + ct * sf * v + ct * cf * w;
  // v̇ = −ω × v + Rᵀ(0,0,−g) + (0,0,T/m) − (c/m)(v − Rᵀw)
  const double g = m.gravity, kd = m.linear_drag_per_mass;
  double air_u = u, air_v = v, air_w = w;  // body velocity relative to the air
  if constexpr (kWindy) {
    const double wx = wind_world.x(), wy = wind_world.y(), wz = wind_world.z();
    air_u -= cs * ct * wx + ss * ct * wy - st * wz;
    air_v -= (cs * st * sf - ss * cf) * wx + (ss * st * sf + cs * cf) * wy + ct * sf * wz;
    air_w -= (cs * st * cf + ss * sf) * wx + (ss * st * cf - cs * sf) * wy + ct * cf * wz;
  }
  dx(idx::kVx) = r * v - q * w + g * st - kd * air_u;
  dx(idx::kVy) = p * w - r * u - g * ct * sf - kd * air_v;
  dx(idx::kVz) = q * u - p * v - g * ct * cf + wr.thrust * m.inv_mass - kd * air_w;
  // η̇ = W(η) ω
  const double tt = st / ct;
  dx(idx::kRoll) = p + (sf * q + cf * r) * tt;
  dx(idx::kPitch) = cf * q - sf * r;
  dx(idx::kYaw) = (sf * q + cf * r) / ct;
  // J ω̇ = τ − ω × Jω − c_r ω
  const double jx = m.inertia.x(), jy = m.inertia.y(), jz = m.inertia.z();
  const double cr = m.rotational_drag;
  dx(idx::kP) = (wr.torque.x() - (jz - jy) * q * r - cr * p) * m.inv_inertia.x();
  dx(idx::kQ) = (wr.torque.y() - (jx - jz) * r * p - cr * q) * m.inv_inertia.y();
  dx(idx::kR) = (wr.torque.z() - (jy - jx) * p * q - cr * r) * m.inv_inertia.z();
}

// Still air (the paper's model).
inline void stateDerivative(const RigidBodyModel& m, const State& x, const Input& f, State& dx) {
  stateDerivativeIn<false>(m, x, f, Vec3::Zero(), dx);
}

// In the wind `wind_world` [m/s], world frame.
inline void stateDerivative(const RigidBodyModel& m, const State& x, const Input& f, const Vec3& wind_world, State& dx) {
  stateDerivativeIn<true>(m, x, f, wind_world, dx);
}

}  // namespace quadfdi
