// quadfdi: thin executable over the libraries; all errors end here as one line.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "cli/detect_command.h"
#include "cli/evaluate_command.h"
#include "cli/generate_command.h"
#include "cli/interrupt.h"
#include "cli/reproduce_command.h"
#include "cli/simulate_command.h"
#include "cli/train_command.h"
#include "networks/trainer.h"

int main(int argc, char** argv) {
  CLI::App app{"quadfdi — detect, isolate and size motor faults on quadrotors (Garg & Fan, dynamic symmetry)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "quadfdi 0.1.0");
  quadfdi::cli::SimulateOptions simulate;
  CLI::App* simulate_cmd = quadfdi::cli::addSimulateCommand(app, simulate);
  quadfdi::cli::GenerateOptions generate;
  CLI::App* generate_cmd = quadfdi::cli::addGenerateCommand(app, generate);
  quadfdi::cli::TrainOptions train;
  CLI::App* train_cmd = quadfdi::cli::addTrainCommand(app, train);
  quadfdi::cli::EvaluateOptions evaluate;
  CLI::App* evaluate_cmd = quadfdi::cli::addEvaluateCommand(app, evaluate);
  quadfdi::cli::ReproduceOptions reproduce;
  CLI::App* reproduce_cmd = quadfdi::cli::addReproduceCommand(app, reproduce);
  quadfdi::cli::DetectOptions detect;
  CLI::App* detect_cmd = quadfdi::cli::addDetectCommand(app, detect);
  try {
    // Parsing also resolves the converted commands' option tables (cli/options.h): a bad value,
    // or a bad --config file, throws a one-line OptionError / ConfigError, reported below (exit 1).
    app.parse(argc, argv);
    // The long-running commands stop at a safe point on SIGINT/SIGTERM; the others keep the default.
    if (generate_cmd->parsed() || train_cmd->parsed() || evaluate_cmd->parsed() || reproduce_cmd->parsed())
      quadfdi::cli::interruptFlag();
    if (simulate_cmd->parsed()) return quadfdi::cli::runSimulate(simulate);
    if (generate_cmd->parsed()) return quadfdi::cli::runGenerate(generate);
    if (detect_cmd->parsed()) return quadfdi::cli::runDetect(detect);
    std::string command_line = "quadfdi";
    for (int i = 1; i < argc; ++i) command_line += std::string(" ") + argv[i];
    if (train_cmd->parsed()) return quadfdi::cli::runTrain(train, command_line);
    if (evaluate_cmd->parsed()) return quadfdi::cli::runEvaluate(evaluate, command_line);
    if (reproduce_cmd->parsed()) return quadfdi::cli::runReproduce(reproduce, command_line);
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
  } catch (const quadfdi::TrainingInterrupted& e) {
    std::cerr << "quadfdi: interrupted: " << e.what() << "\n";
    return 130;
  } catch (const std::exception& e) {
    std::cerr << "quadfdi: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
