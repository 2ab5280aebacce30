// Detector throughput and latency (docs/benchmarks.md): a 500 Hz log through a detection session
// with a shipped network (the paper's windowed LSTM, or the streaming TCN), all four symmetry
// maps and a decision per sample. Reported: samples per
// second on one core (real-time factor = that / 500), and the worst per-sample latency in
// stream mode (each sample handled as it arrives).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include "control/controller_factory.h"
#include "detection/numbering_check.h"
#include "detection/sequential.h"
#include "io/calibration_file.h"
#include "detection/session.h"
#include "io/model_file.h"
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
    for (int i = 0; i < 3; ++i) s.rates[static_cast<std::size_t>(i)] = log.states[static_cast<std::size_t>(k)](idx::kRate + i);
    out.push_back(s);
  }
  return out;
}

// The shipped models: 0 the paper's windowed LSTM, 1 the still-air streaming TCN, 2 the general
// streaming TCN that `detect` runs by default (scale-free features), 3 a streaming TCN on body
// rates (scale-free-rates: the 1.5 kg quad's, run here on the Crazyflie's flight, which costs the same).
const TrainedModel& shippedModel(int which) {
  static const TrainedModel lstm = readModelFile(QUADFDI_SOURCE_DIR "/models/lstm-model-free.qfdw");
  static const TrainedModel tcn = readModelFile(QUADFDI_SOURCE_DIR "/models/tcn-model-free.qfdw");
  static const TrainedModel general = readModelFile(QUADFDI_SOURCE_DIR "/models/tcn-randomised.qfdw");
  static const TrainedModel rates = readModelFile(QUADFDI_SOURCE_DIR "/models/tcn-quad450-rates.qfdw");
  return which == 0 ? lstm : which == 1 ? tcn : which == 2 ? general : rates;
}

// A log in memory as a sample source; the longest time between two calls is the worst
// per-sample latency (the detector's work on one sample, in stream mode).
class TimedLogSource : public SampleSource {
 public:
  explicit TimedLogSource(const std::vector<TelemetrySample>& log) : log_(log) {}
  Next next(TelemetrySample& sample, std::string&) override {
    const auto now = std::chrono::steady_clock::now();
    if (at_ > 0) worst_ms = std::max(worst_ms, std::chrono::duration<double, std::milli>(now - last_).count());
    last_ = now;
    if (at_ == log_.size()) return Next::kEnd;
    sample = log_[at_++];
    return Next::kSample;
  }
  std::string where() const override { return "log:" + std::to_string(at_); }
  bool moreReady() const override { return false; }  // stream mode: as from an idle live pipe
  bool carriesRates() const override { return true; }  // the flight's true body rates
  double worst_ms = 0.0;

 private:
  const std::vector<TelemetrySample>& log_;
  std::size_t at_ = 0;
  std::chrono::steady_clock::time_point last_;
};

class CountingSink : public DetectionSink {
 public:
  void output(const DetectorOutput& d) override { benchmark::DoNotOptimize(d); }
  void warning(const std::string&) override {}
};

// Args: model (0 LSTM, 1 TCN, 2 general TCN, 3 TCN on body rates), faulty motor (0 healthy), stride, stream mode (0/1), command gate (0 off, 1 the default).
void detectLog(benchmark::State& state) {
  const TrainedModel& model = shippedModel(static_cast<int>(state.range(0)));
  const int motor = static_cast<int>(state.range(1));
  const std::vector<TelemetrySample> log = flight(motor, motor ? 1000 : 5000);
  DetectorConfig config;
  config.stride = static_cast<int>(state.range(2));
  if (state.range(4) == 0) config.command_gate.min_share = 0.0;  // its cost: the same run without it
  SessionConfig session;
  session.live = state.range(3) != 0;
  double worst_ms = 0.0;
  long alarms = 0;
  std::string label;
  for (auto _ : state) {
    Detector detector(config, model);
    TimedLogSource source(log);
    CountingSink sink;
    runDetection(detector, source, sink, session);
    worst_ms = std::max(worst_ms, source.worst_ms);
    alarms = detector.summary().alarms_raised;
    label = std::string(toString(model.metadata.architecture)) + " " + detector.kernel() + (session.live ? " stream" : " file") +
            (state.range(4) == 0 ? " no gate" : "");
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(log.size()));
  state.counters["x_real_time"] = benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(log.size()) * 0.002,
                                                    benchmark::Counter::kIsRate);
  state.counters["worst_ms"] = worst_ms;
  state.counters["alarms"] = static_cast<double>(alarms);
  state.SetLabel(label);
}

BENCHMARK(detectLog)
    ->ArgNames({"model", "motor", "stride", "stream", "gate"})
    ->Args({0, 0, 4, 0, 1})
    ->Args({0, 0, 4, 1, 1})
    ->Args({0, 1, 4, 0, 1})
    ->Args({0, 0, 1, 0, 1})
    ->Args({1, 0, 1, 0, 1})
    ->Args({1, 0, 1, 0, 0})
    ->Args({1, 0, 1, 1, 1})
    ->Args({1, 1, 1, 0, 1})
    ->Args({2, 0, 1, 0, 1})
    ->Args({3, 0, 1, 0, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The motor-numbering check alone (detection/numbering_check.h), which every detection session
// runs beside the detector: its cost per sample on the 10 s flight. Arg: 1 from the body rates,
// 0 from the attitude (a rotation vector per node).
void numberingCheck(benchmark::State& state) {
  const std::vector<TelemetrySample> log = flight(0, 5000);
  NumberingCheckResult r;
  for (auto _ : state) {
    NumberingCheck check;
    check.setup(state.range(0) != 0);
    for (const TelemetrySample& s : log) check.step(s);
    r = check.result();
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(log.size()));
  state.SetLabel(std::string(toString(r.verdict)) + (state.range(0) ? " from rates" : " from attitude"));
}
BENCHMARK(numberingCheck)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond)->UseRealTime();

// The sequential rule alone, one update with an alarm held (the estimate and its interval are
// stated every update then). Arg: the interval (0 the spread per range, 1 the confidence belt
// inverted on its 0.001 grid), from the racer's shipped calibration.
void sequentialUpdateWithAlarm(benchmark::State& state) {
  static const DecisionCalibration racer = readCalibrationFile(QUADFDI_SOURCE_DIR "/models/tcn-racer250.calibration.json");
  SequentialConfig config = sequentialConfig(racer);
  if (state.range(0) == 0) config.noise.belt.clear();
  SequentialRule rule(config);
  MotorTheta theta{1.0f, 0.42f, 1.0f, 1.0f};
  while (!rule.active()) rule.update(theta, 1);
  for (auto _ : state) {
    theta[1] = theta[1] == 0.42f ? 0.43f : 0.42f;  // the estimate moves
    benchmark::DoNotOptimize(rule.update(theta, 1));
    benchmark::DoNotOptimize(rule.state().theta_lo);
  }
  state.SetLabel(state.range(0) ? "belt" : "spread");
}

BENCHMARK(sequentialUpdateWithAlarm)->ArgNames({"belt"})->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace quadfdi
