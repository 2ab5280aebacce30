// `quadfdi import LOG -o telemetry.csv`: a flight log (PX4 ULog, ArduPilot DataFlash, Crazyflie
// micro-SD) → our telemetry CSV on the model's clock, airborne phases only, and the import report
// (signals, rates, conventions, thrust scaling, phases).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "cli/log_input.h"

namespace quadfdi::cli {

struct ImportCommandOptions {
  std::string input;
  std::string config;         // --config FILE (keys as the long flags)
  std::string output = "-";
  std::string report;         // also write the report to this file; empty: none
  double dt = 0.002;          // [s] the model's period
  double max_gap = 0.02;      // [s] the detector's: holes longer than this are not bridged
  bool quiet = false;
  LogInputOptions log;
};

CLI::App* addImportCommand(CLI::App& app, ImportCommandOptions& options);
int runImport(const ImportCommandOptions& options);

}  // namespace quadfdi::cli
