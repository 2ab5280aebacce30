#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace quadfdi::cli {

struct TrainOptions {
  std::string config;
  std::string scale = "default";
  std::string architecture = "lstm";
  std::string features = "model-free";
  std::string output_kind = "position-euler";
  std::string symmetry = "exact";
  std::string loss = "norm";
  std::string controller = "lqr";
  std::string params = "nominal";
  std::vector<double> thetas{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  int batch_size = 0;       // 0: from the scale
  int passes = 0;
  int max_minibatches = -1;
  int min_iterations = -1;
  int max_iterations = -1;
  double preroll = 0.0;
  int heldout_initial_conditions = 0;  // 0: from the scale
  unsigned long long seed = 1;
  std::string device = "cpu";
  int threads = 0;
  std::string output;
  std::string checkpoint;   // default: <output>.ckpt
  std::string log;          // default: <output>.log.csv
  bool resume = false;
  bool quiet = false;
};

CLI::App* addTrainCommand(CLI::App& app, TrainOptions& options);
int runTrain(TrainOptions options, const CLI::App& command, const std::string& command_line);
// Trains with fully resolved options (no config file) and writes options.output.
int trainAndSave(const TrainOptions& options, const std::string& command_line);

}  // namespace quadfdi::cli
