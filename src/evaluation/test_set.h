// Test sets (docs/decisions.md): healthy flights and flights of each fault class, 2T steps, fault at T,
// every window k = T … 2T evaluated; each flight from its own initial condition.
#pragma once

#include <string>
#include <vector>

#include "data/rollout.h"
#include "evaluation/metrics.h"

namespace quadfdi {

struct FaultClass {
  int motor = 0;       // 1..4; 0 = healthy
  double theta = 1.0;  // effectiveness after the fault
  std::string label() const;
};

struct TestSetConfig {
  RolloutConfig rollout;  // controller, plant, T, seed
  std::vector<FaultClass> classes;  // include {0, 1} for the healthy class
  int flights_per_class = 50;
  std::uint64_t first_scenario = 1ull << 41;  // disjoint from training and held-out streams
  int threads = 0;
};

struct TestSet {
  TrajectoryBatch batch;
  std::vector<int> class_of;  // per trajectory: index into classes
  std::vector<WindowRef> windows;
};

TestSet generateTestSet(const TestSetConfig& config);

enum class DecisionRule { kOurs, kPaper };

// Runs the model on every window through the symmetry maps and decides each one.
std::vector<WindowOutcome> evaluateTestSet(const TrainedModel& model, const TestSetConfig& config,
                                           const TestSet& set, double theta_tol, DecisionRule rule,
                                           SymmetryMode mode);

}  // namespace quadfdi
