#include <gtest/gtest.h>

#include <cmath>

#include "data/rollout.h"
#include "evaluation/metrics.h"
#include "evaluation/test_set.h"
#include "networks/model.h"

namespace quadfdi {
namespace {

TEST(Decision, AlarmIsolationTiesAndNoAlarm) {
  Decision d = decide(Input(0.9, 0.1, 0.95, 1.0), 0.2);
  EXPECT_TRUE(d.alarm);
  EXPECT_EQ(d.motor, 2);
  EXPECT_FLOAT_EQ(static_cast<float>(d.min_theta), 0.1f);
  d = decide(Input(0.9, 0.3, 0.95, 1.0), 0.2);
  EXPECT_FALSE(d.alarm);
  EXPECT_EQ(d.motor, 0);
  d = decide(Input(0.1, 0.9, 0.1, 1.0), 0.2);  // tie between motors 1 and 3 → lowest
  EXPECT_EQ(d.motor, 1);
  d = decide(Input(0.9, 0.3, 0.95, 1.0), 0.95);  // partial-fault tolerance
  EXPECT_TRUE(d.alarm);
  EXPECT_EQ(d.motor, 2);
}

TEST(Decision, PaperRuleReadsTheOutputBackThroughTheMap) {
  // Map for motor 4 (exact: 180°, 1↔3, 2↔4): its output 2 being low means original motor 4.
  std::array<Input, 4> out{Input::Ones(), Input::Ones(), Input::Ones(), Input(1, 0.05, 1, 1)};
  Decision d = decidePaperRule(out, SymmetryMode::kExactGroup, 0.2);
  EXPECT_TRUE(d.alarm);
  EXPECT_EQ(d.motor, 4);
  // Output 1 of the map for motor 1 (x → −x, 1↔2) stands for original motor 2.
  out = {Input(0.1, 1, 1, 1), Input::Ones(), Input::Ones(), Input::Ones()};
  EXPECT_EQ(decidePaperRule(out, SymmetryMode::kExactGroup, 0.2).motor, 2);
  out = {Input::Ones(), Input::Ones(), Input::Ones(), Input::Ones()};
  EXPECT_FALSE(decidePaperRule(out, SymmetryMode::kPaperRotation, 0.2).alarm);
}

WindowOutcome outcome(int traj, int length, int motor, double theta, Input theta_hat, double tol = 0.2) {
  WindowOutcome o;
  o.trajectory = traj;
  o.faulty_length = length;
  o.true_motor = motor;
  o.true_theta = theta;
  o.theta_hat = theta_hat;
  o.decision = decide(theta_hat, tol);
  return o;
}

TEST(Metrics, HandMadeCase) {
  const Input healthy = Input::Ones();
  std::vector<WindowOutcome> w = {
      // Trajectory 0: motor 3 fails (Θ = 0); detected from L = 2 on; estimate 0.04 then 0.0.
      outcome(0, 0, 3, 0.0, healthy), outcome(0, 1, 3, 0.0, Input(1, 1, 0.5, 1)),
      outcome(0, 2, 3, 0.0, Input(1, 1, 0.04, 1)), outcome(0, 3, 3, 0.0, Input(1, 1, 0.0, 1)),
      // Trajectory 1: motor 1 fails but the detector names motor 2 at L = 1 and 2, right at 3.
      outcome(1, 0, 1, 0.0, Input(1, 0.1, 1, 1)),  // false alarm before the fault
      outcome(1, 1, 1, 0.0, Input(1, 0.1, 1, 1)), outcome(1, 2, 1, 0.0, Input(1, 0.1, 1, 1)),
      outcome(1, 3, 1, 0.0, Input(0.1, 1, 1, 1)),
      // Trajectory 2: healthy, one false alarm out of 3 windows.
      outcome(2, 0, 0, 1.0, healthy), outcome(2, 0, 0, 1.0, Input(1, 1, 1, 0.15)), outcome(2, 0, 0, 1.0, healthy),
  };
  const AccuracyByLength iso = isolationAccuracy(w, 3, false);
  EXPECT_DOUBLE_EQ(iso.accuracy[0], 0.5);  // trajectory 1 alarms before the fault
  EXPECT_DOUBLE_EQ(iso.accuracy[1], 0.0);  // neither right
  EXPECT_DOUBLE_EQ(iso.accuracy[2], 0.5);
  EXPECT_DOUBLE_EQ(iso.accuracy[3], 1.0);
  EXPECT_EQ(iso.windows[3], 2);
  const AccuracyByLength h = isolationAccuracy(w, 3, true);
  EXPECT_NEAR(h.accuracy[0], 2.0 / 3.0, 1e-15);
  EXPECT_TRUE(std::isnan(h.accuracy[1]));
  const AccuracyByLength id = identificationAccuracy(w, 3);
  EXPECT_DOUBLE_EQ(id.accuracy[2], 0.5);  // 0.04 is within 0.05 of 0
  EXPECT_DOUBLE_EQ(id.accuracy[3], 0.5);  // trajectory 0: Θ̂ = 0 ok; trajectory 1 names motor 1 but Θ̂ = 0.1 is too far
  const DetectionDelay d = detectionDelay(w);
  EXPECT_EQ(d.faulty, 2);
  EXPECT_EQ(d.detected, 2);
  EXPECT_DOUBLE_EQ(d.median, 2.0);  // delays {2, 3}: nearest-rank median is 2
  EXPECT_DOUBLE_EQ(d.p95, 3.0);
  EXPECT_NEAR(falseAlarmRate(w), 2.0 / 5.0, 1e-15);  // 5 fault-free windows, 2 alarms
  EXPECT_NEAR(thetaMae(w), (0.5 + 0.04 + 0.0 + 1.0 + 1.0 + 0.1) / 6.0, 1e-12);
}

TEST(Metrics, NeverDetectedAndEmpty) {
  std::vector<WindowOutcome> w = {outcome(0, 1, 2, 0.0, Input::Ones()), outcome(0, 2, 2, 0.0, Input::Ones())};
  const DetectionDelay d = detectionDelay(w);
  EXPECT_EQ(d.faulty, 1);
  EXPECT_EQ(d.detected, 0);
  EXPECT_TRUE(std::isnan(d.median));
  EXPECT_EQ(falseAlarmRate({}), 0.0);
  EXPECT_EQ(thetaMae({}), 0.0);
}

}  // namespace
}  // namespace quadfdi

namespace quadfdi {
namespace {

// The batched estimate equals one window at a time through the map of each motor (LibTorch, to
// float round-off), motor 2's estimate is the network on the unmapped window (g₂ = identity), and
// the thread count changes nothing.
// The causal mean E1–E6 can decide on (evaluate --average-windows): over a flight's last windows,
// fewer at its start, never across flights.
TEST(AverageOverFlight, MeansTheFlightsLastWindowsOnly) {
  const std::vector<WindowRef> windows = {{0, 100}, {0, 101}, {0, 102}, {1, 100}, {1, 101}};
  std::vector<Input> theta;
  for (double v : {1.0, 0.5, 0.0, 0.2, 0.4}) theta.push_back(Input::Constant(v));
  const std::vector<Input> two = averageOverFlight(windows, theta, 2);
  const double expected[] = {1.0, 0.75, 0.25, 0.2, 0.3};
  for (std::size_t i = 0; i < windows.size(); ++i) EXPECT_DOUBLE_EQ(two[i](0), expected[i]) << i;
  const std::vector<Input> all = averageOverFlight(windows, theta, 10);
  EXPECT_DOUBLE_EQ(all[2](3), 0.5);  // flight 0's three windows
  EXPECT_DOUBLE_EQ(all[4](3), 0.3);  // flight 1's two, nothing of flight 0
  const std::vector<Input> one = averageOverFlight(windows, theta, 1);
  for (std::size_t i = 0; i < windows.size(); ++i) EXPECT_EQ(one[i], theta[i]);
  // A one-window dip naming another motor is outvoted by the windows around it.
  std::vector<Input> blip(5, Input(0.1, 0.9, 0.9, 0.9));
  blip[3] = Input(0.4, 0.9, 0.05, 0.9);
  const std::vector<WindowRef> flight = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {0, 5}};
  EXPECT_EQ(decide(blip[3], 0.2).motor, 3);
  EXPECT_EQ(decide(averageOverFlight(flight, blip, 4)[3], 0.2).motor, 1);
}

TEST(EstimateAllMotors, MatchesPerWindowMappedPredictions) {
  ModelMetadata m;
  m.window = 10;
  m.hidden = 8;
  const FaultIdentifier net = FaultIdentifier::create(m, 2);
  const TrainedModel model{net.metadata(), exportWeights(net)};
  RolloutConfig rc;
  rc.window = 10;
  TrajectoryBatch b;
  RolloutEngine(rc).run(algorithm1Jobs(0, 2, {0.0, 0.7}, {1, 3}), 1, b);
  std::vector<WindowRef> windows;
  enumerateWindows(b, 10, windows);
  std::vector<std::array<Input, 4>> raw;
  const std::vector<Input> theta = estimateAllMotors(model, SymmetryMode::kExactGroup, b, windows, &raw);
  ASSERT_EQ(theta.size(), windows.size());
  std::vector<float> f(static_cast<std::size_t>(10 * m.channels()));
  float out[4];
  for (std::size_t i = 0; i < windows.size(); i += 5) {
    for (int k = 1; k <= 4; ++k) {
      const SymmetryMap g = mapMotorToMotor2(k, SymmetryMode::kExactGroup);
      gatherWindowFeatures(b, windows[i], 10, m.features, m.output, k == 2 ? nullptr : &g, f.data());
      net.predict(f.data(), 1, out);
      EXPECT_NEAR(theta[i](k - 1), out[1], 1e-6) << "window " << i << " motor " << k;
      EXPECT_NEAR(raw[i][static_cast<std::size_t>(k - 1)](0), out[0], 1e-6);
    }
  }
  // The same bits on one worker and on three.
  std::vector<std::array<Input, 4>> raw1, raw3;
  EXPECT_EQ(estimateAllMotors(model, SymmetryMode::kExactGroup, b, windows, &raw1, 1),
            estimateAllMotors(model, SymmetryMode::kExactGroup, b, windows, &raw3, 3));
  EXPECT_EQ(raw1, raw3);
}

}  // namespace
}  // namespace quadfdi
