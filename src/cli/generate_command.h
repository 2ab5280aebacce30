#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace quadfdi::cli {

// Filled by the option table (generate_command.cpp), the only place that names the flags.
struct GenerateOptions {
  std::string config;                // key = value file; flags given on the command line win
  std::string scale = "default";     // named scale (data/scales.h): initial conditions per iteration
  std::string controller = "lqr";    // lqr | cbf
  std::string controller_config;     // optional controller FILE
  std::string params = "nominal";    // plant: a named parameter set or a FILE
  std::string output_kind = "position-euler";  // position-euler | position-rates
  std::string integrator = "rk4";    // rk4 | euler
  std::vector<int> motors{2};        // faulty motors 1..4
  std::vector<double> thetas{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};  // [-]
  std::optional<int> initial_conditions;  // per iteration; empty: from the scale
  int iterations = 1;                // outer iterations' worth of data
  int window = 100;                  // T [samples]
  double preroll = 0.0;              // max random pre-roll [s]
  std::string randomise;             // randomisation FILE (docs/data.md#randomisation); empty: none
  double post_fault = 0.0;           // [s] recorded after the fault; 0 = T
  unsigned long long seed = 1;
  unsigned long long first_scenario = 0;  // index of the first scenario stream
  int threads = 0;                   // 0 = all cores
  std::string output;                // HDF5 file
  bool quiet = false;                // no progress bar or summary
  std::set<std::string> given;       // keys given explicitly (controller wins over the controller file)
};

// Declares the options (validated while CLI11 parses, --config included).
CLI::App* addGenerateCommand(CLI::App& app, GenerateOptions& options);
int runGenerate(const GenerateOptions& options);

}  // namespace quadfdi::cli
