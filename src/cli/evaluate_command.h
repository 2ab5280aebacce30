#pragma once

#include <CLI/CLI.hpp>
#include <set>
#include <string>
#include <vector>

namespace quadfdi::cli {

// Filled by the option table (evaluate_command.cpp), the only place that names the flags; reproduce
// fills it directly.
struct EvaluateOptions {
  std::string config;       // key = value file; flags given on the command line win
  std::string model_free;   // model files by role; empty: experiments needing it are not run
  std::string model_based;
  std::string residual;
  std::string mlp;
  std::vector<std::string> experiments{"e1", "e3", "e4", "e5", "e6"};
  std::string scale = "quick";  // named scale (data/scales.h): test flights per class
  unsigned long long seed = 7;  // test-set seed
  double theta_tol = 0.2;       // alarm threshold on min_k Θ̂_k [-]
  int average_windows = 1;      // [windows] E1–E6 decide on the mean Θ̂ of a flight's last this many (1: each alone)
  int threads = 0;              // 0 = all cores
  std::string output = "evaluation";  // folder
  // E7 (transfer matrix) and `decisions` (severity, delay against Θ, false alarms per flight hour):
  std::vector<std::string> vehicles{"configs/vehicles/crazyflie2.toml", "configs/vehicles/racer250.toml",
                                    "configs/vehicles/quad450.toml"};  // description FILEs
  std::string randomise = "configs/randomisation-default.toml";  // `decisions`: the healthy flights' randomisation
  std::string calibration;      // sequential rule's calibration JSON; default MODEL.calibration.json, else defaults
  int flights_per_class = 0;    // [flights] E7 per (motor, Θ); 0: from --scale
  double flight_hours = 0.0;    // [h] `decisions`: healthy flight time; 0: from --scale
  int faulty_per_theta = 0;     // [flights] `decisions`: faulty flights per (vehicle, Θ); 0: 4 × flights_per_class
  double log_rate = 0.0;        // [Hz] E7, `decisions`: the telemetry logged at this rate and resampled as detect does; 0: every model sample
  bool quiet = false;           // no progress
  std::set<std::string> given;  // keys given explicitly: options the chosen experiments ignore are refused
};

// Declares the options (validated while CLI11 parses).
CLI::App* addEvaluateCommand(CLI::App& app, EvaluateOptions& options);
int runEvaluate(const EvaluateOptions& options, const std::string& command_line);

}  // namespace quadfdi::cli
