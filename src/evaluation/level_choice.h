// Choosing the `degraded` level from calibration flights (docs/decisions.md "Choosing the level").
// A higher level reports milder faults but needs a higher threshold for the same false-alarm
// rate, so it reports them later; which wins depends on the model's healthy Θ̂. Each candidate is
// calibrated on the same healthy streams (same target rate, same cap) and scored on faulty ones:
// the share of faults below the highest candidate whose motor the rule names (either severity)
// `delay_budget` samples after the fault. The best score wins; a tie goes to the higher level.
// No I/O.
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

}  // namespace quadfdi
