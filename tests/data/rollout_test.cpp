#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "data/algorithm1.h"
#include "data/residual.h"
#include "data/rollout.h"
#include "data/window_buffer.h"
#include "simulation/closed_loop.h"

namespace quadfdi {
namespace {

RolloutConfig smallConfig(int window = 20) {
  RolloutConfig c;
  c.window = window;
  c.seed = 17;
  return c;
}

TEST(Residual, ExactlyZeroForTheNominalModelsOwnStep) {
  std::mt19937_64 gen(1);
  std::uniform_real_distribution<double> d(-0.5, 0.5);
  const RigidBodyModel m = RigidBodyModel::fromParams(nominalParams());
  for (Integrator integ : {Integrator::kRk4, Integrator::kEuler}) {
    for (int t = 0; t < 100; ++t) {
      PlantState p;
      for (int i = 0; i < kStateDim; ++i) p.x(i) = d(gen);
      const Input u = Input::Constant(0.07) + 0.02 * Input(d(gen), d(gen), d(gen), d(gen));
      const State prev = p.x;
      stepPlant(m, integ, 0.002, 0.0, u, p);
      EXPECT_EQ(oneStepResidual(m, integ, 0.002, prev, u, p.x, OutputKind::kPositionEuler), Output::Zero());
      // A weaker motor shows up in the residual within one RK4 step. (One Euler step moves only
      // velocities and rates, so y sees the fault one step later there.)
      if (integ == Integrator::kEuler) continue;
      PlantState faulty;
      faulty.x = prev;
      stepPlant(m, integ, 0.002, 0.0, Input(u(0), 0.5 * u(1), u(2), u(3)), faulty);
      EXPECT_GT(oneStepResidual(m, integ, 0.002, prev, u, faulty.x, OutputKind::kPositionEuler).norm(), 1e-9);
    }
  }
}

TEST(Rollout, ResidualZeroBeforeTheFaultAndNonZeroAfter) {
  const RolloutEngine engine(smallConfig());
  ASSERT_EQ(engine.error(), "");
  TrajectoryBatch b;
  engine.run(algorithm1Jobs(0, 3, {1.0, 0.5, 0.0}, {2}), 1, b);
  ASSERT_EQ(b.count, 9);
  ASSERT_EQ(b.samples, 41);
  for (int i = 0; i < b.count; ++i) {
    const float theta2 = b.theta[static_cast<std::size_t>(i) * 4 + 1];
    ASSERT_EQ(b.length[static_cast<std::size_t>(i)], 41) << "no crash expected in 0.08 s";
    for (int k = 0; k < b.samples; ++k) {
      double norm = 0;
      for (int c = 0; c < kOutputDim; ++c) norm += std::abs(static_cast<double>(b.residuals[b.sampleOffset(i, k) * kOutputDim + static_cast<std::size_t>(c)]));
      if (k <= 20 || theta2 == 1.0f)
        EXPECT_EQ(norm, 0.0) << "trajectory " << i << " sample " << k;
      else
        EXPECT_GT(norm, 0.0) << "trajectory " << i << " sample " << k;
    }
  }
}

TEST(Rollout, MatchesTheReferenceSimulator) {
  RolloutConfig c = smallConfig(50);
  for (ControllerKind kind : {ControllerKind::kLqr, ControllerKind::kCbfQp}) {
    c.controller.kind = kind;
    const RolloutEngine engine(c);
    TrajectoryBatch b;
    engine.run({TrajectoryJob{5, 3, 0.3}}, 1, b);
    Rng rng(c.seed, 5);
    const Scenario sc = sampleScenario(c.ranges, rng);
    auto ctrl = makeController(c.plant, c.controller, c.dt).controller;
    ctrl->setGoal(sc.goal);
    SimulationSettings s;
    s.steps = b.samples;
    s.fault.theta(2) = 0.3;
    s.fault.fault_step = 50;
    FlightLog log;
    ClosedLoopSimulator(c.plant, s).run(*ctrl, sc.initial_state, &log);
    for (int k = 0; k < b.samples; ++k) {
      for (int i = 0; i < kStateDim; ++i)
        EXPECT_EQ(b.states[b.sampleOffset(0, k) * kStateDim + static_cast<std::size_t>(i)],
                  static_cast<float>(log.states[static_cast<std::size_t>(k)](i)));
      for (int j = 0; j < kInputDim; ++j)
        EXPECT_EQ(b.inputs[b.sampleOffset(0, k) * kInputDim + static_cast<std::size_t>(j)],
                  static_cast<float>(log.controls[static_cast<std::size_t>(k)].u_cmd(j)));
    }
  }
}

TEST(Rollout, OutputIsIndependentOfThreadCount) {
  RolloutConfig c = smallConfig();
  c.preroll_max_steps = 100;
  const RolloutEngine engine(c);
  const auto jobs = algorithm1Jobs(0, 20, {0.0, 0.3, 1.0}, {1, 2});
  TrajectoryBatch one, two;
  engine.run(jobs, 1, one);
  engine.run(algorithm1Jobs(500, 20, {0.0}, {4, 1, 3}), 2, two);  // reuse: no stale samples
  engine.run(jobs, 2, two);
  EXPECT_EQ(one.states, two.states);
  EXPECT_EQ(one.residuals, two.residuals);
  EXPECT_EQ(one.inputs, two.inputs);
  EXPECT_EQ(one.outputs, two.outputs);
  EXPECT_EQ(one.length, two.length);
  EXPECT_EQ(one.initial_state, two.initial_state);
}

TEST(Rollout, InvalidConfigIsReported) {
  RolloutConfig c = smallConfig();
  c.window = 0;
  EXPECT_NE(RolloutEngine(c).error(), "");
  c = smallConfig();
  c.plant.mass = -1;
  EXPECT_NE(RolloutEngine(c).error().find("mass"), std::string::npos);
}

// Hand-checked: T = 3, 7 samples (0…6), F = 3, Θ₂ = 0.4.
TEST(Windows, EndsFaultyLengthsAndLabels) {
  TrajectoryBatch b;
  b.resize(2, 7);
  for (int i = 0; i < 2; ++i) {
    b.fault_step[static_cast<std::size_t>(i)] = 3;
    b.theta[static_cast<std::size_t>(i) * 4 + 1] = 0.4f;
  }
  b.length[0] = 7;
  b.length[1] = 5;  // cut after sample 4
  std::vector<WindowRef> w;
  enumerateWindows(b, 3, w);
  ASSERT_EQ(w.size(), 6u);  // trajectory 0: ends 3,4,5,6; trajectory 1: ends 3,4
  const int ends[] = {3, 4, 5, 6, 3, 4};
  const int traj[] = {0, 0, 0, 0, 1, 1};
  const int faulty[] = {0, 1, 2, 3, 0, 1};
  for (std::size_t i = 0; i < w.size(); ++i) {
    EXPECT_EQ(w[i].end_sample, ends[i]);
    EXPECT_EQ(w[i].trajectory, traj[i]);
    EXPECT_EQ(faultyLength(b, w[i]), faulty[i]);
    const Input label = windowLabel(b, w[i]);
    EXPECT_EQ(label, faulty[i] == 0 ? Input(1, 1, 1, 1) : Input(1, 0.4f, 1, 1)) << i;
  }
}

TEST(WindowBuffer, KeepsTheNewestWindowsFifo) {
  auto make = [](int count, int tag) {
    auto b = std::make_shared<TrajectoryBatch>();
    b->resize(count, 7);
    for (int i = 0; i < count; ++i) {
      b->fault_step[static_cast<std::size_t>(i)] = 3;
      b->length[static_cast<std::size_t>(i)] = 7;
      b->scenario_index[static_cast<std::size_t>(i)] = static_cast<std::uint64_t>(tag * 100 + i);
    }
    return b;
  };
  WindowBuffer buf(10, 3);  // 4 windows per trajectory
  buf.add(make(2, 0));      // 8 windows
  EXPECT_EQ(buf.size(), 8u);
  buf.add(make(1, 1));      // 12 → trims the 2 oldest
  EXPECT_EQ(buf.size(), 10u);
  EXPECT_EQ(buf.at(0).ref.end_sample, 5);  // trajectory 0's windows ending at 3, 4 are gone
  EXPECT_EQ(buf.at(0).batch->scenario_index[0], 0u);
  buf.add(make(2, 2));  // 18 → the first batch is released entirely
  EXPECT_EQ(buf.size(), 10u);
  EXPECT_EQ(buf.batchCount(), 2u);
  EXPECT_EQ(buf.at(9).batch->scenario_index[1], 201u);
  EXPECT_EQ(buf.at(9).ref.end_sample, 6);
  EXPECT_THROW(buf.at(10), std::out_of_range);
}

}  // namespace
}  // namespace quadfdi

namespace quadfdi {
namespace {

TEST(Algorithm1Data, IterationsAreFreshDisjointAndCapped) {
  Algorithm1DataConfig c;
  c.rollout.window = 10;
  c.rollout.seed = 4;
  c.scale = {"test", 3, 100};  // 3 × 11 trajectories × 11 windows = 363 per iteration > 100
  c.threads = 2;
  Algorithm1Data data(c);
  ASSERT_EQ(data.error(), "");
  data.nextIteration();
  EXPECT_EQ(data.buffer().size(), 100u);
  data.nextIteration();
  EXPECT_EQ(data.iteration(), 2);
  EXPECT_EQ(data.buffer().size(), 100u);
  // Only the newest iteration's windows remain; its scenarios are 3, 4, 5.
  for (std::size_t i = 0; i < data.buffer().size(); ++i) {
    const auto e = data.buffer().at(i);
    EXPECT_GE(e.batch->scenario_index[static_cast<std::size_t>(e.ref.trajectory)], 3u);
  }
  // Resuming regenerates exactly the same buffer.
  Algorithm1Data resumed(c);
  resumed.restoreTo(2);
  ASSERT_EQ(resumed.buffer().size(), data.buffer().size());
  for (std::size_t i = 0; i < data.buffer().size(); i += 7) {
    const auto a = data.buffer().at(i), b = resumed.buffer().at(i);
    EXPECT_EQ(a.ref.end_sample, b.ref.end_sample);
    EXPECT_EQ(a.batch->states, b.batch->states);
  }
  ASSERT_NE(findScale("paper"), nullptr);
  EXPECT_EQ(findScale("paper")->data.initial_conditions * 11, 1100);
  EXPECT_EQ(findScale("huge"), nullptr);
}

// Flyability (docs/data.md#flyability): a draw whose controller cannot hold the plant is redrawn.
constexpr double kSlowCycleMotorLag = 0.035;  // [s] with this LQR gain, delay and noise, scenario 3 passes a short
constexpr double kSlowCycleGain = 0.77;       // [-]   probe and fails a one-minute one (found by a search over lags and gains)
RolloutConfig lqrOnlyRandomised(double motor_time_constant) {
  RolloutConfig c;
  c.seed = 5;
  c.randomisation.vehicles = {nominalParams()};
  c.randomisation.vehicle_names = {"nominal"};
  c.randomisation.parameters.motor_time_constant = {motor_time_constant, motor_time_constant};
  c.randomisation.manoeuvres = {1.0, 0.0, 0.0, 0.0, {0.3, 2.0}, {0.5, 2.0}, 4.9};
  c.randomisation.controllers = {1.0, 0.0, 0.0, {1.4, 1.4}};
  c.randomisation.preroll_seconds = {0.2, 0.2};
  return c;
}

TEST(Flyability, AnLqrOnAMotorFarSlowerThanItWasDesignedForIsRedrawnAndAFastOneIsKept) {
  // The Crazyflie's LQR, designed without motor lag, on motors with a 150 ms time constant:
  // every draw is the same pairing, so all 8 attempts fail and the last draw is flown anyway.
  const RolloutEngine slow(lqrOnlyRandomised(0.15));
  ASSERT_EQ(slow.error(), "");
  int attempts = 0;
  const FlightDraw d = slow.flightDraw(3, &attempts);
  EXPECT_FALSE(slow.flyable(d, 3));
  EXPECT_EQ(attempts, 8);
  // The same design on motors as fast as it assumes: the first draw, unchanged.
  const RolloutEngine fast(lqrOnlyRandomised(0.0));
  const FlightDraw kept = fast.flightDraw(3, &attempts);
  EXPECT_TRUE(fast.flyable(kept, 3));
  EXPECT_EQ(attempts, 1);
  Rng first(fast.config().seed ^ 0xD4A35EEDull, 3);
  EXPECT_EQ(kept.plant.mass, drawFlight(fast.config().randomisation, fast.config().dt, first).plant.mass);
}

// The probe flies the whole flight: an LQR whose cycle on slow motors takes seconds to grow passes
// as a short training flight and is redrawn as a one-minute flight (docs/data.md#flyability: such
// flights passed a 1 s probe and held the largest healthy excursions of a calibration).
TEST(Flyability, ASlowlyGrowingCycleIsCaughtOnALongFlight) {
  RolloutConfig short_flight = lqrOnlyRandomised(kSlowCycleMotorLag);
  short_flight.randomisation.controllers.gain_scale = {kSlowCycleGain, kSlowCycleGain};
  SensorRanges& sensors = short_flight.randomisation.sensors;  // an autopilot's estimate: delay, noise, gyro filter
  sensors.delay_steps_max = 5;
  sensors.attitude_std = {0.002, 0.002};
  sensors.rate_std = {0.02, 0.02};
  sensors.rate_filter_tau = {0.004, 0.004};
  RolloutConfig long_flight = short_flight;
  long_flight.post_fault_steps = 30000;  // one minute at 500 Hz
  const RolloutEngine a(short_flight), b(long_flight);
  ASSERT_EQ(b.error(), "");
  int attempts = 0;
  const FlightDraw d = a.flightDraw(3, &attempts);
  EXPECT_EQ(attempts, 1);
  EXPECT_FALSE(b.flyable(d, 3));
}

// The body rates are the log's: the true state's without a sensor model, the estimate's with one
// (a gyro's white noise here, 0.05 rad/s: their difference from the truth has about that RMS).
TEST(Rollout, RecordsTheBodyRatesTheLogHas) {
  auto rateError = [](const TrajectoryBatch& b, int trajectory, double& sum_squares, int& samples) {
    for (int k = 0; k < b.length[static_cast<std::size_t>(trajectory)]; ++k)
      for (int i = 0; i < kRateDim; ++i) {
        const double d =
            static_cast<double>(b.rates[b.sampleOffset(trajectory, k) * kRateDim + static_cast<std::size_t>(i)]) -
            static_cast<double>(b.states[b.sampleOffset(trajectory, k) * kStateDim + static_cast<std::size_t>(idx::kRate + i)]);
        sum_squares += d * d;
        ++samples;
      }
  };
  TrajectoryBatch paper;
  RolloutEngine(smallConfig(50)).run({TrajectoryJob{5, 3, 0.3}}, 1, paper);
  ASSERT_EQ(paper.rates.size(), paper.states.size() / kStateDim * kRateDim);
  double sum_squares = 0.0;
  int samples = 0;
  rateError(paper, 0, sum_squares, samples);
  EXPECT_GT(samples, 0);
  EXPECT_EQ(sum_squares, 0.0);

  RolloutConfig c = lqrOnlyRandomised(0.02);
  c.randomisation.sensors.rate_std = {0.05, 0.05};
  TrajectoryBatch noisy;
  RolloutEngine(c).run(algorithm1Jobs(0, 4, {1.0}, {2}), 1, noisy);
  sum_squares = 0.0;
  samples = 0;
  for (int i = 0; i < noisy.count; ++i) rateError(noisy, i, sum_squares, samples);
  ASSERT_GT(samples, 100);
  const double rms = std::sqrt(sum_squares / samples);
  EXPECT_GT(rms, 0.04);
  EXPECT_LT(rms, 0.06);
}

}  // namespace
}  // namespace quadfdi
