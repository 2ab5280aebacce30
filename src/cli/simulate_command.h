#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace quadfdi::cli {

struct SimulateOptions {
  std::string controller = "lqr";
  std::string params = "nominal";
  std::string controller_params;  // empty: same as params
  std::string lqr_weights = "bryson";
  std::string controller_config;  // optional file
  int motor = 0;                  // 0: healthy
  double theta = 0.0;
  int fault_step = 500;
  int steps = 1000;
  unsigned long long seed = 1;
  std::string integrator = "rk4";
  std::string output = "-";
  bool full_state = false;
  std::vector<double> goal;       // optional override, 3 values
  std::vector<double> start;      // optional override, 12 values
  double position_noise = 0.0;
  double attitude_noise = 0.0;
  double cbf_min_altitude = 0.5;
  double cbf_max_tilt = 0.5;
  bool quiet = false;
};

CLI::App* addSimulateCommand(CLI::App& app, SimulateOptions& options);
// Runs the command; throws std::runtime_error / ConfigError with a one-line message on bad input.
int runSimulate(const SimulateOptions& options, const CLI::App& command);

}  // namespace quadfdi::cli
