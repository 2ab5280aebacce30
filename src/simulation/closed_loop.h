// One closed-loop flight: controller → saturation → fault diag(Θ) → plant (docs/model.md, docs/control.md).
// This is the reference implementation, written for clarity; batched generation
// must agree with it.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "control/controller.h"
#include "control/reference.h"
#include "model/integrator.h"
#include "model/vehicle_params.h"
#include "simulation/wind.h"

namespace quadfdi {

// Seed eq. 2: from step `fault_step` on the plant receives diag(theta)·u_cmd.
struct FaultSpec {
  Input theta = Input::Ones();  // [-] per-motor effectiveness in [0, 1]; all ones = healthy
  int fault_step = 0;           // [steps] first step at which theta applies
  bool healthy() const { return (theta.array() == 1.0).all(); }
};

// Additive white Gaussian noise on the logged output y and the logged body rates (off by default).
struct SensorNoise {
  double position_std = 0.0;  // [m]
  double attitude_std = 0.0;  // [rad] on Euler angles
  double rate_std = 0.0;      // [rad/s] on the logged body rates (a gyro's white noise), own stream
  std::uint64_t seed = 0;     // noise stream, independent of the scenario stream
};

struct SimulationSettings {
  double dt = 0.002;  // [s] control/logging period, 500 Hz (Crazyflie attitude loop, authors' dt)
  int steps = 1000;   // [steps] control steps to run
  Integrator integrator = Integrator::kRk4;
  StateBounds bounds;
  FaultSpec fault;
  SensorNoise noise;
  // The air (docs/model.md#wind), drawn on the stream of noise.seed; it acts through the plant's
  // linear_drag only. Still air by default.
  WindConfig wind;
  // A manoeuvre to fly: before step k the simulator calls controller.setReference(referenceAt(
  // *trajectory, k·dt)). Empty (default): the controller keeps the reference it was given.
  std::optional<TrajectorySpec> trajectory;
};

// Empty when valid, else a one-line description of the first problem.
std::string validate(const SimulationSettings& settings);

// Per-step record. Step k: state x(k) at t = k·dt, the command computed from it and the
// thrust applied over [t, t + dt). A cut flight holds only the steps before the bad state.
struct FlightLog {
  std::vector<State> states;          // x(k), true state
  std::vector<Output> outputs;        // y(k) = (position, Euler angles) [+ sensor noise]
  std::vector<ControlStep> controls;  // u_cmd(k), LQR command, controller status
  std::vector<Input> applied;         // diag(Θ)·u_cmd(k) once k ≥ F, else u_cmd(k)
  std::vector<Vec3> rates;            // logged body rates p,q,r(k) [rad/s] [+ gyro noise]; empty: the true ones
  int size() const { return static_cast<int>(states.size()); }
};

struct FlightSummary {
  int steps_completed = 0;           // steps logged
  StepStatus end_status = StepStatus::kOk;  // kOk unless the flight was cut
  State final_state = State::Zero();  // last valid state (after the last logged step)
  int saturated_steps = 0;           // LQR command clipped to motor bounds
  int filtered_steps = 0;            // CBF-QP changed the command
  int infeasible_steps = 0;          // CBF-QP infeasible or failed: fell back to clipped LQR
  int altitude_active_steps = 0;
  int tilt_active_steps = 0;
  bool cut() const { return end_status != StepStatus::kOk; }
};

class ClosedLoopSimulator {
 public:
  // setup: the plant's true parameters (may differ from the controller's design model).
  ClosedLoopSimulator(const VehicleParams& plant_params, const SimulationSettings& settings);
  // Runs settings.steps steps from x0 (rotors start at hover thrust), after controller.reset().
  // `log` may be null;
  // otherwise it is cleared and filled (reserve happens here, not per step).
  FlightSummary run(Controller& controller, const State& x0, FlightLog* log) const;

 private:
  VehicleParams params_;
  RigidBodyModel model_;
  SimulationSettings settings_;
};

}  // namespace quadfdi
