// Closed-loop simulation throughput on one core (docs/benchmarks.md). items/s = simulated steps/s.
#include <benchmark/benchmark.h>

#include "control/controller_factory.h"
#include "simulation/closed_loop.h"
#include "simulation/sampling.h"

namespace quadfdi {
namespace {

void closedLoop(benchmark::State& state, ControllerKind kind, Integrator integrator) {
  const VehicleParams p = nominalParams();
  ControllerConfig cc;
  cc.kind = kind;
  ControllerBuild build = makeController(p, cc, 0.002);
  SimulationSettings s;
  s.steps = 1000;
  s.integrator = integrator;
  s.fault.theta(1) = 0.5;
  s.fault.fault_step = 500;
  const ClosedLoopSimulator sim(p, s);
  std::uint64_t index = 0;
  std::int64_t steps = 0;
  for (auto _ : state) {
    Rng rng(1, index++);
    const Scenario sc = sampleScenario(SamplingRanges{}, rng);
    build.controller->setGoal(sc.goal);
    const FlightSummary sum = sim.run(*build.controller, sc.initial_state, nullptr);
    benchmark::DoNotOptimize(sum.final_state);
    steps += sum.steps_completed;
  }
  state.SetItemsProcessed(steps);
}

void plantStepOnly(benchmark::State& state) {
  const VehicleParams p = nominalParams();
  const RigidBodyModel m = RigidBodyModel::fromParams(p);
  PlantState plant;
  plant.x(idx::kPz) = 1.0;
  plant.x(idx::kRoll) = 0.1;
  const Input u = Input::Constant(p.hoverThrust());
  for (auto _ : state) {
    stepPlant(m, Integrator::kRk4, 0.002, 0.0, u, plant);
    benchmark::DoNotOptimize(plant.x);
  }
  state.SetItemsProcessed(state.iterations());
}

// The same step in the wind (docs/model.md#wind): rotor drag on the air-relative velocity, the
// wind stepped by its model (turbulence and gust draws every step), as randomised flights fly it.
void plantStepInWind(benchmark::State& state) {
  VehicleParams p = nominalParams();
  p.linear_drag = 0.26 * p.mass;
  const RigidBodyModel m = RigidBodyModel::fromParams(p);
  WindConfig c;
  c.mean_speed = 3.0;
  c.turbulence_std = 1.0;
  c.gust_rate = 0.1;
  c.gust_peak = 3.0;
  WindModel wind(c, 0.002);
  Rng rng(1, 1);
  wind.reset(rng);
  PlantState plant;
  plant.x(idx::kPz) = 1.0;
  plant.x(idx::kRoll) = 0.1;
  const Input u = Input::Constant(p.hoverThrust());
  for (auto _ : state) {
    stepPlant(m, Integrator::kRk4, 0.002, 0.0, u, plant, &wind.step(rng));
    benchmark::DoNotOptimize(plant.x);
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_CAPTURE(closedLoop, lqr_rk4, ControllerKind::kLqr, Integrator::kRk4)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(closedLoop, cbf_qp_rk4, ControllerKind::kCbfQp, Integrator::kRk4)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(closedLoop, lqr_euler, ControllerKind::kLqr, Integrator::kEuler)->Unit(benchmark::kMillisecond);
BENCHMARK(plantStepOnly);
BENCHMARK(plantStepInWind);

}  // namespace
}  // namespace quadfdi
