// Experiment E7, the transfer matrix (issue 13, docs/results): a model trained on one setting is
// flown on every library vehicle under conditions it was or was not trained on — controllers and
// gains, manoeuvres, plant errors — with complete and partial faults of every motor and healthy
// flights, and scored by the sequential rule (evaluation/sequential_metrics.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "data/randomisation.h"
#include "evaluation/sequential_metrics.h"
#include "inference/weights_file.h"

namespace quadfdi {

// One test condition: a randomisation without vehicles whose ranges pin one controller, one
// manoeuvre family and the plant's error.
struct TransferCondition {
  std::string name;
  bool held_out = false;  // outside the shipped training randomisation (configs/randomisation-default.toml)
  Randomisation randomisation;
};

// E7's conditions, all flown with the estimator `sensors` (noise, lag and delay inside the training ranges).
std::vector<TransferCondition> e7Conditions(const SensorRanges& sensors);

struct TransferConfig {
  std::vector<VehicleParams> vehicles;     // described vehicles (configs/vehicles/)
  std::vector<std::string> vehicle_names;  // parallel
  std::vector<TransferCondition> conditions;
  std::vector<double> thetas{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};  // [-] faults flown, every motor
  int flights_per_class = 5;               // [flights] per (motor, Θ) and healthy ×4
  double post_fault_seconds = 0.6;         // [s] recorded after the fault: +300 ms checks and the flown-through estimate
  std::uint64_t seed = 17;                 // test flights; disjoint from training streams
  int threads = 0;
  double log_period = 0.0;  // [s] the flights logged every this long and resampled as detect does (flight_streams.h); 0: every sample
  SequentialEvaluationConfig decision;
};

struct TransferCell {
  std::string vehicle, condition;
  bool held_out = false;
  int flights = 0;
  SequentialEvaluation complete;  // healthy flights and Θ = 0
  SequentialEvaluation partial;   // healthy flights and 0 < Θ ≤ 0.8
  SequentialEvaluation all;       // every flight (Θ 0 … 0.9 and healthy)
};

// Runs every (vehicle, condition) cell. `progress` gets "vehicle / condition" as each starts.
std::vector<TransferCell> runTransfer(const TrainedModel& model, const TransferConfig& config,
                                      const std::function<void(const std::string&)>& progress = {});

}  // namespace quadfdi
