// The one fault-estimation core (docs/decisions.md): Θ̂ for every motor from a window of samples.
// Motor k's effectiveness is the network's trained-motor output on g_k(window), where g_k is the
// symmetry element that sends motor k to the trained motor. Evaluation, the online detector, the
// benchmarks and the fuzz harness all go through this file; nothing else maps windows or reads
// the trained motor's output.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "core/types.h"
#include "inference/engine.h"
#include "inference/weights_file.h"
#include "symmetry/symmetry.h"

namespace quadfdi {

// Windowed estimation: any architecture, windows of T samples.
class MotorEstimator {
 public:
  // setup: checks the model (trained motor, features), builds the maps and the engine. `mode`
  // chooses the maps (normally the model's own metadata.symmetry). Throws std::invalid_argument.
  MotorEstimator(const TrainedModel& model, SymmetryMode mode);

  const ModelMetadata& metadata() const { return metadata_; }
  int window() const { return metadata_.window; }
  std::size_t featuresPerWindow() const { return per_window_; }  // T × channels floats, one map
  const char* kernel() const { return engine_->kernel(); }
  int preferredBatch() const { return engine_->lanes() / kMotors; }  // windows per engine pass, ×4 maps

  // The four mapped feature windows of T consecutive samples (outputs [T][6], inputs [T][4],
  // residuals [T][6] or null, body rates [T][3] or null; a model that reads rates refuses null)
  // → out: 4 × T × channels floats.
  void gather(const float* outputs, const float* inputs, const float* residuals, const float* rates, float* out) const;

  // `count` gathered windows (each 4 maps) → theta[count]; with `raw`, also the network's four
  // outputs for every (window, map): raw[i][k] (the paper's printed rule needs them). No allocation.
  void estimate(const float* features, int count, MotorTheta* theta, std::array<MotorTheta, kMotors>* raw = nullptr);

 private:
  ModelMetadata metadata_;
  std::array<SymmetryMap, kMotors> maps_{};
  std::size_t per_window_ = 0;
  std::unique_ptr<InferenceEngine> engine_;
  std::vector<float> out_;  // [windows × 4 maps][4]
};

// Streaming estimation (exact streaming networks: a TCN on model-free-heading or scale-free features): one
// sample in, Θ̂ out, at a cost independent of T. After T samples since reset() the estimate is
// the windowed MotorEstimator's on the last T samples, bit for bit.
class StreamingMotorEstimator {
 public:
  // setup; throws std::invalid_argument if the model cannot stream (see canStream).
  StreamingMotorEstimator(const TrainedModel& model, SymmetryMode mode);
  static bool canStream(const ModelMetadata& m);

  void reset();
  // One sample (y: position, Euler angles; u: commanded thrust; rates: body rates p, q, r [rad/s],
  // read by a model on scale-free-rates features). Returns true when `theta` holds an estimate (T
  // samples since reset). No allocation.
  bool push(const Output& y, const Input& u, const Vec3& rates, MotorTheta& theta);
  // The same for a model that reads no rates; throws std::logic_error for one that does.
  bool push(const Output& y, const Input& u, MotorTheta& theta);
  int window() const { return metadata_.window; }
  const char* kernel() const { return streamer_->kernel(); }

 private:
  ModelMetadata metadata_;
  bool reads_rates_ = false;  // featuresReadRates(metadata_.features), set once
  std::array<SymmetryMap, kMotors> maps_{};
  std::unique_ptr<TcnStreamer> streamer_;
  std::array<Output, kMotors> previous_{};
  std::array<Input, kMotors> previous_u_{};
  long samples_ = 0;
  std::array<float, kMotors * (kOutputDim + kInputDim + 1 + kRateDim)> rows_{};  // the widest streaming row (scale-free-rates)
  std::array<float, kMotors * 4> out_{};
};

}  // namespace quadfdi
