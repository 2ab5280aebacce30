#include "networks/trainer.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

#include "networks/torch_net.h"

namespace quadfdi {
namespace {

constexpr double kIdentificationTolerance = 0.05;  // SPEC §7: |Θ̂ − Θ| ≤ 0.05
constexpr std::uint64_t kHeldoutFirstScenario = 1ull << 40;  // disjoint from training streams

struct Minibatch {
  std::vector<float> features;
  std::vector<float> labels;
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

torch::Tensor hingeLoss(const torch::Tensor& pred, const torch::Tensor& target, LossKind kind, double eps) {
  if (kind == LossKind::kNorm) return torch::relu((pred - target).norm(2, 1) - eps).mean();
  return torch::relu((pred - target).abs() - eps).mean();
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

std::string validate(const TrainConfig& c) {
  if (const std::string e = validate(c.data.rollout); !e.empty()) return e;
  if (c.data.scale.initial_conditions < 1 || c.data.scale.buffer_windows < 1) return "scale needs N1 >= 1 and N_buf >= 1";
  if (c.data.thetas.empty() || c.data.motors.empty()) return "need at least one theta and one motor";
  if (c.batch_size < 1) return "batch size must be >= 1";
  if (c.passes < 1) return "passes must be >= 1";
  if (c.max_minibatches < 0) return "max minibatches must be >= 0";
  if (c.min_iterations < 0 || c.max_iterations < 1 || c.min_iterations > c.max_iterations)
    return "need 0 <= min iterations <= max iterations, max >= 1";
  if (!(c.learning_rate > 0.0) || !std::isfinite(c.learning_rate) || !(c.weight_decay >= 0.0) ||
      !std::isfinite(c.weight_decay) || !(c.epsilon >= 0.0) || !std::isfinite(c.epsilon))
    return "bad optimiser settings (learning rate > 0, weight decay and epsilon >= 0, all finite)";
  if (c.device != "cpu" && c.device != "cuda") return "device must be cpu or cuda";
  if (c.model.window != c.data.rollout.window) return "model window must equal the data window";
  return {};
}

TrainResult train(const TrainConfig& config, const std::function<void(const IterationReport&)>& on_iteration,
                  const std::function<void(int, int)>& on_minibatch) {
  if (const std::string e = validate(config); !e.empty()) throw std::runtime_error("invalid training settings: " + e);
  if (config.device == "cuda" && !torch::cuda::is_available())
    throw std::runtime_error("--device cuda: no CUDA device (this LibTorch build or machine has none)");
  const torch::Device device(config.device == "cuda" ? torch::kCUDA : torch::kCPU);
  configureCpuThreads(config.threads);

  Algorithm1Data data(config.data);
  if (!data.error().empty()) throw std::runtime_error("invalid data settings: " + data.error());

  TrainResult result{FaultIdentifier::create(config.model, config.seed)};
  FaultIdentifier& model = result.model;
  model.metadata().output = config.data.rollout.output;
  model.metadata().window = config.data.rollout.window;
  model.metadata().dt = config.data.rollout.dt;
  model.metadata().trained_motor = config.data.motors.size() == 1 ? config.data.motors.front() : 2;
  model.metadata().seed = config.seed;
  model.metadata().scale = config.data.scale.name;

  int start_iteration = 0;
  const bool have_checkpoint = !config.checkpoint_path.empty() && access(config.checkpoint_path.c_str(), R_OK) == 0;
  if (config.resume && have_checkpoint) {
    FaultIdentifier loaded = FaultIdentifier::load(config.checkpoint_path);
    const ModelMetadata& lm = loaded.metadata();
    if (lm.architecture != config.model.architecture || lm.features != config.model.features ||
        lm.window != config.model.window || lm.hidden != config.model.hidden)
      throw std::runtime_error(config.checkpoint_path + ": checkpoint is for a different model configuration");
    result.model = loaded;
    start_iteration = lm.iterations;
    result.resumed = true;
  }
  FaultIdentifier::Impl& impl = *result.model.impl();
  impl.net->to(device);
  torch::optim::Adam optimizer(impl.net->parameters(),
                               torch::optim::AdamOptions(config.learning_rate).weight_decay(config.weight_decay));
  if (result.resumed) {
    // The optimiser state is renamed into place just before the model; a kill between the two
    // renames leaves it one iteration ahead. Then Adam restarts from fresh moments (reported).
    try {
      torch::serialize::InputArchive archive;
      archive.load_from(config.checkpoint_path + ".optim");
      torch::Tensor saved_iteration;
      archive.read("iteration", saved_iteration);
      if (saved_iteration.item<std::int64_t>() == start_iteration)
        optimizer.load(archive);
      else
        result.optimizer_state_reset = true;
    } catch (const c10::Error&) {
      result.optimizer_state_reset = true;
    }
    data.restoreTo(start_iteration);
  }

  // Held-out windows: fresh scenarios from a disjoint stream range, generated once.
  TrajectoryBatch heldout;
  {
    RolloutEngine engine(config.data.rollout);
    engine.run(algorithm1Jobs(kHeldoutFirstScenario, config.heldout_initial_conditions, config.data.thetas,
                              config.data.motors),
               config.data.threads, heldout);
  }
  std::vector<WindowRef> heldout_windows;
  enumerateWindows(heldout, config.data.rollout.window, heldout_windows);

  std::ofstream log;
  if (!config.log_path.empty()) {
    std::vector<std::string> kept;
    if (result.resumed) {  // keep the rows of iterations the checkpoint covers
      std::ifstream old(config.log_path);
      std::string line;
      while (std::getline(old, line)) {
        if (kept.empty()) { kept.push_back(line); continue; }
        if (std::atoi(line.c_str()) <= start_iteration) kept.push_back(line);
      }
    }
    log.open(config.log_path, std::ios::trunc);
    if (!log) throw std::runtime_error(config.log_path + ": cannot write the training log");
    if (kept.empty()) kept.push_back("iteration,loss,heldout_loss,heldout_accuracy,buffer_windows,seconds,windows_per_second");
    for (const auto& l : kept) log << l << '\n';
    log.flush();
  }

  const ModelMetadata& meta = impl.metadata;
  const double previous_seconds = result.resumed ? impl.metadata.training_seconds : 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  Minibatch mb;
  std::vector<std::size_t> order;
  std::int64_t windows_trained = 0;
  int iteration = start_iteration;
  while (iteration < config.max_iterations) {
    data.nextIteration();
    if (iteration == 0) {
      computeNormalisation(data.buffer(), impl.metadata);
      loadNormalisation(impl);
    }
    impl.net->train();
    const std::size_t n = data.buffer().size();
    order.resize(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    Rng shuffle_rng(config.seed, 0x5000000ull + static_cast<std::uint64_t>(iteration));
    double loss_sum = 0.0;
    int minibatches = 0;
    const std::size_t bs = static_cast<std::size_t>(config.batch_size);
    const int per_pass = static_cast<int>((n + bs - 1) / bs);
    int total = per_pass * config.passes;
    if (config.max_minibatches > 0) total = std::min(total, config.max_minibatches);
    for (int pass = 0; pass < config.passes && minibatches < total; ++pass) {
      for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[shuffle_rng.next() % i]);  // Fisher–Yates
      for (std::size_t first = 0; first < n && minibatches < total; first += bs) {
        if (config.stop && config.stop->load(std::memory_order_relaxed))
          throw TrainingInterrupted(
              "training stopped during outer iteration " + std::to_string(iteration + 1) + "; " +
              (config.checkpoint_path.empty() || iteration == 0
                   ? std::string("no iteration was complete, nothing was saved")
                   : config.checkpoint_path + " holds the " + std::to_string(iteration) +
                         " completed iterations: run again with --resume to continue"));
        const std::size_t count = std::min(bs, n - first);
        gather(count, [&](std::size_t i) {
          const auto e = data.buffer().at(order[first + i]);
          return std::make_pair(e.batch, e.ref);
        }, meta, mb);
        const auto b = static_cast<std::int64_t>(count);
        const torch::Tensor x =
            torch::from_blob(mb.features.data(), {b, meta.window, meta.channels()}, torch::kFloat32).to(device);
        const torch::Tensor y = torch::from_blob(mb.labels.data(), {b, 4}, torch::kFloat32).to(device);
        optimizer.zero_grad();
        const torch::Tensor loss = hingeLoss(impl.net->forward(x), y, config.loss, config.epsilon);
        const double value = loss.item<double>();
        if (!std::isfinite(value))
          throw std::runtime_error("training diverged: non-finite loss at outer iteration " +
                                   std::to_string(iteration + 1) + " (lower the learning rate?)");
        loss.backward();
        optimizer.step();
        loss_sum += value;
        windows_trained += b;
        ++minibatches;
        if (on_minibatch) on_minibatch(minibatches, total);
      }
    }
    ++iteration;

    // Held-out evaluation.
    impl.net->eval();
    double heldout_loss = 0.0;
    int correct = 0;
    {
      torch::NoGradGuard no_grad;
      for (std::size_t first = 0; first < heldout_windows.size(); first += 4096) {
        const std::size_t count = std::min<std::size_t>(4096, heldout_windows.size() - first);
        gather(count, [&](std::size_t i) { return std::make_pair(&heldout, heldout_windows[first + i]); }, meta, mb);
        const auto b = static_cast<std::int64_t>(count);
        const torch::Tensor x = torch::from_blob(mb.features.data(), {b, meta.window, meta.channels()}, torch::kFloat32).to(device);
        const torch::Tensor y = torch::from_blob(mb.labels.data(), {b, 4}, torch::kFloat32).to(device);
        const torch::Tensor pred = impl.net->forward(x);
        heldout_loss += hingeLoss(pred, y, config.loss, config.epsilon).item<double>() * static_cast<double>(count);
        correct += ((pred - y).abs().amax(1) <= kIdentificationTolerance).sum().item<int>();
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    IterationReport report;
    report.iteration = iteration;
    report.loss = minibatches > 0 ? loss_sum / minibatches : 0.0;
    report.heldout_loss = heldout_windows.empty() ? 0.0 : heldout_loss / static_cast<double>(heldout_windows.size());
    report.heldout_accuracy = heldout_windows.empty() ? 0.0 : static_cast<double>(correct) / static_cast<double>(heldout_windows.size());
    report.buffer_windows = n;
    report.seconds = seconds;
    report.windows_per_second = static_cast<double>(windows_trained) / seconds;
    impl.metadata.final_loss = report.loss;
    impl.metadata.heldout_loss = report.heldout_loss;
    impl.metadata.heldout_accuracy = report.heldout_accuracy;
    impl.metadata.training_seconds = previous_seconds + seconds;
    if (log.is_open()) {
      log << report.iteration << ',' << report.loss << ',' << report.heldout_loss << ',' << report.heldout_accuracy << ','
          << report.buffer_windows << ',' << report.seconds << ',' << report.windows_per_second << '\n';
      log.flush();
    }
    if (!config.checkpoint_path.empty()) {
      impl.net->to(torch::kCPU);
      writeCheckpoint(config.checkpoint_path, result.model, optimizer, iteration);
      impl.net->to(device);
    }
    if (on_iteration) on_iteration(report);
    if (iteration >= config.min_iterations && report.loss < config.stop_loss) {
      result.converged = true;
      break;
    }
  }
  impl.net->to(torch::kCPU);
  impl.metadata.iterations = iteration;
  impl.metadata.training_seconds =
      previous_seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  result.iterations = iteration;
  return result;
}

}  // namespace quadfdi
