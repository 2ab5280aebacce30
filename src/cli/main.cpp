// quadfdi: thin executable over the libraries; all errors end here as one line (cli/command_line.h).
// It links no LibTorch: train, reproduce and convert-model are handed over to quadfdi-training.
#include <CLI/CLI.hpp>
#include <string>

#include "cli/calibrate_command.h"
#include "cli/command_line.h"
#include "cli/detect_command.h"
#include "cli/evaluate_command.h"
#include "cli/generate_command.h"
#include "cli/hand_over.h"
#include "cli/import_command.h"
#include "cli/interrupt.h"
#include "cli/simulate_command.h"

int main(int argc, char** argv) {
  // The command is always the first argument: quadfdi has no options of its own but --help and --version.
  if (argc > 1 && quadfdi::cli::trainingCommand(argv[1])) return quadfdi::cli::handOverToTraining(argc, argv);
  CLI::App app{"quadfdi — detect, isolate and size motor faults on quadrotors (Garg & Fan, dynamic symmetry)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", quadfdi::cli::kVersion);
  quadfdi::cli::SimulateOptions simulate;
  CLI::App* simulate_cmd = quadfdi::cli::addSimulateCommand(app, simulate);
  quadfdi::cli::GenerateOptions generate;
  CLI::App* generate_cmd = quadfdi::cli::addGenerateCommand(app, generate);
#ifdef QUADFDI_TRAINING_EXECUTABLE
  // Listed by --help; never parsed here (handed over above).
  for (const quadfdi::cli::CommandSummary& command : quadfdi::cli::kTrainingCommands)
    app.add_subcommand(command.name, command.description);
#endif
  quadfdi::cli::EvaluateOptions evaluate;
  CLI::App* evaluate_cmd = quadfdi::cli::addEvaluateCommand(app, evaluate);
  quadfdi::cli::DetectOptions detect;
  CLI::App* detect_cmd = quadfdi::cli::addDetectCommand(app, detect);
  quadfdi::cli::CalibrateOptions calibrate;
  CLI::App* calibrate_cmd = quadfdi::cli::addCalibrateCommand(app, calibrate);
  quadfdi::cli::ImportCommandOptions import_options;
  CLI::App* import_cmd = quadfdi::cli::addImportCommand(app, import_options);
  return quadfdi::cli::runCommandLine(app, argc, argv, [&](const std::string& command_line) {
    // The long-running commands stop at a safe point on SIGINT/SIGTERM; the others keep the default.
    if (generate_cmd->parsed() || evaluate_cmd->parsed()) quadfdi::cli::interruptFlag();
    if (simulate_cmd->parsed()) return quadfdi::cli::runSimulate(simulate);
    if (generate_cmd->parsed()) return quadfdi::cli::runGenerate(generate);
    if (detect_cmd->parsed()) return quadfdi::cli::runDetect(detect);
    if (calibrate_cmd->parsed()) return quadfdi::cli::runCalibrate(calibrate);
    if (import_cmd->parsed()) return quadfdi::cli::runImport(import_options);
    if (evaluate_cmd->parsed()) return quadfdi::cli::runEvaluate(evaluate, command_line);
    return 0;
  });
}
