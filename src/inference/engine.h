// A LibTorch-free inference path for trained identifiers (issue 6). The detector evaluates four
// symmetry-mapped windows per sample, so it needs (a) speed at small batches and (b) estimates
// that do not depend on what else shares the batch — LibTorch gives neither (its GEMM kernels
// change the summation order with the batch size; measured in tests/networks). This engine runs
// lanes() windows in lock-step, one SIMD lane each, with a fixed per-lane summation order: a
// window's Θ̂ is bitwise the same alone or in any batch, on a given machine. Kernels for generic
// x86-64, AVX2 + FMA and AVX-512 are built in and the fastest the CPU runs is used.
#pragma once

#include <memory>
#include <vector>

#include "inference/kernel.h"
#include "inference/network_weights.h"

namespace quadfdi {

// Packed dense layer: rows in blocks of kRowBlock, each block stored column-major: w[block][k][row].
struct PackedDense {
  int in = 0, out = 0, blocks = 0;
  std::vector<float> w, b;
};
// Packs a layer for the kernels (rows in blocks of kRowBlock), its subnormal weights and biases as
// zero (engine.cpp says why). Throws std::invalid_argument on inconsistent shapes.
PackedDense packDense(const DenseWeights& d);

// The TCN as a stream (docs/networks.md): each of `streams` sequences (the four symmetry-mapped
// copies of one flight) is advanced one sample at a time, with ring buffers holding what each
// dilated layer still needs. Cost per sample is independent of the window length; after
// receptiveField() samples the output is exactly the windowed network's on the last T samples
// (same arithmetic in the same order: bitwise equal to InferenceEngine::predict).
class TcnStreamer {
 public:
  // setup: packs the weights and allocates every buffer; step() allocates nothing.
  TcnStreamer(const NetworkWeights& weights, int streams);
  TcnStreamer(const TcnStreamer&) = delete;
  TcnStreamer& operator=(const TcnStreamer&) = delete;

  void reset();  // forget the history of every stream
  // rows: streams × channels raw features of one sample → theta: streams × 4. Meaningful once
  // samples() ≥ receptiveField().
  void step(const float* rows, float* theta);
  long samples() const { return samples_; }
  int receptiveField() const { return receptive_field_; }
  int streams() const { return streams_; }
  int channels() const { return channels_; }
  const char* kernel() const { return kernel_name_; }

 private:
  struct Layer {
    PackedDense dense;  // taps flattened: input [x(t−(K−1)d); …; x(t)]
    int in = 0, kernel = 0, dilation = 0, ring = 0;  // ring: history length, a power of two
    std::vector<float> history;                       // [ring][streams][in]
  };
  const char* kernel_name_ = "";
  void (*dense_rows_)(const inference::DenseRowsArgs&) = nullptr;
  int streams_ = 0, channels_ = 0, receptive_field_ = 0;
  long samples_ = 0;
  std::vector<float> mean_, scale_;
  std::vector<Layer> layers_;
  std::vector<PackedDense> head_;
  std::vector<float> taps_, out_, head_a_, head_b_;  // scratch
};

class InferenceEngine {
 public:
  // setup: packs the weights, picks the kernel, allocates scratch. Throws std::invalid_argument.
  explicit InferenceEngine(const NetworkWeights& weights);
  InferenceEngine(const InferenceEngine&) = delete;  // the layer tables point into its own weights
  InferenceEngine& operator=(const InferenceEngine&) = delete;

  int lanes() const { return lanes_; }  // windows per pass: 8 (generic, AVX2) or 16 (AVX-512)
  const char* kernel() const { return kernel_name_; }
  int window() const { return window_; }
  int channels() const { return channels_; }
  // windows: count × T × channels raw features → theta: count × 4. No allocation.
  void predict(const float* windows, int count, float* theta);

 private:
  using Packed = PackedDense;
  void predictGroup(const float* windows, int count, float* theta);

  const char* kernel_name_ = "";
  int lanes_ = 8;
  void (*lstm_)(const inference::LstmArgs&) = nullptr;
  void (*dense_stack_)(const inference::DenseStackArgs&) = nullptr;
  void (*normalise_)(const float*, int, int, const float*, const float*, float*) = nullptr;
  Architecture architecture_;
  int window_, channels_, hidden_;
  std::vector<float> mean_, scale_;
  Packed gates_;
  std::vector<Packed> head_;
  static constexpr std::size_t kMaxLayers = 16;
  // head_ as the kernel's tables, built once at setup.
  std::vector<const float*> head_w_, head_b_;
  std::vector<int> head_in_, head_out_, head_blocks_;
  std::vector<float> z_, gate_out_, cell_, act_a_, act_b_;  // [rows][lanes] scratch
  std::vector<float> padded_;                               // a short group, padded to lanes windows
  std::unique_ptr<TcnStreamer> tcn_;                        // kTcn: windows run as streams
  std::vector<float> tcn_rows_, tcn_theta_;
};

}  // namespace quadfdi
