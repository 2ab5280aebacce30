// quadfdi-training: the commands that need LibTorch (train, reproduce, convert-model). quadfdi
// hands them over here with its arguments unchanged (cli/hand_over.cpp); it may also be run
// directly. Errors follow quadfdi's convention (cli/command_line.h).
#include <CLI/CLI.hpp>
#include <string>

#include "cli/command_line.h"
#include "cli/convert_model_command.h"
#include "cli/interrupt.h"
#include "cli/reproduce_command.h"
#include "cli/train_command.h"
#include "networks/trainer.h"

int main(int argc, char** argv) {
  CLI::App app{"quadfdi — the commands that train (LibTorch); quadfdi runs them here"};
  app.require_subcommand(1);
  app.set_version_flag("--version", quadfdi::cli::kVersion);
  quadfdi::cli::TrainOptions train;
  CLI::App* train_cmd = quadfdi::cli::addTrainCommand(app, train);
  quadfdi::cli::ReproduceOptions reproduce;
  CLI::App* reproduce_cmd = quadfdi::cli::addReproduceCommand(app, reproduce);
  quadfdi::cli::ConvertModelOptions convert;
  CLI::App* convert_cmd = quadfdi::cli::addConvertModelCommand(app, convert);
  return quadfdi::cli::runCommandLine(app, argc, argv, [&](const std::string& command_line) {
    // Training and the reproduction stop at a safe point on SIGINT/SIGTERM.
    if (train_cmd->parsed() || reproduce_cmd->parsed()) quadfdi::cli::interruptFlag();
    try {
      if (train_cmd->parsed()) return quadfdi::cli::runTrain(train, command_line);
      if (reproduce_cmd->parsed()) return quadfdi::cli::runReproduce(reproduce, command_line);
      if (convert_cmd->parsed()) return quadfdi::cli::runConvertModel(convert);
    } catch (const quadfdi::TrainingInterrupted& e) {
      throw quadfdi::cli::Interrupted(e.what());  // the same exit (130) as every interrupted command
    }
    return 0;
  });
}
