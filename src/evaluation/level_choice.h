// Choosing the `degraded` level from calibration flights (docs/decisions.md "Choosing the level").
// A higher level reports milder faults but needs a higher threshold for the same false-alarm
// rate, so it reports them later; which wins depends on the model's healthy Θ̂. Each candidate is
// calibrated on the same healthy streams (same target rate, same cap) and scored on faulty ones:
// the share of faults below the highest candidate whose motor the rule names (either severity)
// `delay_budget` samples after the fault. The best score wins; a tie goes to the higher level.
// The failed statistic's increment cap is chosen alike (chooseFailedCap): each cap calibrated on
// the healthy streams, the degraded level chosen again under it, and scored on the faults below
// the failed level by the share named 50 ms after the fault. No I/O.
#pragma once

#include <vector>

#include "detection/calibration.h"
#include "evaluation/sequential_metrics.h"

namespace quadfdi {

struct LevelChoiceConfig {
  std::vector<double> candidates;  // [-] degraded levels to try, each above failed.level
  double cap = kNoIncrementCap;    // [effectiveness] degraded increment cap, the same for every candidate
  LevelCalibration failed;         // the failed level's calibration, shared by every candidate
  ThetaNoiseModel noise;           // of the healthy streams (fitNoiseModel, model_sigma from faulty flights)
  ThetaReference reference = ThetaReference::kAbsolute;  // the rule's input: the healthy streams are of that quantity
                                                          //     (ruleInput), the faulty ones the network's output
  double flight_hours = 0.0;       // [h] healthy flight time of the streams, per vehicle
  double rate_per_hour = 0.05;     // [1/flight hour] the degraded level's share of the target rate
  double dt = 0.002;               // [s] model sample period
  long delay_budget = 150;         // [samples] after the fault: 300 ms at 500 Hz, issue 14's bound for mild faults
};

struct LevelCandidate {
  LevelCalibration degraded;  // this level's calibration on the healthy streams
  int faults = 0;             // [-] faulty flights scored (true Θ below the highest candidate)
  int isolated = 0;           // [-] … whose motor the rule names delay_budget samples after the fault
};

struct LevelChoice {
  std::vector<LevelCandidate> candidates;  // in the order given
  int chosen = -1;                         // index into candidates; −1 when there were none
};

// Throws std::invalid_argument for an empty candidate list or a candidate not above failed.level.
// `healthy_observable`: the healthy streams' CommandGate masks (excursionMaxima), or null.
LevelChoice chooseDegradedLevel(const std::vector<std::vector<MotorTheta>>& healthy, const std::vector<FlightThetaStream>& faulty,
                                const LevelChoiceConfig& config,
                                const std::vector<std::vector<std::uint8_t>>* healthy_observable = nullptr);

struct FailedCapChoiceConfig {
  std::vector<double> caps;    // [effectiveness] failed increment caps to try, each > 0 (kNoIncrementCap: none)
  double level = 0.3;          // [-] the failed level
  LevelChoiceConfig degraded;  // the degraded level's choice, made again under each cap (its `failed` is set here)
  long delay_budget = 25;      // [samples] after the fault: 50 ms at 500 Hz, issue 14's bound for complete faults
};

struct FailedCapCandidate {
  LevelCalibration failed;  // the failed level calibrated with this cap on the healthy streams
  LevelChoice degraded;     // the degraded level chosen under it
  int faults = 0;           // [-] faulty flights with true Θ below the failed level still recorded at the budget
  int named = 0;            // [-] … whose motor the rule (its chosen degraded level, this failed one) names there
};

struct FailedCapChoice {
  std::vector<FailedCapCandidate> candidates;  // in the order given
  int chosen = -1;                             // index into candidates; −1 when there were none
};

// The cap that names the most faults below the failed level within the budget; a tie goes to the
// smaller cap, which bounds a deep healthy dip's weight more. Throws std::invalid_argument for no
// cap, a cap ≤ 0, or a level outside (0, 1) — and, as chooseDegradedLevel, for a degraded candidate
// not above the level.
FailedCapChoice chooseFailedCap(const std::vector<std::vector<MotorTheta>>& healthy, const std::vector<FlightThetaStream>& faulty,
                                const FailedCapChoiceConfig& config,
                                const std::vector<std::vector<std::uint8_t>>* healthy_observable = nullptr);

}  // namespace quadfdi
