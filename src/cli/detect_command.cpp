#include "cli/detect_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "cli/cli_util.h"
#include "cli/detection_plot.h"
#include "cli/detection_summary.h"
#include "cli/options.h"
#include "cli/shipped_files.h"
#include "core/motor_numbering.h"
#include "data/features.h"
#include "detection/session.h"
#include "io/atomic_file.h"
#include "io/calibration_file.h"
#include "io/key_value.h"
#include "io/model_file.h"
#include "io/randomisation_file.h"
#include "io/telemetry_heading.h"
#include "io/telemetry_reader.h"
#include "io/vehicle_file.h"

namespace quadfdi::cli {

namespace {
// $QUADFDI_MODEL, or empty when it is unset or empty.
std::string environmentModel() {
  const char* env = std::getenv("QUADFDI_MODEL");
  return env ? env : "";
}

// PATH when it is a regular file, else empty. An unreadable folder is "no such file", not an error:
// the model or calibration chosen next serves.
std::string existingFile(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) ? path.string() : std::string();
}

// The rotor lever aspects |x| / |y| a randomised model was trained on: its described vehicles'
// (library names, as the model file records them) and, where it flew synthetic airframes, their
// range. None when the model records no randomisation or names a vehicle this install lacks.
struct TrainedAspects {
  double lo = 0.0, hi = 0.0;  // [-]
  std::string from;           // "crazyflie2, racer250, quad450; synthetic airframes 0.75–1.33"
};
std::optional<TrainedAspects> trainedAspects(const ModelMetadata& m, const std::string& model_path) {
  if (m.randomisation.empty()) return std::nullopt;
  Randomisation r;
  try {
    // The model file records the library's vehicles by name: found where quadfdi finds --vehicle NAME.
    r = randomisationFromText(m.randomisation, model_path + " (its randomisation)", [](const std::string& name) {
      std::string problem;
      const std::string file = vehicleFile(name, &problem);
      return problem.empty() ? file : std::string();
    });
  } catch (const std::exception&) {
    return std::nullopt;  // a randomisation this quadfdi cannot read back (its vehicles moved): no claim
  }
  TrainedAspects out{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), ""};
  for (std::size_t i = 0; i < r.vehicles.size(); ++i) {
    const double aspect = r.vehicles[i].pitchLever() / r.vehicles[i].rollLever();
    out.lo = std::min(out.lo, aspect);
    out.hi = std::max(out.hi, aspect);
    out.from += (out.from.empty() ? "" : ", ") + (i < r.vehicle_names.size() ? r.vehicle_names[i] : std::string("?"));
  }
  if (r.airframes.enabled()) {
    out.lo = std::min(out.lo, r.airframes.aspect.lo);
    out.hi = std::max(out.hi, r.airframes.aspect.hi);
    char range[64];
    std::snprintf(range, sizeof range, "; synthetic airframes %.2f–%.2f", r.airframes.aspect.lo, r.airframes.aspect.hi);
    out.from += range;
  }
  if (!(out.lo <= out.hi)) return std::nullopt;
  return out;
}

// A lever aspect this far outside the trained range (relative) is worth a warning: the library's
// own vehicles sit 2 % inside the rotor-position tolerance of one another (kRotorPositionTolerance).
constexpr double kAspectMargin = 0.05;  // [-]
// How detect's heading lines name a CSV's gyro (logs/heading_resets.h headingResetsLine).
constexpr const char* kCsvGyro = "the gyro (columns p,q,r)";  // as the merged export's line names it
}  // namespace

std::string generalModelPath() { return (std::filesystem::path(shippedModelsDir()) / kGeneralModelName).string(); }

std::string defaultModelPath() {
  const std::string env = environmentModel();
  return env.empty() ? generalModelPath() : env;
}

std::string vehicleModelName(const std::string& vehicle_file) {
  return "tcn-" + std::filesystem::path(vehicle_file).stem().string() + ".qfdw";
}

std::string vehicleRatesModelName(const std::string& vehicle_file) {
  return "tcn-" + std::filesystem::path(vehicle_file).stem().string() + "-rates.qfdw";
}

std::string vehicleModelPath(const std::string& vehicle_file, const std::string& models_dir, bool rates) {
  if (vehicle_file.empty()) return {};
  return existingFile(std::filesystem::path(models_dir) / (rates ? vehicleRatesModelName(vehicle_file) : vehicleModelName(vehicle_file)));
}

DetectModelChoice detectModelPath(const std::string& model_option, const std::string& vehicle_file) {
  return detectModelPath(model_option, vehicle_file, shippedModelsDir());
}

DetectModelChoice detectModelPath(const std::string& model_option, const std::string& vehicle_file, const std::string& models_dir) {
  using Source = DetectModelChoice::Source;
  if (!model_option.empty()) return {model_option, Source::kOption, {}};
  if (const std::string env = environmentModel(); !env.empty()) return {env, Source::kEnvironment, {}};
  const std::string rates = vehicleModelPath(vehicle_file, models_dir, true);
  const std::string own = vehicleModelPath(vehicle_file, models_dir);
  if (!own.empty()) return {own, Source::kVehicle, rates};
  // No vehicle model: the vehicle's body-rates model, else the general one on rates (a vehicle with a
  // model of its own keeps it: it was trained and calibrated for that airframe alone).
  return {(std::filesystem::path(models_dir) / kGeneralModelName).string(), Source::kGeneral,
          rates.empty() ? existingFile(std::filesystem::path(models_dir) / kGeneralRatesModelName) : rates};
}

std::string ratesModelPairProblem(const ModelMetadata& model, const ModelMetadata& rates_model) {
  if (!featuresReadRates(rates_model.features)) return std::string("it reads no body rates (features ") + toString(rates_model.features) + ")";
  if (std::abs(model.dt - rates_model.dt) > 1e-12 * model.dt)
    return "it runs at dt = " + std::to_string(rates_model.dt) + " s, the model for telemetry without rates at " + std::to_string(model.dt) + " s";
  if (featuresScaleFree(model.features) != featuresScaleFree(rates_model.features))
    return std::string("its features (") + toString(rates_model.features) + ") and those of the model for telemetry without rates (" +
           toString(model.features) + ") read commands differently (scale-free or in newtons)";
  return {};
}

CLI::App* addDetectCommand(CLI::App& app, DetectOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "detect",
      "Online fault detection on flight telemetry (docs/conventions.md): reads the CSV t,x,y,z,roll,pitch,yaw,u1..u4\n"
      "(SI units, z up or --csv-frame ned, ZYX Euler angles or a quaternion qw,qx,qy,qz, u = commanded thrust per\n"
      "motor [N] or --csv-commands rotor-speed|throttle|pwm, Crazyflie numbering; extra columns ignored; any rate down to\n"
      "125 Hz, resampled to the model's) or a flight log (PX4 ULog, ArduPilot DataFlash, Crazyflie micro-SD:\n"
      "recognised from its content, airborne phases only), writes one JSON object per sample from the first full\n"
      "window on: {\"t\", \"theta\": [4], \"alarm\", \"motor\"} and, with the sequential rule (default), \"severity\",\n"
      "\"theta_est\", \"theta_lo\", \"theta_hi\", \"motor_position\", \"autopilot_motor\". A summary goes to stderr.");
  auto t = std::make_shared<OptionTable>();
  t->addConfigFile(o.config);
  t->add("--model,-m", o.model,
         "Model file (default: $QUADFDI_MODEL; else, with --vehicle FILE, the shipped models/tcn-STEM.qfdw trained for that "
         "vehicle when there is one, or its models/tcn-STEM-rates.qfdw where the telemetry carries body rates p,q,r; else "
         "the shipped general model, or models/tcn-randomised-rates.qfdw where the telemetry carries body rates and that "
         "file is there)").defaultText("").shippedFile();
  t->add("--input,-i", o.input,
         "Telemetry CSV or flight log (.ulg, .BIN, Crazyflie micro-SD), or - for standard input: CSV, streamed line by line, or "
         "a flight log piped in with its --format named (zcat log.ulg.gz | quadfdi detect --format ulog)");
  t->add("--plot", o.plot, "Also draw Θ̂ per motor against time, alarms and evaluated phases into this PNG (needs gnuplot)");
  t->add("--output,-o", o.output, "JSON Lines output, or - for standard output");
  t->add("--summary", o.summary,
         "Also write the run's verdict as one JSON object to this file (- for standard output): \"verdict\" (fault, no "
         "fault, no decision), every alarm with the times it rose and cleared, the motor (quadfdi's and the autopilot's "
         "number, its position), its worst severity, its latest and its lowest Θ̂ estimate with their intervals, the model, the calibration and the decided flight time");
  t->add("--rule", o.rule,
         "Alarm rule: sequential (per-motor CUSUM, severity levels, thresholds from --false-alarms-per-hour) or "
         "persistence (--raise-below for --raise-after evaluations: the earlier rule, output unchanged)")
      .choices({"sequential", "persistence"});
  t->add("--degraded-below", o.degraded_below, "Sequential: a motor below this effectiveness is degraded")
      .above(0.0, 1.0)
      .defaultText("the calibration's level; 0.8 without one");
  t->add("--failed-below", o.failed_below, "Sequential: a motor below this effectiveness has failed")
      .above(0.0, 1.0)
      .defaultText("the calibration's level; 0.3 without one");
  t->add("--false-alarms-per-hour", o.false_alarms_per_hour,
         "Sequential: target false alarms per flight hour; the CUSUM thresholds are solved for it")
      .above(0.0, 3600.0)
      .defaultText("the calibration's target; 0.1 without one");
  t->add("--calibration", o.calibration,
         "Sequential: noise model and threshold data from `quadfdi calibrate` (default: documented defaults)").shippedFile();
  t->add("--stride", o.stride, "Evaluate every N samples while all Θ̂ are above --watch (extra first-look delay ≤ N−1 samples)")
      .range(1, 1000);
  t->add("--watch", o.watch, "Below this min Θ̂, evaluate every sample").range(0.0, 1.0);
  t->add("--raise-below", o.raise_below, "Persistence: alarm evidence: the weakest motor's Θ̂ below this").range(0.0, 1.0);
  t->add("--clear-above", o.clear_above, "Persistence: healthy evidence: every Θ̂ above this").range(0.0, 1.0);
  t->add("--raise-after", o.raise_after, "Persistence: consecutive evaluations of evidence (same motor) to raise the alarm").range(1, 100000);
  t->add("--watch-samples", o.watch_samples, "Full-rate evaluations after Θ̂ first dips below --watch").range(0, 100000);
  t->add("--clear-after", o.clear_after,
         "Samples of healthy evidence to clear an alarm (persistence: every Θ̂ above --clear-above; sequential: the "
         "flagged motor at or above its level)").range(1, 100000);
  t->add("--max-input-period", o.max_input_period, "Refuse logs sampled coarser than this [s] (0.011 reads a 100 Hz log: complete failures are then named ~10 ms later, docs/results/log-rates)").above(0.0);
  t->add("--max-gap", o.max_gap, "A longer hole in the log restarts the detector [s]").above(0.0);
  t->add("--fault-exit-code", o.fault_exit_code,
         "Exit with this status when an alarm was raised (the summary's verdict \"fault\"), after every output is written, "
         "so that a script over a fleet's logs can branch on it; 1, 2 and 130 stay error, usage and interrupt")
      .range(3, 125)
      .defaultText("0: a fault exits 0");
  t->add("--quiet,-q", o.quiet, "No summary or warnings on stderr (errors still go there)");
  addLogInputOptions(*t, o.log);
  attachOptions(*cmd, t);
  return cmd;
}

namespace {

std::string fmtMs(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g ms", 1000.0 * seconds);
  return buf;
}

// JSON Lines on a stream; warnings on stderr.
class JsonLinesSink : public DetectionSink {
 public:
  JsonLinesSink(std::ostream& out, bool quiet, bool severity, MotorNumbering numbering)
      : out_(out), quiet_(quiet), severity_(severity), numbering_(std::move(numbering)) {}
  void output(const DetectorOutput& d) override {
    // A flight's own clock prints as before; an absolute one (seconds since 1970, 1.7e9) would lose
    // its milliseconds to %.10g, and 4 decimals hold every grid of the models (dt ≥ 0.5 ms).
    char t_text[48];
    if (std::abs(d.t) < 1e5) std::snprintf(t_text, sizeof t_text, "%.10g", d.t);
    else std::snprintf(t_text, sizeof t_text, "%.4f", d.t);
    char buf[256];
    const int n = std::snprintf(buf, sizeof buf, "{\"t\": %s, \"theta\": [%.4f, %.4f, %.4f, %.4f], \"alarm\": %s, \"motor\": ", t_text,
                                static_cast<double>(d.theta[0]), static_cast<double>(d.theta[1]),
                                static_cast<double>(d.theta[2]), static_cast<double>(d.theta[3]), d.alarm ? "true" : "false");
    out_.write(buf, n);
    if (d.motor > 0) out_ << d.motor;
    else out_ << "null";
    if (severity_) {  // added keys (issue 14); the four above keep their meaning
      char more[160];
      const int m = d.motor > 0 ? std::snprintf(more, sizeof more, ", \"severity\": \"%s\", \"theta_est\": %.4f, \"theta_lo\": %.4f, \"theta_hi\": %.4f",
                                                toString(d.severity), d.theta_est, d.theta_lo, d.theta_hi)
                                : std::snprintf(more, sizeof more, ", \"severity\": \"healthy\", \"theta_est\": null, \"theta_lo\": null, \"theta_hi\": null");
      out_.write(more, m);
      // Which motor to look at (added keys): its position, and its number in the autopilot's own
      // numbering (the log's, else the --vehicle description's, else quadfdi's).
      if (d.motor > 0)
        out_ << ", \"motor_position\": \"" << motorPosition(numbering_, d.motor) << "\", \"autopilot_motor\": "
             << numbering_.autopilot_motor[static_cast<std::size_t>(d.motor - 1)];
      else
        out_ << ", \"motor_position\": null, \"autopilot_motor\": null";
    }
    out_ << "}\n";
  }
  void warning(const std::string& text) override {
    if (!quiet_) std::fprintf(stderr, "detect: warning: %s\n", text.c_str());
  }
  void idle() override { out_.flush(); }  // a live pipe sees each decision at once

 private:
  std::ostream& out_;
  bool quiet_;
  bool severity_;  // sequential rule: the severity keys
  MotorNumbering numbering_;
};

// Keeps every output for the plot (when asked), the alarm episodes and the warnings for the
// summary, then passes them on.
class RecordingSink : public DetectionSink {
 public:
  RecordingSink(DetectionSink& next, std::vector<DetectorOutput>* record, AlarmEpisodes& episodes,
                std::vector<std::string>& warnings)
      : next_(next), record_(record), episodes_(episodes), warnings_(warnings) {}
  void output(const DetectorOutput& d) override {
    if (record_) record_->push_back(d);
    episodes_.add(d);
    next_.output(d);
  }
  void warning(const std::string& text) override {
    warnings_.push_back(text);
    next_.warning(text);
  }
  void idle() override { next_.idle(); }

 private:
  DetectionSink& next_;
  std::vector<DetectorOutput>* record_;
  AlarmEpisodes& episodes_;
  std::vector<std::string>& warnings_;
};

}  // namespace

std::string calibrationSidecarPath(const std::string& model_path) {
  const std::string ext = ".qfdw";
  const bool has = model_path.size() > ext.size() && model_path.compare(model_path.size() - ext.size(), ext.size(), ext) == 0;
  return (has ? model_path.substr(0, model_path.size() - ext.size()) : model_path) + ".calibration.json";
}

std::string vehicleCalibrationPath(const std::string& model_path, const std::string& vehicle_file) {
  const std::string sidecar = calibrationSidecarPath(model_path);
  const std::string suffix = ".calibration.json";
  return sidecar.substr(0, sidecar.size() - suffix.size()) + "." + std::filesystem::path(vehicle_file).stem().string() + suffix;
}

CalibrationChoice defaultCalibrationPath(const std::string& model_path, const std::string& vehicle_file) {
  if (!vehicle_file.empty())
    if (std::string own = existingFile(vehicleCalibrationPath(model_path, vehicle_file)); !own.empty()) return {own, true};
  return {existingFile(calibrationSidecarPath(model_path)), false};
}

SequentialSetup sequentialSetup(const std::string& calibration_file, std::optional<double> degraded_below,
                                std::optional<double> failed_below, std::optional<double> false_alarms_per_hour, double dt,
                                std::uint32_t model_crc32) {
  SequentialSetup s;
  DecisionCalibration& c = s.calibration;
  if (calibration_file.empty()) {
    const SequentialConfig defaults;
    c = defaultCalibration(degraded_below.value_or(defaults.degraded_below), failed_below.value_or(defaults.failed_below),
                           false_alarms_per_hour.value_or(DecisionCalibration{}.target_rate), dt);
  } else {
    c = readCalibrationFile(calibration_file);
    if (const std::string other = calibrationModelProblem(c, model_crc32); !other.empty()) throw ConfigError(calibration_file + ": " + other);
    const double rate = false_alarms_per_hour.value_or(c.target_rate);
    const double per_level = rate / 2.0;  // the vehicle's budget, split over the two levels
    if (std::abs(c.dt - dt) > 1e-12 * dt)
      throw ConfigError(calibration_file + ": calibrated at dt = " + std::to_string(c.dt) + " s, the model runs at " + std::to_string(dt) + " s");
    // A level other than the calibrated one has no excursion data: Siegmund on the calibrated noise model.
    for (auto [level, below] : {std::pair<LevelCalibration*, double>{&c.degraded, degraded_below.value_or(c.degraded.level)},
                                {&c.failed, failed_below.value_or(c.failed.level)}}) {
      if (std::abs(level->level - below) > 1e-9) {
        const double share = level->min_command_share;  // the gate stays the calibration's
        *level = calibrateLevel({}, below, 0.0, per_level, c.noise, dt, level->increment_cap);
        level->min_command_share = share;
      } else {
        retarget(*level, c.flight_hours, per_level, c.noise, dt);
      }
    }
    c.target_rate = rate;
  }
  if (!(c.failed.level < c.degraded.level))
    throw ConfigError("--failed-below (" + std::to_string(c.failed.level) + ") must be below --degraded-below (" +
                      std::to_string(c.degraded.level) + ")" + (calibration_file.empty() ? "" : ", the calibration's where not given"));
  s.config = sequentialConfig(c);
  return s;
}

int runDetect(const DetectOptions& o) {
  const bool sequential = o.rule == "sequential";
  // Checked whichever rule runs: a config file stays valid for both.
  require(o.clear_above >= o.raise_below, "--clear-above must not be below --raise-below");
  require(o.watch >= o.raise_below, "--watch must not be below --raise-below (the alarm must be decided at full rate)");
  require(!o.failed_below || !o.degraded_below || *o.failed_below < *o.degraded_below, "--failed-below must be below --degraded-below");
  require(o.max_input_period > 0.0 && o.max_gap >= o.max_input_period, "--max-gap must be at least --max-input-period (> 0)");
  // Checked for every input: with a CSV the description picks the model and numbers the motors, and a missing or
  // broken one must be refused ("FILE:LINE: problem"), not read as "no model of its own".
  // The motor numbers a pilot reads: a CSV is in quadfdi's numbering, which the description's
  // [motor.N] table (its autopilot's numbering) translates; a log's extractor overrides both.
  const std::optional<VehicleDescription> vehicle = describedVehicle(o.log);  // the one read of --vehicle
  MotorNumbering numbering = vehicleNumbering(vehicle);
  const bool renumber = csvInVehicleNumbering(o.log);  // checked before any work or message
  const std::string format = resolveInputFormat(o.input, o.log.format);
  const bool csv = format == "csv" || format == "csv-merged";
  refuseOptionsUnreadBy(format, o.log);  // --csv-frame, --csv-commands on a log; a log's options on a CSV
  const TelemetryReaderOptions reading = csv ? csvReadingOptions(o.log, vehicle) : TelemetryReaderOptions{};
  const bool rotor_speed = reading.commands == CommandQuantity::kRotorSpeed;
  const bool through_curve = reading.commands == CommandQuantity::kThrottle || reading.commands == CommandQuantity::kPwm;
  // The other rule's options are warned about, not refused: a config file may serve both rules.
  if (!o.quiet) {
    const std::string unread = sequential ? firstGiven(o.log.given, {"raise_below", "raise_after", "clear_above"})
                                          : firstGiven(o.log.given, {"calibration", "degraded_below", "failed_below", "false_alarms_per_hour"});
    if (!unread.empty())
      std::fprintf(stderr, "detect: warning: %s is the %s rule's; --rule %s does not read it\n", unread.c_str(),
                   sequential ? "persistence" : "sequential", o.rule.c_str());
  }
  const DetectModelChoice choice = detectModelPath(o.model, o.log.vehicle);
  TrainedModel model = readModelFile(choice.path);
  // A vehicle's own body-rates model is read now too, and must agree with the other on what the
  // input is opened for: which of them runs is known once the input says whether it has rates.
  std::optional<TrainedModel> rates_model;
  if (!choice.rates_path.empty()) {
    rates_model = readModelFile(choice.rates_path);
    if (const std::string why = ratesModelPairProblem(model.metadata, rates_model->metadata); !why.empty())
      throw ConfigError(choice.rates_path + ": cannot stand in for " + choice.path + " on telemetry with body rates: " + why);
  }
  // Body rates are read only for a model that reads them: for any other, p, q, r are extra columns
  // (whatever their unit) and a log's rates topic neither cuts nor drops a sample.
  TelemetryReaderOptions csv_reading = reading;
  csv_reading.read_rates = featuresReadRates(model.metadata.features) || rates_model.has_value();
  // Squared rotor speeds are thrust times an unknown k_f: only commands made dimensionless ignore it.
  if (rotor_speed && !featuresScaleFree(model.metadata.features))
    throw ConfigError("--csv-commands rotor-speed: gives thrust only up to a constant factor, which a scale-free model ignores; " +
                      choice.path + " reads commands in newtons (features " + toString(model.metadata.features) +
                      "): give u1..u4 as thrust in N, or use a scale-free model (every shipped randomised one)");
  if (!o.plot.empty()) requireGnuplot();  // before any work
  require(o.summary != "-" || o.output != "-", "--summary -: the JSON Lines already go to standard output (--output FILE)");
  require(o.summary.empty() || o.summary == "-" || o.summary != o.output, "--summary: the same file as --output");
  const bool live = o.input == "-" && format == "csv";  // a merged export is read to its end first
  std::ios::sync_with_stdio(false);  // buffered standard input: the reader asks it what is waiting
  std::ifstream file;
  const std::string name = o.input == "-" ? std::string("<stdin>") : o.input;
  std::unique_ptr<TelemetryReader> reader;
  TelemetryFileChecks file_checks;                   // a CSV file's p,q,r against its attitude, its heading resets
  std::string heading_unread;                        // why its rows could not all be read for the checks
  std::unique_ptr<HeadingCorrectedSource> corrected;  // the reader with them taken out
  OpenedLog log;
  SampleSource* source = nullptr;
  if (format == "csv") {
    if (!live) {
      file.open(o.input);
      require(file.is_open(), o.input + ": cannot open");
    }
    reader = std::make_unique<TelemetryReader>(live ? std::cin : file, name, csv_reading);  // throws on an empty file or a bad header
    source = reader.get();
    if (o.log.given.count("csv_quaternion") && !reader->quaternionAttitude())
      throw ConfigError("--csv-quaternion: " + name + "'s header has roll, pitch, yaw, which are read; the flag reads qw,qx,qy,qz only");
    // A CSV written by `quadfdi import` records its log's numbering (u1..u4 are quadfdi's order).
    if (reader->numbering() && !renumber) numbering = *reader->numbering();
    // Estimator heading resets the file does not record (io/telemetry_heading.h): a file is read
    // whole once to find them with its own p,q,r, then streamed with them taken out. A pipe, named
    // or not, is read once.
    if (!live && std::filesystem::is_regular_file(o.input)) {
      std::ifstream whole(o.input);
      try {
        file_checks = checkTelemetryFile(whole, name, csv_reading);
      } catch (const TelemetryError& e) {
        heading_unread = e.what();  // a row the detector would refuse is refused below; a rates cell only stops the check
      }
      if (!file_checks.heading.resets.empty()) {
        corrected = std::make_unique<HeadingCorrectedSource>(*reader, file_checks.heading.resets);
        source = corrected.get();
      }
    }
  } else {
    // throws one line naming file, byte, topic
    log = openFlightLog(o.input, format, o.log, vehicle, csv_reading, model.metadata.dt, o.max_gap,
                        featuresScaleFree(model.metadata.features),
                        csv_reading.read_rates);
    source = log.source.get();
    // A merged CSV names its numbering only in a comment (else the description's stands); a log always.
    const MotorNumbering& logged = log.source->report().numbering;
    if (format != "csv-merged" || (!logged.isQuadfdis() && !renumber)) numbering = logged;
    if (!o.quiet)
      for (const std::string& w : log.warnings) std::fprintf(stderr, "detect: warning: %s\n", w.c_str());
  }

  // The body-rates model where the telemetry carries rates that agree with its attitude; the other model where not.
  std::string model_path = choice.path;
  const bool rates_differ = file_checks.rates.verdict == RateAgreementVerdict::kDiffers;
  const bool rates = rates_model && source->carriesRates() && !rates_differ;
  if (rates) {
    model = std::move(*rates_model);
    model_path = choice.rates_path;
  }
  const ModelMetadata& m = model.metadata;
  if (!o.quiet && o.model.empty() && o.log.vehicle.empty() && rates)
    std::fprintf(stderr, "detect: model %s (the telemetry carries body rates: the general body-rates model)\n", model_path.c_str());
  if (!o.quiet && o.model.empty() && o.log.vehicle.empty() && rates_model && rates_differ)
    std::fprintf(stderr, "detect: model %s (the telemetry's p,q,r do not agree with its attitude's turn, warned below: the general "
                         "model, which does not read them, not %s)\n", model_path.c_str(), choice.rates_path.c_str());
  if (!o.quiet && o.model.empty() && !o.log.vehicle.empty()) {
    // Say where the model came from: the vehicle's own, the general one (so a user knows to train
    // one), or $QUADFDI_MODEL, which wins over the vehicle's own.
    using Source = DetectModelChoice::Source;
    const bool general_rates = rates && std::filesystem::path(model_path).filename() == kGeneralRatesModelName;
    const std::string no_own = "no " + vehicleModelName(o.log.vehicle) + " in " + std::filesystem::path(model_path).parent_path().string();
    const std::string why = choice.source == Source::kEnvironment ? "from $QUADFDI_MODEL, which wins over the own model of"
                            : general_rates ? "the telemetry carries body rates: the general body-rates model, " + no_own + " for"
                            : rates ? "the telemetry carries body rates: the body-rates model for"
                            : choice.source == Source::kGeneral ? "the general model: " + no_own + " for"
                                                                : "for";
    std::fprintf(stderr, "detect: model %s (%s --vehicle %s)\n", model_path.c_str(), why.c_str(), o.log.vehicle.c_str());
    if (!choice.rates_path.empty() && !rates && rates_differ)
      std::fprintf(stderr, "detect: the telemetry's p,q,r do not agree with its attitude's turn (warned below): %s, which reads them, "
                           "is not run\n", choice.rates_path.c_str());
    else if (!choice.rates_path.empty() && !rates)
      std::fprintf(stderr, "detect: the telemetry has no body rates: %s, which reads them, is not run (give columns p,q,r, or "
                           "log them: docs/conventions.md#body-rates)\n", choice.rates_path.c_str());
  }

  // A vehicle whose rotor levers the model never flew (a props-out stretched X is the transposed
  // one): said, with what it measured, since the calibration's numbers do not carry over.
  if (vehicle && !o.quiet)
    if (const std::optional<TrainedAspects> trained = trainedAspects(m, model_path)) {
      const double aspect = vehicle->params.pitchLever() / vehicle->params.rollLever();
      if (aspect < trained->lo * (1.0 - kAspectMargin) || aspect > trained->hi * (1.0 + kAspectMargin))
        std::fprintf(stderr,
                     "detect: warning: the vehicle's rotor levers |x|/|y| = %.2f%s lie outside those %s was trained on "
                     "(%.2f–%.2f: %s); its false-alarm rate and Θ̂ there are not what its calibration measured "
                     "(docs/results/props-out/: the 1.5 kg quad read as props-out, |x|/|y| 1.62, raised 141 false "
                     "alarms in 49 healthy hours with the general model against 4 as an X, and 0 with its own model)\n",
                     aspect, vehicle->body_turn.swapsXY() ? " (a props-out X, read in axes turned 90°: its x and y levers swap)" : "",
                     model_path.c_str(), trained->lo, trained->hi, trained->from.c_str());
    }

  bool vehicle_calibration = false;  // the sequential rule runs the model's calibration for --vehicle

  DetectorConfig config;
  config.symmetry = m.symmetry;
  config.stride = o.stride;
  config.watch = o.watch;
  config.watch_samples = o.watch_samples;
  config.resampler.dt = m.dt;
  config.resampler.max_input_period = o.max_input_period;
  config.resampler.max_gap = o.max_gap;
  config.alarm.raise_below = o.raise_below;
  config.alarm.clear_above = o.clear_above;
  config.alarm.raise_after = o.raise_after;
  config.alarm.clear_after = o.clear_after;
  config.rule = sequential ? AlarmRule::kSequential : AlarmRule::kPersistence;
  std::string calibration = o.calibration;  // sequential: the one run with; empty: the documented defaults
  if (sequential) {
    // The model's calibration for the vehicle (MODEL.STEM.calibration.json), else its own
    // (MODEL.calibration.json beside MODEL.qfdw), unless one is named.
    if (calibration.empty()) {
      const CalibrationChoice chosen = defaultCalibrationPath(model_path, o.log.vehicle);
      calibration = chosen.path;
      if (calibration.empty() && !o.quiet)
        std::fprintf(stderr, "detect: warning: no calibration for %s (%s): default noise model, Siegmund thresholds; run quadfdi calibrate\n",
                     model_path.c_str(), calibrationSidecarPath(model_path).c_str());
      else if (!o.quiet && chosen.for_vehicle)
        std::fprintf(stderr, "detect: calibration %s (for --vehicle %s)\n", calibration.c_str(), o.log.vehicle.c_str());
      vehicle_calibration = chosen.for_vehicle;
    }
    config.sequential = sequentialSetup(calibration, o.degraded_below, o.failed_below, o.false_alarms_per_hour, m.dt, model.file_crc32).config;
    config.sequential.clear_after = o.clear_after;
  }
  std::unique_ptr<Detector> detector;
  try {
    detector = std::make_unique<Detector>(config, model);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(model_path + ": " + e.what());
  }

  // With a telemetry CSV a vehicle description chooses the model and its calibration (and numbers the motors): say so
  // when it chose neither, rather than let it look as if the detector knew the airframe.
  if (!o.quiet && csv && !o.log.vehicle.empty() && !renumber && !through_curve &&
      choice.source != DetectModelChoice::Source::kVehicle &&
      choice.source != DetectModelChoice::Source::kGeneral && !vehicle_calibration)
    std::fprintf(stderr, "detect: warning: --vehicle %s only names the motors in its numbering: the model is given and has no "
                         "calibration for it (%s); calibrate one (quadfdi calibrate --randomise … --vehicle)\n",
                 o.log.vehicle.c_str(), vehicleCalibrationPath(model_path, o.log.vehicle).c_str());
  std::unique_ptr<AtomicFileWriter> file_out;
  if (o.output != "-") file_out = std::make_unique<AtomicFileWriter>(o.output);
  std::ostream& out = file_out ? file_out->stream() : std::cout;
  std::unique_ptr<AtomicFileWriter> summary_out;  // opened now: an unwritable summary is refused before any work
  if (!o.summary.empty() && o.summary != "-") summary_out = std::make_unique<AtomicFileWriter>(o.summary);
  JsonLinesSink json(out, o.quiet, sequential, numbering);
  std::vector<DetectorOutput> recorded;
  AlarmEpisodes episodes(o.max_gap);
  std::vector<std::string> warnings = log.warnings;
  RecordingSink sink(json, o.plot.empty() ? nullptr : &recorded, episodes, warnings);
  SessionConfig session;
  session.live = live;
  session.numbering_from_rates = !rates_differ;
  const SessionResult r = runDetection(*detector, *source, sink, session);
  if (r.status == SessionStatus::kNotIncreasing)
    throw TelemetryError(r.where + ": time goes backwards (t = " + std::to_string(r.t) + " s)");
  if (r.status == SessionStatus::kNoRates)
    throw TelemetryError(name + ": the model " + model_path + " reads body rates (" + toString(m.features) +
                         " features) and this telemetry has none: give columns p,q,r [rad/s] (docs/conventions.md), a log "
                         "that records them, or a model on scale-free features");
  if (r.status == SessionStatus::kTooCoarse) {
    // Intervals of a second or more are no autopilot's rate: most likely t is not in seconds.
    const double mean_interval = r.samples > 1 ? (r.t - r.first_t) / static_cast<double>(r.samples - 1) : 0.0;
    char hint[160] = "";
    if (mean_interval >= 0.5)
      std::snprintf(hint, sizeof hint, " (its samples are %.4g s apart: is t in milliseconds or microseconds? --csv-time-unit ms or us)",
                    mean_interval);
    throw TelemetryError(r.where + ": the log is sampled too coarsely: most of its first intervals exceed " +
                         fmtMs(o.max_input_period) + " (--max-input-period); the model needs " + fmtMs(m.dt) + " samples" + hint +
                         (mean_interval < 0.5 ? "; a 100 Hz log is read with --max-input-period 0.011, at a measured cost "
                                                "(docs/results/log-rates/README.md)"
                                              : ""));
  }
  const DetectorSummary& s = detector->summary();
  // Rows with empty cells throughout are the mark of an export that merges signals sampled at
  // different times, each row holding only the ones sampled then: say so, rather than only count.
  const std::string merged_hint =
      "an export that merges signals logged at different times (PlotJuggler, a ROS bag) leaves the others' cells "
      "empty: read it with --format csv-merged, which takes each signal from the rows that hold it (docs/conventions.md)";
  // Before the commit: a header-only log must not replace an existing output file.
  if (s.input_samples == 0)
    throw TelemetryError(name + ": no telemetry rows after the header" +
                         (r.skipped > 0 ? ": all " + std::to_string(r.skipped) + " rows have an empty or non-finite cell; " +
                                              merged_hint
                                        : std::string()));
  // A CSV file's attitude quaternion against the flight (logs/quaternion_check.h): read otherwise
  // than written, every attitude the detector sees is wrong, and the checks below judge against it.
  const bool quaternion_misread = file_checks.quaternion.verdict == QuaternionVerdict::kOtherReading;
  if (quaternion_misread) {
    warnings.push_back(name + ": " + file_checks.quaternion.text() + " (docs/conventions.md#attitude-as-a-quaternion)");
    if (!o.quiet) std::fprintf(stderr, "detect: warning: %s\n", warnings.back().c_str());
  } else if (!o.quiet && file_checks.has_quaternion) {
    std::fprintf(stderr, "detect: %s\n", file_checks.quaternion.text().c_str());
  }
  // A CSV file's heading resets: taken out, so said as a warning; a check that ran and found none, in a line.
  const HeadingResets& heading = file_checks.heading;
  if (quaternion_misread) {
    if (!o.quiet && file_checks.has_rates)
      std::fprintf(stderr, "detect: body rates and heading resets: not checked (against an attitude read otherwise than written, warned above)\n");
  } else if (heading.count > 0) {
    warnings.push_back(name + ": " + headingResetsLine(heading, kCsvGyro, ""));
    if (!o.quiet) std::fprintf(stderr, "detect: warning: %s\n", warnings.back().c_str());
  } else if (!o.quiet && (file_checks.has_rates || !heading_unread.empty())) {
    const std::string why = rates_differ ? "the gyro columns do not agree with the attitude's turn (warned below)" : "p,q,r not read: " + heading_unread;
    std::fprintf(stderr, "detect: %s\n", headingResetsLine(heading, kCsvGyro, why).c_str());
  }
  // Its p,q,r against the attitude's own turn: another frame, unit or order is a warning (a rates
  // model reads them), agreement or no verdict a line.
  if (rates_differ) {
    warnings.push_back(name + ": " + file_checks.rates.text() + " (docs/conventions.md#body-rates)");
    if (!o.quiet) std::fprintf(stderr, "detect: warning: %s\n", warnings.back().c_str());
  } else if (!o.quiet && file_checks.has_rates && !quaternion_misread) {
    std::fprintf(stderr, "detect: %s\n", file_checks.rates.text().c_str());
  }
  // The numbering check turns the attitude as read: where that is not the flight's, its verdict is too.
  const std::string numbering_caveat =
      quaternion_misread ? "; judged on the attitude as read, which the quaternion check above finds read otherwise: read it right first" : "";
  // The motor columns against the flight's rotation (detection/numbering_check.h): a numbering
  // that does not fit gets every fault named on the wrong motor, so it is a warning, in the summary too.
  if (r.numbering.verdict == NumberingVerdict::kUpsideDown) {
    warnings.push_back(name + ": motor numbering: " + r.numbering.text() +
                       (log.source ? "; the log is not in the frames its reader takes it to be in"
                        : o.log.csv_frame == "ned" ? "; read it without --csv-frame ned"
                                               : "; read it with --csv-frame ned") +
                       numbering_caveat + " (docs/conventions.md#checking-the-motor-numbering)");
    if (!o.quiet) std::fprintf(stderr, "detect: warning: %s\n", warnings.back().c_str());
  } else if (r.numbering.verdict == NumberingVerdict::kOtherNumbering) {
    warnings.push_back(name + ": motor numbering: " + r.numbering.text() +
                       (log.source ? "; the log's motor outputs do not sit where its frame puts them (its frame parameters, or outputs "
                                     "mapped to other motors?)"
                                   : "; a file in that order is read with --csv-numbering vehicle and a --vehicle description of it, or "
                                     "with u1..u4 put in quadfdi's order") +
                       numbering_caveat + " (docs/conventions.md#checking-the-motor-numbering)");
    if (!o.quiet) std::fprintf(stderr, "detect: warning: %s\n", warnings.back().c_str());
  } else if (!o.quiet) {
    std::fprintf(stderr, "detect: motor numbering: %s\n", r.numbering.text().c_str());
  }
  if (format == "csv" && r.skipped >= r.samples) {
    warnings.push_back(name + ": " + std::to_string(r.skipped) + " of " + std::to_string(r.skipped + r.samples) +
                       " rows skipped for an empty or non-finite cell; " + merged_hint);
    if (!o.quiet) std::fprintf(stderr, "detect: warning: %s\n", warnings.back().c_str());
  }
  // The summary is made before anything is committed: both files are written, or neither is replaced.
  if (!o.summary.empty()) {
    DetectionSummaryInputs in;
    in.input = o.input;
    in.format = log.source ? log.source->report().format : "telemetry CSV";
    in.model = model_path;
    in.calibration = sequential ? calibration : std::string();
    in.vehicle = o.log.vehicle;
    in.rule = o.rule;
    in.detector = &detector->summary();
    in.episodes = &episodes;
    in.numbering = &numbering;
    in.numbering_check = &r.numbering;
    if (file_checks.has_quaternion) in.quaternion_check = &file_checks.quaternion;
    if (log.source)
      for (const PhaseReport& p : log.source->report().phases)
        if (p.evaluated) in.evaluated_phases.emplace_back(p.eval_begin, p.eval_end);
    in.warnings = warnings;
    const std::string text = detectionSummaryJson(in);
    (summary_out ? summary_out->stream() : std::cout) << text;
  }
  out.flush();
  if (!out) throw std::runtime_error(o.output + ": write failed");
  if (file_out) file_out->commit();
  if (summary_out) summary_out->commit();
  if (!o.plot.empty()) {
    DetectionPlotData plot;
    plot.outputs = std::move(recorded);
    plot.max_gap = o.max_gap;
    if (log.source) {
      for (const PhaseReport& p : log.source->report().phases)
        if (p.evaluated) plot.phases.push_back({p.eval_begin, p.eval_end});
      plot.title = o.input + " (" + log.source->report().format + "): estimated motor effectiveness";
    } else {
      if (!plot.outputs.empty()) plot.phases.push_back({plot.outputs.front().t, plot.outputs.back().t});
      plot.title = name + ": estimated motor effectiveness";
    }
    plotDetections(plot, o.plot);
  }
  if (!o.quiet) {
    if (log.source) {
      const ImportReport& rep = log.source->report();
      std::fprintf(stderr, "detect: %s, %s\n", rep.format.c_str(), rep.phasesLine().c_str());
      std::fprintf(stderr, "detect: thrust: %s\n", rep.thrust.c_str());
    }
    if (s.outputs == 0)
      std::fprintf(stderr, "detect: %s: %ld samples, shorter than one window (%.2f s): no decision\n", name.c_str(),
                   s.input_samples, m.window * m.dt);
    else if (s.alarms_raised == 0)
      std::fprintf(stderr, "detect: no fault: %ld samples, %ld decisions, no alarm\n", s.input_samples, s.outputs);
    else if (sequential && !episodes.episodes().empty())  // every raised alarm opens an episode
      std::fputs(sequentialFirstAlarmLine(episodes.episodes().front(), config.sequential.interval_level, s.alarms_raised, s.input_samples)
                     .c_str(),
                 stderr);
    else
      std::fprintf(stderr,
                   "detect: FAULT in motor %d at t = %.3f s (Θ̂ = %.2f when raised, lowest %.2f while it held); %ld alarm%s "
                   "over %ld samples\n",
                   s.first_alarm_motor, s.first_alarm_t, static_cast<double>(s.first_alarm_theta),
                   static_cast<double>(s.lowest_theta), s.alarms_raised, s.alarms_raised == 1 ? "" : "s", s.input_samples);
    if (s.alarms_raised > 0)
      std::fprintf(stderr, "detect: motor %d is the %s motor%s\n", s.first_alarm_motor, motorPosition(numbering, s.first_alarm_motor),
                   numbering.isQuadfdis()
                       ? " (quadfdi's numbering: 1 front-right, 2 back-right, 3 back-left, 4 front-left)"
                       : (": " + numbering.name + " motor " +
                          std::to_string(numbering.autopilot_motor[static_cast<std::size_t>(s.first_alarm_motor - 1)]))
                             .c_str());
  }
  return s.alarms_raised > 0 && o.fault_exit_code != 0 ? o.fault_exit_code : 0;
}

}  // namespace quadfdi::cli
