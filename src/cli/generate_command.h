#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace quadfdi::cli {

struct GenerateOptions {
  std::string config;            // key = value file; flags given on the command line win
  std::string scale = "default";  // tiny | default | paper: initial conditions per iteration
  std::string controller = "lqr";
  std::string controller_config;
  bool controller_given = false;  // --controller or the config's `controller` key: wins over the controller file
  std::string params = "nominal";
  std::string output_kind = "position-euler";
  std::string integrator = "rk4";
  std::vector<int> motors{2};
  std::vector<double> thetas{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  int initial_conditions = 0;    // 0: from the scale
  int iterations = 1;
  int window = 100;
  double preroll = 0.0;          // [s] max random pre-roll
  unsigned long long seed = 1;
  unsigned long long first_scenario = 0;
  int threads = 0;
  std::string output;
  bool quiet = false;
};

CLI::App* addGenerateCommand(CLI::App& app, GenerateOptions& options);
int runGenerate(GenerateOptions options, const CLI::App& command);

// Initial conditions per outer iteration for a named scale; -1 if unknown.
int scaleInitialConditions(const std::string& scale);

}  // namespace quadfdi::cli
