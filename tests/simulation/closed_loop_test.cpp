#include <gtest/gtest.h>

#include "test_support.h"

namespace quadfdi {
namespace {

TEST(ClosedLoop, FaultScalesTheCommandFromTheFaultStepOn) {
  const VehicleParams p = nominalParams();
  auto ctrl = test::makeOrDie(p, ControllerKind::kLqr);
  ctrl->setGoal(Vec3(0, 0, 1));
  SimulationSettings s;
  s.steps = 200;
  s.fault.theta = Input(1, 0.3, 1, 1);
  s.fault.fault_step = 100;
  FlightLog log;
  const FlightSummary sum = ClosedLoopSimulator(p, s).run(*ctrl, test::hoverState(Vec3(0.2, 0, 1)), &log);
  ASSERT_FALSE(sum.cut());
  ASSERT_EQ(log.size(), 200);
  for (int k = 0; k < 200; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    const Input& u = log.controls[ku].u_cmd;
    const Input expected = k >= 100 ? Input(u(0), 0.3 * u(1), u(2), u(3)) : u;
    EXPECT_EQ(log.applied[ku], expected) << "step " << k;
    EXPECT_TRUE((u.array() >= p.min_thrust).all() && (u.array() <= p.max_thrust).all());
  }
  // Before the fault the flight is the healthy one, bit for bit.
  SimulationSettings healthy = s;
  healthy.fault = FaultSpec{};
  FlightLog ref;
  ClosedLoopSimulator(p, healthy).run(*ctrl, test::hoverState(Vec3(0.2, 0, 1)), &ref);
  for (int k = 0; k <= 100; ++k) EXPECT_EQ(log.states[static_cast<std::size_t>(k)], ref.states[static_cast<std::size_t>(k)]);
  EXPECT_NE(log.states[150], ref.states[150]);
}

TEST(ClosedLoop, CompleteFailureIsCutAndFlaggedNotKeptAsNaN) {
  const VehicleParams p = nominalParams();
  auto ctrl = test::makeOrDie(p, ControllerKind::kLqr);
  ctrl->setGoal(Vec3(0, 0, 1));
  SimulationSettings s;
  s.steps = 5000;
  s.fault.theta = Input(0, 1, 1, 1);
  s.fault.fault_step = 10;
  FlightLog log;
  const FlightSummary sum = ClosedLoopSimulator(p, s).run(*ctrl, test::hoverState(Vec3(0, 0, 1)), &log);
  ASSERT_TRUE(sum.cut());
  EXPECT_TRUE(sum.end_status == StepStatus::kAttitudeLimit || sum.end_status == StepStatus::kBelowGround);
  EXPECT_EQ(log.size(), sum.steps_completed);
  EXPECT_LT(log.size(), 5000);
  for (const State& x : log.states) {
    EXPECT_TRUE(x.allFinite());
    EXPECT_EQ(checkState(x, s.bounds), StepStatus::kOk);
  }
}

TEST(ClosedLoop, InvalidStartIsFlaggedWithoutSteps) {
  const VehicleParams p = nominalParams();
  auto ctrl = test::makeOrDie(p, ControllerKind::kLqr);
  ctrl->setGoal(Vec3(0, 0, 1));
  SimulationSettings s;
  State x = test::hoverState(Vec3(0, 0, 1));
  x(idx::kRoll) = 2.0;
  FlightLog log;
  const FlightSummary sum = ClosedLoopSimulator(p, s).run(*ctrl, x, &log);
  EXPECT_EQ(sum.end_status, StepStatus::kAttitudeLimit);
  EXPECT_EQ(log.size(), 0);
}

TEST(ClosedLoop, SensorNoiseIsSeededAndOnlyOnTheOutput) {
  const VehicleParams p = nominalParams();
  auto ctrl = test::makeOrDie(p, ControllerKind::kLqr);
  ctrl->setGoal(Vec3(0, 0, 1));
  SimulationSettings s;
  s.steps = 300;
  FlightLog clean, noisy, again;
  const ClosedLoopSimulator plain(p, s);
  plain.run(*ctrl, test::hoverState(Vec3(0.3, 0, 1)), &clean);
  s.noise.position_std = 0.01;
  s.noise.attitude_std = 0.005;
  s.noise.seed = 9;
  const ClosedLoopSimulator sim(p, s);
  sim.run(*ctrl, test::hoverState(Vec3(0.3, 0, 1)), &noisy);
  sim.run(*ctrl, test::hoverState(Vec3(0.3, 0, 1)), &again);
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < 300; ++k) {
    EXPECT_EQ(noisy.states[k], clean.states[k]);  // the controller flies the true state
    EXPECT_EQ(noisy.outputs[k], again.outputs[k]);  // reproducible
    sum_sq += (noisy.outputs[k] - clean.outputs[k]).head<3>().squaredNorm();
  }
  const double std_est = std::sqrt(sum_sq / (3 * 300));
  EXPECT_NEAR(std_est, 0.01, 0.0015);
}

TEST(ClosedLoop, GyroNoiseIsOnTheLoggedRatesOnlyAndLeavesTheOtherNoiseAsItWas) {
  const VehicleParams p = nominalParams();
  auto ctrl = test::makeOrDie(p, ControllerKind::kLqr);
  ctrl->setGoal(Vec3(0, 0, 1));
  SimulationSettings s;
  s.steps = 400;
  s.noise.attitude_std = 0.005;
  s.noise.seed = 4;
  FlightLog without, with;
  ClosedLoopSimulator(p, s).run(*ctrl, test::hoverState(Vec3(0.3, 0, 1)), &without);
  s.noise.rate_std = 0.02;
  ClosedLoopSimulator(p, s).run(*ctrl, test::hoverState(Vec3(0.3, 0, 1)), &with);
  ASSERT_EQ(without.rates.size(), 400u);
  ASSERT_EQ(with.rates.size(), 400u);
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < 400; ++k) {
    EXPECT_EQ(with.states[k], without.states[k]);    // the controller flies the true state
    EXPECT_EQ(with.outputs[k], without.outputs[k]);  // the attitude noise of the seed is unchanged
    EXPECT_EQ(without.rates[k], Vec3(without.states[k].segment<3>(idx::kRate)));  // no gyro noise: the truth
    sum_sq += (with.rates[k] - without.rates[k]).squaredNorm();
  }
  EXPECT_NEAR(std::sqrt(sum_sq / (3 * 400)), 0.02, 0.002);
  s.noise.rate_std = -1.0;
  EXPECT_NE(validate(s), "");
}

TEST(ClosedLoop, ValidateRejectsBadSettings) {
  SimulationSettings s;
  EXPECT_EQ(validate(s), "");
  s.fault.theta(2) = 1.5;
  EXPECT_NE(validate(s).find("motor 3"), std::string::npos);
  s = SimulationSettings{};
  s.steps = 0;
  EXPECT_NE(validate(s), "");
  s = SimulationSettings{};
  s.dt = -1;
  EXPECT_NE(validate(s), "");
}

}  // namespace
}  // namespace quadfdi
