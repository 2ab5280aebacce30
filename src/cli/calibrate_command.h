#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "core/types.h"
#include "detection/calibration.h"

namespace quadfdi::cli {

struct CalibrateOptions {
  std::string config;               // --config FILE
  std::string model;                // empty: the shipped default model
  std::string output;               // calibration JSON (required)
  int flights = 20;                 // [-] healthy flights
  double flight_seconds = 60.0;     // [s] each
  double settle = 1.0;              // [s] each healthy flight's first seconds are not counted: its recovery from the random
                                    //     initial state (evaluation/flight_streams.h, kUpsetRecoverySeconds)
  double goal_period = 2.0;         // [s] a new goal from the sampling ranges this often
  int faulty_flights = 40;          // [-] for the model error of the Θ̂ estimate
  unsigned long long seed = 1;      // scenario streams 2⁴² + …, disjoint from training and test sets
  double false_alarms_per_hour = 0.1;  // [1/flight hour]
  std::vector<double> degraded_below{0.8};  // [-] the degraded level; with several, the one chosen on the faulty flights
                                           //     (evaluation/level_choice.h); 0.8 as detect's default (docs/decisions.md)
  double delay_budget = 0.3;        // [s] level choice: a fault counts when its motor is named this long after it (issue 14)
  double failed_below = 0.3;        // [-]
  std::string refit_interval;       // a calibration FILE: refit only its interval on the faulty flights, keeping the rest
  std::string interval = "spread";  // the Θ interval: spread (per range of the estimate) or belt (Neyman's, per Θ;
                                    //     detection/calibration.h fitThetaBelt)
  double degraded_cap = kDefaultDegradedCap;  // [effectiveness] degraded CUSUM's increment cap per sample (0: none)
  std::vector<double> failed_cap{0.0};  // [effectiveness] failed CUSUM's increment cap per sample (0: none, the plain Page
                                        //     CUSUM); with several, the one chosen on the faulty flights (level_choice.h)
  double failed_min_share = 0.0;        // [-] of the mean command: below it a motor takes no failed evidence (CommandGateConfig::
                                        //     failed_min_share; 0: off)
  double degraded_min_share = 0.0;      // [-] of the mean command: below it a motor takes no evidence at either level
                                        //     (CommandGateConfig::degraded_min_share; 0: off)
  double failed_delay_budget = 0.05;    // [s] cap choice: a fault below the failed level counts when its motor is named this
                                        //     long after it (issue 14's 50 ms)
  std::string reference = "others";  // the rule's input (detection/sequential.h ThetaReference): "others" calibrated the
                                     //     general model's degraded level at 0.9 with h 9.7 where absolute Θ̂ needed 17.8
                                     //     (docs/decisions.md "Relative evidence")
  std::string estimate_reference = "absolute";  // what the estimate reads: the relative estimate carried the siblings'
                                                //     errors (racer MAE at Θ 0.3–0.5 0.008 → 0.03–0.04, docs/decisions.md)
  double position_noise = 0.0;      // [m] sensor noise on the logged position
  double attitude_noise = 0.0;      // [rad] on the logged Euler angles
  std::string randomise;            // randomisation FILE: fly its vehicles, controllers, manoeuvres and estimator instead
  std::vector<std::string> vehicles;  // with --randomise: these vehicle description FILEs instead of the file's
  bool quiet = false;
  std::set<std::string> given;      // keys given explicitly: options this run would ignore are refused
};

CLI::App* addCalibrateCommand(CLI::App& app, CalibrateOptions& options);
int runCalibrate(const CalibrateOptions& options);

}  // namespace quadfdi::cli
