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

// theta[i] replaced by the mean over window i and the windows before it of the same flight, at
// most `count` (≥ 1) in all; `windows` are enumerated flight by flight, in time order
// (enumerateWindows), so a mean never reaches into another flight.
std::vector<Input> averageOverFlight(const std::vector<WindowRef>& windows, const std::vector<Input>& theta, int count);

// Runs the model on every window through the symmetry maps and decides each one. With
// `average_windows` > 1 each decision reads the mean of the flight's last that many windows' Θ̂
// (this one included; fewer at the flight's first windows): a causal filter on the estimates,
// which costs up to that many samples of delay. 1 decides every window alone, as the paper does.
std::vector<WindowOutcome> evaluateTestSet(const TrainedModel& model, const TestSetConfig& config,
                                           const TestSet& set, double theta_tol, DecisionRule rule,
                                           SymmetryMode mode, int average_windows = 1);

}  // namespace quadfdi
