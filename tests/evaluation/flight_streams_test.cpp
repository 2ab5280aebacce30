#include <gtest/gtest.h>

#include <algorithm>

#include <cstdio>

#include "evaluation/flight_streams.h"
#include "evaluation/transfer.h"
#include "inference/weights_file.h"

namespace quadfdi {
namespace {

const TrainedModel& shippedTcn() {
  static const std::vector<std::uint8_t> bytes = [] {
    std::FILE* f = std::fopen(QUADFDI_SOURCE_DIR "/models/tcn-model-free.qfdw", "rb");
    std::vector<std::uint8_t> b;
    for (int c; f && (c = std::fgetc(f)) != EOF;) b.push_back(static_cast<std::uint8_t>(c));
    if (f) std::fclose(f);
    return b;
  }();
  static const TrainedModel model = decodeWeightsFile(bytes.data(), bytes.size(), "tcn-model-free.qfdw");
  return model;
}

Randomisation twoControllers() {
  Randomisation r;
  r.vehicles = {nominalParams()};
  r.vehicle_names = {"nominal"};
  r.controllers = {1.0, 1.0, 0.0, {0.8, 1.2}};
  r.manoeuvres = {1.0, 1.0, 0.0, 0.0, {0.5, 1.0}, {0.5, 1.0}, 4.9};
  r.sensors.position_std = {0.0, 0.001};
  r.preroll_seconds = {0.2, 0.5};
  return r;
}

ThetaStreamOptions streamOn(int threads, int chunk = 64, double log_period = 0.0) {
  ThetaStreamOptions o;
  o.threads = threads;
  o.chunk = chunk;
  o.log_period = log_period;
  return o;
}

TEST(FlightStreams, OneEstimatePerSampleFromTheFirstFullWindowAndThreadIndependent) {
  RolloutConfig c;
  c.randomisation = twoControllers();
  c.post_fault_steps = 150;
  c.seed = 4;
  const std::vector<TrajectoryJob> jobs{{0, 2, 1.0}, {1, 3, 0.0}, {2, 1, 0.5}};
  const auto one = simulateThetaStreams(shippedTcn(), c, jobs, streamOn(1, 2));
  const auto two = simulateThetaStreams(shippedTcn(), c, jobs, streamOn(2, 64));
  ASSERT_EQ(one.size(), 3u);
  const int T = shippedTcn().metadata.window;
  const int samples = c.samplesPerTrajectory();
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].theta, two[i].theta);
    EXPECT_EQ(one[i].theta.size(), static_cast<std::size_t>(samples - T + 1));
  }
  EXPECT_EQ(one[0].truth.motor, 0);
  EXPECT_EQ(one[0].truth.fault_sample, -1);
  EXPECT_EQ(one[1].truth.motor, 3);
  EXPECT_EQ(one[1].truth.fault_sample, T + 1 - (T - 1));  // flight sample F + 1 = T + 1
  // The complete fault of motor 3 is visible in the estimates a while after it: Θ̂₃ well below 1.
  EXPECT_LT(one[1].theta[static_cast<std::size_t>(one[1].truth.fault_sample + 60)][2], 0.5f);
}

// A coarser log goes through detect's resampler: logged every dt it is the flight itself, bit for
// bit; logged at 100 Hz the grid ends at the last logged sample, a complete fault still shows, and
// the estimates differ from the flight's (they read interpolated outputs and held commands).
TEST(FlightStreams, ALogPeriodResamplesAsDetectDoes) {
  RolloutConfig c;
  c.randomisation = twoControllers();
  c.post_fault_steps = 150;
  c.seed = 4;
  const std::vector<TrajectoryJob> jobs{{0, 2, 1.0}, {1, 3, 0.0}};
  const auto flown = simulateThetaStreams(shippedTcn(), c, jobs, streamOn(1));
  const auto every_dt = simulateThetaStreams(shippedTcn(), c, jobs, streamOn(2, 64, c.dt));
  const auto coarse = simulateThetaStreams(shippedTcn(), c, jobs, streamOn(1, 64, 0.01));
  const auto coarse_two = simulateThetaStreams(shippedTcn(), c, jobs, streamOn(2, 1, 0.01));
  const int T = shippedTcn().metadata.window;
  const int samples = c.samplesPerTrajectory();
  const int last_logged = (samples - 1) / 5 * 5;  // 100 Hz: every fifth 2-ms sample
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    EXPECT_EQ(every_dt[i].theta, flown[i].theta);
    EXPECT_EQ(every_dt[i].observable, flown[i].observable);
    EXPECT_EQ(coarse[i].theta, coarse_two[i].theta);
    ASSERT_EQ(coarse[i].theta.size(), static_cast<std::size_t>(last_logged + 1 - T + 1));
    EXPECT_EQ(coarse[i].observable.size(), coarse[i].theta.size());
    EXPECT_EQ(coarse[i].truth.fault_sample, flown[i].truth.fault_sample);
  }
  EXPECT_NE(coarse[1].theta[static_cast<std::size_t>(coarse[1].truth.fault_sample + 60)],
            flown[1].theta[static_cast<std::size_t>(flown[1].truth.fault_sample + 60)]);
  EXPECT_LT(coarse[1].theta[static_cast<std::size_t>(coarse[1].truth.fault_sample + 60)][2], 0.5f);
  EXPECT_THROW(simulateThetaStreams(shippedTcn(), c, jobs, streamOn(1, 64, -0.01)), std::invalid_argument);
}

// Healthy flights are counted from kUpsetRecoverySeconds on (calibrate, decisions): the estimates
// and the gate's masks lose the same leading samples, and a fault keeps its place in the flight.
TEST(FlightStreams, DroppingLeadingSamplesKeepsMasksAlignedAndTheFaultInPlace) {
  FlightThetaStream s;
  for (int i = 0; i < 10; ++i) {
    s.theta.push_back({static_cast<float>(i), 1.0f, 1.0f, 1.0f});
    s.observable.push_back(static_cast<std::uint8_t>(i % 16));
  }
  s.truth = {2, 0.5, 6};
  dropLeadingSamples(s, 4);
  ASSERT_EQ(s.theta.size(), 6u);
  ASSERT_EQ(s.observable.size(), 6u);
  EXPECT_EQ(s.theta[0][0], 4.0f);
  EXPECT_EQ(s.observable[0], 4);
  EXPECT_EQ(s.truth.fault_sample, 2);  // still flight sample 6
  dropLeadingSamples(s, 3);            // the fault is now in the dropped part: it starts the stream
  EXPECT_EQ(s.truth.fault_sample, 0);
  FlightThetaStream healthy;
  healthy.theta.resize(3);
  healthy.truth = {0, 1.0, -1};
  dropLeadingSamples(healthy, 5);  // more than it holds: empty, and still healthy
  EXPECT_TRUE(healthy.theta.empty());
  EXPECT_TRUE(healthy.observable.empty());
  EXPECT_EQ(healthy.truth.fault_sample, -1);
}

TEST(FlightStreams, RefusesAModelThatCannotStream) {
  TrainedModel lstm = shippedTcn();
  lstm.metadata.architecture = Architecture::kLstm;
  RolloutConfig c;
  EXPECT_THROW(simulateThetaStreams(lstm, c, {{0, 2, 1.0}}), std::invalid_argument);
}

TEST(FlightStreams, RefusesChunksOfNoFlight) {
  RolloutConfig c;
  EXPECT_THROW(simulateThetaStreams(shippedTcn(), c, {{0, 2, 1.0}}, streamOn(1, 0)), std::invalid_argument);
}

TEST(Transfer, ConditionsPinOneControllerAndManoeuvreAndCellsCountTheirFlights) {
  const std::vector<TransferCondition> conditions = e7Conditions(SensorRanges{});
  ASSERT_GE(conditions.size(), 5u);
  int held_out = 0;
  for (const TransferCondition& c : conditions) {
    held_out += c.held_out;
    const ControllerMix& m = c.randomisation.controllers;
    EXPECT_EQ((m.lqr > 0) + (m.pid > 0) + (m.cbf > 0) + (m.geometric > 0), 1) << c.name;
    EXPECT_EQ(m.gain_scale.lo, m.gain_scale.hi) << c.name;
    Randomisation r = c.randomisation;
    r.vehicles = {nominalParams()};
    r.vehicle_names = {"nominal"};
    EXPECT_EQ(validate(r), "") << c.name;
  }
  EXPECT_GE(held_out, 4);
  // A control law training never flies is among them (docs/decisions.md, E7).
  EXPECT_TRUE(std::any_of(conditions.begin(), conditions.end(),
                          [](const TransferCondition& c) { return c.held_out && c.randomisation.controllers.geometric > 0; }));
  TransferConfig config;
  config.vehicles = {nominalParams()};
  config.vehicle_names = {"nominal"};
  config.conditions = {conditions.front()};
  config.thetas = {0.0};
  config.flights_per_class = 1;
  config.post_fault_seconds = 0.2;
  const std::vector<TransferCell> cells = runTransfer(shippedTcn(), config);
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_EQ(cells[0].flights, 4 + 4);  // 4 healthy, one complete fault per motor
  EXPECT_EQ(cells[0].complete.isolation_flights, 4);
  EXPECT_GT(cells[0].complete.healthy_hours, 0.0);
}

}  // namespace
}  // namespace quadfdi
