#include "cli/train_command.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cli/cli_util.h"
#include "cli/command_line.h"
#include "cli/interrupt.h"
#include "cli/options.h"
#include "cli/progress.h"
#include "data/scales.h"
#include "io/key_value.h"
#include "io/model_file.h"
#include "io/params_file.h"
#include "io/randomisation_file.h"
#include "networks/trainer.h"
#include "symmetry/symmetry.h"

namespace quadfdi::cli {


CLI::App* addTrainCommand(CLI::App& app, TrainOptions& o) {
  CLI::App* cmd = app.add_subcommand("train", trainingCommand("train")->description);
  auto t = std::make_shared<OptionTable>();
  t->addConfigFile(o.config);
  t->recordGivenIn(o.given);
  t->add("--scale", o.scale, "Data per iteration, buffer and schedule: tiny (tests), quick, default (CPU), "
                             "paper (GPU)")
      .choices(scaleNames());
  t->add("--architecture", o.architecture, "Network: lstm (the paper's), mlp, or tcn (streaming, docs/networks.md)")
      .choices({"lstm", "mlp", "tcn"});
  t->add("--features", o.features,
         "model-free (y, u), model-free-heading (local increments; needed by tcn), scale-free (model-free-heading with "
         "the commands as shares of the collective: any vehicle size), scale-free-rates (scale-free with the measured body "
         "rates: detect feeds it from a CSV's p,q,r or a log's gyro topic, docs/networks.md#body-rates), "
         "model-based (y, u, residual) or residual")
      .choices({"model-free", "model-free-heading", "scale-free", "scale-free-rates", "model-based", "residual"});
  t->add("--training", o.training,
         "windows (the paper's: one label per window) or sequences (causal networks: whole trajectories, a label "
         "per position; docs/networks.md)")
      .choices({"windows", "sequences"})
      .defaultText("sequences for tcn, else windows");
  t->add("--tcn-channels", o.tcn_channels, "Hidden channels of a tcn (cost grows with their square)").range(4, 256);
  t->add("--output-kind", o.output_kind, "Measured output y").choices({"position-euler", "position-rates"});
  t->add("--symmetry", o.symmetry, "Symmetry the model will be used with (recorded)").choices({"exact", "paper"});
  t->add("--loss", o.loss, "norm (seed eq. 4) or per-motor (authors' code)").choices({"norm", "per-motor"});
  t->add("--controller", o.controller, "Controller flying the training data").choices({"lqr", "cbf"});
  t->add("--params", o.params, "Plant of the training data: nominal, perturbed, perturbed-strong or FILE").paramsFile();
  t->add("--thetas", o.thetas, "Θ₂ values flown from every initial condition, each in [0, 1]").range(0.0, 1.0);
  t->add("--batch-size", o.batch_size, "Windows per minibatch (windows training)").atLeast(1).defaultText("from --scale");
  t->add("--batch-trajectories", o.batch_trajectories, "Trajectories per minibatch (sequences training)").atLeast(1);
  t->add("--learning-rate", o.learning_rate, "Adam step size").range(1e-7, 1.0);
  t->add("--lr-decay", o.learning_rate_decay,
         "Learning rate factor per outer iteration: iteration j runs at learning-rate * decay^j (1 = constant)")
      .range(1e-3, 1.0);
  t->add("--passes", o.passes, "Passes over the buffer per outer iteration").atLeast(1).defaultText("from --scale");
  t->add("--buffer-windows", o.buffer_windows,
         "N_buf: windows the FIFO buffer keeps; larger draws minibatches from several iterations' flights")
      .atLeast(1)
      .defaultText("from --scale");
  t->add("--max-minibatches", o.max_minibatches, "Cap on minibatches per outer iteration, 0 = none")
      .atLeast(0)
      .defaultText("from --scale");
  t->add("--min-iterations", o.min_iterations, "N_m: no stop before this many outer iterations")
      .atLeast(0)
      .defaultText("from --scale");
  t->add("--max-iterations", o.max_iterations, "N_M: outer iterations at most").atLeast(1).defaultText("from --scale");
  t->add("--average-last", o.average_last,
         "Write the mean of the weights after each of the last N outer iterations (Polyak averaging, docs/networks.md#weight-averaging) instead of the last weights; 0 = none")
      .atLeast(0);
  t->add("--preroll", o.preroll, "Random healthy pre-roll before each flight, up to this many seconds").atLeast(0);
  t->add("--randomise", o.randomise,
         "Randomisation FILE: vehicles, plant errors, estimator noise/lag/delay, controller mix and gains, manoeuvres "
         "(configs/randomisation-default.toml; docs/data.md)").shippedFile();
  t->add("--vehicle", o.vehicles,
         "Vehicle description FILE or library name (repeatable; configs/vehicles/, e.g. quad450): with --randomise, the vehicles flown; alone, the plant").vehicleFile();
  t->add("--post-fault", o.post_fault, "Seconds recorded after the fault (0: the window T, the paper's)").atLeast(0);
  t->add("--seed", o.seed, "Seed of weights, data and shuffling");
  t->add("--device", o.device, "Where to train").choices({"cpu", "cuda"});
  t->add("--threads,-j", o.threads, "CPU threads for data and LibTorch (0 = all cores)").atLeast(0);
  t->add("--output,-o", o.output, "Model file to write").required();
  t->add("--checkpoint", o.checkpoint, "Checkpoint file").defaultText("OUTPUT.ckpt");
  t->add("--log", o.log, "Training log CSV").defaultText("OUTPUT.log.csv");
  t->add("--resume", o.resume, "Continue from the checkpoint if there is one");
  t->add("--start-from", o.start_from,
         "Fine-tune: start from this finished model's weights and normalisation (a .qfdw whose network matches "
         "this training's) instead of fresh ones, e.g. the general model on your vehicle (docs/networks.md#fine-tuning)").shippedFile();
  t->add("--quiet,-q", o.quiet, "No progress bar or summary");
  attachOptions(*cmd, t);
  return cmd;
}

int runTrain(const TrainOptions& o, const std::string& command_line) { return trainAndSave(o, command_line); }

namespace {

// The option table has checked every value; the enum conversions below only guard direct callers.
TrainConfig makeTrainConfig(const TrainOptions& o, const std::string& command_line) {
  std::string problem;
  const NamedScale* scale = findScale(o.scale, &problem);
  require(scale != nullptr, "--scale: " + problem);
  const TrainSchedule& s = scale->training;

  TrainConfig c;
  c.data.scale = scale->data;
  if (o.buffer_windows) c.data.scale.buffer_windows = static_cast<std::size_t>(*o.buffer_windows);
  c.data.thetas = o.thetas;
  c.data.motors = {2};
  c.data.threads = o.threads;
  if (!o.randomise.empty())
    refuseGiven(o.given, {"params", "controller", "preroll"},
                "has no effect with --randomise (its vehicles, controller mix and preroll_seconds are flown)");
  c.data.rollout.plant = loadVehicleParams(o.vehicles.size() == 1 && o.randomise.empty() ? o.vehicles[0] : o.params);
  c.data.rollout.controller_model = c.data.rollout.plant;
  require(o.vehicles.size() <= 1 || !o.randomise.empty(), "--vehicle: several vehicles need --randomise FILE");
  if (!o.randomise.empty()) {
    Randomisation& r = c.data.rollout.randomisation;
    r = loadRandomisation(o.randomise);
    if (!o.vehicles.empty()) flyOnlyVehicles(r, o.vehicles);
    c.model.randomisation = randomisationToText(r);
  }
  c.data.rollout.post_fault_steps = static_cast<int>(std::lround(o.post_fault / c.data.rollout.dt));
  require(parseControllerKind(o.controller, c.data.rollout.controller.kind), "--controller must be lqr or cbf");
  c.data.rollout.output = o.output_kind == "position-rates" ? OutputKind::kPositionRates : OutputKind::kPositionEuler;
  c.data.rollout.preroll_max_steps = static_cast<int>(std::lround(o.preroll / c.data.rollout.dt));
  c.data.rollout.seed = o.seed;
  require(parseArchitecture(o.architecture, c.model.architecture), "--architecture must be lstm, mlp or tcn");
  require(parseFeatureSet(o.features, c.model.features),
          "--features must be model-free, model-free-heading, scale-free, scale-free-rates, model-based or residual");
  require(!isStreamingFeatureSet(c.model.features) || c.data.rollout.output == OutputKind::kPositionEuler,
          "--features " + o.features + " needs --output-kind position-euler (it reads the yaw angle)");
  if (o.training.empty())
    c.mode = c.model.architecture == Architecture::kTcn ? TrainingMode::kSequences : TrainingMode::kWindows;
  else
    require(parseTrainingMode(o.training, c.mode), "--training must be windows or sequences");
  require(c.mode == TrainingMode::kWindows || c.model.architecture == Architecture::kTcn,
          "--training sequences needs --architecture tcn (an LSTM's or MLP's output depends on where the window starts)");
  if (c.mode == TrainingMode::kWindows)
    refuseGiven(o.given, {"batch_trajectories"}, "is for --training sequences; windows training takes --batch-size");
  else
    refuseGiven(o.given, {"batch_size"}, "is for --training windows; sequences training takes --batch-trajectories");
  if (c.model.architecture != Architecture::kTcn) refuseGiven(o.given, {"tcn_channels"}, "only --architecture tcn has channels");
  c.model.tcn.channels = o.tcn_channels;
  require(c.model.architecture != Architecture::kTcn || c.model.tcn.receptiveField() <= c.data.rollout.window - 1,
          "--architecture tcn: the receptive field (" + std::to_string(c.model.tcn.receptiveField()) +
              " samples) must fit in the window minus one (" + std::to_string(c.data.rollout.window - 1) + ")");
  require(parseSymmetryMode(o.symmetry, c.model.symmetry), "--symmetry must be exact or paper");
  const std::string symmetry_problem = symmetryModeProblem(c.model.symmetry, c.data.rollout.plant);
  require(symmetry_problem.empty(), "--symmetry " + o.symmetry + ": " + symmetry_problem);
  c.loss = o.loss == "norm" ? LossKind::kNorm : LossKind::kPerMotor;
  c.model.window = c.data.rollout.window;
  c.model.params = o.vehicles.size() == 1 && o.randomise.empty() ? o.vehicles[0] : o.params;  // the plant flown
  c.model.controller = o.controller;
  c.model.command = command_line;
  c.batch_size = o.batch_size.value_or(s.batch_size);
  c.batch_trajectories = o.batch_trajectories;
  c.learning_rate = o.learning_rate;
  c.learning_rate_decay = o.learning_rate_decay;
  c.passes = o.passes.value_or(s.passes);
  c.max_minibatches = o.max_minibatches.value_or(s.max_minibatches);
  c.max_iterations = o.max_iterations.value_or(s.max_iterations);
  c.min_iterations = std::min(o.min_iterations.value_or(s.min_iterations), c.max_iterations);
  c.average_last = o.average_last;
  require(c.average_last <= c.max_iterations, "--average-last " + std::to_string(c.average_last) +
                                                  ": more iterations than the run has (" + std::to_string(c.max_iterations) + ")");
  c.heldout_initial_conditions = s.heldout_initial_conditions;
  c.seed = o.seed;
  c.device = o.device;
  c.threads = o.threads;
  c.checkpoint_path = o.checkpoint.empty() ? o.output + ".ckpt" : o.checkpoint;
  c.log_path = o.log.empty() ? o.output + ".log.csv" : o.log;
  c.resume = o.resume;
  c.stop = &interruptFlag();
  if (!o.start_from.empty()) {
    c.start_from = std::make_shared<const TrainedModel>(readModelFile(o.start_from));  // "PATH: problem"
    c.start_from_name = o.start_from;
    const std::string mismatch = startingModelProblem(c);
    require(mismatch.empty(), "--start-from " + o.start_from + ": " + mismatch);
  }
  return c;
}

}  // namespace

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
        if (!o.quiet && it.iteration == 0) {
          std::fprintf(stderr, "train: the starting model on this run's held-out flights: loss %.5f accuracy %.3f\n",
                       it.heldout_loss, it.heldout_accuracy);
        } else if (!o.quiet) {
          bar.finish();
          std::fprintf(stderr, "train: iteration %d/%d loss %.5f held-out loss %.5f accuracy %.3f (%zu windows, %.0f "
                               "windows/s, %.1f s: data %.1f, train %.1f, held-out %.1f)\n",
                       it.iteration, c.max_iterations, it.loss, it.heldout_loss, it.heldout_accuracy, it.buffer_windows,
                       it.windows_per_second, it.seconds, it.data_seconds, it.train_seconds, it.heldout_seconds);
        }
      },
      [&](int done, int total) { bar.update(done, total, last); });
  bar.finish();
  writeModelFile(o.output, r.model.metadata(), exportWeights(r.model));
  if (!o.quiet && r.averaged_iterations > 1)
    std::fprintf(stderr, "train: the weights of the last %d iterations averaged: held-out accuracy %.3f (the last "
                         "iteration's own: %.3f)\n", r.averaged_iterations, r.model.metadata().heldout_accuracy,
                 r.last_heldout_accuracy);
  if (c.average_last > 1 && r.averaged_iterations < c.average_last)
    std::fprintf(stderr, "quadfdi train: warning: %d of the %d iterations asked were averaged (the run %s)\n",
                 r.averaged_iterations, c.average_last, r.converged ? "converged early" : "resumed inside the window");
  if (r.optimizer_state_reset)
    std::fprintf(stderr, "quadfdi train: warning: %s.optim was missing or did not match the checkpoint; "
                         "Adam restarted from fresh moments\n", c.checkpoint_path.c_str());
  if (!o.quiet) {
    const ModelMetadata& m = r.model.metadata();
    std::fprintf(stderr,
                 "quadfdi train: %s %s, %d outer iterations%s%s, %.1f s; final loss %.5f, held-out accuracy %.3f "
                 "(|theta error| <= 0.05 on every motor)%s%s; wrote %s\n",
                 toString(m.architecture), toString(m.features), r.iterations, r.resumed ? " (resumed)" : "",
                 r.converged ? " (converged)" : "", m.training_seconds, m.final_loss, m.heldout_accuracy,
                 m.started_from.empty() ? "" : ", fine-tuned from ", m.started_from.c_str(), o.output.c_str());
  }
  return 0;
}

}  // namespace quadfdi::cli
