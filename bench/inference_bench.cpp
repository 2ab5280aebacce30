// Inference throughput of the identifier (issue 6): windows per second through FaultIdentifier::predict
// (LibTorch, no gradients) and through the LibTorch-free InferenceEngine the detector uses, at batch sizes from one sample's four symmetry maps to file-mode batches.
#include <benchmark/benchmark.h>

#include <vector>

#include "inference/engine.h"
#include "networks/model.h"

namespace quadfdi {
namespace {

void predictBatch(benchmark::State& state, Architecture arch) {
  configureCpu(1);
  const int batch = static_cast<int>(state.range(0));
  ModelMetadata m;
  m.architecture = arch;
  m.window = 100;
  m.hidden = static_cast<int>(state.range(1));
  const FaultIdentifier model = FaultIdentifier::create(m, 1);
  std::vector<float> x(static_cast<std::size_t>(batch) * m.window * m.channels(), 0.1f);
  std::vector<float> theta(static_cast<std::size_t>(batch) * 4);
  for (auto _ : state) {
    model.predict(x.data(), batch, theta.data());
    benchmark::DoNotOptimize(theta.data());
  }
  state.SetItemsProcessed(state.iterations() * batch);
}

// The LibTorch-free engine the detector uses (inference/engine.h).
void enginePredict(benchmark::State& state, Architecture arch) {
  const int batch = static_cast<int>(state.range(0));
  ModelMetadata m;
  m.architecture = arch;
  m.window = 100;
  m.hidden = static_cast<int>(state.range(1));
  InferenceEngine engine(exportWeights(FaultIdentifier::create(m, 1)));
  std::vector<float> x(static_cast<std::size_t>(batch) * m.window * m.channels(), 0.1f);
  std::vector<float> theta(static_cast<std::size_t>(batch) * 4);
  for (auto _ : state) {
    engine.predict(x.data(), batch, theta.data());
    benchmark::DoNotOptimize(theta.data());
  }
  state.SetItemsProcessed(state.iterations() * batch);
}

BENCHMARK_CAPTURE(enginePredict, lstm, Architecture::kLstm)->ArgsProduct({{4, 8, 64}, {128}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(enginePredict, mlp, Architecture::kMlp)->Args({4, 128})->Args({64, 128})->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_CAPTURE(predictBatch, lstm, Architecture::kLstm)
    ->ArgsProduct({{4, 64, 512}, {128}})
    ->Args({512, 32})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(predictBatch, mlp, Architecture::kMlp)->Args({4, 128})->Args({512, 128})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace quadfdi
