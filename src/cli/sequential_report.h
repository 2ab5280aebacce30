// The sequential rule's experiments as report sections (edge code: it writes CSV, gnuplot and PNG
// files beside the Markdown it returns): E7, the transfer matrix (issue 13), and `decisions` —
// detection against Θ, false alarms per flight hour over long healthy flights, and the trade-off
// between delay and false-alarm rate (issue 14).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "data/randomisation.h"
#include "detection/calibration.h"
#include "evaluation/sequential_metrics.h"
#include "inference/weights_file.h"

namespace quadfdi::cli {

struct SequentialReportInputs {
  const TrainedModel* model = nullptr;
  std::string model_path, calibration_path, randomise_path;
  SequentialEvaluationConfig decision;  // the rule as detect runs it
  DecisionCalibration calibration;      // its thresholds' source (for the trade-off curve)
  std::vector<VehicleParams> vehicles;
  std::vector<std::string> vehicle_names;
  Randomisation randomisation;  // decisions: the long healthy and the faulty flights (vehicles replaced by the above)
  int flights_per_class = 5;    // [flights] E7: per (vehicle, motor, Θ)
  int faulty_per_theta = 20;    // [flights] decisions: faulty flights per (vehicle, Θ), motors in turn
  double flight_hours = 10.0;   // [h] decisions: healthy flight time
  std::uint64_t seed = 7;
  int threads = 0;
  double log_period = 0.0;  // [s] the flights logged every this long and resampled as detect does (flight_streams.h); 0: every sample
  std::string output_dir;
};

// One drawn flight in words, for lists of the flights that alarmed or set a threshold: "quad450,
// pid ×0.81, circle 1.4 m/s, 0.5 m, nose along the path, sweep 1.1 rad / 4.6 s, wind 2.9 m/s".
std::string manoeuvreText(const ManoeuvreDraw& m);
std::string drawnFlightText(const FlightDraw& d, const Randomisation& r);

using ReportProgress = std::function<void(const std::string&)>;

std::string transferReport(const SequentialReportInputs& in, const ReportProgress& progress);   // + e7.csv
std::string decisionsReport(const SequentialReportInputs& in, const ReportProgress& progress);  // + decisions*.csv, tradeoff.png

}  // namespace quadfdi::cli
