// One zero-order-hold step of the plant (docs/model.md): RK4 (default) or forward Euler
// (parity with the authors' code), with an optional first-order motor lag.
#pragma once

#include <cmath>

#include "model/dynamics.h"

namespace quadfdi {

enum class Integrator { kRk4, kEuler };

// The plant's full internal state: the 12-state rigid body plus the thrust the
// rotors actually produce (differs from the command only with a motor lag).
struct PlantState {
  State x = State::Zero();
  Input rotor_thrust = Input::Zero();  // [N]
};

// Why a step was cut (docs/model.md): a trajectory that leaves these bounds is flagged, never kept.
enum class StepStatus { kOk, kNonFinite, kAttitudeLimit, kBelowGround };

const char* toString(StepStatus s);
const char* toString(Integrator i);

// Physical bounds of a valid state (docs/model.md).
struct StateBounds {
  double max_tilt_angle = 1.5;  // [rad] bound on |φ| and |θ|
  double min_altitude = 0.0;    // [m] z below this is a crash
};

inline StepStatus checkState(const State& x, const StateBounds& bounds) {
  if (!x.allFinite()) return StepStatus::kNonFinite;
  if (std::abs(x(idx::kRoll)) > bounds.max_tilt_angle || std::abs(x(idx::kPitch)) > bounds.max_tilt_angle)
    return StepStatus::kAttitudeLimit;
  if (x(idx::kPz) < bounds.min_altitude) return StepStatus::kBelowGround;
  return StepStatus::kOk;
}

// One step for stepPlant below, still air or in the wind (dynamics.h: a template parameter keeps
// the still-air step free of any test).
template <bool kWindy>
inline void stepPlantIn(const RigidBodyModel& model, Integrator integrator, double dt, double motor_time_constant,
                        const Input& applied, const Vec3& wind_world, PlantState& plant) {
  Input f0 = applied, f_mid = applied, f1 = applied;
  if (motor_time_constant > 0.0) {
    const Input gap = plant.rotor_thrust - applied;
    f0 = plant.rotor_thrust;
    f_mid = applied + gap * std::exp(-0.5 * dt / motor_time_constant);
    f1 = applied + gap * std::exp(-dt / motor_time_constant);
  }
  State& x = plant.x;
  if (integrator == Integrator::kEuler) {
    State k1;
    stateDerivativeIn<kWindy>(model, x, f0, wind_world, k1);
    x += dt * k1;
  } else {
    State k1, k2, k3, k4, tmp;
    stateDerivativeIn<kWindy>(model, x, f0, wind_world, k1);
    tmp = x + (0.5 * dt) * k1;
    stateDerivativeIn<kWindy>(model, tmp, f_mid, wind_world, k2);
    tmp = x + (0.5 * dt) * k2;
    stateDerivativeIn<kWindy>(model, tmp, f_mid, wind_world, k3);
    tmp = x + dt * k3;
    stateDerivativeIn<kWindy>(model, tmp, f1, wind_world, k4);
    x += (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  plant.rotor_thrust = f1;
}

// Advances `plant` by dt under the thrust command `applied` (after the fault), held constant.
// motor_time_constant > 0: rotor thrust follows f(t) = a + (f0 − a) e^{−t/τ}, evaluated exactly
// at the RK4 stage times, so the lag costs no extra states. `wind_world` [m/s] (null = still air)
// is held over the step like the command (zero-order hold).
inline void stepPlant(const RigidBodyModel& model, Integrator integrator, double dt,
                      double motor_time_constant, const Input& applied, PlantState& plant,
                      const Vec3* wind_world = nullptr) {
  if (wind_world)
    stepPlantIn<true>(model, integrator, dt, motor_time_constant, applied, *wind_world, plant);
  else
    stepPlantIn<false>(model, integrator, dt, motor_time_constant, applied, Vec3::Zero(), plant);
}

}  // namespace quadfdi
