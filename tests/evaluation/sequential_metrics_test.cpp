// The sequential rule's evaluation hook (issue 14) on synthetic flights with known answers, and
// the interval's coverage on AR(1) noise around a known Θ.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <vector>

#include "evaluation/sequential_metrics.h"
#include "simulation/rng.h"

namespace quadfdi {
namespace {

double normal(Rng& rng) {
  const double u = 1.0 - rng.uniform(), v = rng.uniform();
  return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
}

// Healthy at 0.97 then, from `fault`, motor `motor` at `theta`; AR(1) noise (σ, φ) on every motor.
FlightThetaStream flight(int samples, int motor, double theta, long fault, double sigma, double phi, Rng& rng) {
  FlightThetaStream f;
  f.truth = {motor, theta, motor ? fault : -1};
  std::array<double, kMotors> e{};
  for (double& v : e) v = sigma * normal(rng);
  for (int i = 0; i < samples; ++i) {
    MotorTheta t;
    for (int k = 0; k < kMotors; ++k) {
      e[static_cast<std::size_t>(k)] = phi * e[static_cast<std::size_t>(k)] + sigma * std::sqrt(1 - phi * phi) * normal(rng);
      const double mean = (motor == k + 1 && i >= fault) ? theta : 0.97;
      t[static_cast<std::size_t>(k)] = static_cast<float>(mean + e[static_cast<std::size_t>(k)]);
    }
    f.theta.push_back(t);
  }
  return f;
}

// The rule the hand counts below assume: issue 14's example level 0.9, both thresholds just under
// 3 (see sequential_test).
SequentialEvaluationConfig handCountConfig() {
  SequentialEvaluationConfig c;
  c.rule.degraded_below = 0.9;
  c.rule.degraded_threshold = c.rule.failed_threshold = 2.999;
  return c;
}

// A noise-free healthy flight whose motor index `motor` reads `value` for 20 samples from each start.
FlightThetaStream healthyWithDips(int samples, int motor, std::initializer_list<int> starts, float value, Rng& rng) {
  FlightThetaStream f = flight(samples, 0, 1.0, -1, 0.0, 0.0, rng);
  for (int start : starts)
    for (int k = start; k < start + 20; ++k) f.theta[static_cast<std::size_t>(k)][static_cast<std::size_t>(motor)] = value;
  return f;
}

TEST(SequentialEvaluation, CountsDelaysIsolationAndFalseAlarmsOnCleanSteps) {
  const SequentialEvaluationConfig c = handCountConfig();
  Rng rng(1, 0);
  std::vector<FlightThetaStream> flights;
  flights.push_back(flight(1000, 0, 1.0, -1, 0.0, 0.0, rng));   // healthy
  flights.push_back(flight(1000, 3, 0.7, 400, 0.0, 0.0, rng));  // degraded after 15 samples
  flights.push_back(flight(1000, 1, 0.1, 400, 0.0, 0.0, rng));  // degraded after 4, failed after 15
  flights.push_back(healthyWithDips(1000, 1, {100}, 0.5f, rng));  // a false alarm
  const SequentialEvaluation r = evaluateSequential(flights, c);
  EXPECT_EQ(r.degraded.flights, 2);
  EXPECT_EQ(r.degraded.detected, 2);
  EXPECT_EQ(r.failed.flights, 1);
  EXPECT_EQ(r.failed.detected, 1);
  EXPECT_NEAR(r.failed.delay_median, 14 * c.dt, 1e-12);  // the 15th sample from the fault is index 14
  EXPECT_NEAR(r.degraded.delay_median, 0.5 * (3 + 14) * c.dt, 1e-12);
  EXPECT_EQ(r.isolated_early, 1.0);
  EXPECT_EQ(r.severity_right_late, 1.0);
  EXPECT_EQ(r.false_alarms, 1);
  EXPECT_EQ(r.false_alarms_at_start, 0);  // no start window asked for
  SequentialEvaluationConfig start = c;
  start.start_samples = 108;  // the dip raises its alarm at sample 107: 8 × (0.9 − 0.5) ≥ 2.999
  EXPECT_EQ(evaluateSequential(flights, start).false_alarms_at_start, 1);
  start.start_samples = 107;
  EXPECT_EQ(evaluateSequential(flights, start).false_alarms_at_start, 0);
  EXPECT_NEAR(r.healthy_hours, (2000 + 800) * c.dt / 3600.0, 1e-12);
  EXPECT_NEAR(r.false_alarms_upper_bound * r.healthy_hours, 4.743864518, 1e-6);
  EXPECT_EQ(r.flights_with_false_alarm, 1);
  EXPECT_NEAR(r.alarmed_flights_upper_bound, r.false_alarms_upper_bound, 1e-12);  // one alarm, one flight
  EXPECT_LT(r.theta_max_error, 1e-6);  // noise-free steps: the estimate is exact once flown through
  // A fault at the degraded level itself (Θ̂ = 0.9 = the level never builds evidence) is still a
  // fault to isolate: it counts, unisolated, instead of dropping out of the fraction.
  flights.push_back(flight(1000, 2, 0.9, 400, 0.0, 0.0, rng));
  const SequentialEvaluation with_mild = evaluateSequential(flights, c);
  EXPECT_EQ(with_mild.isolation_flights, 3);
  EXPECT_EQ(with_mild.degraded.flights, 2);  // not `degraded` by the rule's own level
  EXPECT_NEAR(with_mild.isolated_late, 2.0 / 3.0, 1e-12);
}

// A flight whose recording ends between the checks (the vehicle crashed) is scored at +50 ms and
// not at +300 ms: the late fractions are of the flights still flying, and the counts say so.
TEST(SequentialEvaluation, IsolationIsScoredOnTheFlightsStillRecordedAtEachCheck) {
  SequentialEvaluationConfig c = handCountConfig();
  Rng rng(3, 0);
  std::vector<FlightThetaStream> flights;
  flights.push_back(flight(1000, 1, 0.0, 400, 0.0, 0.0, rng));  // failed after 4 samples, flies on
  FlightThetaStream crashed = flight(1000, 2, 0.0, 400, 0.0, 0.0, rng);
  crashed.theta.resize(400 + 100);  // ends 100 samples after the fault: after +25, before +150
  flights.push_back(crashed);
  FlightThetaStream wrong = flight(1000, 3, 0.0, 400, 0.0, 0.0, rng);
  wrong.truth.motor = 4;  // the rule names motor 3: wrong at both checks
  flights.push_back(wrong);
  const SequentialEvaluation r = evaluateSequential(flights, c);
  EXPECT_EQ(r.isolation_flights, 3);
  EXPECT_EQ(r.recorded_early, 3);
  EXPECT_EQ(r.named_early, 2);
  EXPECT_NEAR(r.isolated_early, 2.0 / 3.0, 1e-12);
  EXPECT_EQ(r.recorded_late, 2);
  EXPECT_EQ(r.named_late, 1);
  EXPECT_EQ(r.severity_named_late, 1);
  EXPECT_NEAR(r.isolated_late, 0.5, 1e-12);
  EXPECT_NEAR(r.severity_right_late, 0.5, 1e-12);
  // None recorded that late: the fraction is 0, not a division by zero.
  c.isolation_late = 5000;
  const SequentialEvaluation none = evaluateSequential(flights, c);
  EXPECT_EQ(none.recorded_late, 0);
  EXPECT_EQ(none.isolated_late, 0.0);
}

// Alarms cluster by flight: a flight that dips twice raises two alarms but is one alarmed flight,
// and the bound on alarmed flights is the Poisson bound on that count, not on the alarms.
TEST(SequentialEvaluation, FalseAlarmsAreAlsoCountedByFlight) {
  SequentialEvaluationConfig c = handCountConfig();
  c.rule.clear_after = 50;
  Rng rng(2, 0);
  std::vector<FlightThetaStream> flights;
  flights.push_back(healthyWithDips(2000, 0, {100, 1000}, 0.5f, rng));  // twice
  flights.push_back(healthyWithDips(2000, 2, {500}, 0.5f, rng));        // once
  flights.push_back(flight(2000, 0, 1.0, -1, 0.0, 0.0, rng));  // clean
  const SequentialEvaluation r = evaluateSequential(flights, c);
  EXPECT_EQ(r.false_alarms, 3);
  EXPECT_EQ(r.flights_with_false_alarm, 2);
  EXPECT_NEAR(r.alarmed_flights_per_hour * r.healthy_hours, 2.0, 1e-9);
  EXPECT_NEAR(r.alarmed_flights_upper_bound * r.healthy_hours, 6.295793622, 1e-6);  // χ²(0.95; 6) / 2
  EXPECT_LT(r.alarmed_flights_upper_bound, r.false_alarms_upper_bound);
  // Each alarm is listed where it was raised (inside its dip), on the dipping motor, at its severity.
  ASSERT_EQ(r.false_alarm_list.size(), 3u);
  const int flight_of[] = {0, 0, 1}, motor_of[] = {1, 1, 3};
  const long dip_of[] = {100, 1000, 500};
  for (std::size_t i = 0; i < 3; ++i) {
    const FalseAlarm& a = r.false_alarm_list[i];
    EXPECT_EQ(a.flight, flight_of[i]) << i;
    EXPECT_EQ(a.motor, motor_of[i]) << i;
    EXPECT_GE(a.sample, dip_of[i]) << i;
    EXPECT_LT(a.sample, dip_of[i] + 20) << i;
    EXPECT_EQ(a.severity, Severity::kDegraded) << i;
    EXPECT_LT(a.theta_est, c.rule.degraded_below) << i;
  }
}

// A false `failed` and a false `degraded` ask different things of a pilot, so the report counts
// them apart: a deep healthy dip either escalates an alarm raised as degraded, or, where the failed
// threshold is the lower, raises it straight at failed; a shallow dip only ever raises degraded.
TEST(SequentialEvaluation, FalseAlarmsAreSplitBySeverity) {
  SequentialEvaluationConfig c = handCountConfig();
  c.rule.clear_after = 50;
  Rng rng(3, 0);
  const std::vector<FlightThetaStream> flights{healthyWithDips(1000, 1, {100}, 0.0f, rng),   // deep
                                               healthyWithDips(1000, 2, {500}, 0.5f, rng)};  // shallow
  // Equal thresholds: degraded after 4 samples of 0.9, failed after 10 of 0.3 → one escalation.
  const SequentialEvaluation equal = evaluateSequential(flights, c);
  EXPECT_EQ(equal.false_alarms, 2);
  EXPECT_EQ(equal.false_alarms_failed, 0);
  EXPECT_EQ(equal.false_escalations, 1);
  // A failed threshold of 0.5: failed after 2 samples, before degraded's 4 → raised at failed.
  c.rule.failed_threshold = 0.5;
  const SequentialEvaluation low = evaluateSequential(flights, c);
  EXPECT_EQ(low.false_alarms, 2);
  EXPECT_EQ(low.false_alarms_failed, 1);
  EXPECT_EQ(low.false_escalations, 0);
  ASSERT_EQ(low.false_alarm_list.size(), 2u);
  EXPECT_EQ(low.false_alarm_list[0].severity, Severity::kFailed);
  EXPECT_EQ(low.false_alarm_list[1].severity, Severity::kDegraded);
  // A fault's own escalation is not a false one.
  c.rule.failed_threshold = 2.999;
  const SequentialEvaluation faulty = evaluateSequential({flight(1000, 1, 0.0, 400, 0.0, 0.0, rng)}, c);
  EXPECT_EQ(faulty.false_alarms, 0);
  EXPECT_EQ(faulty.false_escalations, 0);
  EXPECT_TRUE(faulty.false_alarm_list.empty());
}

// An alarm that returns from failed to degraded and fails again is one alarm: "escalated" counts
// the false alarms raised as degraded that reached failed, not every degraded → failed step.
TEST(SequentialEvaluation, AnAlarmEscalatesOnceHoweverOftenItFlaps) {
  SequentialEvaluationConfig c = handCountConfig();
  c.rule.clear_after = 50;
  Rng rng(4, 0);
  FlightThetaStream f = flight(1000, 0, 1.0, -1, 0.0, 0.0, rng);
  // Motor 2: a deep dip, 80 samples between the levels (back to degraded), a second deep dip.
  for (int k = 100; k < 300; ++k) f.theta[static_cast<std::size_t>(k)][1] = (k < 120 || (k >= 200 && k < 220)) ? 0.0f : 0.5f;
  const SequentialEvaluation equal = evaluateSequential({f}, c);  // raised degraded, escalated, back, again
  EXPECT_EQ(equal.false_alarms, 1);
  EXPECT_EQ(equal.false_alarms_failed, 0);
  EXPECT_EQ(equal.false_escalations, 1);
  c.rule.failed_threshold = 0.5;  // raised straight at failed, back to degraded, failed again
  const SequentialEvaluation low = evaluateSequential({f}, c);
  EXPECT_EQ(low.false_alarms, 1);
  EXPECT_EQ(low.false_alarms_failed, 1);
  EXPECT_EQ(low.false_escalations, 0);
}

TEST(SequentialEvaluation, TheIntervalCoversTheTruthAtItsNominalRate) {
  // Noise matching the rule's noise model, no model error: the 90 % interval must cover Θ in
  // 85–95 % of the samples after the fault has been flown through.
  SequentialEvaluationConfig c;
  c.rule.noise.sigma = 0.02;
  c.rule.noise.phi = 0.9;
  c.rule.noise.model_sigma = 0.0;
  c.rule.interval_level = 0.9;
  Rng rng(7, 0);
  std::vector<FlightThetaStream> flights;
  for (int f = 0; f < 200; ++f) flights.push_back(flight(1000, 1 + f % 4, 0.2 + 0.003 * f, 300, 0.02, 0.9, rng));
  const SequentialEvaluation r = evaluateSequential(flights, c);
  ASSERT_GT(r.estimate_samples, 100000);
  EXPECT_NEAR(r.coverage, 0.90, 0.05);
  EXPECT_LT(r.theta_mae, 0.05);
  // An interval that ignores the autocorrelation (φ = 0 in the model) covers far too little.
  c.rule.noise.phi = 0.0;
  EXPECT_LT(evaluateSequential(flights, c).coverage, 0.6);
}

}  // namespace
}  // namespace quadfdi
