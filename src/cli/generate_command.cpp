#include "cli/generate_command.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "cli/cli_util.h"
#include "cli/interrupt.h"
#include "cli/progress.h"
#include "data/algorithm1.h"
#include "io/controller_config.h"
#include "io/hdf5_dataset.h"
#include "io/key_value.h"
#include "io/params_file.h"

namespace quadfdi::cli {

int scaleInitialConditions(const std::string& scale) {
  const auto s = dataScale(scale);
  return s ? s->initial_conditions : -1;
}

CLI::App* addGenerateCommand(CLI::App& app, GenerateOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "generate",
      "Generate a training or test dataset (SPEC §5, Algorithm 1's data side): for each of N initial\n"
      "conditions, one 2T-step closed-loop flight per motor and per Θ value, the fault at step T,\n"
      "with y, u, the true state and the model-based residual at every sample; written as HDF5\n"
      "(schema: docs/dataset-format.md). Same seed, same bytes, whatever --threads.");
  cmd->add_option("--config", o.config, "Configuration file (key = value; keys as the long flags, '-' → '_')");
  cmd->add_option("--scale", o.scale, "Initial conditions per iteration: tiny (4), default (40), paper (100 → 1 100 "
                                      "trajectories, as the authors' code)")
      ->capture_default_str();
  cmd->add_option("--controller", o.controller, "lqr or cbf")->capture_default_str();
  cmd->add_option("--controller-config", o.controller_config, "Controller FILE (configs/controller-example.toml)");
  cmd->add_option("--params", o.params, "Plant: nominal, perturbed, perturbed-strong or a FILE")->capture_default_str();
  cmd->add_option("--motors", o.motors, "Faulty motors (1..4); the paper trains on motor 2 only")->capture_default_str();
  cmd->add_option("--thetas", o.thetas, "Effectiveness values after the fault, each in [0, 1]")->capture_default_str();
  cmd->add_option("--initial-conditions,-n", o.initial_conditions, "Initial conditions per iteration (overrides --scale)");
  cmd->add_option("--iterations", o.iterations, "Outer iterations' worth of data in the file")->capture_default_str();
  cmd->add_option("--window", o.window, "Window length T [samples]; flights have 2T steps")->capture_default_str();
  cmd->add_option("--preroll", o.preroll, "Random healthy pre-roll before recording, up to this many seconds")
      ->capture_default_str();
  cmd->add_option("--output-kind", o.output_kind, "y: position-euler (paper text) or position-rates (authors' code)")
      ->capture_default_str();
  cmd->add_option("--integrator", o.integrator, "rk4 or euler")->capture_default_str();
  cmd->add_option("--seed", o.seed, "Seed; scenario i uses the stream (seed, first-scenario + i)")->capture_default_str();
  cmd->add_option("--first-scenario", o.first_scenario, "Index of the first scenario stream")->capture_default_str();
  cmd->add_option("--threads,-j", o.threads, "Worker threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--output,-o", o.output, "HDF5 file to write")->required();
  cmd->add_flag("--quiet,-q", o.quiet, "No progress bar or summary");
  return cmd;
}

namespace {

// Applies config-file values for every option not given on the command line.
void applyConfig(GenerateOptions& o, const CLI::App& cmd) {
  if (o.config.empty()) return;
  const KeyValueDocument doc = readKeyValueFile(o.config);
  auto given = [&](const char* flag) { return cmd.count(flag) > 0; };
  for (const KeyValueEntry& e : doc.entries) {
    const std::string& k = e.key;
    if (k == "scale") { if (!given("--scale")) o.scale = doc.string(e); }
    else if (k == "controller") {
      if (!given("--controller")) o.controller = doc.string(e);
      o.controller_given = true;
    }
    else if (k == "controller_config") { if (!given("--controller-config")) o.controller_config = doc.string(e); }
    else if (k == "params") { if (!given("--params")) o.params = doc.string(e); }
    else if (k == "output_kind") { if (!given("--output-kind")) o.output_kind = doc.string(e); }
    else if (k == "integrator") { if (!given("--integrator")) o.integrator = doc.string(e); }
    else if (k == "motors") {
      if (!given("--motors")) {
        o.motors.clear();
        for (double m : doc.numberList(e)) {
          if (m != std::floor(m) || m < 1 || m > 4) doc.fail(e, "motors must be integers 1..4");
          o.motors.push_back(static_cast<int>(m));
        }
      }
    } else if (k == "thetas") { if (!given("--thetas")) o.thetas = doc.numberList(e); }
    else if (k == "initial_conditions") { if (!given("--initial-conditions")) o.initial_conditions = static_cast<int>(doc.integer(e)); }
    else if (k == "iterations") { if (!given("--iterations")) o.iterations = static_cast<int>(doc.integer(e)); }
    else if (k == "window") { if (!given("--window")) o.window = static_cast<int>(doc.integer(e)); }
    else if (k == "preroll") { if (!given("--preroll")) o.preroll = doc.number(e); }
    else if (k == "seed") { if (!given("--seed")) o.seed = static_cast<unsigned long long>(doc.integer(e)); }
    else if (k == "first_scenario") { if (!given("--first-scenario")) o.first_scenario = static_cast<unsigned long long>(doc.integer(e)); }
    else if (k == "threads") { if (!given("--threads")) o.threads = static_cast<int>(doc.integer(e)); }
    else doc.fail(e, "unknown key '" + k + "'");
  }
}

}  // namespace

int runGenerate(GenerateOptions o, const CLI::App& command) {
  applyConfig(o, command);
  int n1 = o.initial_conditions;
  if (n1 == 0) {
    n1 = scaleInitialConditions(o.scale);
    require(n1 > 0, "--scale must be tiny, default or paper, got '" + o.scale + "'");
  }
  require(n1 > 0, "--initial-conditions must be > 0");
  require(o.iterations > 0, "--iterations must be > 0");
  require(!o.motors.empty(), "--motors needs at least one motor");
  for (int m : o.motors) require(m >= 1 && m <= 4, "--motors: motor " + std::to_string(m) + " is not 1..4");
  require(!o.thetas.empty(), "--thetas needs at least one value");
  for (double t : o.thetas) require(t >= 0.0 && t <= 1.0, "--thetas: " + std::to_string(t) + " is outside [0, 1]");
  require(o.threads >= 0, "--threads must be >= 0");
  require(o.preroll >= 0.0 && std::isfinite(o.preroll), "--preroll must be >= 0");
  require(o.output_kind == "position-euler" || o.output_kind == "position-rates",
          "--output-kind must be position-euler or position-rates");
  require(o.integrator == "rk4" || o.integrator == "euler", "--integrator must be rk4 or euler");

  RolloutConfig rc;
  rc.plant = loadVehicleParams(o.params);
  rc.controller_model = rc.plant;
  if (!o.controller_config.empty()) rc.controller = loadControllerConfig(o.controller_config, rc.controller);
  if (o.controller_config.empty() || o.controller_given || command.count("--controller"))
    require(parseControllerKind(o.controller, rc.controller.kind), "--controller must be lqr or cbf, got '" + o.controller + "'");
  rc.integrator = o.integrator == "euler" ? Integrator::kEuler : Integrator::kRk4;
  rc.window = o.window;
  rc.output = o.output_kind == "position-rates" ? OutputKind::kPositionRates : OutputKind::kPositionEuler;
  rc.preroll_max_steps = static_cast<int>(std::lround(o.preroll / rc.dt));
  rc.seed = o.seed;
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
  meta.controller = toString(rc.controller.kind);
  meta.params = o.params;
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
