// Choosing the degraded level and the failed cap (evaluation/level_choice.h) on hand-made Θ̂ with
// known answers.
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

// 40 healthy streams of 5 000 samples at 0.98 in which motor 1 dips to `dip` for `dip_samples`
// samples at most (stream j: 1 + j mod dip_samples), and motor 2 sits at 0.7 for 300 samples: a
// long shallow dip below the degraded level 0.8 that puts its h (cap 0.1) above 30, out of reach
// within 50 ms, so that only the failed statistic can name a fault in the cap choice's budget.
std::vector<std::vector<MotorTheta>> healthyFailedStreams(float dip, int dip_samples) {
  std::vector<std::vector<MotorTheta>> streams(40, std::vector<MotorTheta>(5000, MotorTheta{kHealthy, kHealthy, kHealthy, kHealthy}));
  for (std::size_t j = 0; j < streams.size(); ++j) {
    for (int i = 1000; i < 1001 + static_cast<int>(j) % dip_samples; ++i) streams[j][static_cast<std::size_t>(i)][0] = dip;
    for (int i = 3000; i < 3300 + 5 * static_cast<int>(j); ++i) streams[j][static_cast<std::size_t>(i)][1] = 0.7F;
  }
  return streams;
}

FailedCapChoiceConfig capConfig(std::vector<double> caps) {
  FailedCapChoiceConfig c;
  c.caps = std::move(caps);
  c.level = 0.3;
  c.degraded = config({0.8});
  return c;
}

TEST(FailedCapChoice, NoCapWinsWhenTheHealthyDipsAreShallowAndTheFailuresDeep) {
  // Healthy dips to 0.2 (0.1 below the level) for up to 40 samples weigh the same under either cap:
  // the same h, above 3.9. Θ̂ = 0 after the fault adds 0.3 a sample uncapped, 0.15 capped: within
  // the 25-sample budget uncapped, past it capped.
  const std::vector<FlightThetaStream> faults{fault(0.0), fault(0.0), fault(0.1), fault(0.5)};
  const FailedCapChoice choice = chooseFailedCap(healthyFailedStreams(0.2F, 40), faults, capConfig({0.15, kNoIncrementCap}));
  ASSERT_EQ(choice.candidates.size(), 2U);
  EXPECT_DOUBLE_EQ(choice.candidates[0].failed.threshold, choice.candidates[1].failed.threshold);
  EXPECT_GT(choice.candidates[0].failed.threshold, 3.9);
  EXPECT_EQ(choice.candidates[0].faults, 3);  // Θ = 0.5 is not a failure
  EXPECT_EQ(choice.candidates[0].named, 0);
  EXPECT_EQ(choice.candidates[1].named, 2);   // the Θ = 0.1 fault adds 0.2 a sample uncapped: past the budget
  EXPECT_EQ(choice.chosen, 1);
  EXPECT_EQ(choice.candidates[1].failed.increment_cap, kNoIncrementCap);
  EXPECT_GT(choice.candidates[1].degraded.candidates[0].degraded.threshold, 25.0);  // degraded cannot name them in 50 ms
}

TEST(FailedCapChoice, TheCapWinsWhenHealthyDipsAreDeepAndTheFailuresSitOnAPlateau) {
  // Healthy dips to 0 for up to 10 samples: maxima up to 1.5 capped at 0.15, 3.0 uncapped, and the
  // tail puts h above them (about 2.7 and 5.4). A failure whose Θ̂ sits at 0.15 adds 0.15 a sample
  // either way: about 18 samples against 36, and the budget is 25.
  const std::vector<FlightThetaStream> faults{fault(0.15), fault(0.15)};
  const FailedCapChoice choice = chooseFailedCap(healthyFailedStreams(0.0F, 10), faults, capConfig({kNoIncrementCap, 0.15}));
  EXPECT_GT(choice.candidates[0].failed.threshold, 1.9 * choice.candidates[1].failed.threshold);
  EXPECT_EQ(choice.candidates[0].named, 0);
  EXPECT_EQ(choice.candidates[1].named, 2);
  EXPECT_EQ(choice.chosen, 1);
}

TEST(FailedCapChoice, ATieGoesToTheSmallerCap) {
  // Dips to 0 for up to 4 samples: both caps name a Θ̂ = 0 failure well within the budget.
  const std::vector<FlightThetaStream> faults{fault(0.0)};
  const FailedCapChoice choice = chooseFailedCap(healthyFailedStreams(0.0F, 4), faults, capConfig({0.25, kNoIncrementCap, 0.15}));
  for (const FailedCapCandidate& c : choice.candidates) EXPECT_EQ(c.named, 1);
  EXPECT_EQ(choice.chosen, 2);
}

TEST(FailedCapChoice, RefusesNoCapACapNotAboveZeroOrALevelOutsideZeroToOne) {
  const std::vector<FlightThetaStream> faults{fault(0.0)};
  const std::vector<std::vector<MotorTheta>> healthy = healthyFailedStreams(0.0F, 4);
  EXPECT_THROW(chooseFailedCap(healthy, faults, capConfig({})), std::invalid_argument);
  EXPECT_THROW(chooseFailedCap(healthy, faults, capConfig({0.15, 0.0})), std::invalid_argument);
  FailedCapChoiceConfig c = capConfig({0.15});
  c.level = 1.0;
  EXPECT_THROW(chooseFailedCap(healthy, faults, c), std::invalid_argument);
}

}  // namespace
}  // namespace quadfdi
