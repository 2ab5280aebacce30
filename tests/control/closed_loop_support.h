// Closed-loop helpers shared by the controller tests (pid_test, geometric_test): a flight driven
// by an arbitrary reference function, its tracking error, and references mapped by a symmetry.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "control/controller.h"
#include "control/controller_factory.h"
#include "control/reference.h"
#include "model/integrator.h"
#include "simulation/closed_loop.h"
#include "symmetry/symmetry.h"
#include "test_support.h"

namespace quadfdi::test {

constexpr double kControlDt = 0.002;  // [s]

// makeController at kControlDt, or throw its error.
inline std::unique_ptr<Controller> builtController(const VehicleParams& design, const ControllerConfig& config) {
  ControllerBuild build = makeController(design, config, kControlDt);
  if (!build.controller) throw std::runtime_error(build.error);
  return std::move(build.controller);
}

// A flight driven by an arbitrary reference function (the simulator's loop, written out so the
// reference can be mapped or stripped of its feed-forward).
struct Flight {
  std::vector<State> states;
  std::vector<Input> commands;
  std::vector<Reference> references;
  bool cut = false;
};

inline Flight fly(Controller& ctrl, const VehicleParams& plant, const State& x0, int steps,
           const std::function<Reference(double)>& reference, const Input& theta = Input::Ones()) {
  const RigidBodyModel model = RigidBodyModel::fromParams(plant);
  PlantState ps;
  ps.x = x0;
  ps.rotor_thrust = Input::Constant(plant.hoverThrust());
  ctrl.reset();
  Flight f;
  ControlStep step;
  for (int k = 0; k < steps; ++k) {
    const Reference r = reference(k * kControlDt);
    ctrl.setReference(r);
    ctrl.compute(ps.x, step);
    f.states.push_back(ps.x);
    f.commands.push_back(step.u_cmd);
    f.references.push_back(r);
    stepPlant(model, Integrator::kRk4, kControlDt, plant.motor_time_constant, theta.cwiseProduct(step.u_cmd), ps);
    if (checkState(ps.x, StateBounds{}) != StepStatus::kOk) {
      f.cut = true;
      break;
    }
  }
  return f;
}

struct TrackingError {
  double rms = 0.0;  // [m]
  double max = 0.0;  // [m]
};

inline TrackingError trackingError(const Flight& f, int from_step) {
  TrackingError e;
  int n = 0;
  for (std::size_t k = static_cast<std::size_t>(from_step); k < f.states.size(); ++k) {
    const double d = (f.states[k].head<3>() - f.references[k].position).norm();
    e.rms += d * d;
    e.max = std::max(e.max, d);
    ++n;
  }
  e.rms = std::sqrt(e.rms / std::max(n, 1));
  return e;
}

inline Reference withoutFeedForward(Reference r) {
  r.velocity.setZero();
  r.acceleration.setZero();
  r.yaw_rate = 0.0;
  return r;
}

inline Reference mapped(const Reference& r, const SymmetryMap& g) {
  const Mat3 s = g.state_map.block<3, 3>(idx::kPos, idx::kPos);
  const double yaw_sign = g.state_map(idx::kYaw, idx::kYaw);
  Reference m;
  m.position = s * r.position;
  m.velocity = s * r.velocity;
  m.acceleration = s * r.acceleration;
  m.yaw = yaw_sign * r.yaw;
  m.yaw_rate = yaw_sign * r.yaw_rate;
  return m;
}

inline TrajectorySpec spec(TrajectoryKind kind, double speed) {
  TrajectorySpec s;
  s.kind = kind;
  s.start = Vec3(0.0, 0.0, 1.0);
  s.goal = Vec3(2.0, 1.0, 1.5);
  s.radius = 1.0;
  s.speed = speed;
  s.yaw_mode = YawMode::kFacingVelocity;
  return s;
}

inline State startOf(const TrajectorySpec& s) {
  const Reference r = referenceAt(s, 0.0);
  State x = hoverState(r.position);
  x(idx::kYaw) = r.yaw;
  return x;
}

}  // namespace quadfdi::test
