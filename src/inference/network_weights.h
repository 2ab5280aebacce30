// Plain weights of a trained identifier (row-major, PyTorch's conventions): what the training
// library exports and the weights file stores, and all the inference engine needs.
#pragma once

#include <vector>

#include "inference/model_metadata.h"

namespace quadfdi {

struct DenseWeights {
  int in = 0, out = 0;
  std::vector<float> weight;  // out × in
  std::vector<float> bias;    // out
};

// A causal dilated 1-D convolution (PyTorch Conv1d, no padding): out[t] = b + Σ_j W[:, :, j]·x[t − (K−1−j)·d].
struct ConvWeights {
  int in = 0, out = 0, kernel = 0, dilation = 0;
  std::vector<float> weight;  // out × in × kernel
  std::vector<float> bias;    // out
};

struct NetworkWeights {
  Architecture architecture = Architecture::kLstm;
  int window = 0;    // T [samples]
  int channels = 0;  // n_in
  int hidden = 0;    // H (LSTM)
  std::vector<float> mean, scale;  // normalisation (x − mean) / scale, per channel
  // LSTM: gate pre-activations of z = [x; h] (4H × (n_in + H), gate order i, f, g, o; bias b_ih + b_hh),
  // then the head (relu(h_T) → H→64 → ReLU → 64→4 → sigmoid). MLP: the layers, ReLU between,
  // sigmoid last. TCN: `convs` (ReLU after each, residual from layer 1 on), then the head on the
  // last sample's channels.
  DenseWeights gates;
  std::vector<ConvWeights> convs;
  std::vector<DenseWeights> head;
};

}  // namespace quadfdi
