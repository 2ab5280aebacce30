#include "cli/convert_model_command.h"

#include <cstdio>

#include "cli/command_line.h"
#include "io/model_file.h"
#include "networks/model.h"

namespace quadfdi::cli {

CLI::App* addConvertModelCommand(CLI::App& app, ConvertModelOptions& o) {
  CLI::App* cmd = app.add_subcommand("convert-model", trainingCommand("convert-model")->description);
  cmd->add_option("input", o.input, "The .qfdi archive")->required();
  cmd->add_option("output", o.output, "The .qfdw file to write")->required();
  return cmd;
}

int runConvertModel(const ConvertModelOptions& o) {
  const FaultIdentifier model = FaultIdentifier::load(o.input);
  writeModelFile(o.output, model.metadata(), exportWeights(model));
  const TrainedModel check = readModelFile(o.output);  // what was written reads back
  std::fprintf(stderr, "convert-model: %s → %s (%s, %s, T = %d)\n", o.input.c_str(), o.output.c_str(),
               toString(check.metadata.architecture), toString(check.metadata.features), check.metadata.window);
  return 0;
}

}  // namespace quadfdi::cli
