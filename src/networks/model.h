// Fault identifiers (SPEC §6): LSTM and MLP networks that read a window and output the four
// motor effectivenesses Θ̂ ∈ [0, 1]⁴. This header is free of LibTorch (pimpl), so only the
// networks' own .cpp files pay for its headers.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "data/features.h"
#include "symmetry/symmetry.h"

namespace quadfdi {

enum class Architecture { kLstm, kMlp };
const char* toString(Architecture a);
bool parseArchitecture(const std::string& text, Architecture& a);  // lstm | mlp

inline constexpr const char* kModelFormat = "quadfdi-model";
inline constexpr int kModelVersion = 1;

// Everything needed to use a model file without guessing (SPEC §6).
struct ModelMetadata {
  Architecture architecture = Architecture::kLstm;
  FeatureSet features = FeatureSet::kModelFree;
  OutputKind output = OutputKind::kPositionEuler;
  SymmetryMode symmetry = SymmetryMode::kExactGroup;  // how other motors are mapped to motor 2
  int trained_motor = 2;
  int window = 100;        // T [samples]
  double dt = 0.002;       // [s]
  int hidden = 128;        // LSTM hidden size / MLP width
  std::string params = "nominal";  // plant parameter set of the training data
  std::string controller = "lqr";
  // Per-channel normalisation, applied inside the network: (x − mean) / std.
  std::vector<float> feature_mean, feature_std;
  // Provenance.
  std::string command;            // how it was trained
  std::string scale;
  std::uint64_t seed = 0;
  int iterations = 0;             // outer iterations run
  double training_seconds = 0.0;
  double final_loss = 0.0;
  double heldout_loss = 0.0;
  double heldout_accuracy = 0.0;  // fraction of held-out windows with max_i |Θ̂_i − Θ_i| ≤ 0.05
  std::string generator = "quadfdi 0.1.0";

  int channels() const { return featureChannels(features); }
};

// "FILE: problem" for unreadable, foreign, truncated or inconsistent model files.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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

  struct Impl;
  std::shared_ptr<Impl> impl() const { return impl_; }

 private:
  explicit FaultIdentifier(std::shared_ptr<Impl> impl);
  std::shared_ptr<Impl> impl_;
};

// LibTorch intra-op threads (0 = all cores); OpenBLAS's own pool is pinned to one thread so the
// two do not oversubscribe the cores (measured: 2 torch threads over an OpenBLAS pool ran 2×
// slower than one thread).
void configureCpuThreads(int threads);
bool cudaAvailable();

}  // namespace quadfdi
