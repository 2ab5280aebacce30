// Flight logs as input to `detect` and `import`: the options both share (one place), format
// detection from the content, and log file → reader → extractor → conventions layer. Errors are
// std::runtime_error with one line "FILE: byte OFFSET[, topic T]: problem" (reader) or
// "FILE: topic T: problem" (extractor, conventions layer).
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cli/options.h"
#include "core/motor_numbering.h"
#include "io/telemetry_reader.h"
#include "io/vehicle_file.h"
#include "logs/telemetry_from_log.h"

namespace quadfdi::cli {

struct LogInputOptions {
  std::string format = "auto";       // auto|csv|csv-merged|ulog|dataflash|crazyflie
  // Rates, thrust scaling and phase margins, filled by the flags directly (defaults and units
  // live in ImportOptions, logs/telemetry_from_log.h); dt and the hole limits are set per run.
  ImportOptions import;
  bool phases_by_rule = false;       // ignore the log's armed/landed events (import.use_events = false)
  int ekf_core = -1;                 // ArduPilot: −1 = the primary core the log names (XKF4 PI)
  std::string crazyflie_thrust = "auto";  // auto|duty|battery
  std::string vehicle;               // a vehicle description (docs/vehicles.md): max thrust, mass, thrust curve
  // Telemetry CSV (plain or merged): its frames and what its u1..u4 hold.
  std::string csv_frame = "zup";          // zup | ned: the frames of a CSV's position and attitude
  std::string csv_commands = "thrust";    // thrust | rotor-speed | throttle | pwm: what a CSV's u1..u4 hold
  double csv_pwm_min = 1000.0;            // [µs] --csv-commands pwm: the pulse at zero throttle
  double csv_pwm_max = 2000.0;            // [µs] --csv-commands pwm: the pulse at full throttle
  std::vector<std::string> csv_columns;   // COLUMN=HEADER: read quadfdi's column from the header's cell named so
  std::string csv_time_unit = "s";        // s | ms | us | ns: the unit of the t column
  std::string csv_angle_unit = "rad";     // rad | deg: the unit of the roll, pitch, yaw columns
  std::string csv_rate_unit = "rad/s";    // rad/s | deg/s: the unit of the p, q, r columns
  std::string csv_quaternion = "wxyz";    // wxyz | xyzw [-world-to-body]: how the qw..qz columns are read
  std::string csv_numbering = "quadfdi";  // quadfdi | vehicle: whose motor numbers a CSV's u1..u4 are in
  std::set<std::string> given;       // keys the command was given (its whole table): options a format does not read
};

// Declares --format, --vehicle, --max-thrust, --mass, --hover-calibrate, --min-rate-*, --settle-*,
// --phases-by-rule, --ekf-core, --cf-thrust-map in a command's option table (cli/options.h).
void addLogInputOptions(OptionTable& table, LogInputOptions& o);

// "csv", "csv-merged", "ulog", "dataflash" or "crazyflie": --format, else the file's first bytes (magic).
// Throws "FILE: unknown format: …" for a binary file with no known magic.
std::string resolveInputFormat(const std::string& path, const std::string& format);

// Refuses, in one line ("--flag: why"), the options above that `format`'s reader does not read:
// a telemetry CSV reads none (its u1..u4 are newtons already), ULog none of ArduPilot's or the
// Crazyflie's, and so on. Run with the format resolveInputFormat gave, before any work.
void refuseOptionsUnreadBy(const std::string& format, const LogInputOptions& o);

// The --vehicle description, read once per run and handed to the functions below (which read no
// file of their own): one read gives the whole run one description, whatever happens to the file
// meanwhile, and lets it be a pipe. nullopt without --vehicle; throws ConfigError "FILE:LINE:
// problem" for a broken one.
std::optional<VehicleDescription> describedVehicle(const LogInputOptions& o);

// How to read a telemetry CSV's cells (--csv-frame, --csv-commands, --csv-pwm-*; the thrust curve
// from `vehicle`, describedVehicle(o)). Throws ConfigError for a combination that cannot be read: a
// command quantity that needs the vehicle's curve without --vehicle, pulse limits without pulses, an
// empty range.
TelemetryReaderOptions csvReadingOptions(const LogInputOptions& o, const std::optional<VehicleDescription>& vehicle);

// The motors' numbering the run reports: the description's [motor.N] table, else quadfdi's. A log's
// or a CSV's own numbering replaces it where the caller reads one.
MotorNumbering vehicleNumbering(const std::optional<VehicleDescription>& vehicle);

// --csv-numbering vehicle: the CSV's u1..u4 are in the vehicle's numbering. Throws ConfigError
// without --vehicle (a flight log's refusal is refuseOptionsUnreadBy's). Run before any work.
// csvReadingOptions then reads the CSV's columns in quadfdi's order (TelemetryReaderOptions::file_motor).
bool csvInVehicleNumbering(const LogInputOptions& o);

struct OpenedLog {
  std::unique_ptr<LogSampleSource> source;
  std::vector<std::string> warnings;  // the reader's, "FILE: …"
};

// Reads, extracts and converts a log; `dt` is the model's period, `max_gap` the detector's; `vehicle`
// (describedVehicle(o)) gives the max thrust, mass and thrust curve where the flags and the log do not,
// and a merged CSV's numbering.
// "csv-merged": a telemetry CSV whose rows each hold some of the signals (io/merged_telemetry.h),
// read from `path` or standard input ("-") to its end as `csv_reading` says (csvReadingOptions, which
// the caller has already checked; unread for a flight log).
// `scale_free_model`: the model ignores a constant thrust scale (ImportOptions::scale_free_model);
// `read_rates`: the log's body rates are read (ImportOptions::read_rates; a merged CSV's by
// csv_reading.read_rates).
OpenedLog openFlightLog(const std::string& path, const std::string& format, const LogInputOptions& o,
                        const std::optional<VehicleDescription>& vehicle, const TelemetryReaderOptions& csv_reading, double dt, double max_gap, bool scale_free_model = false,
                        bool read_rates = true);

}  // namespace quadfdi::cli
