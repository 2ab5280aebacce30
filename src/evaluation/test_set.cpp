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

std::vector<Input> averageOverFlight(const std::vector<WindowRef>& windows, const std::vector<Input>& theta, int count) {
  std::vector<Input> out(theta.size());
  for (std::size_t i = 0; i < theta.size(); ++i) {
    Input sum = Input::Zero();
    int n = 0;
    for (std::size_t j = i + 1; j-- > 0 && n < count && windows[j].trajectory == windows[i].trajectory; ++n) sum += theta[j];
    out[i] = sum / static_cast<double>(n);
  }
  return out;
}

std::vector<WindowOutcome> evaluateTestSet(const TrainedModel& model, const TestSetConfig& c, const TestSet& set,
                                           double theta_tol, DecisionRule rule, SymmetryMode mode, int average_windows) {
  std::vector<std::array<Input, 4>> raw;
  std::vector<Input> theta =
      estimateAllMotors(model, mode, set.batch, set.windows, rule == DecisionRule::kPaper ? &raw : nullptr, c.threads);
  if (average_windows > 1) {
    theta = averageOverFlight(set.windows, theta, average_windows);
    for (std::size_t map = 0; map < 4 && !raw.empty(); ++map) {
      std::vector<Input> outputs(raw.size());
      for (std::size_t i = 0; i < raw.size(); ++i) outputs[i] = raw[i][map];
      outputs = averageOverFlight(set.windows, outputs, average_windows);
      for (std::size_t i = 0; i < raw.size(); ++i) raw[i][map] = outputs[i];
    }
  }
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
