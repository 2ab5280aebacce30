// Training throughput (docs/benchmarks.md): windows per second for forward + backward + Adam on the
// LSTM identifier, T = 100, hidden 128, model-free features, at 1 and 2 LibTorch threads; the same
// for the TCN trained on windows and densely on whole trajectories (2T + 1 samples, a label per
// position from the receptive field on: items = labelled positions, i.e. windows-equivalent).
// bench/compare-training.sh runs this and the same model in PyTorch's Python API.
#include <benchmark/benchmark.h>

#include "networks/torch_net.h"

namespace quadfdi {
namespace {

void trainStep(benchmark::State& state, Architecture arch, FeatureSet features) {
  configureCpu(static_cast<int>(state.range(0)));
  const int batch = static_cast<int>(state.range(1));
  ModelMetadata m;
  m.architecture = arch;
  m.features = features;
  m.window = 100;
  m.hidden = 128;
  const FaultIdentifier model = FaultIdentifier::create(m, 1);
  auto& net = model.impl()->net;
  torch::optim::Adam opt(net->parameters(), torch::optim::AdamOptions(5e-4).weight_decay(1e-5));
  torch::manual_seed(0);
  const torch::Tensor x = torch::randn({batch, m.window, m.channels()});
  const torch::Tensor y = torch::rand({batch, 4});
  for (auto _ : state) {
    opt.zero_grad();
    const torch::Tensor loss = torch::relu((net->forward(x) - y).norm(2, 1) - 0.01).mean();
    loss.backward();
    opt.step();
    benchmark::DoNotOptimize(loss.item<float>());
  }
  state.SetItemsProcessed(state.iterations() * batch);
  state.counters["threads"] = static_cast<double>(state.range(0));
}

// Dense step: state.range(1) trajectories of 2T + 1 samples.
void denseTrainStep(benchmark::State& state) {
  configureCpu(static_cast<int>(state.range(0)));
  const int trajectories = static_cast<int>(state.range(1));
  ModelMetadata m;
  m.architecture = Architecture::kTcn;
  m.features = FeatureSet::kModelFreeHeading;
  m.window = 100;
  const FaultIdentifier model = FaultIdentifier::create(m, 1);
  auto& net = model.impl()->net;
  torch::optim::Adam opt(net->parameters(), torch::optim::AdamOptions(5e-4).weight_decay(1e-5));
  torch::manual_seed(0);
  const int samples = 2 * m.window + 1, positions = samples - (m.tcn.receptiveField() - 1);
  const torch::Tensor x = torch::randn({trajectories, samples, m.channels()});
  const torch::Tensor y = torch::rand({trajectories, positions, 4});
  const torch::Tensor mask = torch::ones({trajectories, positions});
  for (auto _ : state) {
    opt.zero_grad();
    const torch::Tensor per_position = torch::relu((net->forwardSequence(x) - y).norm(2, 2) - 0.01);
    const torch::Tensor loss = (per_position * mask).sum() / mask.sum();
    loss.backward();
    opt.step();
    benchmark::DoNotOptimize(loss.item<float>());
  }
  state.SetItemsProcessed(state.iterations() * trajectories * positions);
  state.counters["threads"] = static_cast<double>(state.range(0));
}

BENCHMARK_CAPTURE(trainStep, tcn, Architecture::kTcn, FeatureSet::kModelFreeHeading)
    ->Args({2, 512})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
BENCHMARK(denseTrainStep)
    ->Args({1, 32})
    ->Args({2, 8})
    ->Args({2, 32})
    ->Args({2, 128})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

BENCHMARK_CAPTURE(trainStep, lstm, Architecture::kLstm, FeatureSet::kModelFree)
    ->Args({1, 512})
    ->Args({2, 512})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3.0);
BENCHMARK_CAPTURE(trainStep, mlp, Architecture::kMlp, FeatureSet::kModelFree)
    ->Args({1, 512})
    ->Args({2, 512})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

}  // namespace
}  // namespace quadfdi
