#include "networks/trainer.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "networks/torch_net.h"

namespace quadfdi {
namespace {

constexpr double kIdentificationTolerance = 0.05;  // docs/decisions.md: |Θ̂ − Θ| ≤ 0.05
constexpr std::uint64_t kHeldoutFirstScenario = 1ull << 40;  // disjoint from training streams

struct Minibatch {
  std::vector<float> features;
  std::vector<float> labels;
  std::vector<float> mask;  // kSequences: 1 where the position is labelled, else 0
};

// Features and labels of `n` windows, window i given by at(i) as (batch, ref).
template <typename At>
void gather(std::size_t n, const At& at, const ModelMetadata& m, Minibatch& out) {
  const std::size_t per = static_cast<std::size_t>(m.window) * static_cast<std::size_t>(m.channels());
  out.features.resize(n * per);
  out.labels.resize(n * 4);
  for (std::size_t i = 0; i < n; ++i) {
    const auto [batch, ref] = at(i);
    gatherWindowFeatures(*batch, ref, m.window, m.features, m.output, nullptr, &out.features[i * per]);
    const Input label = windowLabel(*batch, ref);
    for (int j = 0; j < 4; ++j) out.labels[i * 4 + static_cast<std::size_t>(j)] = static_cast<float>(label(j));
  }
}

// Dense training (docs/networks.md): features of `n` whole trajectories, trajectory i given by
// at(i), and the labels and mask of their positions k = R − 1 … samples − 1 (positionLabels).
template <typename At>
void gatherSequences(std::size_t n, const At& at, const ModelMetadata& m, Minibatch& out) {
  const int first = m.tcn.receptiveField() - 1;
  const auto* probe = at(0).batch;
  const int samples = probe->samples, positions = samples - first;
  const std::size_t per = static_cast<std::size_t>(samples) * static_cast<std::size_t>(m.channels());
  out.features.resize(n * per);
  out.labels.resize(n * static_cast<std::size_t>(positions) * 4);
  out.mask.resize(n * static_cast<std::size_t>(positions));
  for (std::size_t i = 0; i < n; ++i) {
    const auto [batch, index] = at(i);
    gatherWindowFeatures(*batch, {index, samples - 1}, samples, m.features, m.output, nullptr, &out.features[i * per]);
    const std::size_t row = i * static_cast<std::size_t>(positions);
    positionLabels(*batch, index, first, &out.labels[row * 4], &out.mask[row]);
  }
}

torch::Tensor hingeLoss(const torch::Tensor& pred, const torch::Tensor& target, LossKind kind, double eps) {
  if (kind == LossKind::kNorm) return torch::relu((pred - target).norm(2, 1) - eps).mean();
  return torch::relu((pred - target).abs() - eps).mean();
}

// The same per labelled position: pred, target [B, P, 4], mask [B, P]; the mean over the
// positions the mask keeps.
torch::Tensor maskedHingeLoss(const torch::Tensor& pred, const torch::Tensor& target, const torch::Tensor& mask,
                              LossKind kind, double eps) {
  const torch::Tensor per_position = kind == LossKind::kNorm ? torch::relu((pred - target).norm(2, 2) - eps)
                                                             : torch::relu((pred - target).abs() - eps).mean(2);
  return (per_position * mask).sum() / mask.sum().clamp_min(1.0);
}

// Per-channel mean and standard deviation over (up to 20 000) buffer windows.
void computeNormalisation(const WindowBuffer& buffer, ModelMetadata& m) {
  const int c = m.channels();
  const std::size_t n = std::min<std::size_t>(buffer.size(), 20000);
  const std::size_t stride = std::max<std::size_t>(1, buffer.size() / std::max<std::size_t>(n, 1));
  std::vector<double> sum(static_cast<std::size_t>(c), 0.0), sq(static_cast<std::size_t>(c), 0.0);
  std::vector<float> w(static_cast<std::size_t>(m.window * c));
  std::size_t count = 0;
  for (std::size_t i = 0; i < buffer.size() && count < n; i += stride, ++count) {
    const auto e = buffer.at(i);
    gatherWindowFeatures(*e.batch, e.ref, m.window, m.features, m.output, nullptr, w.data());
    for (int k = 0; k < m.window; ++k)
      for (int j = 0; j < c; ++j) {
        const double v = w[static_cast<std::size_t>(k * c + j)];
        sum[static_cast<std::size_t>(j)] += v;
        sq[static_cast<std::size_t>(j)] += v * v;
      }
  }
  const double samples = static_cast<double>(count) * m.window;
  m.feature_mean.assign(static_cast<std::size_t>(c), 0.0f);
  m.feature_std.assign(static_cast<std::size_t>(c), 1.0f);
  for (std::size_t j = 0; j < static_cast<std::size_t>(c); ++j) {
    const double mu = sum[j] / samples;
    const double var = std::max(0.0, sq[j] / samples - mu * mu);
    m.feature_mean[j] = static_cast<float>(mu);
    // Channels that never vary (e.g. residuals identically zero) keep unit scale.
    m.feature_std[j] = static_cast<float>(std::sqrt(var) > 1e-12 ? std::sqrt(var) : 1.0);
  }
}

void writeCheckpoint(const std::string& path, FaultIdentifier& model, torch::optim::Adam& optimizer, int iteration) {
  const std::string temp = path + ".tmp." + std::to_string(::getpid());
  model.metadata().iterations = iteration;
  model.save(temp + ".model");
  try {
    torch::serialize::OutputArchive archive;
    optimizer.save(archive);
    archive.write("iteration", torch::tensor(static_cast<std::int64_t>(iteration)));
    archive.save_to(temp + ".optim");
  } catch (const c10::Error&) {
    throw std::runtime_error(path + ": cannot write the checkpoint");
  }
  // Two files, renamed model last: a present ".model" always has its ".optim" beside it.
  if (std::rename((temp + ".optim").c_str(), (path + ".optim").c_str()) != 0 ||
      std::rename((temp + ".model").c_str(), path.c_str()) != 0)
    throw std::runtime_error(path + ": cannot replace the checkpoint");
}

}  // namespace

const char* toString(TrainingMode m) { return m == TrainingMode::kSequences ? "sequences" : "windows"; }

bool parseTrainingMode(const std::string& text, TrainingMode& m) {
  if (text == "windows") { m = TrainingMode::kWindows; return true; }
  if (text == "sequences") { m = TrainingMode::kSequences; return true; }
  return false;
}

std::string startingModelProblem(const TrainConfig& c) {
  if (!c.start_from) return {};
  const ModelMetadata& s = c.start_from->metadata;
  const std::string prefix = "the starting model's ";
  if (s.architecture != c.model.architecture)
    return prefix + "architecture is " + toString(s.architecture) + ", this training's " + toString(c.model.architecture);
  if (s.features != c.model.features)
    return prefix + "features are " + toString(s.features) + ", this training's " + toString(c.model.features);
  if (s.output != c.data.rollout.output) return prefix + "measured output differs from this training's";
  if (s.window != c.model.window || std::abs(s.dt - c.data.rollout.dt) > 1e-12)
    return prefix + "window (" + std::to_string(s.window) + " samples of " + std::to_string(s.dt) +
           " s) differs from this training's (" + std::to_string(c.model.window) + " of " +
           std::to_string(c.data.rollout.dt) + " s)";
  if (s.architecture == Architecture::kTcn && (s.tcn.channels != c.model.tcn.channels ||
                                               s.tcn.kernel != c.model.tcn.kernel ||
                                               s.tcn.dilations != c.model.tcn.dilations))
    return prefix + "TCN has " + std::to_string(s.tcn.channels) + " channels, kernel " +
           std::to_string(s.tcn.kernel) + " and " + std::to_string(s.tcn.dilations.size()) +
           " layers; this training's " + std::to_string(c.model.tcn.channels) + ", " +
           std::to_string(c.model.tcn.kernel) + " and " + std::to_string(c.model.tcn.dilations.size());
  if (s.architecture != Architecture::kTcn && s.hidden != c.model.hidden)
    return prefix + "hidden size is " + std::to_string(s.hidden) + ", this training's " + std::to_string(c.model.hidden);
  return {};
}

std::string validate(const TrainConfig& c) {
  if (const std::string e = validate(c.data.rollout); !e.empty()) return e;
  if (c.data.scale.initial_conditions < 1 || c.data.scale.buffer_windows < 1) return "scale needs N1 >= 1 and N_buf >= 1";
  if (c.data.thetas.empty() || c.data.motors.empty()) return "need at least one theta and one motor";
  if (c.batch_size < 1 || c.batch_trajectories < 1) return "batch size must be >= 1";
  if (c.mode == TrainingMode::kSequences && c.model.architecture != Architecture::kTcn)
    return "sequence training needs a causal network (tcn): an LSTM or MLP output depends on the window's start";
  if (c.passes < 1) return "passes must be >= 1";
  if (c.max_minibatches < 0) return "max minibatches must be >= 0";
  if (c.min_iterations < 0 || c.max_iterations < 1 || c.min_iterations > c.max_iterations)
    return "need 0 <= min iterations <= max iterations, max >= 1";
  if (c.average_last < 0 || c.average_last > c.max_iterations)
    return "the iterations averaged must lie in 0 … max iterations";
  if (!(c.learning_rate > 0.0) || !std::isfinite(c.learning_rate) || !(c.weight_decay >= 0.0) ||
      !std::isfinite(c.weight_decay) || !(c.epsilon >= 0.0) || !std::isfinite(c.epsilon) ||
      !(c.learning_rate_decay > 0.0 && c.learning_rate_decay <= 1.0))
    return "bad optimiser settings (learning rate > 0, weight decay and epsilon >= 0, all finite; decay in (0, 1])";
  if (c.device != "cpu" && c.device != "cuda") return "device must be cpu or cuda";
  if (c.model.window != c.data.rollout.window) return "model window must equal the data window";
  return startingModelProblem(c);
}

namespace {

// ---- The steps of train(), in the order it takes them. ----

torch::Device trainingDevice(const TrainConfig& config) {
  if (config.device == "cuda" && !torch::cuda::is_available())
    throw std::runtime_error("--device cuda: no CUDA device (this LibTorch build or machine has none)");
  return torch::Device(config.device == "cuda" ? torch::kCUDA : torch::kCPU);
}

// A fresh model (its weights drawn from config.seed, or config.start_from's), replaced by the
// checkpoint's when resuming.
TrainResult createOrResumeModel(const TrainConfig& config) {
  TrainResult result{config.start_from ? importWeights(config.model, config.start_from->weights)
                                       : FaultIdentifier::create(config.model, config.seed)};
  ModelMetadata& m = result.model.metadata();
  if (config.start_from) {
    const ModelMetadata& s = config.start_from->metadata;
    char brief[160];
    std::snprintf(brief, sizeof brief, " (%d iterations, %.0f s, held-out accuracy %.3f)", s.iterations,
                  s.training_seconds, s.heldout_accuracy);
    m.started_from = (config.start_from_name.empty() ? std::string("a model") : config.start_from_name) + brief;
  }
  m.output = config.data.rollout.output;
  m.window = config.data.rollout.window;
  m.dt = config.data.rollout.dt;
  m.trained_motor = config.data.motors.size() == 1 ? config.data.motors.front() : 2;
  m.seed = config.seed;
  m.scale = config.data.scale.name;

  const bool have_checkpoint = !config.checkpoint_path.empty() && access(config.checkpoint_path.c_str(), R_OK) == 0;
  if (!config.resume || !have_checkpoint) return result;
  FaultIdentifier loaded = FaultIdentifier::load(config.checkpoint_path);
  const ModelMetadata& lm = loaded.metadata();
  if (lm.architecture != config.model.architecture || lm.features != config.model.features ||
      lm.window != config.model.window || lm.hidden != config.model.hidden)
    throw std::runtime_error(config.checkpoint_path + ": checkpoint is for a different model configuration");
  result.model = loaded;
  result.resumed = true;
  return result;
}

// Loads the Adam moments saved with the checkpoint of `iteration`; false when they are missing or
// belong to another iteration. (The optimiser state is renamed into place just before the model;
// a kill between the two renames leaves it one iteration ahead: Adam then restarts, reported.)
bool restoreOptimizer(const std::string& checkpoint_path, int iteration, torch::optim::Adam& optimizer) {
  try {
    torch::serialize::InputArchive archive;
    archive.load_from(checkpoint_path + ".optim");
    torch::Tensor saved_iteration;
    archive.read("iteration", saved_iteration);
    if (saved_iteration.item<std::int64_t>() != iteration) return false;
    optimizer.load(archive);
    return true;
  } catch (const c10::Error&) {
    return false;
  }
}

// Fresh scenarios from a stream range disjoint from training's, generated once per run.
struct HeldoutSet {
  TrajectoryBatch batch;
  std::vector<WindowRef> windows;  // grouped by trajectory, in order (enumerateWindows)
};

HeldoutSet makeHeldoutSet(const TrainConfig& config) {
  HeldoutSet set;
  RolloutEngine engine(config.data.rollout);
  engine.run(algorithm1Jobs(kHeldoutFirstScenario, config.heldout_initial_conditions, config.data.thetas,
                            config.data.motors),
             config.data.threads, set.batch);
  enumerateWindows(set.batch, config.data.rollout.window, set.windows);
  return set;
}

// The CSV log, one row per outer iteration. A resumed run keeps the rows its checkpoint covers.
class TrainingLog {
 public:
  TrainingLog(const std::string& path, bool resumed, int start_iteration) {
    if (path.empty()) return;
    std::vector<std::string> kept;
    if (resumed) {
      std::ifstream old(path);
      std::string line;
      while (std::getline(old, line)) {
        if (kept.empty()) { kept.push_back(line); continue; }
        if (std::atoi(line.c_str()) <= start_iteration) kept.push_back(line);
      }
    }
    file_.open(path, std::ios::trunc);
    if (!file_) throw std::runtime_error(path + ": cannot write the training log");
    if (kept.empty()) kept.push_back("iteration,loss,heldout_loss,heldout_accuracy,buffer_windows,seconds,windows_per_second");
    for (const auto& l : kept) file_ << l << '\n';
    file_.flush();
  }
  void append(const IterationReport& r) {
    if (!file_.is_open()) return;
    file_ << r.iteration << ',' << r.loss << ',' << r.heldout_loss << ',' << r.heldout_accuracy << ','
          << r.buffer_windows << ',' << r.seconds << ',' << r.windows_per_second << '\n';
    file_.flush();
  }

 private:
  std::ofstream file_;
};

// Throws TrainingInterrupted, saying what the checkpoint holds, once config.stop is raised.
void throwIfStopRequested(const TrainConfig& config, int completed_iterations) {
  if (!config.stop || !config.stop->load(std::memory_order_relaxed)) return;
  throw TrainingInterrupted(
      "training stopped during outer iteration " + std::to_string(completed_iterations + 1) + "; " +
      (config.checkpoint_path.empty() || completed_iterations == 0
           ? std::string("no iteration was complete, nothing was saved")
           : config.checkpoint_path + " holds the " + std::to_string(completed_iterations) +
                 " completed iterations: run again with --resume to continue"));
}

// Features and labels of one minibatch as tensors on `device` (they view `mb`'s storage first).
std::pair<torch::Tensor, torch::Tensor> toTensors(Minibatch& mb, std::size_t count, const ModelMetadata& meta,
                                                  const torch::Device& device) {
  const auto b = static_cast<std::int64_t>(count);
  return {torch::from_blob(mb.features.data(), {b, meta.window, meta.channels()}, torch::kFloat32).to(device),
          torch::from_blob(mb.labels.data(), {b, 4}, torch::kFloat32).to(device)};
}

// One minibatch's backward pass and Adam step on its loss; returns the loss value.
double optimiserStep(const torch::Tensor& loss, torch::optim::Adam& optimizer, int completed) {
  const double value = loss.item<double>();
  if (!std::isfinite(value))
    throw std::runtime_error("training diverged: non-finite loss at outer iteration " + std::to_string(completed + 1) +
                             " (lower the learning rate?)");
  loss.backward();
  optimizer.step();
  return value;
}

struct PassesOutcome {
  double loss_sum = 0.0;          // over the minibatches
  int minibatches = 0;
  std::int64_t windows = 0;       // windows trained on
};

// The shuffled schedule both training modes share: config.passes passes over `order` (reshuffled
// by Fisher–Yates each pass, from a stream fixed by the iteration), in minibatches of `batch`
// items, stopping at config.max_minibatches when it is set. `step(first, count)` trains one
// minibatch on order[first … first + count) and returns its loss and trained windows.
template <typename Item, typename Step>
PassesOutcome shuffledPasses(const TrainConfig& config, int completed, std::vector<Item>& order, std::size_t batch,
                             const std::function<void(int, int)>& on_minibatch, Step&& step) {
  const std::size_t n = order.size();
  Rng shuffle_rng(config.seed, 0x5000000ull + static_cast<std::uint64_t>(completed));
  const int per_pass = static_cast<int>((n + batch - 1) / batch);
  int total = per_pass * config.passes;
  if (config.max_minibatches > 0) total = std::min(total, config.max_minibatches);
  PassesOutcome out;
  for (int pass = 0; pass < config.passes && out.minibatches < total; ++pass) {
    for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[shuffle_rng.next() % i]);  // Fisher–Yates
    for (std::size_t first = 0; first < n && out.minibatches < total; first += batch) {
      throwIfStopRequested(config, completed);
      const auto [loss, windows] = step(first, std::min(batch, n - first));
      out.loss_sum += loss;
      out.windows += windows;
      ++out.minibatches;
      if (on_minibatch) on_minibatch(out.minibatches, total);
    }
  }
  return out;
}

// One outer iteration's optimisation: config.passes shuffled passes over the buffer in
// minibatches (at most config.max_minibatches), one Adam step each. `completed` outer
// iterations precede this one; it seeds the shuffle.
PassesOutcome trainOnBuffer(const TrainConfig& config, const WindowBuffer& buffer, int completed,
                            FaultIdentifier::Impl& impl, torch::optim::Adam& optimizer, const torch::Device& device,
                            Minibatch& mb, const std::function<void(int, int)>& on_minibatch) {
  const ModelMetadata& meta = impl.metadata;
  impl.net->train();
  std::vector<std::size_t> order(buffer.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  return shuffledPasses(config, completed, order, static_cast<std::size_t>(config.batch_size), on_minibatch,
                        [&](std::size_t first, std::size_t count) {
                          gather(count, [&](std::size_t i) {
                            const auto e = buffer.at(order[first + i]);
                            return std::make_pair(e.batch, e.ref);
                          }, meta, mb);
                          const auto [x, y] = toTensors(mb, count, meta, device);
                          optimizer.zero_grad();
                          const double loss =
                              optimiserStep(hingeLoss(impl.net->forward(x), y, config.loss, config.epsilon), optimizer, completed);
                          return std::make_pair(loss, static_cast<std::int64_t>(count));
                        });
}

// kSequences: as trainOnBuffer, but over the buffer's trajectories, config.batch_trajectories a
// minibatch, every labelled position of each (docs/networks.md, "Dense training").
PassesOutcome trainOnSequences(const TrainConfig& config, const WindowBuffer& buffer, int completed,
                               FaultIdentifier::Impl& impl, torch::optim::Adam& optimizer, const torch::Device& device,
                               Minibatch& mb, const std::function<void(int, int)>& on_minibatch) {
  const ModelMetadata& meta = impl.metadata;
  impl.net->train();
  std::vector<WindowBuffer::Trajectory> order;
  buffer.trajectories(order);
  return shuffledPasses(config, completed, order, static_cast<std::size_t>(config.batch_trajectories), on_minibatch,
                        [&](std::size_t first, std::size_t count) {
                          gatherSequences(count, [&](std::size_t i) { return order[first + i]; }, meta, mb);
                          const auto b = static_cast<std::int64_t>(count);
                          const std::int64_t samples = static_cast<std::int64_t>(mb.features.size()) / (b * meta.channels());
                          const std::int64_t positions = static_cast<std::int64_t>(mb.mask.size()) / b;
                          const torch::Tensor x = torch::from_blob(mb.features.data(), {b, samples, meta.channels()}).to(device);
                          const torch::Tensor y = torch::from_blob(mb.labels.data(), {b, positions, 4}).to(device);
                          const torch::Tensor mask = torch::from_blob(mb.mask.data(), {b, positions}).to(device);
                          optimizer.zero_grad();
                          const double loss = optimiserStep(
                              maskedHingeLoss(impl.net->forwardSequence(x), y, mask, config.loss, config.epsilon), optimizer, completed);
                          std::int64_t windows = 0;
                          for (float v : mb.mask) windows += v > 0.0f ? 1 : 0;
                          return std::make_pair(loss, windows);
                        });
}

struct HeldoutScore {
  double loss = 0.0;      // mean over the windows
  double accuracy = 0.0;  // fraction with max_i |Θ̂_i − Θ_i| ≤ kIdentificationTolerance
};

// Sums over the held-out windows → their means (zeros for an empty set).
HeldoutScore meanScore(double loss_sum, int correct, std::size_t windows) {
  HeldoutScore score;
  if (windows == 0) return score;
  const auto n = static_cast<double>(windows);
  score.loss = loss_sum / n;
  score.accuracy = static_cast<double>(correct) / n;
  return score;
}

HeldoutScore evaluateHeldout(const TrainConfig& config, const HeldoutSet& heldout, FaultIdentifier::Impl& impl,
                             const torch::Device& device, Minibatch& mb) {
  const ModelMetadata& meta = impl.metadata;
  impl.net->eval();
  double loss_sum = 0.0;
  int correct = 0;
  {
    torch::NoGradGuard no_grad;
    for (std::size_t first = 0; first < heldout.windows.size(); first += 4096) {
      const std::size_t count = std::min<std::size_t>(4096, heldout.windows.size() - first);
      gather(count, [&](std::size_t i) { return std::make_pair(&heldout.batch, heldout.windows[first + i]); }, meta,
             mb);
      const auto [x, y] = toTensors(mb, count, meta, device);
      const torch::Tensor pred = impl.net->forward(x);
      loss_sum += hingeLoss(pred, y, config.loss, config.epsilon).item<double>() * static_cast<double>(count);
      correct += ((pred - y).abs().amax(1) <= kIdentificationTolerance).sum().item<int>();
    }
  }
  return meanScore(loss_sum, correct, heldout.windows.size());
}

// kSequences: the same windows and the same numbers (to float round-off), from one forward pass
// per held-out trajectory: the output at position k is the window ending at k's (k ≥ T − 1 ≥ R − 1).
HeldoutScore evaluateHeldoutDense(const TrainConfig& config, const HeldoutSet& heldout, FaultIdentifier::Impl& impl,
                                  const torch::Device& device, Minibatch& mb) {
  const ModelMetadata& meta = impl.metadata;
  const int first_position = meta.tcn.receptiveField() - 1;
  impl.net->eval();
  torch::NoGradGuard no_grad;
  double loss_sum = 0.0;
  int correct = 0;
  constexpr int kChunk = 64;  // trajectories per forward pass
  std::size_t w = 0;          // next held-out window (grouped by trajectory, in order)
  for (int first = 0; first < heldout.batch.count; first += kChunk) {
    const int count = std::min(kChunk, heldout.batch.count - first);
    gatherSequences(static_cast<std::size_t>(count),
                    [&](std::size_t i) { return WindowBuffer::Trajectory{&heldout.batch, first + static_cast<int>(i)}; },
                    meta, mb);
    const torch::Tensor x =
        torch::from_blob(mb.features.data(), {count, heldout.batch.samples, meta.channels()}).to(device);
    const torch::Tensor pred = impl.net->forwardSequence(x).to(torch::kCPU).contiguous();  // [count, P, 4]
    const std::int64_t positions = pred.size(1);
    const float* p = pred.data_ptr<float>();
    for (; w < heldout.windows.size() && heldout.windows[w].trajectory < first + count; ++w) {
      const WindowRef& ref = heldout.windows[w];
      const float* o = p + ((ref.trajectory - first) * positions + (ref.end_sample - first_position)) * 4;
      const Input label = windowLabel(heldout.batch, ref);
      double norm2 = 0.0, per_motor = 0.0, worst = 0.0;
      for (int j = 0; j < 4; ++j) {
        const double e = std::abs(static_cast<double>(o[j]) - static_cast<double>(static_cast<float>(label(j))));
        norm2 += e * e;
        per_motor += std::max(0.0, e - config.epsilon) / 4.0;
        worst = std::max(worst, e);
      }
      loss_sum += config.loss == LossKind::kNorm ? std::max(0.0, std::sqrt(norm2) - config.epsilon) : per_motor;
      correct += worst <= kIdentificationTolerance ? 1 : 0;
    }
  }
  return meanScore(loss_sum, correct, heldout.windows.size());
}

// Writes the checkpoint from the CPU (LibTorch archives), then moves the net back to `device`.
void checkpoint(const std::string& path, FaultIdentifier& model, torch::optim::Adam& optimizer, int iteration,
                const torch::Device& device) {
  FaultIdentifier::Impl& impl = *model.impl();
  impl.net->to(torch::kCPU);
  writeCheckpoint(path, model, optimizer, iteration);
  impl.net->to(device);
}

// Algorithm 1's stopping rule (N_M is the loop's bound): the iteration's mean loss below
// config.stop_loss once N_m iterations are done.
bool converged(const TrainConfig& config, int completed_iterations, double iteration_loss) {
  return completed_iterations >= config.min_iterations && iteration_loss < config.stop_loss;
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TrainResult train(const TrainConfig& config, const std::function<void(const IterationReport&)>& on_iteration,
                  const std::function<void(int, int)>& on_minibatch) {
  // Set-up: settings, device, data source, model (fresh or from the checkpoint), optimiser.
  if (const std::string e = validate(config); !e.empty()) throw std::runtime_error("invalid training settings: " + e);
  const torch::Device device = trainingDevice(config);
  configureCpu(config.threads);
  Algorithm1Data data(config.data);
  if (!data.error().empty()) throw std::runtime_error("invalid data settings: " + data.error());

  TrainResult result = createOrResumeModel(config);
  const int start_iteration = result.resumed ? result.model.metadata().iterations : 0;
  FaultIdentifier::Impl& impl = *result.model.impl();
  impl.net->to(device);
  torch::optim::Adam optimizer(impl.net->parameters(),
                               torch::optim::AdamOptions(config.learning_rate).weight_decay(config.weight_decay));
  if (result.resumed) {
    result.optimizer_state_reset = !restoreOptimizer(config.checkpoint_path, start_iteration, optimizer);
    data.restoreTo(start_iteration);  // the buffer as it stood at the checkpoint
  }
  const HeldoutSet heldout = makeHeldoutSet(config);
  TrainingLog log(config.log_path, result.resumed, start_iteration);

  const double previous_seconds = result.resumed ? impl.metadata.training_seconds : 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  Minibatch mb;  // reused by every minibatch
  auto scoreHeldout = [&] {
    return config.mode == TrainingMode::kSequences ? evaluateHeldoutDense(config, heldout, impl, device, mb)
                                                   : evaluateHeldout(config, heldout, impl, device, mb);
  };
  if (config.start_from && !result.resumed) {  // where fine-tuning starts, on this run's held-out flights
    IterationReport start;
    auto phase = std::chrono::steady_clock::now();
    const HeldoutScore score = scoreHeldout();
    start.heldout_seconds = secondsSince(phase);
    start.loss = std::numeric_limits<double>::quiet_NaN();
    start.heldout_loss = score.loss;
    start.heldout_accuracy = score.accuracy;
    start.seconds = secondsSince(t0);
    log.append(start);
    if (on_iteration) on_iteration(start);
  }
  std::int64_t windows_trained = 0;
  int iteration = start_iteration;
  std::vector<torch::Tensor> weight_sum;  // Polyak averaging: the sum of the window's weights so far
  while (iteration < config.max_iterations) {
    // This outer iteration's fresh data; the first one also fixes the feature normalisation.
    IterationReport report;
    auto phase = std::chrono::steady_clock::now();
    data.nextIteration();
    if (iteration == 0 && !config.start_from) {  // a fine-tuned network keeps the scale it learnt
      computeNormalisation(data.buffer(), impl.metadata);
      loadNormalisation(impl);
    }
    report.data_seconds = secondsSince(phase);
    // A function of the iteration alone, so a resumed run continues the same schedule.
    for (auto& group : optimizer.param_groups())
      static_cast<torch::optim::AdamOptions&>(group.options())
          .lr(config.learning_rate * std::pow(config.learning_rate_decay, iteration));
    phase = std::chrono::steady_clock::now();
    const PassesOutcome passes =
        config.mode == TrainingMode::kSequences
            ? trainOnSequences(config, data.buffer(), iteration, impl, optimizer, device, mb, on_minibatch)
            : trainOnBuffer(config, data.buffer(), iteration, impl, optimizer, device, mb, on_minibatch);
    windows_trained += passes.windows;
    ++iteration;
    report.train_seconds = secondsSince(phase);
    if (iteration > config.max_iterations - config.average_last) {
      torch::NoGradGuard no_grad;
      const std::vector<torch::Tensor> weights = impl.net->parameters();
      if (weight_sum.empty())
        for (const torch::Tensor& w : weights) weight_sum.push_back(w.detach().clone());
      else
        for (std::size_t i = 0; i < weights.size(); ++i) weight_sum[i].add_(weights[i].detach());
      ++result.averaged_iterations;
    }

    phase = std::chrono::steady_clock::now();
    const HeldoutScore heldout_score = scoreHeldout();
    report.heldout_seconds = secondsSince(phase);
    const double seconds = secondsSince(t0);
    report.iteration = iteration;
    report.loss = passes.minibatches > 0 ? passes.loss_sum / passes.minibatches : 0.0;
    report.heldout_loss = heldout_score.loss;
    report.heldout_accuracy = heldout_score.accuracy;
    report.buffer_windows = data.buffer().size();
    report.seconds = seconds;
    report.windows_per_second = static_cast<double>(windows_trained) / seconds;
    impl.metadata.final_loss = report.loss;
    impl.metadata.heldout_loss = report.heldout_loss;
    impl.metadata.heldout_accuracy = report.heldout_accuracy;
    impl.metadata.training_seconds = previous_seconds + seconds;
    log.append(report);
    if (!config.checkpoint_path.empty()) checkpoint(config.checkpoint_path, result.model, optimizer, iteration, device);
    if (on_iteration) on_iteration(report);
    if (converged(config, iteration, report.loss)) {
      result.converged = true;
      break;
    }
  }
  result.last_heldout_accuracy = impl.metadata.heldout_accuracy;
  if (result.averaged_iterations > 1) {  // the written model is the mean; its held-out score is its own
    {
      torch::NoGradGuard no_grad;
      const std::vector<torch::Tensor> weights = impl.net->parameters();
      for (std::size_t i = 0; i < weights.size(); ++i)
        weights[i].copy_(weight_sum[i] / static_cast<double>(result.averaged_iterations));
    }
    const HeldoutScore averaged = scoreHeldout();
    impl.metadata.heldout_loss = averaged.loss;
    impl.metadata.heldout_accuracy = averaged.accuracy;
  }
  impl.net->to(torch::kCPU);
  impl.metadata.iterations = iteration;
  impl.metadata.training_seconds = previous_seconds + secondsSince(t0);
  result.iterations = iteration;
  return result;
}

}  // namespace quadfdi
