// Trainable fault identifiers (docs/networks.md): LSTM, MLP and TCN networks in LibTorch that
// read a window and output the four motor effectivenesses Θ̂ ∈ [0, 1]⁴. The training library's
// own archive (save/load) holds checkpoints; a finished model leaves it as plain weights
// (exportWeights → inference/weights_file.h), which the LibTorch-free inference library runs.
// This header is free of LibTorch (pimpl).
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "inference/model_metadata.h"
#include "inference/network_weights.h"

namespace quadfdi {

inline constexpr const char* kModelFormat = "quadfdi-model";  // the LibTorch archive (checkpoints, format 1 models)
inline constexpr int kModelVersion = 1;

class FaultIdentifier {
 public:
  // Fresh network with weights from `seed` (normalisation from metadata, identity if empty).
  static FaultIdentifier create(const ModelMetadata& metadata, std::uint64_t seed);
  static FaultIdentifier load(const std::string& path);  // throws ModelError
  void save(const std::string& path) const;               // atomic; throws ModelError

  const ModelMetadata& metadata() const;
  ModelMetadata& metadata();

  // windows: count × T × channels raw features (gatherWindowFeatures) → theta: count × 4.
  // Runs without gradients, in chunks, on the CPU.
  void predict(const float* windows, int count, float* theta) const;
  // TCN only (dense training, docs/networks.md): sequences: count × length × channels raw
  // features → theta: count × (length − R + 1) × 4, the output at every position k ≥ R − 1 (R the
  // receptive field), which is the windowed output of any window ending at k. No gradients, CPU.
  void predictSequences(const float* sequences, int count, int length, float* theta) const;

  struct Impl;
  std::shared_ptr<Impl> impl() const { return impl_; }

 private:
  explicit FaultIdentifier(std::shared_ptr<Impl> impl);
  std::shared_ptr<Impl> impl_;
};

// LibTorch intra-op threads (0 = all cores); OpenBLAS's own pool is pinned to one thread so the
// two do not oversubscribe the cores (measured: 2 torch threads over an OpenBLAS pool ran 2×
// slower than one thread). Subnormal floats are flushed to zero on this thread and the threads it
// starts later (x86 FTZ/DAZ): training's weight decay leaves weights there, and each operation on
// one costs an Intel core a microcode assist — fine-tuning the general model ran 2.4× slower for it
// (docs/benchmarks.md, "Subnormal numbers").
void configureCpu(int threads);
bool cudaAvailable();

// The network's weights in the plain form the inference engine and the weights file use.
NetworkWeights exportWeights(const FaultIdentifier& model);
// The inverse: a trainable network holding `weights` (normalisation included), for fine-tuning a
// finished model. Throws ModelError when a tensor's shape does not match `metadata`'s network.
// (An LSTM's two bias vectors come back as their sum and zero: the same network.)
FaultIdentifier importWeights(const ModelMetadata& metadata, const NetworkWeights& weights);

}  // namespace quadfdi
