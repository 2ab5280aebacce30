#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

#include "cli/log_input.h"
#include "detection/calibration.h"
#include "inference/model_metadata.h"

namespace quadfdi::cli {

struct DetectOptions {
  std::string config;          // --config FILE (keys as the long flags)
  std::string model;           // empty: the shipped default model
  std::string input = "-";
  std::string output = "-";
  std::string rule = "sequential";  // sequential | persistence (docs/decisions.md)
  std::optional<double> degraded_below;  // [-] sequential: severity `degraded` below this effectiveness; unset: the
                                         //     calibration's level, else 0.8 (docs/decisions.md: why 0.8)
  std::optional<double> failed_below;    // [-] sequential: `failed` below this; unset: the calibration's, else 0.3
  std::optional<double> false_alarms_per_hour;  // [1/flight hour] sequential: target rate the thresholds are solved
                                                //     for; unset: the calibration's, else 0.1 (issue 14)
  std::string calibration;          // sequential: calibration JSON from `quadfdi calibrate`; empty: defaults
  int stride = 4;              // [samples]
  double watch = 0.9;
  double raise_below = 0.5;
  double clear_above = 0.8;
  int raise_after = 5;
  int clear_after = 100;           // [samples]
  int watch_samples = 16;
  double max_input_period = 0.008;  // [s]
  double max_gap = 0.02;            // [s]
  bool quiet = false;
  std::string plot;                 // PNG of Θ̂ against time; empty: none
  std::string summary;              // JSON summary of the run (cli/detection_summary.h); empty: none; - : stdout
  int fault_exit_code = 0;          // exit status when an alarm was raised (3–125: 1, 2 and 130 mean error, usage and
                                    //     interrupt); 0: a fault exits 0, as any run that read its input
  LogInputOptions log;              // flight logs (PX4, ArduPilot, Crazyflie): shared with `import`
};

CLI::App* addDetectCommand(CLI::App& app, DetectOptions& options);
int runDetect(const DetectOptions& options);

// The sequential rule's configuration from the options (levels, target rate, calibration file
// or the documented defaults); `dt` is the model's. An unset level is the calibration's (the
// SequentialConfig default without one); a level other than the calibrated one is solved by
// Siegmund on the calibrated noise model. Throws ConfigError / std::runtime_error.
struct SequentialSetup {
  SequentialConfig config;
  DecisionCalibration calibration;  // as used: thresholds re-solved for the options' target rate
};
// A calibration that records another weights file's CRC than `model_crc32` is refused (ConfigError
// "CALIBRATION: made for another model (…)").
SequentialSetup sequentialSetup(const std::string& calibration_file, std::optional<double> degraded_below,
                                std::optional<double> failed_below, std::optional<double> false_alarms_per_hour, double dt,
                                std::uint32_t model_crc32);

// MODEL.qfdw → MODEL.calibration.json: the calibration detect uses when none is named.
std::string calibrationSidecarPath(const std::string& model_path);

// MODEL.qfdw and the description FILE STEM.toml → MODEL.STEM.calibration.json: the model's
// calibration for that airframe (`quadfdi calibrate --vehicle FILE -o …`), when one is shipped.
std::string vehicleCalibrationPath(const std::string& model_path, const std::string& vehicle_file);

// The calibration a model runs with when none is named, and why: with a vehicle, its
// vehicleCalibrationPath if that file exists; else the sidecar if it exists; else an empty path
// (the documented defaults).
struct CalibrationChoice {
  std::string path;
  bool for_vehicle = false;  // the model's calibration for the vehicle, not its own
};
CalibrationChoice defaultCalibrationPath(const std::string& model_path, const std::string& vehicle_file);

// The shipped general model: kGeneralModelName in shippedModelsDir() (installed, else the source tree's).
std::string generalModelPath();

// The model run when none is named: $QUADFDI_MODEL if set, else generalModelPath().
std::string defaultModelPath();

// The file name of a vehicle's own model: tcn-STEM.qfdw for the description FILE STEM.toml (the
// shipped per-vehicle models are named so, models/README.md).
std::string vehicleModelName(const std::string& vehicle_file);

// The file name of a vehicle's own body-rates model: tcn-STEM-rates.qfdw (models/README.md). It
// needs telemetry with p, q, r, so it is shipped beside a model that does not.
std::string vehicleRatesModelName(const std::string& vehicle_file);

// A vehicle's own model: MODELS_DIR/vehicleModelName(FILE) (or, with `rates`,
// vehicleRatesModelName(FILE)), or empty when there is no such file.
std::string vehicleModelPath(const std::string& vehicle_file, const std::string& models_dir, bool rates = false);

// Which model detect runs, and why: --model; else $QUADFDI_MODEL; else the --vehicle's own model
// in the models folder (the shipped one by default); else the shipped general model. Without a
// named model, a body-rates model is the choice for telemetry that carries body rates, known only
// once the input is open (`rates_path`): the vehicle's own, else, where the general model runs, the
// general one on rates (kGeneralRatesModelName) when that file is there.
struct DetectModelChoice {
  enum class Source { kOption, kEnvironment, kVehicle, kGeneral };
  std::string path;        // the model for telemetry without body rates (and for any, when rates_path is empty)
  Source source = Source::kGeneral;
  std::string rates_path;  // the body-rates model, run instead where the telemetry carries rates; empty: none
};
DetectModelChoice detectModelPath(const std::string& model_option, const std::string& vehicle_file);
DetectModelChoice detectModelPath(const std::string& model_option, const std::string& vehicle_file,
                                  const std::string& models_dir);

// Why a body-rates model cannot stand in for its other model on the same input (another
// sample period, or one reads commands in newtons and the other scale-free: the input is opened
// once, for both), or empty when it can.
std::string ratesModelPairProblem(const ModelMetadata& model, const ModelMetadata& rates_model);

}  // namespace quadfdi::cli
