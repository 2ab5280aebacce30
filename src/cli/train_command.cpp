#include "cli/train_command.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cli/cli_util.h"
#include "cli/interrupt.h"
#include "cli/progress.h"
#include "io/key_value.h"
#include "io/model_file.h"
#include "io/params_file.h"
#include "networks/trainer.h"

namespace quadfdi::cli {
namespace {

// Training schedule per named scale (the data side is dataScale()).
struct TrainSchedule {
  int batch_size, passes, max_minibatches, min_iterations, max_iterations;
};
TrainSchedule schedule(const std::string& scale) {
  if (scale == "tiny") return {256, 1, 8, 1, 2};
  if (scale == "default") return {512, 1, 60, 10, 16};  // ≈ 15 min on 2 cores
  return {50000, 400, 0, 250, 500};  // paper: authors' batch, passes and N_m
}

void applyConfig(TrainOptions& o, const CLI::App& cmd) {
  if (o.config.empty()) return;
  const KeyValueDocument doc = readKeyValueFile(o.config);
  auto given = [&](const char* flag) { return cmd.count(flag) > 0; };
  for (const KeyValueEntry& e : doc.entries) {
    const std::string& k = e.key;
    auto str = [&](const char* flag, std::string& v) { if (!given(flag)) v = doc.string(e); };
    auto num = [&](const char* flag, int& v) { if (!given(flag)) v = static_cast<int>(doc.integer(e)); };
    if (k == "scale") str("--scale", o.scale);
    else if (k == "architecture") str("--architecture", o.architecture);
    else if (k == "features") str("--features", o.features);
    else if (k == "output_kind") str("--output-kind", o.output_kind);
    else if (k == "symmetry") str("--symmetry", o.symmetry);
    else if (k == "loss") str("--loss", o.loss);
    else if (k == "controller") str("--controller", o.controller);
    else if (k == "params") str("--params", o.params);
    else if (k == "device") str("--device", o.device);
    else if (k == "thetas") { if (!given("--thetas")) o.thetas = doc.numberList(e); }
    else if (k == "batch_size") num("--batch-size", o.batch_size);
    else if (k == "passes") num("--passes", o.passes);
    else if (k == "max_minibatches") num("--max-minibatches", o.max_minibatches);
    else if (k == "min_iterations") num("--min-iterations", o.min_iterations);
    else if (k == "max_iterations") num("--max-iterations", o.max_iterations);
    else if (k == "threads") num("--threads", o.threads);
    else if (k == "preroll") { if (!given("--preroll")) o.preroll = doc.number(e); }
    else if (k == "seed") { if (!given("--seed")) o.seed = static_cast<unsigned long long>(doc.integer(e)); }
    else doc.fail(e, "unknown key '" + k + "'");
  }
}

}  // namespace

static TrainConfig makeTrainConfig(const TrainOptions& o, const std::string& command_line);

CLI::App* addTrainCommand(CLI::App& app, TrainOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "train",
      "Train a fault identifier by Algorithm 1 (SPEC §6): fresh closed-loop data every outer iteration\n"
      "(faults of motor 2 only; other motors are reached through the symmetry maps), a FIFO window\n"
      "buffer, minibatch passes with the hinge loss, Adam (lr 5e-4, wd 1e-5), and the stopping rule\n"
      "(loss < 1e-3 after N_m iterations, or N_M). Checkpointed every outer iteration: --resume\n"
      "continues a killed run, losing at most one iteration.");
  cmd->add_option("--config", o.config, "Configuration file (key = value; keys as the long flags, '-' → '_')");
  cmd->add_option("--scale", o.scale, "tiny | default (CPU) | paper (GPU): data per iteration, buffer and schedule")
      ->capture_default_str();
  cmd->add_option("--architecture", o.architecture, "lstm or mlp")->capture_default_str();
  cmd->add_option("--features", o.features, "model-free (y, u), model-based (y, u, residual) or residual")
      ->capture_default_str();
  cmd->add_option("--output-kind", o.output_kind, "position-euler or position-rates")->capture_default_str();
  cmd->add_option("--symmetry", o.symmetry, "Symmetry the model will be used with: exact or paper (recorded)")
      ->capture_default_str();
  cmd->add_option("--loss", o.loss, "norm (seed eq. 4) or per-motor (authors' code)")->capture_default_str();
  cmd->add_option("--controller", o.controller, "Controller flying the training data: lqr or cbf")->capture_default_str();
  cmd->add_option("--params", o.params, "Plant of the training data: nominal, perturbed, perturbed-strong or FILE")
      ->capture_default_str();
  cmd->add_option("--thetas", o.thetas, "Θ₂ values flown from every initial condition")->capture_default_str();
  cmd->add_option("--batch-size", o.batch_size, "Windows per minibatch (default: from the scale)");
  cmd->add_option("--passes", o.passes, "Passes over the buffer per outer iteration (default: from the scale)");
  cmd->add_option("--max-minibatches", o.max_minibatches, "Cap on minibatches per outer iteration, 0 = none");
  cmd->add_option("--min-iterations", o.min_iterations, "N_m: no stop before this many outer iterations");
  cmd->add_option("--max-iterations", o.max_iterations, "N_M: outer iterations at most");
  cmd->add_option("--preroll", o.preroll, "Random healthy pre-roll before each flight, up to this many seconds")
      ->capture_default_str();
  cmd->add_option("--seed", o.seed, "Seed of weights, data and shuffling")->capture_default_str();
  cmd->add_option("--device", o.device, "cpu or cuda")->capture_default_str();
  cmd->add_option("--threads,-j", o.threads, "CPU threads for data and LibTorch (0 = all cores)")->capture_default_str();
  cmd->add_option("--output,-o", o.output, "Model file to write")->required();
  cmd->add_option("--checkpoint", o.checkpoint, "Checkpoint file (default: OUTPUT.ckpt)");
  cmd->add_option("--log", o.log, "Training log CSV (default: OUTPUT.log.csv)");
  cmd->add_flag("--resume", o.resume, "Continue from the checkpoint if there is one");
  cmd->add_flag("--quiet,-q", o.quiet, "No progress bar or summary");
  return cmd;
}

int runTrain(TrainOptions o, const CLI::App& command, const std::string& command_line) {
  applyConfig(o, command);
  return trainAndSave(o, command_line);
}

static TrainConfig makeTrainConfig(const TrainOptions& o, const std::string& command_line) {
  const auto scale = dataScale(o.scale);
  require(scale.has_value(), "--scale must be tiny, default or paper, got '" + o.scale + "'");
  const TrainSchedule s = schedule(o.scale);

  TrainConfig c;
  c.data.scale = *scale;
  c.data.thetas = o.thetas;
  c.data.motors = {2};
  c.data.threads = o.threads;
  for (double t : o.thetas) require(t >= 0.0 && t <= 1.0, "--thetas: " + std::to_string(t) + " is outside [0, 1]");
  c.data.rollout.plant = loadVehicleParams(o.params);
  c.data.rollout.controller_model = c.data.rollout.plant;
  require(parseControllerKind(o.controller, c.data.rollout.controller.kind), "--controller must be lqr or cbf");
  require(o.output_kind == "position-euler" || o.output_kind == "position-rates",
          "--output-kind must be position-euler or position-rates");
  c.data.rollout.output = o.output_kind == "position-rates" ? OutputKind::kPositionRates : OutputKind::kPositionEuler;
  require(o.preroll >= 0.0 && std::isfinite(o.preroll), "--preroll must be >= 0");
  c.data.rollout.preroll_max_steps = static_cast<int>(std::lround(o.preroll / c.data.rollout.dt));
  c.data.rollout.seed = o.seed;
  require(parseArchitecture(o.architecture, c.model.architecture), "--architecture must be lstm, mlp or tcn");
  require(parseFeatureSet(o.features, c.model.features),
          "--features must be model-free, model-free-heading, model-based or residual");
  require(c.model.features != FeatureSet::kModelFreeHeading || c.data.rollout.output == OutputKind::kPositionEuler,
          "--features model-free-heading needs --output-kind position-euler (it reads the yaw angle)");
  require(c.model.architecture != Architecture::kTcn || c.model.tcn.receptiveField() <= c.data.rollout.window - 1,
          "--architecture tcn: the receptive field (" + std::to_string(c.model.tcn.receptiveField()) +
              " samples) must fit in the window minus one (" + std::to_string(c.data.rollout.window - 1) + ")");
  require(parseSymmetryMode(o.symmetry, c.model.symmetry), "--symmetry must be exact or paper");
  require(o.loss == "norm" || o.loss == "per-motor", "--loss must be norm or per-motor");
  c.loss = o.loss == "norm" ? LossKind::kNorm : LossKind::kPerMotor;
  c.model.window = c.data.rollout.window;
  c.model.params = o.params;
  c.model.controller = o.controller;
  c.model.command = command_line;
  c.batch_size = o.batch_size > 0 ? o.batch_size : s.batch_size;
  c.passes = o.passes > 0 ? o.passes : s.passes;
  c.max_minibatches = o.max_minibatches >= 0 ? o.max_minibatches : s.max_minibatches;
  c.min_iterations = o.min_iterations >= 0 ? o.min_iterations : s.min_iterations;
  c.max_iterations = o.max_iterations >= 0 ? o.max_iterations : s.max_iterations;
  c.min_iterations = std::min(c.min_iterations, c.max_iterations);
  c.heldout_initial_conditions = o.heldout_initial_conditions > 0 ? o.heldout_initial_conditions
                                                                 : (o.scale == "tiny" ? 1 : 20);
  c.seed = o.seed;
  c.device = o.device;
  c.threads = o.threads;
  c.checkpoint_path = o.checkpoint.empty() ? o.output + ".ckpt" : o.checkpoint;
  c.log_path = o.log.empty() ? o.output + ".log.csv" : o.log;
  c.resume = o.resume;
  c.stop = &interruptFlag();
  return c;
}

int trainAndSave(const TrainOptions& o, const std::string& command_line) {
  const TrainConfig c = makeTrainConfig(o, command_line);
  ProgressBar bar("train", !o.quiet);
  std::string last;
  const TrainResult r = train(
      c,
      [&](const IterationReport& it) {
        char line[200];
        std::snprintf(line, sizeof line, "iter %d loss %.4f held-out acc %.3f", it.iteration, it.loss,
                      it.heldout_accuracy);
        last = line;
        if (!o.quiet) {
          bar.finish();
          std::fprintf(stderr, "train: iteration %d/%d loss %.5f held-out loss %.5f accuracy %.3f (%zu windows, %.0f "
                               "windows/s, %.1f s)\n",
                       it.iteration, c.max_iterations, it.loss, it.heldout_loss, it.heldout_accuracy, it.buffer_windows,
                       it.windows_per_second, it.seconds);
        }
      },
      [&](int done, int total) { bar.update(done, total, last); });
  bar.finish();
  writeModelFile(o.output, r.model.metadata(), exportWeights(r.model));
  if (r.optimizer_state_reset)
    std::fprintf(stderr, "quadfdi train: warning: %s.optim was missing or did not match the checkpoint; "
                         "Adam restarted from fresh moments\n", c.checkpoint_path.c_str());
  if (!o.quiet) {
    const ModelMetadata& m = r.model.metadata();
    std::fprintf(stderr,
                 "quadfdi train: %s %s, %d outer iterations%s%s, %.1f s; final loss %.5f, held-out accuracy %.3f "
                 "(|theta error| <= 0.05 on every motor); wrote %s\n",
                 toString(m.architecture), toString(m.features), r.iterations, r.resumed ? " (resumed)" : "",
                 r.converged ? " (converged)" : "", m.training_seconds, m.final_loss, m.heldout_accuracy,
                 o.output.c_str());
  }
  return 0;
}

}  // namespace quadfdi::cli
