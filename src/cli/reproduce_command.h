#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace quadfdi::cli {

// Filled by the option table (reproduce_command.cpp), the only place that names the flags.
struct ReproduceOptions {
  std::string config;                   // key = value file; flags given on the command line win
  std::string scale = "quick";          // named scale (data/scales.h): training schedule and test sets
  std::string output = "reproduction";  // folder
  unsigned long long seed = 1;          // training seed
  int threads = 0;                      // 0 = all cores
  std::string device = "cpu";           // cpu | cuda (training)
  bool quiet = false;                   // less output
};

// Declares the options (validated while CLI11 parses).
CLI::App* addReproduceCommand(CLI::App& app, ReproduceOptions& options);
int runReproduce(const ReproduceOptions& options, const std::string& command_line);

}  // namespace quadfdi::cli
