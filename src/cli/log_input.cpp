#include "cli/log_input.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include "io/file_bytes.h"
#include "io/key_value.h"
#include "io/merged_telemetry.h"
#include "io/vehicle_file.h"
#include "logs/ardupilot_signals.h"
#include "logs/crazyflie_signals.h"
#include "logs/crazyflie_usd.h"
#include "logs/dataflash.h"
#include "logs/dataflash_text.h"
#include "logs/log_magic.h"
#include "logs/px4_signals.h"
#include "logs/ulog.h"

namespace quadfdi::cli {

void addLogInputOptions(OptionTable& t, LogInputOptions& o) {
  t.recordGivenIn(o.given);
  t.add("--format", o.format,
        "Input format: auto (from the content: ULog, DataFlash or Crazyflie magic, else CSV), csv, csv-merged (a "
        "telemetry CSV whose rows each hold only some signals, as PlotJuggler or a ROS bag export them: each signal "
        "read from the rows that hold it, then put on the model's clock as a log's), ulog, dataflash, crazyflie")
      .choices({"auto", "csv", "csv-merged", "ulog", "dataflash", "crazyflie"});
  t.add("--vehicle", o.vehicle,
        "Logs with thrust-fraction commands: a vehicle description FILE (docs/vehicles.md), or a library vehicle's name "
        "(crazyflie2, racer250, quad450: configs/vehicles/NAME.toml, wherever quadfdi runs from); its max thrust and mass "
        "stand in for --max-thrust and --mass where those are not given, and its thrust curve for THR_MDL_FAC / "
        "MOT_THST_EXPO where the log has none; detect also runs the vehicle's own shipped model (models/tcn-STEM.qfdw) when "
        "there is one")
      .defaultText("").vehicleFile();
  t.add("--csv-frame", o.csv_frame,
        "Telemetry CSV: the frames of its position and attitude: zup (quadfdi's: world z up, body x forward, y left, z "
        "up) or ned (world north, east, down, body forward, right, down: PX4, ArduPilot, AirSim, PX4's Gazebo bridge); "
        "either way the attitude may be roll,pitch,yaw (ZYX Euler) or qw,qx,qy,qz (quaternion, body → world)")
      .choices({"zup", "ned"});
  t.add("--csv-commands", o.csv_commands,
        "Telemetry CSV: what u1..u4 hold: thrust (commanded thrust per motor [N]); rotor-speed (commanded rotor "
        "speed in any unit — rad/s, RPM, a fraction of the maximum — as simulators write it: read as its square, "
        "which a fixed-pitch propeller's thrust is proportional to; needs a scale-free model, as every shipped one is); "
        "throttle (the motor command in [0, 1]) or pwm (the ESC pulse [µs]): both through the --vehicle "
        "description's thrust curve ([thrust] max and model_factor)")
      .choices({"thrust", "rotor-speed", "throttle", "pwm"});
  t.add("--csv-pwm-min", o.csv_pwm_min, "--csv-commands pwm: the pulse at zero throttle [µs]").atLeast(0.0);
  t.add("--csv-pwm-max", o.csv_pwm_max, "--csv-commands pwm: the pulse at full throttle [µs]").above(0.0);
  t.add("--csv-columns", o.csv_columns,
        "Telemetry CSV: columns named otherwise in the header, as COLUMN=NAME (e.g. t=__time "
        "x=/mavros/local_position/pose/pose/position/x u1=/motors/0), COLUMN one of t, x, y, z, roll, pitch, yaw, qw, qx, qy, "
        "qz, u1..u4, p, q, r")
      .check([](const std::string& text) -> std::string {
        const std::size_t eq = text.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) return "'" + text + "' is not COLUMN=NAME";
        const std::string column = text.substr(0, eq);
        for (const char* c : TelemetryReader::kColumns)
          if (column == c) return "";
        return "'" + column + "' is no telemetry column (t, x, y, z, roll, pitch, yaw, qw, qx, qy, qz, u1, u2, u3, u4, p, q, r)";
      })
      .defaultText("");
  t.add("--csv-time-unit", o.csv_time_unit,
        "Telemetry CSV: the unit of t: s, ms, us or ns (a ROS time stamp); seconds since 1970 are fine as s, an ISO 8601 "
        "date and time has its own; a unit in the header ('t [ms]') says the same")
      .choices({"s", "ms", "us", "ns"});
  t.add("--csv-angle-unit", o.csv_angle_unit,
        "Telemetry CSV: the unit of roll, pitch, yaw: rad or deg (a quaternion has none); a unit in the header "
        "('roll [deg]') says the same. Small angles in degrees read as radians pass the range check and tilt the vehicle "
        "57 times too far: say so")
      .choices({"rad", "deg"});
  t.add("--csv-rate-unit", o.csv_rate_unit,
        "Telemetry CSV: the unit of the optional body rates p, q, r (read by models on scale-free-rates features): rad/s "
        "or deg/s; a unit in the header ('p [deg/s]') says the same")
      .choices({"rad/s", "deg/s"});
  t.add("--csv-quaternion", o.csv_quaternion,
        "Telemetry CSV: how its qw,qx,qy,qz columns hold the attitude quaternion: wxyz (Hamilton, scalar first, body → "
        "world: PX4, ArduPilot, the Crazyflie) or xyzw (scalar last: Eigen's coeffs(), ROS messages, SciPy's as_quat()), "
        "either with -world-to-body for the inverse rotation (some estimators, JPL-convention filters); detect checks the "
        "reading against the flight and names a better one (docs/conventions.md)")
      .choices({"wxyz", "xyzw", "wxyz-world-to-body", "xyzw-world-to-body"});
  t.add("--csv-numbering", o.csv_numbering,
        "Telemetry CSV: whose motor numbers u1..u4 are in: quadfdi (1 front-right, 2 back-right, 3 back-left, 4 "
        "front-left) or vehicle (the --vehicle description's [motor.N] numbering, e.g. PX4's, as a simulator of that "
        "autopilot writes them; for a plus or props-out frame the attitude and p,q,r are then in its own body axes, "
        "read turned onto the X: docs/vehicles.md); detect's outputs keep quadfdi's `motor` and add the vehicle's `autopilot_motor`, and "
        "import writes u1..u4 in quadfdi's order with the vehicle's numbers in its '# motor_numbering' comment")
      .choices({"quadfdi", "vehicle"});
  t.add("--max-thrust", o.import.max_thrust, "Logs with thrust-fraction commands (PX4, ArduPilot): the motor's maximum thrust [N per motor]; detect with a "
        "scale-free model (the default) needs no scale")
      .atLeast(0.0)
      .defaultText("");
  t.add("--mass", o.import.mass,
        "Logs with thrust-fraction commands: the vehicle's mass [kg]; without --max-thrust the thrust scale is "
        "calibrated from the log's own steady hover")
      .atLeast(0.0)
      .defaultText("");
  t.add("--hover-calibrate", o.import.hover_calibrate,
        "Calibrate the thrust scale from the log's steady hover even when --max-thrust is given (needs --mass)");
  t.add("--min-rate-attitude", o.import.min_rate_attitude, "Refuse logs whose attitude is logged slower than this [Hz] (90 reads a 100 Hz log, at the cost in docs/results/log-rates)").above(0.0);
  t.add("--min-rate-command", o.import.min_rate_command, "Refuse logs whose motor commands are logged slower than this [Hz] (as --min-rate-attitude)").above(0.0);
  t.add("--min-rate-position", o.import.min_rate_position, "Refuse logs whose position is logged slower than this [Hz]").above(0.0);
  t.add("--settle-after-takeoff", o.import.settle_after_takeoff, "Skipped after each take-off [s]").atLeast(0.0);
  t.add("--settle-before-landing", o.import.settle_before_landing, "Skipped before each controlled landing [s]").atLeast(0.0);
  t.add("--phases-by-rule", o.phases_by_rule, "Find airborne phases from height and thrust even when the log has armed/landed events");
  t.add("--ekf-core", o.ekf_core, "ArduPilot: the EKF core whose position is used").range(0, 255).defaultText("the primary core, as XKF4 PI names it over the flight");
  t.add("--cf-thrust-map", o.crazyflie_thrust,
        "Crazyflie: motor command → thrust: auto (battery model when pwm.* and pm.vbatMV are logged), duty, battery")
      .choices({"auto", "duty", "battery"});
}

void refuseOptionsUnreadBy(const std::string& format, const LogInputOptions& o) {
  const bool csv = format == "csv" || format == "csv-merged";
  if (!csv) {
    // The message names what reads the flag instead: the log's own conventions.
    refuseGiven(o.given, {"csv_frame"}, "reads a telemetry CSV; a " + format + " log's frames are its autopilot's, which quadfdi knows");
    refuseGiven(o.given, {"csv_commands", "csv_pwm_min", "csv_pwm_max"},
                "reads a telemetry CSV; a " + format + " log's commands are converted by its reader");
    refuseGiven(o.given, {"csv_columns", "csv_time_unit", "csv_angle_unit", "csv_rate_unit", "csv_quaternion"},
                "reads a telemetry CSV; a " + format + " log names its own fields and units");
    refuseGiven(o.given, {"csv_numbering"}, "reads a telemetry CSV; a " + format + " log carries its autopilot's own motor numbering");
  }
  if (format == "csv") {
    refuseGiven(o.given,
                {"max_thrust", "mass", "hover_calibrate", "min_rate_attitude", "min_rate_command", "min_rate_position",
                 "settle_after_takeoff", "settle_before_landing", "phases_by_rule", "ekf_core", "cf_thrust_map"},
                "reads flight logs (ULog, DataFlash, Crazyflie micro-SD) and merged CSV exports (--format csv-merged); a "
                "telemetry CSV's u1..u4 are newtons per motor already (docs/conventions.md)");
    return;
  }
  if (format == "csv-merged") {
    refuseGiven(o.given, {"max_thrust", "mass", "hover_calibrate", "ekf_core", "cf_thrust_map"},
                "reads flight logs (ULog, DataFlash, Crazyflie micro-SD); a merged CSV's u1..u4 are read as --csv-commands says");
    return;
  }
  if (format != "dataflash") refuseGiven(o.given, {"ekf_core"}, "is ArduPilot's (DataFlash); this log is " + format);
  if (format != "crazyflie") refuseGiven(o.given, {"cf_thrust_map"}, "is the Crazyflie's; this log is " + format);
  if (format == "crazyflie")
    refuseGiven(o.given, {"max_thrust", "mass", "hover_calibrate"},
                "scales thrust-fraction commands; a Crazyflie log's commands become newtons through the firmware's thrust "
                "map (--cf-thrust-map)");
  else if (o.given.count("max_thrust") && !o.import.hover_calibrate)
    refuseGiven(o.given, {"mass"}, "unused with --max-thrust unless --hover-calibrate (which calibrates the scale from the hover)");
}

std::optional<VehicleDescription> describedVehicle(const LogInputOptions& o) {
  if (o.vehicle.empty()) return std::nullopt;
  // Read once, so a pipe (`--vehicle <(…)`) serves as well as a file.
  return loadVehicleDescription(o.vehicle, PipeReading::kRead);  // throws "FILE:LINE: problem"
}

TelemetryReaderOptions csvReadingOptions(const LogInputOptions& o, const std::optional<VehicleDescription>& vehicle) {
  TelemetryReaderOptions r;
  r.frame = o.csv_frame == "ned" ? TelemetryFrame::kNed : TelemetryFrame::kZUp;
  r.commands = o.csv_commands == "rotor-speed" ? CommandQuantity::kRotorSpeed
               : o.csv_commands == "throttle"  ? CommandQuantity::kThrottle
               : o.csv_commands == "pwm"       ? CommandQuantity::kPwm
                                               : CommandQuantity::kThrust;
  if ((r.commands == CommandQuantity::kThrottle || r.commands == CommandQuantity::kPwm) && !vehicle)
    throw quadfdi::ConfigError("--csv-commands " + o.csv_commands + ": needs --vehicle FILE, whose [thrust] max and model_factor "
                      "turn the motor command into newtons (docs/vehicles.md)");
  if (r.commands != CommandQuantity::kPwm) refuseGiven(o.given, {"csv_pwm_min", "csv_pwm_max"}, "is read only with --csv-commands pwm");
  if (o.csv_pwm_max <= o.csv_pwm_min) throw quadfdi::ConfigError("--csv-pwm-max must be above --csv-pwm-min");
  if (vehicle) {
    r.curve.max_thrust = vehicle->params.max_thrust;
    r.curve.model_factor = vehicle->params.thrust_model_factor;
    if (csvInVehicleNumbering(o)) {  // the airframe's own numbering and axes, read in quadfdi's
      r.file_motor = vehicle->autopilot_motor_of_quadfdi_motor;
      r.body_turn = vehicle->body_turn;
    }
  }
  r.curve.pwm_min = o.csv_pwm_min;
  r.curve.pwm_max = o.csv_pwm_max;
  std::set<std::string> renamed;
  for (const std::string& pair : o.csv_columns) {  // COLUMN=NAME, checked by the option
    const std::size_t eq = pair.find('=');
    if (!renamed.insert(pair.substr(0, eq)).second)
      throw quadfdi::ConfigError("--csv-columns: column '" + pair.substr(0, eq) + "' is named twice");
    r.header_names.emplace_back(pair.substr(0, eq), pair.substr(eq + 1));
  }
  r.time_unit = secondsPerTimeUnit(o.csv_time_unit);  // one of s, ms, us, ns (the option's choices)
  r.angles_in_degrees = o.csv_angle_unit == "deg";
  r.rates_in_degrees = o.csv_rate_unit == "deg/s";
  r.quaternion.scalar_last = o.csv_quaternion.rfind("xyzw", 0) == 0;
  r.quaternion.world_to_body = o.csv_quaternion.find("world-to-body") != std::string::npos;
  return r;
}

MotorNumbering vehicleNumbering(const std::optional<VehicleDescription>& vehicle) {
  MotorNumbering numbering;
  if (!vehicle) return numbering;
  numbering.name = vehicle->motor_numbering.substr(0, vehicle->motor_numbering.find(" ("));
  numbering.autopilot_motor = vehicle->autopilot_motor_of_quadfdi_motor;
  numbering.body_turn = vehicle->body_turn;
  return numbering;
}

bool csvInVehicleNumbering(const LogInputOptions& o) {
  const bool renumber = o.csv_numbering == "vehicle";
  if (renumber && o.vehicle.empty())
    throw quadfdi::ConfigError("--csv-numbering vehicle: needs --vehicle FILE, whose [motor.N] sections give the numbering");
  return renumber;
}

namespace {

std::string where(const std::string& path, const LogIssue& issue, bool with_offset) {
  std::string s = path + ": ";
  if (issue.line > 0) s += "line " + std::to_string(issue.line) + (issue.topic.empty() ? ": " : ", ");
  else if (with_offset) s += "byte " + std::to_string(issue.offset) + (issue.topic.empty() ? ": " : ", ");
  if (!issue.topic.empty()) s += "topic " + issue.topic + ": ";
  return s + issue.message;
}

}  // namespace

std::string resolveInputFormat(const std::string& path, const std::string& format) {
  if (format != "auto" && format != "csv" && format != "csv-merged") return format;
  if (path == "-") return format == "auto" ? "csv" : format;
  std::error_code ignored;  // a folder opens, and reads as an empty file: say what it is
  const std::filesystem::file_status status = std::filesystem::status(path, ignored);
  if (std::filesystem::is_directory(status)) throw std::runtime_error(path + ": is a folder, not a flight log or telemetry CSV");
  // A pipe (`<(zcat log.ulg.gz)`) gives its bytes once: the magic read here would be missing from the read that follows.
  if (std::filesystem::is_fifo(status)) {
    if (format != "auto") return format;
    throw std::runtime_error(path + ": a pipe: its format cannot be told from its first bytes without losing them; "
                             "name it with --format (ulog, dataflash, crazyflie, csv or csv-merged)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) throw std::runtime_error(path + ": cannot open");
  std::vector<std::uint8_t> head(512);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const ByteSpan span{head.data(), head.size()};
  const char* magic = logFormatOfMagic(span);
  if (magic && format != "auto")
    throw std::runtime_error(path + ": byte 0: --format " + format + ", but the file starts with the " + magic +
                             " magic; use --format auto or " + magic);
  if (magic) return magic;
  if (format != "auto") return format;
  if (looksBinary(span))
    throw std::runtime_error(path + ": unknown format: binary, but no ULog, DataFlash or Crazyflie micro-SD magic at "
                             "byte 0 (and not CSV telemetry); --format names one");
  return "csv";
}

namespace {

// The conventions layer's options for this run: the flags', the model's period, the detector's gap.
ImportOptions importOptions(const LogInputOptions& o, double dt, double max_gap) {
  quadfdi::ImportOptions io = o.import;
  io.dt = dt;
  io.use_events = !o.phases_by_rule;
  io.max_hole = max_gap;
  io.restart_gap = max_gap;
  return io;
}

// A merged telemetry CSV: its signals from the rows that hold them, then the conventions layer.
// A merged CSV read in the vehicle's numbering (--csv-numbering vehicle; TelemetryReaderOptions::
// file_motor reordered its columns): the report names the vehicle's motors and how they were read.
void inVehicleNumbering(FlightSignals& s, const MotorNumbering& vehicle) {
  s.numbering = vehicle;
  std::string columns;
  for (std::size_t k = 0; k < kMotors; ++k)
    columns += (k ? ", " : "") + std::to_string(k + 1) + " ← u" + std::to_string(vehicle.autopilot_motor[k]);
  s.conventions.push_back("u1..u4 in the vehicle's numbering (" + vehicle.name + ", --csv-numbering vehicle), put in quadfdi's (motor ← column): " + columns);
}

OpenedLog openMergedCsv(const std::string& path, const LogInputOptions& o, const std::optional<VehicleDescription>& vehicle,
                        const TelemetryReaderOptions& reading, double dt, double max_gap) {
  const ImportOptions io = importOptions(o, dt, max_gap);  // its u1..u4 are newtons: no thrust scale
  std::ifstream file;
  if (path != "-") {
    file.open(path);
    if (!file.is_open()) throw std::runtime_error(path + ": cannot open");
  }
  const std::string name = path == "-" ? "<stdin>" : path;
  TelemetryReaderOptions unturned = reading;  // a plus or props-out frame's axes are turned by the conventions layer
  unturned.body_turn = {};
  TelemetryReader reader(path == "-" ? std::cin : file, name, unturned);  // throws on an empty file or a bad header
  FlightSignals signals;
  const MergedTelemetryCounts counts = readMergedTelemetry(reader, signals);
  if (csvInVehicleNumbering(o)) inVehicleNumbering(signals, vehicleNumbering(vehicle));
  OpenedLog opened;
  if (counts.without_time > 0 || counts.partial > 0)
    opened.warnings.push_back(std::to_string(counts.without_time) + " row(s) without a time skipped, " +
                              std::to_string(counts.partial) + " signal(s) left out of a row for an empty or non-finite cell "
                              "among its others (first: " + counts.first_problem + ")");
  opened.source = std::make_unique<LogSampleSource>();
  const ImportRefusal refusal = buildLogSampleSource(std::move(signals), LogFormat::kMergedCsv, io, *opened.source);
  if (refusal.refused())
    throw std::runtime_error(name + ": " + refusal.message);  // the message names the columns
  opened.source->setName(name);
  return opened;
}

}  // namespace

OpenedLog openFlightLog(const std::string& path, const std::string& format, const LogInputOptions& o,
                        const std::optional<VehicleDescription>& vehicle, const TelemetryReaderOptions& csv_reading, double dt,
                        double max_gap, bool scale_free_model, bool read_rates) {
  if (format == "csv-merged") return openMergedCsv(path, o, vehicle, csv_reading, dt, max_gap);
  // A log piped in (`zcat log.ulg.gz | quadfdi detect --format ulog`) is read whole, as a file is.
  const bool piped = path == "-";
  const std::string name = piped ? "<stdin>" : path;
  const std::string bytes = piped ? readStandardInputBounded(kMaxLogFileBytes, "a flight log")
                                  : readFileBounded(path, kMaxLogFileBytes, "a flight log", PipeReading::kRead);
  const ByteSpan span{reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()};
  DecodedLog log;
  LogIssue issue;
  const bool dataflash_text = format == "dataflash" && looksLikeDataflashText(span);
  if (format == "ulog") issue = readUlog(span, log);
  else if (format == "dataflash") issue = dataflash_text ? readDataflashText(span, log) : readDataflash(span, log);
  else if (format == "crazyflie") issue = readCrazyflieUsd(span, log);
  else throw std::runtime_error(name + ": unknown format '" + format + "'");
  if (!issue.ok()) throw std::runtime_error(where(name, issue, true));

  OpenedLog opened;
  for (const std::string& w : log.warnings) opened.warnings.push_back(name + ": " + w);

  ImportOptions io = importOptions(o, dt, max_gap);
  io.scale_free_model = scale_free_model;
  io.read_rates = read_rates;
  double thrust_model_factor = -1.0;  // [-] the vehicle description's, < 0 without one
  if (vehicle) {
    if (!(io.max_thrust > 0.0)) io.max_thrust = vehicle->params.max_thrust;
    if (!(io.mass > 0.0)) io.mass = vehicle->params.mass;
    thrust_model_factor = vehicle->params.thrust_model_factor;
  }

  FlightSignals signals;
  if (format == "ulog") {
    Px4SignalOptions p;
    if (thrust_model_factor >= 0.0) p.default_thrust_model_factor = thrust_model_factor;
    issue = extractPx4Signals(log, p, signals);
  } else if (format == "dataflash") {
    ArdupilotSignalOptions a;
    a.ekf_core = o.ekf_core;
    if (thrust_model_factor >= 0.0) a.thrust_expo = thrust_model_factor;
    issue = extractArdupilotSignals(log, a, signals);
  } else {
    CrazyflieSignalOptions c;
    c.thrust_map = o.crazyflie_thrust == "duty"      ? CrazyflieThrustMap::kQuadraticDuty
                   : o.crazyflie_thrust == "battery" ? CrazyflieThrustMap::kBatteryVoltage
                                                     : CrazyflieThrustMap::kAuto;
    issue = extractCrazyflieSignals(log, c, signals);
  }
  if (!issue.ok()) {
    // A missing signal names itself; a log that is also too coarse says so in the same line.
    std::string line = where(name, issue, issue.status != LogStatus::kMissingSignal && issue.offset != 0);
    if (issue.status == LogStatus::kMissingSignal) line += coarseTopicsNote(log, io);
    throw std::runtime_error(line);
  }
  if (dataflash_text)
    signals.conventions.insert(signals.conventions.begin(), "log: the DataFlash log as text (Mission Planner's .log), each line re-encoded "
                                                            "into the binary message it was printed from");
  opened.source = std::make_unique<LogSampleSource>();
  const ImportRefusal refusal = buildLogSampleSource(std::move(signals), log.format, io, *opened.source);
  if (refusal.refused())
    throw std::runtime_error(name + ": " + (refusal.topic.empty() ? "" : "topic " + refusal.topic + ": ") + refusal.message);
  opened.source->setName(name);
  return opened;
}

}  // namespace quadfdi::cli
