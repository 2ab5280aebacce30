// Simulated Crazyflie missions for the log tests (header only): the vehicle sits on the ground
// with its motors off, takes off (LQR to a hover goal), flies, and either lands (a descent in
// steps, then the ground again) or loses a motor mid-flight and crashes. Samples every 2 ms in
// quadfdi's conventions (body rates the true ones), with the truth the writers need (armed,
// take-off and landing times).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "control/controller_factory.h"
#include "core/types.h"
#include "model/vehicle_params.h"
#include "simulation/closed_loop.h"

namespace quadfdi::test {

struct Mission {
  std::vector<TelemetrySample> samples;  // every 2 ms from t = 0
  double armed_at = 0.0;                 // [s]
  double takeoff_at = 0.0;               // [s] the LQR starts climbing from the ground
  double landed_at = -1.0;               // [s] touchdown (< 0: never: crashed or still flying)
  double fault_at = -1.0;                // [s] (< 0: healthy)
  double dt = 0.002;
};

// One sample of a mission, in quadfdi's conventions.
inline void appendSample(Mission& m, double t, const Output& y, const Input& u, const Vec3& rates) {
  TelemetrySample s;
  s.t = t;
  for (int i = 0; i < 6; ++i) s.y[static_cast<std::size_t>(i)] = y(i);
  for (int i = 0; i < 4; ++i) s.u[static_cast<std::size_t>(i)] = u(i);
  for (int i = 0; i < 3; ++i) s.rates[static_cast<std::size_t>(i)] = rates(i);
  m.samples.push_back(s);
}

// `fault_motor` 0: healthy, lands. Otherwise motor `fault_motor` gets Θ = `theta` at `fault_at`
// and the flight runs on until the simulator cuts it (a crash) or 1 s later.
inline Mission simulateMission(int fault_motor, double theta, double fault_at, double yaw0 = 0.3) {
  Mission m;
  const double dt = m.dt;
  const double ground = 1.0;  // [s] on the ground, motors off, before take-off
  m.armed_at = 0.5;
  m.takeoff_at = ground;
  const VehicleParams params = nominalParams();
  auto push = [&](double t, const Output& y, const Input& u, const Vec3& rates = Vec3::Zero()) { appendSample(m, t, y, u, rates); };
  Output rest = Output::Zero();
  rest(5) = yaw0;
  rest(0) = 0.2;
  rest(1) = -0.1;
  long k = 0;
  for (; static_cast<double>(k) * dt < ground - 1e-9; ++k) push(static_cast<double>(k) * dt, rest, Input::Zero());

  State x = State::Zero();
  x(idx::kPx) = rest(0);
  x(idx::kPy) = rest(1);
  x(idx::kYaw) = yaw0;
  ControllerBuild build = makeController(params, ControllerConfig{}, dt);
  // Legs: (goal z, duration [s]). Healthy: climb, hover, descend in steps. Faulty: climb, hover to the fault and on.
  struct Leg {
    double z, seconds;
    bool fault;
  };
  std::vector<Leg> legs;
  if (fault_motor == 0) {
    legs = {{1.0, 3.0, false}, {0.6, 1.5, false}, {0.3, 1.5, false}, {0.12, 1.5, false}};
  } else {
    legs = {{1.0, fault_at - ground, false}, {1.0, 1.0, true}};
    m.fault_at = fault_at;
  }
  bool cut = false;
  for (const Leg& leg : legs) {
    SimulationSettings settings;
    settings.dt = dt;
    settings.steps = static_cast<int>(std::lround(leg.seconds / dt));
    if (leg.fault) {
      settings.fault.theta(fault_motor - 1) = theta;
      settings.fault.fault_step = 0;
    }
    build.controller->setGoal(Vec3(rest(0), rest(1), leg.z));
    const ClosedLoopSimulator sim(params, settings);
    FlightLog log;
    const FlightSummary summary = sim.run(*build.controller, x, &log);
    for (int i = 0; i < log.size(); ++i, ++k)
      push(static_cast<double>(k) * dt, log.outputs[static_cast<std::size_t>(i)], log.controls[static_cast<std::size_t>(i)].u_cmd,
           log.states[static_cast<std::size_t>(i)].segment<3>(idx::kRate));
    x = summary.final_state;
    if (summary.cut()) {
      cut = true;
      break;
    }
  }
  if (fault_motor == 0 && !cut) {
    // Touchdown: the ground again, motors off after a short idle (the autopilot disarms).
    m.landed_at = static_cast<double>(k) * dt;
    Output y = Output::Zero();
    y(0) = x(idx::kPx);
    y(1) = x(idx::kPy);
    y(5) = x(idx::kYaw);
    for (int i = 0; i < 500; ++i, ++k) push(static_cast<double>(k) * dt, y, Input::Zero());
  }
  return m;
}

// A healthy mission that manoeuvres: take-off as above, then 12 s of hover goals stepped 0.4 m
// around a square every second (each step a sharp roll and pitch), then the descent and landing.
// What the motor-numbering check needs to see the motors turn the vehicle.
inline Mission simulateManoeuvringMission(double yaw0 = 0.3) {
  Mission m;
  const double dt = m.dt, ground = 1.0;
  m.armed_at = 0.5;
  m.takeoff_at = ground;
  const VehicleParams params = nominalParams();
  auto push = [&](long k, const Output& y, const Input& u, const Vec3& rates) { appendSample(m, static_cast<double>(k) * dt, y, u, rates); };
  Output rest = Output::Zero();
  rest(5) = yaw0;
  long k = 0;
  for (; static_cast<double>(k) * dt < ground - 1e-9; ++k) push(k, rest, Input::Zero(), Vec3::Zero());
  State x = State::Zero();
  x(idx::kYaw) = yaw0;
  ControllerBuild build = makeController(params, ControllerConfig{}, dt);
  std::vector<Vec3> goals = {Vec3(0, 0, 1.0)};
  const double corner[4][2] = {{0.4, 0.0}, {0.4, 0.4}, {0.0, 0.4}, {0.0, 0.0}};
  for (int i = 0; i < 12; ++i) goals.push_back(Vec3(corner[i % 4][0], corner[i % 4][1], 1.0));
  for (const double z : {0.6, 0.3, 0.12}) goals.push_back(Vec3(0, 0, z));
  for (std::size_t leg = 0; leg < goals.size(); ++leg) {
    SimulationSettings settings;
    settings.dt = dt;
    settings.steps = static_cast<int>(std::lround((leg == 0 ? 3.0 : 1.0) / dt));
    build.controller->setGoal(goals[leg]);
    FlightLog log;
    const FlightSummary summary = ClosedLoopSimulator(params, settings).run(*build.controller, x, &log);
    for (int i = 0; i < log.size(); ++i, ++k)
      push(k, log.outputs[static_cast<std::size_t>(i)], log.controls[static_cast<std::size_t>(i)].u_cmd,
           log.states[static_cast<std::size_t>(i)].segment<3>(idx::kRate));
    x = summary.final_state;
  }
  m.landed_at = static_cast<double>(k) * dt;
  Output y = Output::Zero();
  y(0) = x(idx::kPx);
  y(1) = x(idx::kPy);
  y(5) = x(idx::kYaw);
  for (int i = 0; i < 500; ++i, ++k) push(k, y, Input::Zero(), Vec3::Zero());
  return m;
}

}  // namespace quadfdi::test
