// Flight logs as input to `detect` and `import`: the options both share (one place), format
// detection from the content, and log file → reader → extractor → conventions layer. Errors are
// std::runtime_error with one line "FILE: byte OFFSET[, topic T]: problem" (reader) or
// "FILE: topic T: problem" (extractor, conventions layer).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "cli/options.h"
#include "logs/telemetry_from_log.h"

namespace quadfdi::cli {

struct LogInputOptions {
  std::string format = "auto";       // auto|csv|ulog|dataflash|crazyflie
  double max_thrust = 0.0;           // [N] per motor; 0: not given
  double mass = 0.0;                 // [kg]; 0: not given
  bool hover_calibrate = false;
  double min_rate_attitude = 125.0;  // [Hz]
  double min_rate_command = 125.0;   // [Hz]
  double min_rate_position = 20.0;   // [Hz]
  double settle_after_takeoff = 1.0; // [s]
  double settle_before_landing = 0.5;// [s]
  bool phases_by_rule = false;       // ignore the log's armed/landed events
  int ekf_core = 0;                  // ArduPilot
  std::string crazyflie_thrust = "auto";  // auto|duty|battery
};

// Declares --format, --max-thrust, --mass, --hover-calibrate, --min-rate-*, --settle-*,
// --phases-by-rule, --ekf-core, --cf-thrust-map in a command's option table (cli/options.h).
void addLogInputOptions(OptionTable& table, LogInputOptions& o);

// "csv", "ulog", "dataflash" or "crazyflie": --format, else the file's first bytes (magic).
// Throws "FILE: unknown format: …" for a binary file with no known magic.
std::string resolveInputFormat(const std::string& path, const std::string& format);

struct OpenedLog {
  std::unique_ptr<LogSampleSource> source;
  std::vector<std::string> warnings;  // the reader's, "FILE: …"
};

// Reads, extracts and converts a log; `dt` is the model's period, `max_gap` the detector's.
OpenedLog openFlightLog(const std::string& path, const std::string& format, const LogInputOptions& o, double dt,
                        double max_gap);

}  // namespace quadfdi::cli
