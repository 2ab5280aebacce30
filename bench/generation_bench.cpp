// Dataset generation throughput (docs/benchmarks.md): Algorithm 1's outer iteration at paper scale
// (1 100 trajectories × 200 steps, residuals and windows), on 1 and on all cores.
#include <benchmark/benchmark.h>

#include <thread>

#include "data/rollout.h"
#include "data/window_buffer.h"

namespace quadfdi {
namespace {

const std::vector<double> kThetas{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};

void paperIteration(benchmark::State& state, ControllerKind kind) {
  RolloutConfig c;
  c.controller.kind = kind;
  c.seed = 1;
  const RolloutEngine engine(c);
  const int threads = static_cast<int>(state.range(0));
  std::uint64_t first = 0;
  std::int64_t steps = 0, windows = 0;
  TrajectoryBatch batch;
  std::vector<WindowRef> refs;
  for (auto _ : state) {
    const auto jobs = algorithm1Jobs(first, 100, kThetas, {2});  // 1 100 trajectories
    first += 100;
    engine.run(jobs, threads, batch);
    refs.clear();
    enumerateWindows(batch, c.window, refs);
    for (int i = 0; i < batch.count; ++i) steps += batch.length[static_cast<std::size_t>(i)] - 1;
    windows += static_cast<std::int64_t>(refs.size());
  }
  state.SetItemsProcessed(steps);
  state.counters["windows"] = benchmark::Counter(static_cast<double>(windows) / static_cast<double>(state.iterations()));
  state.counters["bytes_per_window"] =
      benchmark::Counter(static_cast<double>(batch.bytes()) / static_cast<double>(refs.size()));
  state.counters["threads"] = threads;
}

BENCHMARK_CAPTURE(paperIteration, lqr, ControllerKind::kLqr)
    ->Arg(1)
    ->Arg(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(paperIteration, cbf_qp, ControllerKind::kCbfQp)
    ->Arg(1)
    ->Arg(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace quadfdi
