#include <gtest/gtest.h>

#include <cmath>

#include "simulation/sensor_model.h"

namespace quadfdi {
namespace {

State rampState(double t) {
  State x = State::Zero();
  for (int i = 0; i < kStateDim; ++i) x(i) = 0.1 * (i + 1) * t;
  return x;
}

TEST(SensorModel, InactiveModelReturnsTheTrueStateExactly) {
  SensorModel sensors(SensorModelConfig{}, 0.002);
  Rng rng(1, 0);
  sensors.reset(rampState(0.0));
  for (int k = 0; k < 50; ++k) {
    const State x = rampState(0.002 * k);
    const State est = sensors.measure(x, rng);
    for (int i = 0; i < kStateDim; ++i) ASSERT_EQ(est(i), x(i));
  }
}

TEST(SensorModel, DelayShiftsTheEstimateByExactlyThatManySteps) {
  SensorModelConfig c;
  c.delay_steps = 7;
  SensorModel sensors(c, 0.002);
  Rng rng(1, 0);
  sensors.reset(rampState(0.0));
  for (int k = 0; k < 40; ++k) {
    const State est = sensors.measure(rampState(0.002 * k), rng);
    const State expected = rampState(0.002 * std::max(0, k - 7));
    for (int i = 0; i < kStateDim; ++i) ASSERT_NEAR(est(i), expected(i), 1e-15) << "k " << k << " i " << i;
  }
}

TEST(SensorModel, LowPassStepResponseFollowsTheTimeConstant) {
  SensorModelConfig c;
  c.attitude_filter_tau = 0.02;
  c.rate_filter_tau = 0.005;
  const double dt = 0.002;
  SensorModel sensors(c, dt);
  Rng rng(1, 0);
  sensors.reset(State::Zero());
  State step = State::Zero();
  step(idx::kRoll) = 1.0;
  step(idx::kP) = 1.0;
  State est;
  const int n = 10;  // 20 ms = one attitude time constant, four rate time constants
  for (int k = 0; k < n; ++k) est = sensors.measure(step, rng);
  EXPECT_NEAR(est(idx::kRoll), 1.0 - std::exp(-n * dt / 0.02), 1e-12);
  EXPECT_NEAR(est(idx::kP), 1.0 - std::exp(-n * dt / 0.005), 1e-12);
  EXPECT_EQ(est(idx::kPx), 0.0);  // position is not filtered
}

TEST(SensorModel, YawFilterFollowsTheShortWayRoundAcrossPi) {
  SensorModelConfig c;
  c.attitude_filter_tau = 0.01;
  SensorModel sensors(c, 0.002);
  Rng rng(1, 0);
  State x = State::Zero();
  x(idx::kYaw) = M_PI - 0.01;
  sensors.reset(x);
  x(idx::kYaw) = -M_PI + 0.01;  // the same heading, 0.02 rad further round
  State est;
  for (int k = 0; k < 200; ++k) est = sensors.measure(x, rng);
  // Converges to the equivalent angle π + 0.01 without passing through zero.
  EXPECT_NEAR(est(idx::kYaw), M_PI + 0.01, 1e-9);
}

TEST(SensorModel, NoiseHasTheStatedStandardDeviationAndIsSeeded) {
  SensorModelConfig c;
  c.position_std = 0.003;
  c.rate_std = 0.05;
  SensorModel a(c, 0.002), b(c, 0.002);
  Rng ra(9, 3), rb(9, 3);
  a.reset(State::Zero());
  b.reset(State::Zero());
  double sum2_pos = 0.0, sum2_rate = 0.0;
  const int n = 40000;
  for (int k = 0; k < n; ++k) {
    const State ea = a.measure(State::Zero(), ra);
    const State eb = b.measure(State::Zero(), rb);
    ASSERT_EQ(ea, eb);
    sum2_pos += ea(idx::kPx) * ea(idx::kPx);
    sum2_rate += ea(idx::kQ) * ea(idx::kQ);
  }
  EXPECT_NEAR(std::sqrt(sum2_pos / n), 0.003, 0.003 * 0.02);
  EXPECT_NEAR(std::sqrt(sum2_rate / n), 0.05, 0.05 * 0.02);
}

TEST(SensorModel, CorrelatedErrorsKeepTheirStdAndHaveTheLag1CorrelationOfTheirTimeConstant) {
  SensorModelConfig c;
  c.position_std = 0.004;
  c.estimate_error_tau = 0.05;
  const double dt = 0.002;
  SensorModel sensors(c, dt);
  Rng rng(2, 5);
  sensors.reset(State::Zero());
  double sum2 = 0.0, lag1 = 0.0, previous = 0.0;
  const int n = 400000;
  for (int k = 0; k < n; ++k) {
    const double e = sensors.measure(State::Zero(), rng)(idx::kPy);
    sum2 += e * e;
    lag1 += e * previous;
    previous = e;
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.004, 0.004 * 0.05);
  EXPECT_NEAR(lag1 / sum2, std::exp(-dt / 0.05), 0.005);
}

TEST(SensorModel, ValidateRefusesNegativeAndNonFiniteValues) {
  SensorModelConfig c;
  EXPECT_EQ(validate(c), "");
  c.attitude_std = -1.0;
  EXPECT_NE(validate(c), "");
  c = {};
  c.rate_filter_tau = NAN;
  EXPECT_NE(validate(c), "");
  c = {};
  c.delay_steps = -1;
  EXPECT_NE(validate(c), "");
}

}  // namespace
}  // namespace quadfdi
