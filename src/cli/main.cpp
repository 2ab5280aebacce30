// quadfdi: thin executable over the libraries; all errors end here as one line.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "cli/calibrate_command.h"
#include "cli/detect_command.h"
#include "cli/evaluate_command.h"
#include "cli/generate_command.h"
#include "cli/import_command.h"
#include "cli/interrupt.h"
#include "cli/simulate_command.h"
#ifdef QUADFDI_WITH_TRAINING
#include "cli/convert_model_command.h"
#include "cli/reproduce_command.h"
#include "cli/train_command.h"
#include "networks/trainer.h"
#endif

int main(int argc, char** argv) {
  CLI::App app{"quadfdi — detect, isolate and size motor faults on quadrotors (Garg & Fan, dynamic symmetry)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "quadfdi 0.2.0");
  quadfdi::cli::SimulateOptions simulate;
  CLI::App* simulate_cmd = quadfdi::cli::addSimulateCommand(app, simulate);
  quadfdi::cli::GenerateOptions generate;
  CLI::App* generate_cmd = quadfdi::cli::addGenerateCommand(app, generate);
#ifdef QUADFDI_WITH_TRAINING
  quadfdi::cli::TrainOptions train;
  CLI::App* train_cmd = quadfdi::cli::addTrainCommand(app, train);
  quadfdi::cli::ReproduceOptions reproduce;
  CLI::App* reproduce_cmd = quadfdi::cli::addReproduceCommand(app, reproduce);
  quadfdi::cli::ConvertModelOptions convert;
  CLI::App* convert_cmd = quadfdi::cli::addConvertModelCommand(app, convert);
#endif
  quadfdi::cli::EvaluateOptions evaluate;
  CLI::App* evaluate_cmd = quadfdi::cli::addEvaluateCommand(app, evaluate);
  quadfdi::cli::DetectOptions detect;
  CLI::App* detect_cmd = quadfdi::cli::addDetectCommand(app, detect);
  quadfdi::cli::CalibrateOptions calibrate;
  CLI::App* calibrate_cmd = quadfdi::cli::addCalibrateCommand(app, calibrate);
  quadfdi::cli::ImportCommandOptions import_options;
  CLI::App* import_cmd = quadfdi::cli::addImportCommand(app, import_options);
  try {
    // Parsing also resolves the converted commands' option tables (cli/options.h): a bad value,
    // or a bad --config file, throws a one-line OptionError / ConfigError, reported below (exit 1).
    app.parse(argc, argv);
    // The long-running commands stop at a safe point on SIGINT/SIGTERM; the others keep the default.
    bool long_running = generate_cmd->parsed() || evaluate_cmd->parsed();
#ifdef QUADFDI_WITH_TRAINING
    long_running = long_running || train_cmd->parsed() || reproduce_cmd->parsed();
#endif
    if (long_running) quadfdi::cli::interruptFlag();
    if (simulate_cmd->parsed()) return quadfdi::cli::runSimulate(simulate);
    if (generate_cmd->parsed()) return quadfdi::cli::runGenerate(generate);
    if (detect_cmd->parsed()) return quadfdi::cli::runDetect(detect);
    if (calibrate_cmd->parsed()) return quadfdi::cli::runCalibrate(calibrate);
    if (import_cmd->parsed()) return quadfdi::cli::runImport(import_options);
    std::string command_line = "quadfdi";
    for (int i = 1; i < argc; ++i) command_line += std::string(" ") + argv[i];
    if (evaluate_cmd->parsed()) return quadfdi::cli::runEvaluate(evaluate, command_line);
#ifdef QUADFDI_WITH_TRAINING
    if (train_cmd->parsed()) return quadfdi::cli::runTrain(train, command_line);
    if (reproduce_cmd->parsed()) return quadfdi::cli::runReproduce(reproduce, command_line);
    if (convert_cmd->parsed()) return quadfdi::cli::runConvertModel(convert);
#endif
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {  // usage: unknown flag, wrong number of values, no subcommand
    std::cerr << "quadfdi: error: " << e.what() << " (see --help)\n";
    return 2;
  } catch (const quadfdi::cli::Interrupted& e) {
    std::cerr << "quadfdi: interrupted: " << e.what() << "\n";
    return 130;
#ifdef QUADFDI_WITH_TRAINING
  } catch (const quadfdi::TrainingInterrupted& e) {
    std::cerr << "quadfdi: interrupted: " << e.what() << "\n";
    return 130;
#endif
  } catch (const std::exception& e) {
    std::cerr << "quadfdi: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
