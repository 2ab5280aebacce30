// Detector throughput and latency (SPEC §9, issue 6): a 500 Hz log through `Detector` with the
// shipped network, all four symmetry maps and a decision per sample. Reported: samples per
// second on one core (real-time factor = that / 500), and the worst per-sample latency in
// stream mode (each sample handled as it arrives).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include "control/controller_factory.h"
#include "detection/detector.h"
#include "networks/inference.h"
#include "simulation/closed_loop.h"
#include "simulation/rng.h"
#include "simulation/sampling.h"

namespace quadfdi {
namespace {

std::vector<TelemetrySample> flight(int motor, int steps) {
  SimulationSettings settings;
  settings.steps = steps;
  if (motor) {
    settings.fault.theta(motor - 1) = 0.0;
    settings.fault.fault_step = steps / 2;
  }
  Rng rng(3, 0);
  const Scenario scenario = sampleScenario(SamplingRanges{}, rng);
  ControllerBuild build = makeController(nominalParams(), ControllerConfig{}, settings.dt);
  build.controller->setGoal(scenario.goal);
  FlightLog log;
  ClosedLoopSimulator(nominalParams(), settings).run(*build.controller, scenario.initial_state, &log);
  std::vector<TelemetrySample> out;
  for (int k = 0; k < log.size(); ++k) {
    TelemetrySample s;
    s.t = settings.dt * k;
    for (int i = 0; i < 6; ++i) s.y[static_cast<std::size_t>(i)] = log.outputs[static_cast<std::size_t>(k)](i);
    for (int i = 0; i < 4; ++i) s.u[static_cast<std::size_t>(i)] = log.controls[static_cast<std::size_t>(k)].u_cmd(i);
    out.push_back(s);
  }
  return out;
}

InferenceEngine& shippedEngine() {
  static const FaultIdentifier model = FaultIdentifier::load(QUADFDI_SOURCE_DIR "/models/lstm-model-free.qfdi");
  static InferenceEngine engine(exportWeights(model));
  return engine;
}

// Args: faulty motor (0 healthy), stride, stream mode (0/1).
void detectLog(benchmark::State& state) {
  configureCpuThreads(1);
  const int motor = static_cast<int>(state.range(0));
  const std::vector<TelemetrySample> log = flight(motor, motor ? 1000 : 5000);
  InferenceEngine& engine = shippedEngine();
  DetectorConfig config;
  config.stride = static_cast<int>(state.range(1));
  const bool stream = state.range(2) != 0;
  double worst_ms = 0.0;
  long alarms = 0;
  for (auto _ : state) {
    Detector detector(config, engine);
    DetectorOutput out;
    for (const TelemetrySample& s : log) {
      const auto t0 = std::chrono::steady_clock::now();
      detector.push(s, !stream);
      while (detector.pop(out)) benchmark::DoNotOptimize(out);
      worst_ms = std::max(worst_ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    detector.finish();
    while (detector.pop(out)) benchmark::DoNotOptimize(out);
    alarms = detector.summary().alarms_raised;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(log.size()));
  state.counters["x_real_time"] = benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(log.size()) * 0.002,
                                                    benchmark::Counter::kIsRate);
  state.counters["worst_ms"] = worst_ms;
  state.counters["alarms"] = static_cast<double>(alarms);
  state.SetLabel(std::string(engine.kernel()) + (stream ? " stream" : " file"));
}

BENCHMARK(detectLog)
    ->ArgNames({"motor", "stride", "stream"})
    ->Args({0, 4, 0})
    ->Args({0, 4, 1})
    ->Args({1, 4, 0})
    ->Args({0, 8, 0})
    ->Args({0, 1, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace quadfdi
