// Choosing the degraded level (evaluation/level_choice.h) on hand-made Θ̂ with known answers.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "evaluation/level_choice.h"

namespace quadfdi {
namespace {

constexpr float kHealthy = 0.98F;

// 40 healthy streams of 5 000 samples at 0.98; in stream j, motor 1 dips to `dip` once, for
// `dip_samples` + j samples (spread maxima: the tail fit, not Siegmund, sets h, and it stays
// above the largest).
std::vector<std::vector<MotorTheta>> healthyStreams(float dip, int dip_samples) {
  std::vector<std::vector<MotorTheta>> streams(40, std::vector<MotorTheta>(5000, MotorTheta{kHealthy, kHealthy, kHealthy, kHealthy}));
  for (std::size_t j = 0; j < streams.size(); ++j)
    for (int i = 1000; i < 1000 + dip_samples + static_cast<int>(j); ++i) streams[j][static_cast<std::size_t>(i)][0] = dip;
  return streams;
}

// A clean step: motor 2 at `theta` from stream sample 1 on, 400 samples.
FlightThetaStream fault(double theta) {
  FlightThetaStream f;
  f.truth = {2, theta, 1};
  f.theta.assign(400, MotorTheta{kHealthy, kHealthy, kHealthy, kHealthy});
  for (std::size_t i = 1; i < f.theta.size(); ++i) f.theta[i][1] = static_cast<float>(theta);
  return f;
}

LevelChoiceConfig config(std::vector<double> candidates) {
  LevelChoiceConfig c;
  c.candidates = std::move(candidates);
  c.cap = 0.1;
  c.failed.level = 0.3;
  c.failed.threshold = 3.0;
  c.noise.healthy_mean = kHealthy;
  c.noise.sigma = 0.02;
  c.noise.phi = 0.5;
  c.flight_hours = 40 * 5000 * 0.002 / 3600.0;
  c.rate_per_hour = 0.05;  // less than one alarm expected in the data: h stays above its largest excursion
  return c;
}

TEST(LevelChoice, AHigherLevelWinsWhenItAlsoReportsTheMildFaults) {
  // Healthy dips of 0.05 below 0.9 for 10–49 samples: h at 0.9 just above 2.45, so a Θ = 0.85 fault
  // (0.05 a sample) reaches it in 50 samples; at 0.8 it is never reported.
  const std::vector<FlightThetaStream> faults{fault(0.5), fault(0.5), fault(0.85), fault(0.85)};
  const LevelChoice choice = chooseDegradedLevel(healthyStreams(0.85F, 10), faults, config({0.8, 0.9}));
  ASSERT_EQ(choice.candidates.size(), 2U);
  EXPECT_EQ(choice.candidates[0].faults, 4);
  EXPECT_EQ(choice.candidates[0].isolated, 2);  // only the Θ = 0.5 faults at 0.8
  EXPECT_EQ(choice.candidates[1].isolated, 4);
  EXPECT_EQ(choice.chosen, 1);
  EXPECT_DOUBLE_EQ(choice.candidates[1].degraded.level, 0.9);
  EXPECT_DOUBLE_EQ(choice.candidates[1].degraded.increment_cap, 0.1);
  EXPECT_GT(choice.candidates[1].degraded.threshold, 2.44);
}

TEST(LevelChoice, ALowerLevelWinsWhenTheHigherOnesThresholdIsOutOfReach) {
  // Healthy dips to 0.85 for 400–439 samples: at 0.9 the statistic reaches 21.95, so h is above it
  // and a Θ = 0.5 fault, adding the cap 0.1 a sample, needs 220 samples, past the 150-sample
  // budget. At 0.8 the dip is invisible and the fault is named within the budget.
  const std::vector<FlightThetaStream> faults{fault(0.5), fault(0.6), fault(0.7)};
  const LevelChoice choice = chooseDegradedLevel(healthyStreams(0.85F, 400), faults, config({0.8, 0.9}));
  EXPECT_GT(choice.candidates[1].degraded.threshold, 21.9);
  EXPECT_EQ(choice.candidates[1].degraded.method, "tail");
  EXPECT_EQ(choice.candidates[1].isolated, 0);
  EXPECT_EQ(choice.candidates[0].isolated, 3);
  EXPECT_EQ(choice.chosen, 0);
}

TEST(LevelChoice, ATieGoesToTheHigherLevelAndFaultsAboveEveryCandidateAreNotScored) {
  // Faults at 0.5 only (and one at 0.95, above both levels, which is not asked of any): both levels
  // name them all; the higher level reports more of the range in use, so it is kept.
  const std::vector<FlightThetaStream> faults{fault(0.5), fault(0.5), fault(0.95)};
  const LevelChoice choice = chooseDegradedLevel(healthyStreams(0.97F, 1), faults, config({0.9, 0.8}));
  EXPECT_EQ(choice.candidates[0].faults, 2);
  EXPECT_EQ(choice.candidates[0].isolated, 2);
  EXPECT_EQ(choice.candidates[1].isolated, 2);
  EXPECT_EQ(choice.chosen, 0);  // 0.9, given first
}

TEST(LevelChoice, RefusesNoCandidateOrOneNotAboveTheFailedLevel) {
  const std::vector<FlightThetaStream> faults{fault(0.5)};
  EXPECT_THROW(chooseDegradedLevel(healthyStreams(0.97F, 1), faults, config({})), std::invalid_argument);
  EXPECT_THROW(chooseDegradedLevel(healthyStreams(0.97F, 1), faults, config({0.8, 0.3})), std::invalid_argument);
}

}  // namespace
}  // namespace quadfdi
