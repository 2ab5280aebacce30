#pragma once

#include <CLI/CLI.hpp>
#include <set>
#include <string>
#include <vector>

namespace quadfdi::cli {

// Filled by the option table (simulate_command.cpp), the only place that names the flags.
struct SimulateOptions {
  std::string config;                   // key = value file; flags given on the command line win
  std::string controller = "lqr";       // lqr | cbf | pid
  std::string params = "nominal";       // plant: a named parameter set or a FILE
  std::string controller_params;        // design model, same forms; empty: same as params
  std::string lqr_weights = "bryson";   // bryson | authors
  std::string controller_config;        // optional controller FILE
  int motor = 0;                        // faulty motor 1..4; 0: healthy
  double theta = 0.0;                   // effectiveness after the fault [-]
  int fault_step = 500;                 // [steps]
  int steps = 1000;                     // [steps]
  unsigned long long seed = 1;          // initial condition, goal and noise draw
  std::string integrator = "rk4";       // rk4 | euler
  std::string output = "-";             // CSV path; - = standard output
  bool full_state = false;              // append state and applied-thrust columns
  bool rates = false;                   // append the logged body rates p,q,r alone
  std::vector<double> goal;             // override [m], 3 values; empty: sampled
  std::vector<double> start;            // override, 12 state values (SI); empty: sampled
  double position_noise = 0.0;          // std. dev. [m]
  double attitude_noise = 0.0;          // std. dev. [rad]
  double rate_noise = 0.0;              // std. dev. [rad/s] on the logged body rates
  double rotor_drag = 0.0;              // [1/s] linear rotor drag per unit mass; 0: the parameter set's linear_drag
  double wind_speed = 0.0;              // [m/s] steady wind
  double wind_direction = 0.0;          // [rad] world heading the wind blows toward
  double turbulence = 0.0;              // [m/s] horizontal std of the turbulence
  double turbulence_tau = 1.0;          // [s] its correlation time
  double gust_rate = 0.0;               // [1/s] discrete gusts per second
  double gust_peak = 0.0;               // [m/s] largest gust peak
  double gust_duration = 1.0;           // [s]
  std::string trajectory = "hover";     // hover | point-to-point | circle | figure-eight
  double speed = 1.0;                   // [m/s] trajectory (peak) speed
  double radius = 1.0;                  // [m] circle radius, figure-eight half-length
  std::string yaw_mode = "fixed";       // fixed | velocity
  double facing_yaw_rate_max = 0.0;     // [rad/s] --yaw-mode velocity on a circle: the nose's slew limit; 0: none
  std::vector<double> yaw_sweep;        // amplitude [rad], period [s]; empty: none
  double cbf_min_altitude = 0.5;        // [m]
  double cbf_max_tilt = 0.5;            // [rad]
  bool quiet = false;                   // no summary on stderr
  std::set<std::string> given;          // keys given explicitly (they win over --controller-config)
};

// Declares the options (validated while CLI11 parses: bad values throw "--flag: problem").
CLI::App* addSimulateCommand(CLI::App& app, SimulateOptions& options);
// Runs the command; throws std::runtime_error / ConfigError with a one-line message on bad input.
int runSimulate(const SimulateOptions& options);

}  // namespace quadfdi::cli
