// Algorithm 1 (seed §III-C, docs/networks.md): fresh data every outer iteration, FIFO buffer, passes in
// minibatches with the hinge loss, Adam, and the stopping rule; checkpointed every iteration.
#pragma once

#include <atomic>
#include <functional>
#include <stdexcept>
#include <string>

#include "data/algorithm1.h"
#include "inference/weights_file.h"
#include "networks/model.h"

namespace quadfdi {

enum class LossKind { kNorm, kPerMotor };

// How minibatches are formed (docs/networks.md, "Dense training").
enum class TrainingMode {
  kWindows,    // the paper's: minibatches of windows, one label each (the output at the last sample)
  kSequences,  // causal networks (TCN) only: minibatches of whole trajectories, one label per
               // position k ≥ R − 1 (R the receptive field) — ≈ T + 1 labels for one forward pass
};
const char* toString(TrainingMode m);
bool parseTrainingMode(const std::string& text, TrainingMode& m);  // windows | sequences

struct TrainConfig {
  Algorithm1DataConfig data;     // rollout settings, scale (N₁, N_buf), Θ values, motors
  ModelMetadata model;           // architecture, features, output, symmetry, …
  LossKind loss = LossKind::kNorm;
  double epsilon = 0.01;         // hinge margin ε (seed eq. 4)
  double learning_rate = 5e-4;   // Adam (authors' code)
  double learning_rate_decay = 1.0;  // [-] per outer iteration: iteration j (0-based) runs at
                                     // learning_rate · decay^j; 1 = constant (the authors')
  double weight_decay = 1e-5;
  TrainingMode mode = TrainingMode::kWindows;
  int batch_size = 1024;         // windows per minibatch (paper: 50 000); kWindows
  int batch_trajectories = 32;   // trajectories per minibatch [trajectories]; kSequences
  int passes = 1;                // passes over the buffer per outer iteration (authors: 400)
  int max_minibatches = 0;       // cap per outer iteration (0 = no cap): keeps CPU scales bounded
  int min_iterations = 2;        // N_m: no stop before this many outer iterations
  int max_iterations = 10;       // N_M
  // Polyak averaging (Polyak & Juditsky 1992; "SWA", Izmailov et al. 2018): the model written is the
  // mean of the weights after each of the last this many outer iterations (0 = the last weights).
  // It removes the minibatch noise the final weights carry. The average lives in memory: a run
  // resumed inside the window averages the iterations it ran (TrainResult::averaged_iterations).
  int average_last = 0;          // [outer iterations]
  double stop_loss = 1e-3;       // stop when the iteration's mean loss is below this (after N_m)
  int heldout_initial_conditions = 20;  // held-out set: fresh scenarios, same Θ values
  std::uint64_t seed = 1;        // weights, shuffling; data uses data.rollout.seed
  std::string device = "cpu";    // cpu | cuda
  int threads = 0;               // torch intra-op threads (0 = all cores)
  std::string checkpoint_path;   // written after every outer iteration (atomic); empty = none
  bool resume = false;           // continue from checkpoint_path if it exists
  // Fine-tuning (docs/networks.md#fine-tuning): start from this finished model's weights and
  // normalisation instead of fresh ones (a resumed checkpoint still wins). Its network must be
  // the one `model` describes; the held-out set is scored once before the first iteration
  // (reported as iteration 0) so the run shows what it added.
  std::shared_ptr<const TrainedModel> start_from;
  std::string start_from_name;   // how the provenance names it (its path)
  std::string log_path;          // CSV, one row per outer iteration; empty = none
  const std::atomic<bool>* stop = nullptr;  // raised (by a signal handler): stop before the next
                                            // minibatch; the last iteration's checkpoint stays
};

// Thrown when `stop` was raised: the message says how far the checkpoint got.
class TrainingInterrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct IterationReport {
  int iteration = 0;        // 1-based, completed; 0: the starting model's score, before training
  double loss = 0.0;        // mean training loss over the iteration's minibatches (NaN at iteration 0)
  double heldout_loss = 0.0;
  double heldout_accuracy = 0.0;  // max_i |Θ̂_i − Θ_i| ≤ 0.05
  std::size_t buffer_windows = 0;
  double seconds = 0.0;     // since the start of this run
  double windows_per_second = 0.0;  // labelled outputs trained on per second (kSequences: positions)
  // Where this iteration's time went [s]: fresh data (and the normalisation, first iteration),
  // the minibatches (gathering, forward, backward, Adam), the held-out evaluation.
  double data_seconds = 0.0, train_seconds = 0.0, heldout_seconds = 0.0;
};

struct TrainResult {
  FaultIdentifier model;
  int iterations = 0;
  bool resumed = false;
  bool converged = false;  // stopped by the loss rule rather than N_M
  bool optimizer_state_reset = false;  // resumed, but the Adam state was missing or newer than the model
  int averaged_iterations = 0;   // iterations whose weights were averaged (0 or 1: the last weights as trained)
  double last_heldout_accuracy = 0.0;  // [-] the last iteration's own weights, before averaging
};

// Empty when valid, else a one-line description.
std::string validate(const TrainConfig& config);
// The part of validate() about config.start_from: empty when its network is the one config.model
// describes (architecture, features, output, window and dt, TCN shape or hidden size).
std::string startingModelProblem(const TrainConfig& config);

// Throws std::runtime_error with a one-line message on bad configuration, an unusable
// checkpoint, a missing CUDA device or a non-finite loss.
TrainResult train(const TrainConfig& config, const std::function<void(const IterationReport&)>& on_iteration = {},
                  const std::function<void(int done, int total)>& on_minibatch = {});

}  // namespace quadfdi
