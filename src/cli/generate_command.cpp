#include "cli/generate_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "cli/cli_util.h"
#include "cli/interrupt.h"
#include "cli/options.h"
#include "cli/progress.h"
#include "data/algorithm1.h"
#include "data/scales.h"
#include "io/controller_config.h"
#include "io/hdf5_dataset.h"
#include "io/params_file.h"
#include "io/randomisation_file.h"

namespace quadfdi::cli {

CLI::App* addGenerateCommand(CLI::App& app, GenerateOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "generate",
      "Generate a training or test dataset (docs/data.md, Algorithm 1's data side): for each of N initial\n"
      "conditions, one 2T-step closed-loop flight per motor and per Θ value, the fault at step T,\n"
      "with y, u, the true state and the model-based residual at every sample; written as HDF5\n"
      "(schema: docs/dataset-format.md). Same seed, same bytes, whatever --threads.");
  auto t = std::make_shared<OptionTable>();
  t->addConfigFile(o.config);
  t->recordGivenIn(o.given);
  t->add("--scale", o.scale, "Initial conditions per iteration: tiny (4), quick and default (40), paper (100 → "
                             "1 100 trajectories, as the authors' code)")
      .choices(scaleNames());
  t->add("--controller", o.controller, "Controller flying the data").choices({"lqr", "cbf"});
  t->add("--controller-config", o.controller_config,
         "Controller FILE (configs/controller-example.toml); --controller given explicitly wins").shippedFile();
  t->add("--params", o.params, "Plant: nominal, perturbed, perturbed-strong or a FILE").paramsFile();
  t->add("--motors", o.motors, "Faulty motors (1..4); the paper trains on motor 2 only").range(1, 4);
  t->add("--thetas", o.thetas, "Effectiveness values after the fault, each in [0, 1]").range(0.0, 1.0);
  t->add("--initial-conditions,-n", o.initial_conditions, "Initial conditions per iteration (overrides --scale)")
      .atLeast(1)
      .defaultText("from --scale");
  t->add("--iterations", o.iterations, "Outer iterations' worth of data in the file").atLeast(1);
  t->add("--window", o.window, "Window length T [samples]; flights have 2T steps").atLeast(1);
  t->add("--preroll", o.preroll, "Random healthy pre-roll before recording, up to this many seconds").atLeast(0);
  t->add("--randomise", o.randomise,
         "Randomisation FILE: vehicles, plant errors, estimator, controller mix, manoeuvres (docs/data.md#randomisation)").shippedFile();
  t->add("--post-fault", o.post_fault, "Seconds recorded after the fault (0: the window T)").atLeast(0);
  t->add("--output-kind", o.output_kind, "y: position-euler (paper text) or position-rates (authors' code)")
      .choices({"position-euler", "position-rates"});
  t->add("--integrator", o.integrator, "Integrator").choices({"rk4", "euler"});
  t->add("--seed", o.seed, "Seed; scenario i uses the stream (seed, first-scenario + i)");
  t->add("--first-scenario", o.first_scenario, "Index of the first scenario stream");
  t->add("--threads,-j", o.threads, "Worker threads (0 = all cores)").atLeast(0);
  t->add("--output,-o", o.output, "HDF5 file to write").required();
  t->add("--quiet,-q", o.quiet, "No progress bar or summary");
  attachOptions(*cmd, t);
  return cmd;
}

int runGenerate(const GenerateOptions& o) {
  std::string problem;
  const NamedScale* scale = findScale(o.scale, &problem);
  require(scale != nullptr, "--scale: " + problem);
  const int n1 = o.initial_conditions.value_or(scale->data.initial_conditions);

  if (!o.randomise.empty())
    refuseGiven(o.given, {"params", "controller", "controller_config", "preroll"},
                "has no effect with --randomise (its vehicles, controller mix and preroll_seconds are flown)");
  RolloutConfig rc;
  rc.plant = loadVehicleParams(o.params);
  rc.controller_model = rc.plant;
  if (!o.controller_config.empty()) rc.controller = loadControllerConfig(o.controller_config, rc.controller);
  if (o.controller_config.empty() || o.given.count("controller"))
    require(parseControllerKind(o.controller, rc.controller.kind), "--controller: unknown controller '" + o.controller + "'");
  rc.integrator = o.integrator == "euler" ? Integrator::kEuler : Integrator::kRk4;
  rc.window = o.window;
  rc.output = o.output_kind == "position-rates" ? OutputKind::kPositionRates : OutputKind::kPositionEuler;
  rc.preroll_max_steps = static_cast<int>(std::lround(o.preroll / rc.dt));
  rc.seed = o.seed;
  rc.post_fault_steps = static_cast<int>(std::lround(o.post_fault / rc.dt));
  if (!o.randomise.empty()) rc.randomisation = loadRandomisation(o.randomise);
  const RolloutEngine engine(rc);
  require(engine.error().empty(), "invalid generation settings: " + engine.error());

  const long long total_ics = static_cast<long long>(n1) * o.iterations;
  const long long total = total_ics * static_cast<long long>(o.thetas.size() * o.motors.size());
  require(total < (1ll << 31), "too many trajectories for one file");
  const std::vector<TrajectoryJob> jobs =
      algorithm1Jobs(o.first_scenario, static_cast<int>(total_ics), o.thetas, o.motors);

  ProgressBar bar("generate", !o.quiet);
  TrajectoryBatch batch;
  const auto t0 = std::chrono::steady_clock::now();
  if (!engine.run(jobs, o.threads, batch, [&](int done, int n) { bar.update(done, n); }, &interruptFlag())) {
    bar.finish();
    throw Interrupted("generate stopped before the dataset was complete; " + o.output + " was not written");
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  bar.finish();

  DatasetMetadata meta;
  meta.dt = rc.dt;
  meta.window = rc.window;
  meta.fault_step = rc.faultStep();
  meta.controller = rc.randomisation.enabled() ? "randomised" : toString(rc.controller.kind);
  meta.params = rc.randomisation.enabled() ? "randomised: " + o.randomise : o.params;
  meta.output = o.output_kind;
  meta.integrator = o.integrator;
  meta.seed = o.seed;
  meta.preroll_max_steps = rc.preroll_max_steps;
  writeDataset(o.output, batch, meta);

  if (!o.quiet) {
    int cut = 0;
    long long steps = 0;
    for (int i = 0; i < batch.count; ++i) {
      cut += batch.end_status[static_cast<std::size_t>(i)] != 0;
      steps += batch.length[static_cast<std::size_t>(i)];
    }
    std::vector<WindowRef> windows;
    enumerateWindows(batch, rc.window, windows);
    std::fprintf(stderr,
                 "quadfdi generate: %d trajectories (%lld initial conditions x %zu motors x %zu thetas), %d cut by a "
                 "crash; %zu windows of T = %d; %.2f s (%.2f M steps/s incl. residuals); wrote %s\n",
                 batch.count, total_ics, o.motors.size(), o.thetas.size(), cut, windows.size(), rc.window, seconds,
                 static_cast<double>(steps) / seconds / 1e6, o.output.c_str());
  }
  return 0;
}

}  // namespace quadfdi::cli
