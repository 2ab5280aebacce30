// A LibTorch-free inference path for trained identifiers (issue 6). The detector evaluates four
// symmetry-mapped windows per sample, so it needs (a) speed at small batches and (b) estimates
// that do not depend on what else shares the batch — LibTorch gives neither (its GEMM kernels
// change the summation order with the batch size; measured in tests/networks). This engine runs
// lanes() windows in lock-step, one SIMD lane each, with a fixed per-lane summation order: a
// window's Θ̂ is bitwise the same alone or in any batch, on a given machine. Kernels for generic
// x86-64, AVX2 + FMA and AVX-512 are built in and the fastest the CPU runs is used.
#pragma once

#include <vector>

#include "networks/inference_kernel.h"
#include "networks/model.h"

namespace quadfdi {

// Plain weights of a trained identifier (row-major, PyTorch's conventions), exported once from
// the LibTorch module by exportWeights (networks/model.cpp).
struct DenseWeights {
  int in = 0, out = 0;
  std::vector<float> weight;  // out × in
  std::vector<float> bias;    // out
};
struct NetworkWeights {
  Architecture architecture = Architecture::kLstm;
  int window = 0;    // T [samples]
  int channels = 0;  // n_in
  int hidden = 0;    // H
  std::vector<float> mean, scale;  // normalisation (x − mean) / scale, per channel
  // LSTM: gate pre-activations of z = [x; h] (4H × (n_in + H), gate order i, f, g, o; bias b_ih + b_hh),
  // then the head (relu(h_T) → H→64 → ReLU → 64→4 → sigmoid). MLP: the layers, ReLU between, sigmoid last.
  DenseWeights gates;
  std::vector<DenseWeights> head;
};
NetworkWeights exportWeights(const FaultIdentifier& model);

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
  struct Packed {  // rows in blocks of kRowBlock, each block stored column-major: w[block][k][row]
    int in = 0, out = 0, blocks = 0;
    std::vector<float> w, b;
  };
  static Packed pack(const DenseWeights& d);
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
};

}  // namespace quadfdi
