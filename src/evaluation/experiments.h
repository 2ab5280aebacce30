// The paper's experiments (docs/decisions.md) as data: each is a set of conditions (model, test set,
// symmetry, decision rule) evaluated into accuracy-vs-faulty-length curves and summary metrics.
// No I/O: the command line writes the tables and figures.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "evaluation/test_set.h"

namespace quadfdi {

struct ConditionResult {
  std::string name;                 // legend entry, e.g. "motor 1" or "CBF-QP input"
  AccuracyByLength isolation;       // faulty classes; L = 0 … T
  AccuracyByLength identification;  // |Θ̂ − Θ| ≤ 0.05 as well
  double healthy_no_alarm = 0.0;    // healthy flights: fraction of windows without alarm
  DetectionDelay delay;             // [samples]
  double false_alarm_rate = 0.0;
  double theta_mae = 0.0;
  double constraint_active = -1.0;  // CBF-QP test sets: fraction of steps with a CBF constraint active
  int flights = 0;
};

struct ExperimentResult {
  std::string id;        // e1 … e6
  std::string title;
  std::string paper_claim;  // what the paper reports, for the table
  std::vector<ConditionResult> conditions;
};

// The test sets' size (from a named scale, data/scales.h).
struct EvaluationScale {
  std::string name;           // the named scale it came from, for the report
  int flights_per_class = 0;  // [flights per fault class]; docs/decisions.md protocol: 2 000 (paper)
};

struct ExperimentInputs {
  std::map<std::string, const TrainedModel*> models;  // by role: "model-free", "model-based", "residual", "mlp"
  EvaluationScale scale;
  std::uint64_t seed = 7;  // test-set seed (training uses others)
  double theta_tol = 0.2;  // complete faults (paper)
  int average_windows = 1;  // [windows] decide on the mean Θ̂ of a flight's last this many (evaluateTestSet); 1: the paper's
  int threads = 0;
};

// Runs experiment `id` (e1 … e6). Returns false with `missing` set when a model it needs was not given.
bool runExperiment(const std::string& id, const ExperimentInputs& in, ExperimentResult& out, std::string& missing,
                   const std::function<void(const std::string&)>& progress = {});

}  // namespace quadfdi
