#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace quadfdi::cli {

struct EvaluateOptions {
  std::string model_free;   // model files by role
  std::string model_based;
  std::string residual;
  std::string mlp;
  std::vector<std::string> experiments{"e1", "e3", "e4", "e5", "e6"};
  std::string scale = "quick";
  unsigned long long seed = 7;
  double theta_tol = 0.2;
  int threads = 0;
  std::string output = "evaluation";
  bool quiet = false;
};

CLI::App* addEvaluateCommand(CLI::App& app, EvaluateOptions& options);
int runEvaluate(const EvaluateOptions& options, const std::string& command_line);

}  // namespace quadfdi::cli
