// The LibTorch modules behind FaultIdentifier. Included only by networks/*.cpp.
#pragma once

#include <torch/torch.h>

#include "networks/model.h"

namespace quadfdi {

// LSTM (seed §IV, authors' code): LSTM(n_in → H) → ReLU(last step) → 128→64 → ReLU → 64→4 → Sigmoid.
// MLP: flattened window (n_in·T) → H → three H×H → 64 → 4 → Sigmoid, ReLU between.
// TCN: causal dilated convolutions (ReLU, residual from layer 1) → last sample → C→64 → ReLU → 64→4 → Sigmoid.
struct FaultNetImpl : torch::nn::Module {
  explicit FaultNetImpl(const ModelMetadata& m);
  torch::Tensor forward(torch::Tensor windows);  // [B, T, n_in] raw features → [B, 4]
  // TCN only (dense training, docs/networks.md): [B, L, n_in] raw features of whole sequences →
  // [B, L − R + 1, 4], the output at every position k ≥ R − 1 (R the receptive field); position
  // k's is the windowed forward's on any window ending at k that holds its R samples.
  torch::Tensor forwardSequence(torch::Tensor sequences);

  torch::Tensor tcnColumns(const torch::Tensor& normalised);  // [B, L, n_in] → [B, C, L − R + 1]

  Architecture architecture;
  torch::Tensor mean, scale;  // buffers: normalisation (x − mean) / scale
  torch::nn::LSTM lstm{nullptr};
  torch::nn::Linear head1{nullptr}, head2{nullptr};
  torch::nn::Sequential mlp{nullptr};
  std::vector<torch::nn::Conv1d> convs;  // TCN
};
TORCH_MODULE(FaultNet);

struct FaultIdentifier::Impl {
  ModelMetadata metadata;
  FaultNet net{nullptr};
};

// Copies normalisation statistics from metadata into the network's buffers.
void loadNormalisation(FaultIdentifier::Impl& impl);

}  // namespace quadfdi
