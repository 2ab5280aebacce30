#include "evaluation/test_set.h"

#include <cstdio>

namespace quadfdi {

std::string FaultClass::label() const {
  if (motor == 0) return "healthy";
  char buf[48];
  std::snprintf(buf, sizeof buf, "motor %d, theta %.2f", motor, theta);
  return buf;
}

TestSet generateTestSet(const TestSetConfig& c) {
  std::vector<TrajectoryJob> jobs;
  TestSet set;
  std::uint64_t scenario = c.first_scenario;
  for (std::size_t k = 0; k < c.classes.size(); ++k)
    for (int i = 0; i < c.flights_per_class; ++i) {
      const FaultClass& fc = c.classes[k];
      jobs.push_back({scenario++, fc.motor == 0 ? 2 : fc.motor, fc.motor == 0 ? 1.0 : fc.theta});
      set.class_of.push_back(static_cast<int>(k));
    }
  RolloutEngine(c.rollout).run(jobs, c.threads, set.batch);
  enumerateWindows(set.batch, c.rollout.window, set.windows);
  return set;
}

std::vector<WindowOutcome> evaluateTestSet(const TrainedModel& model, const TestSetConfig& c, const TestSet& set,
                                           double theta_tol, DecisionRule rule, SymmetryMode mode) {
  std::vector<std::array<Input, 4>> raw;
  const std::vector<Input> theta =
      estimateAllMotors(model, mode, set.batch, set.windows, rule == DecisionRule::kPaper ? &raw : nullptr, c.threads);
  std::vector<WindowOutcome> out(set.windows.size());
  for (std::size_t i = 0; i < set.windows.size(); ++i) {
    const WindowRef& w = set.windows[i];
    const FaultClass& fc = c.classes[static_cast<std::size_t>(set.class_of[static_cast<std::size_t>(w.trajectory)])];
    WindowOutcome& o = out[i];
    o.trajectory = w.trajectory;
    o.faulty_length = faultyLength(set.batch, w);
    o.true_motor = fc.motor;
    o.true_theta = fc.motor == 0 ? 1.0 : fc.theta;
    o.theta_hat = theta[i];
    o.decision = rule == DecisionRule::kOurs ? decide(theta[i], theta_tol)
                                             : decidePaperRule(raw[i], mode, theta_tol);
  }
  return out;
}

}  // namespace quadfdi
