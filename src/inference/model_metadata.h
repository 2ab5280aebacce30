// What a trained fault identifier is, independent of how it was trained: architecture, the
// features it reads, the symmetry it is used with, normalisation and provenance. Shared by the
// training library (LibTorch) and the LibTorch-free inference library. Reference:
// docs/networks.md, docs/weights-format.md.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "data/features.h"
#include "symmetry/symmetry.h"

namespace quadfdi {

enum class Architecture {
  kLstm,  // the paper's windowed LSTM: cost per window grows with T
  kMlp,   // the paper's MLP baseline
  kTcn,   // causal dilated convolutions: exact streaming, constant cost per sample (docs/networks.md)
};
const char* toString(Architecture a);
bool parseArchitecture(const std::string& text, Architecture& a);  // lstm | mlp | tcn

// Shape of a TCN (docs/networks.md): layer 0 maps the features to `channels`, every later layer
// is channels → channels with a residual connection; all have `kernel` taps.
struct TcnShape {
  int channels = 32;                            // [-] hidden channels
  int kernel = 3;                               // [taps]
  std::vector<int> dilations{1, 2, 4, 8, 16, 16};  // [samples] per layer; receptive field 1 + (kernel−1)·Σd = 95
  int receptiveField() const;                   // [samples]
};

// Everything needed to use a model without guessing.
struct ModelMetadata {
  Architecture architecture = Architecture::kLstm;
  FeatureSet features = FeatureSet::kModelFree;
  OutputKind output = OutputKind::kPositionEuler;
  SymmetryMode symmetry = SymmetryMode::kExactGroup;  // how other motors are mapped to the trained motor
  int trained_motor = 2;
  int window = 100;        // T [samples]
  double dt = 0.002;       // [s]
  int hidden = 128;        // LSTM hidden size / MLP width (TCN: head width is 64 as for the LSTM)
  TcnShape tcn;            // used when architecture == kTcn
  std::string params = "nominal";  // plant parameter set of the training data
  std::string controller = "lqr";
  // The randomisation of the training flights in its file form (io/randomisation_file.h,
  // docs/data.md#randomisation); empty: the fixed plant and controller above.
  std::string randomisation;
  // Per-channel normalisation, applied inside the network: (x − mean) / std.
  std::vector<float> feature_mean, feature_std;
  // Provenance.
  std::string command;            // how it was trained
  // Fine-tuned models: the model whose weights and normalisation training started from, and its
  // own provenance in brief; empty when trained from fresh weights. `iterations` and
  // `training_seconds` count this run only.
  std::string started_from;
  std::string scale;
  std::uint64_t seed = 0;
  int iterations = 0;             // outer iterations run
  double training_seconds = 0.0;
  double final_loss = 0.0;
  double heldout_loss = 0.0;
  double heldout_accuracy = 0.0;  // fraction of held-out windows with max_i |Θ̂_i − Θ_i| ≤ 0.05
  std::string generator = "quadfdi 0.2.0";

  int channels() const { return featureChannels(features); }
};

// "FILE: problem" for unreadable, foreign, truncated or inconsistent model files.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Metadata as JSON text and back. Parsing checks types, ranges and consistency (feature
// statistics against the feature set, TCN receptive field against T) and throws
// ModelError("WHERE: problem").
std::string metadataToJson(const ModelMetadata& m);
ModelMetadata metadataFromJson(const std::string& json, const std::string& where);

}  // namespace quadfdi
