#include "cli/reproduce_command.h"


#include <chrono>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "cli/cli_util.h"
#include "cli/command_line.h"
#include "cli/evaluate_command.h"
#include "cli/options.h"
#include "cli/train_command.h"
#include "data/scales.h"

namespace quadfdi::cli {

CLI::App* addReproduceCommand(CLI::App& app, ReproduceOptions& o) {
  CLI::App* cmd = app.add_subcommand("reproduce", trainingCommand("reproduce")->description);
  auto t = std::make_shared<OptionTable>();
  t->addConfigFile(o.config);
  t->add("--scale", o.scale, "Named scale of training and test sets").choices(scaleNames());
  t->add("--output,-o", o.output, "Output folder");
  t->add("--seed", o.seed, "Training seed");
  t->add("--threads,-j", o.threads, "Threads (0 = all cores)").atLeast(0);
  t->add("--device", o.device, "Where to train").choices({"cpu", "cuda"});
  t->add("--quiet,-q", o.quiet, "Less output");
  attachOptions(*cmd, t);
  return cmd;
}

int runReproduce(const ReproduceOptions& o, const std::string& command_line) {
  std::string problem;
  require(findScale(o.scale, &problem) != nullptr, "--scale: " + problem);
  ensureDirectory(o.output);
  const std::string models = o.output + "/models";
  ensureDirectory(models);

  struct Role {
    const char* name;
    const char* architecture;
    const char* features;
  };
  const Role roles[] = {{"model-free", "lstm", "model-free"},
                        {"model-based", "lstm", "model-based"},
                        {"residual", "lstm", "residual"},
                        {"mlp", "mlp", "model-free"}};
  EvaluateOptions eval;
  eval.scale = o.scale;
  eval.threads = o.threads;
  eval.output = o.output;
  eval.quiet = o.quiet;
  eval.experiments = {"e1", "e2", "e3", "e4", "e5", "e6"};
  const auto t0 = std::chrono::steady_clock::now();
  for (const Role& r : roles) {
    TrainOptions t;
    t.architecture = r.architecture;
    t.features = r.features;
    t.seed = o.seed;
    t.threads = o.threads;
    t.device = o.device;
    t.quiet = o.quiet;
    t.resume = true;  // a re-run picks up where a killed one stopped
    t.output = models + "/" + r.name + ".qfdw";
    t.scale = o.scale;  // the schedule and data of the named scale (default: configs/train-*.toml's)
    if (!o.quiet) std::fprintf(stderr, "reproduce: training %s (%s, %s)\n", r.name, r.architecture, r.features);
    trainAndSave(t, command_line + "  [" + r.name + "]");
    if (std::string(r.name) == "model-free") eval.model_free = t.output;
    if (std::string(r.name) == "model-based") eval.model_based = t.output;
    if (std::string(r.name) == "residual") eval.residual = t.output;
    if (std::string(r.name) == "mlp") eval.mlp = t.output;
  }
  runEvaluate(eval, command_line);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  {  // the report's wall time covers the evaluation; add the whole chain's
    std::ofstream report(o.output + "/REPORT.md", std::ios::app);
    report << "\n---\nWhole chain (training the four networks, then evaluation): " << static_cast<long>(seconds)
           << " s wall time on this machine.\n";
    if (!report) throw std::runtime_error(o.output + "/REPORT.md: cannot append");
  }
  if (!o.quiet)
    std::fprintf(stderr, "quadfdi reproduce: %s scale done in %.0f s; see %s/REPORT.md\n", o.scale.c_str(), seconds,
                 o.output.c_str());
  return 0;
}

}  // namespace quadfdi::cli
