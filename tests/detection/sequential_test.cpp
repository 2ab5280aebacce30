// The sequential rule (issue 14) on hand-made Θ̂ sequences: steps, ties, flapping, recovery, gaps,
// held estimates; its calibration on AR(1) noise with known parameters; the Poisson bound; the
// calibration file.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "config_refusal.h"
#include "detection/calibration.h"
#include "detection/sequential.h"
#include "io/calibration_file.h"
#include "io/key_value.h"
#include "simulation/rng.h"

namespace quadfdi {
namespace {

MotorTheta healthy() { return {0.97f, 0.97f, 0.97f, 0.97f}; }
MotorTheta with(int motor, float theta) {
  MotorTheta t = healthy();
  t[static_cast<std::size_t>(motor - 1)] = theta;
  return t;
}

SequentialConfig handConfig() {  // thresholds for counting samples by hand: just under 3, so that the
  SequentialConfig c;               // float round-off of Θ̂ (0.1f > 0.1) cannot move a crossing by one sample
  c.degraded_below = 0.9;           // the hand counts below use issue 14's example level
  c.degraded_threshold = 2.999;
  c.failed_threshold = 2.999;
  c.noise.model_sigma = 0.0;
  return c;
}

// The number of updates until `status`, or −1.
int updatesUntil(SequentialRule& rule, const MotorTheta& theta, SequentialStatus status, int limit = 100000) {
  for (int i = 1; i <= limit; ++i)
    if (rule.update(theta, 1) == status) return i;
  return -1;
}

TEST(SequentialRule, AStepTo07IsDegradedOnTheRightMotorAfterTheExpectedSamples) {
  SequentialRule rule(handConfig());
  for (int i = 0; i < 500; ++i) ASSERT_EQ(rule.update(healthy(), 1), SequentialStatus::kHealthy);
  // Deficit 0.9 − 0.7 = 0.2 per sample: h = 3 is reached on the 15th sample.
  EXPECT_EQ(updatesUntil(rule, with(3, 0.7f), SequentialStatus::kRaised), 15);
  EXPECT_EQ(rule.state().severity, Severity::kDegraded);
  EXPECT_EQ(rule.state().motor, 3);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(rule.update(with(3, 0.7f), 1), SequentialStatus::kActive);
  EXPECT_NEAR(rule.state().theta_est, 0.7, 1e-6);  // the window holds only the fault
  EXPECT_LT(rule.state().theta_lo, 0.7);
  EXPECT_GT(rule.state().theta_hi, 0.7);
}

TEST(SequentialRule, AStepTo01RaisesDegradedThenFailed) {
  SequentialRule rule(handConfig());
  for (int i = 0; i < 100; ++i) rule.update(healthy(), 1);
  // Degraded deficit 0.8 per sample: 3.2 ≥ 3 on the 4th; failed deficit 0.2: the 15th.
  EXPECT_EQ(updatesUntil(rule, with(2, 0.1f), SequentialStatus::kRaised), 4);
  EXPECT_EQ(rule.state().severity, Severity::kDegraded);
  EXPECT_EQ(updatesUntil(rule, with(2, 0.1f), SequentialStatus::kEscalated), 11);
  EXPECT_EQ(rule.state().severity, Severity::kFailed);
  EXPECT_EQ(rule.state().motor, 2);
  // The estimate comes from the samples since the change point only (14 of them, all 0.1).
  EXPECT_NEAR(rule.state().theta_est, 0.1, 1e-6);
}

TEST(SequentialRule, TiesGoToTheLowestMotor) {
  SequentialRule rule(handConfig());
  MotorTheta t = healthy();
  t[1] = t[3] = 0.7f;
  EXPECT_EQ(updatesUntil(rule, t, SequentialStatus::kRaised), 15);
  EXPECT_EQ(rule.state().motor, 2);
  // With more evidence on motor 4 it wins.
  SequentialRule other(handConfig());
  t[3] = 0.6f;
  EXPECT_EQ(updatesUntil(other, t, SequentialStatus::kRaised), 10);
  EXPECT_EQ(other.state().motor, 4);
}

TEST(SequentialRule, FlappingAroundTheLevelRaisesNoStorm) {
  SequentialRule rule(handConfig());
  // Mean on the level: the statistic stays bounded, no alarm.
  for (int i = 0; i < 20000; ++i) ASSERT_NE(rule.update(with(1, i % 2 ? 0.85f : 0.95f), 1), SequentialStatus::kRaised) << i;
  // Mean below the level (0.875), flapping above it every other sample: one alarm, held.
  int raised = 0, cleared = 0;
  for (int i = 0; i < 20000; ++i) {
    const SequentialStatus s = rule.update(with(1, i % 2 ? 0.8f : 0.95f), 1);
    raised += s == SequentialStatus::kRaised;
    cleared += s == SequentialStatus::kCleared;
  }
  EXPECT_EQ(raised, 1);
  EXPECT_EQ(cleared, 0);
  EXPECT_EQ(rule.state().motor, 1);
}

TEST(SequentialRule, RecoveryClearsAfterTheStatedHold) {
  SequentialConfig c = handConfig();
  c.clear_after = 100;
  SequentialRule rule(c);
  ASSERT_GT(updatesUntil(rule, with(4, 0.5f), SequentialStatus::kRaised), 0);
  for (int i = 0; i < 300; ++i) rule.update(with(4, 0.5f), 1);
  // Back above the level: cleared on the 100th sample; a dip restarts the count.
  for (int i = 0; i < 60; ++i) ASSERT_EQ(rule.update(healthy(), 1), SequentialStatus::kActive);
  ASSERT_EQ(rule.update(with(4, 0.85f), 1), SequentialStatus::kActive);
  EXPECT_EQ(updatesUntil(rule, healthy(), SequentialStatus::kCleared), 100);
  EXPECT_EQ(rule.state().severity, Severity::kHealthy);
  EXPECT_EQ(rule.state().motor, 0);
  EXPECT_EQ(rule.degradedStatistic(3), 0.0);
  // Failed de-escalates to degraded once Θ̂ stays above the failed level.
  SequentialRule f(c);
  ASSERT_GT(updatesUntil(f, with(1, 0.0f), SequentialStatus::kEscalated), 0);
  EXPECT_EQ(updatesUntil(f, with(1, 0.6f), SequentialStatus::kRecovered), 100);
  EXPECT_EQ(f.state().severity, Severity::kDegraded);
}

TEST(SequentialRule, AResetAfterAGapStartsFromNothing) {
  SequentialRule rule(handConfig());
  for (int i = 0; i < 14; ++i) ASSERT_EQ(rule.update(with(2, 0.7f), 1), SequentialStatus::kBuilding);
  rule.reset();  // the detector's restart on a gap
  for (int k = 0; k < kMotors; ++k) EXPECT_EQ(rule.degradedStatistic(k), 0.0);
  EXPECT_EQ(updatesUntil(rule, with(2, 0.7f), SequentialStatus::kRaised), 15);  // the full count again
  rule.reset();
  EXPECT_EQ(rule.state().severity, Severity::kHealthy);
}

TEST(SequentialRule, AHeldEstimateCountsAsManySamples) {
  SequentialRule a(handConfig()), b(handConfig());
  for (int i = 0; i < 5; ++i) a.update(with(3, 0.8f), 4);
  for (int i = 0; i < 20; ++i) b.update(with(3, 0.8f), 1);
  EXPECT_NEAR(a.degradedStatistic(2), b.degradedStatistic(2), 1e-12);
  EXPECT_EQ(a.state().severity, b.state().severity);
}

// The capped (Huber-type) CUSUM: a deep dip adds at most the cap per sample, so a short dip that
// the plain CUSUM alarms on passes, while a mild fault's deficit below the cap counts in full.
TEST(SequentialRule, ACappedIncrementWeighsADeepDipNoMoreThanTheCap) {
  SequentialConfig c = handConfig();
  c.failed_threshold = 1000.0;  // only the degraded statistic decides here
  c.degraded_cap = 0.25;
  SequentialRule capped(c);
  c.degraded_cap = kNoIncrementCap;
  SequentialRule plain(c);
  // A 5-sample dip to 0.2: 0.7 a sample uncapped (3.5 ≥ 3, raised on the 5th), 0.25 capped (1.25).
  for (int i = 0; i < 4; ++i) EXPECT_EQ(plain.update(with(1, 0.2f), 1), SequentialStatus::kBuilding);
  EXPECT_EQ(plain.update(with(1, 0.2f), 1), SequentialStatus::kRaised);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(capped.update(with(1, 0.2f), 1), SequentialStatus::kBuilding);
  EXPECT_NEAR(capped.degradedStatistic(0), 1.25, 1e-6);
  for (int i = 0; i < 100; ++i) capped.update(healthy(), 1);  // the dip's evidence drains away
  EXPECT_EQ(capped.degradedStatistic(0), 0.0);
  // A step to 0.7: 0.2 a sample, under the cap, raised on the 15th sample as without a cap.
  EXPECT_EQ(updatesUntil(capped, with(4, 0.7f), SequentialStatus::kRaised), 15);
  EXPECT_EQ(capped.state().motor, 4);
  // A held estimate adds the capped increment once per sample it stands for.
  SequentialRule held(capped.config()), single(capped.config());
  held.update(with(2, 0.1f), 4);
  for (int i = 0; i < 4; ++i) single.update(with(2, 0.1f), 1);
  EXPECT_NEAR(held.degradedStatistic(1), 1.0, 1e-6);
  EXPECT_NEAR(held.degradedStatistic(1), single.degradedStatistic(1), 1e-12);
}

// The failed statistic's cap (calibrate --failed-cap): a complete failure's Θ̂ plateau at 0.15–0.2
// adds 0.10–0.15 a sample, under a 0.15 cap, so it counts in full; a healthy dip to 0 adds the cap,
// not 0.3.
TEST(SequentialRule, TheFailedCapTrimsADeepDipAndKeepsTheFailuresPlateau) {
  SequentialConfig c = handConfig();
  c.degraded_threshold = 1000.0;  // only the failed statistic decides here
  c.failed_threshold = 0.999;  // just under 1: see handConfig
  c.failed_cap = 0.15;
  SequentialRule capped(c);
  c.failed_cap = kNoIncrementCap;
  SequentialRule plain(c);
  // A 4-sample dip to 0: 0.3 a sample uncapped (raised on the 4th: 1.2), 0.15 capped (0.6).
  for (int i = 0; i < 3; ++i) EXPECT_EQ(plain.update(with(2, 0.0f), 1), SequentialStatus::kBuilding);
  EXPECT_EQ(plain.update(with(2, 0.0f), 1), SequentialStatus::kRaised);
  EXPECT_EQ(plain.state().severity, Severity::kFailed);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(capped.update(with(2, 0.0f), 1), SequentialStatus::kBuilding);
  EXPECT_NEAR(capped.failedStatistic(1), 0.6, 1e-6);
  capped.reset();
  plain.reset();
  // The plateau at 0.175: 0.125 a sample either way, raised `failed` on the 8th sample by both.
  EXPECT_EQ(updatesUntil(capped, with(3, 0.175f), SequentialStatus::kRaised), 8);
  EXPECT_EQ(updatesUntil(plain, with(3, 0.175f), SequentialStatus::kRaised), 8);
  EXPECT_EQ(capped.state().severity, Severity::kFailed);
  EXPECT_EQ(capped.state().motor, 3);
}

TEST(RelativeToOthers, DividesByTheMedianOfTheSiblingsWithAFloor) {
  const MotorTheta r = relativeToOthers({0.6f, 0.9f, 1.0f, 0.8f});
  EXPECT_FLOAT_EQ(r[0], 0.6f / 0.9f);  // siblings 0.9, 1.0, 0.8: median 0.9
  EXPECT_FLOAT_EQ(r[1], 0.9f / 0.8f);  // 0.6, 1.0, 0.8
  EXPECT_FLOAT_EQ(r[2], 1.0f / 0.8f);  // 0.6, 0.9, 0.8
  EXPECT_FLOAT_EQ(r[3], 0.8f / 0.9f);  // 0.6, 0.9, 1.0
  // One faulty sibling does not move the median: a healthy motor stays at 1 beside it.
  const MotorTheta one_fault = relativeToOthers({0.97f, 0.0f, 0.97f, 0.97f});
  EXPECT_FLOAT_EQ(one_fault[0], 1.0f);
  EXPECT_FLOAT_EQ(one_fault[1], 0.0f);
  // Siblings mostly below the floor (outside the single-fault model): divided by the floor.
  EXPECT_FLOAT_EQ(relativeToOthers({0.3f, 0.1f, 0.2f, 0.9f})[0], 0.3f / kMinOthersMedian);
  // A dip every motor shares cancels.
  for (float x : relativeToOthers({0.8f, 0.8f, 0.8f, 0.8f})) EXPECT_FLOAT_EQ(x, 1.0f);
}

// Motor relabelling (the symmetry group's action on motor indices) commutes with the reference, exactly.
TEST(RelativeToOthers, PermutingTheMotorsPermutesTheResult) {
  Rng rng(17, 0);
  std::array<int, kMotors> p{0, 1, 2, 3};
  for (int trial = 0; trial < 50; ++trial) {
    MotorTheta theta;
    for (float& x : theta) x = static_cast<float>(rng.uniform(0.0, 1.1));
    const MotorTheta r = relativeToOthers(theta);
    std::sort(p.begin(), p.end());
    do {
      MotorTheta permuted;
      for (int k = 0; k < kMotors; ++k) permuted[static_cast<std::size_t>(k)] = theta[static_cast<std::size_t>(p[static_cast<std::size_t>(k)])];
      const MotorTheta rp = relativeToOthers(permuted);
      for (int k = 0; k < kMotors; ++k) ASSERT_EQ(rp[static_cast<std::size_t>(k)], r[static_cast<std::size_t>(p[static_cast<std::size_t>(k)])]);
    } while (std::next_permutation(p.begin(), p.end()));
  }
}

TEST(SequentialRule, AgainstTheOthersADipEveryMotorSharesRaisesNothing) {
  SequentialConfig others = handConfig();
  others.reference = ThetaReference::kOthers;
  others.estimate_reference = ThetaReference::kOthers;
  SequentialRule absolute_rule(handConfig()), others_rule(others);
  const MotorTheta shared{0.8f, 0.8f, 0.8f, 0.8f};  // below the 0.9 level on every motor
  EXPECT_EQ(updatesUntil(absolute_rule, shared, SequentialStatus::kRaised, 1000), 30);  // 0.1 a sample, tie: motor 1
  EXPECT_EQ(updatesUntil(others_rule, shared, SequentialStatus::kRaised, 1000), -1);
  // One motor at 0.7 beside siblings at 0.97 reads 0.7 / 0.97 = 0.7216: deficit 0.1784 a sample,
  // h = 2.999 on the 17th (16.8 samples).
  SequentialRule fresh(others);
  EXPECT_EQ(updatesUntil(fresh, with(2, 0.7f), SequentialStatus::kRaised), 17);
  EXPECT_EQ(fresh.state().motor, 2);
  for (int i = 0; i < 100; ++i) fresh.update(with(2, 0.7f), 1);
  EXPECT_NEAR(fresh.state().theta_est, 0.7 / 0.97, 1e-6);  // the estimate is of the same quantity
}

TEST(SequentialRule, TheEstimateCanReadTheNetworksOwnThetaWhileTheStatisticsReadTheOthers) {
  SequentialConfig split = handConfig();
  split.reference = ThetaReference::kOthers;
  split.estimate_reference = ThetaReference::kAbsolute;
  SequentialRule rule(split);
  EXPECT_EQ(updatesUntil(rule, with(2, 0.7f), SequentialStatus::kRaised), 17);  // the statistics as above
  EXPECT_EQ(rule.state().motor, 2);
  for (int i = 0; i < 100; ++i) rule.update(with(2, 0.7f), 1);
  EXPECT_NEAR(rule.state().theta_est, 0.7, 1e-6);  // not 0.7 / 0.97
  // A shared dip under the fault: the statistics hold the alarm (0.6 / 0.8 = 0.75 < 0.9), the
  // estimate follows the network's own Θ̂ of the motor.
  MotorTheta dip{0.8f, 0.6f, 0.8f, 0.8f};
  for (int i = 0; i < 100; ++i) EXPECT_EQ(rule.update(dip, 1), SequentialStatus::kActive);
  EXPECT_NEAR(rule.state().theta_est, 0.6, 1e-6);
}

TEST(SequentialRule, RefusesBadConfigs) {
  SequentialConfig c;
  c.failed_below = 0.95;
  EXPECT_THROW(SequentialRule{c}, std::invalid_argument);
  c = SequentialConfig{};
  c.noise.phi = 1.0;
  EXPECT_THROW(SequentialRule{c}, std::invalid_argument);
  for (double cap : {0.0, -0.1, std::nan("")}) {
    c = SequentialConfig{};
    c.degraded_cap = cap;
    EXPECT_THROW(SequentialRule{c}, std::invalid_argument) << cap;
  }
}

TEST(Ar1MeanVariance, MatchesTheDirectSumAndTheIidCase) {
  const double sigma = 0.02, phi = 0.9;
  for (long n : {1L, 2L, 7L, 50L}) {
    double direct = 0.0;
    for (long i = 0; i < n; ++i)
      for (long j = 0; j < n; ++j) direct += std::pow(phi, static_cast<double>(std::labs(i - j)));
    EXPECT_NEAR(ar1MeanVariance(sigma, phi, n), sigma * sigma * direct / static_cast<double>(n * n), 1e-15) << n;
  }
  EXPECT_NEAR(ar1MeanVariance(0.1, 0.0, 25), 0.0004, 1e-15);
  EXPECT_NEAR(normalQuantile(0.95), 1.6448536269514722, 1e-9);
}

// The capped CUSUM's floor: the fewest samples to reach h, checked against the rule itself fed the
// clearest possible fault (Θ̂ = 0 on one motor from the first sample).
TEST(SequentialRule, NoFailureIsNamedSoonerThanTheThresholdOverTheCapAllows) {
  LevelCalibration failed;
  failed.level = 0.3;
  failed.increment_cap = 0.15;
  failed.threshold = 3.72;  // the quad's calibration (models/README.md): 24.8 samples
  EXPECT_EQ(fewestSamplesToAlarm(failed), 25);
  failed.threshold = 3.0;  // an exact multiple stays at its count
  EXPECT_EQ(fewestSamplesToAlarm(failed), 20);
  failed.increment_cap = kNoIncrementCap;  // uncapped: the level itself is the most a sample adds
  failed.threshold = 6.49;
  EXPECT_EQ(fewestSamplesToAlarm(failed), 22);

  for (const double cap : {0.15, kNoIncrementCap}) {
    SequentialConfig config = handConfig();
    config.failed_cap = cap;
    config.failed_threshold = cap == 0.15 ? 3.72 : 6.49;
    config.degraded_threshold = 1e9;  // only the failed statistic can raise
    SequentialRule rule(config);
    LevelCalibration level;
    level.level = config.failed_below;
    level.increment_cap = cap;
    level.threshold = config.failed_threshold;
    int first_failed = -1;
    for (int n = 1; n <= 100 && first_failed < 0; ++n)
      if (rule.update(with(2, 0.0f), 1) != SequentialStatus::kHealthy && rule.state().severity == Severity::kFailed)
        first_failed = n;
    EXPECT_EQ(first_failed, fewestSamplesToAlarm(level)) << "cap " << cap;
  }
}

TEST(PoissonBound, KnownValues) {
  EXPECT_NEAR(poissonUpperBound(0, 0.95), 2.995732273553991, 1e-9);  // −ln 0.05
  EXPECT_NEAR(poissonUpperBound(1, 0.95), 4.743864518, 1e-6);        // ½ χ²₄(0.95) = 9.487729/2
  EXPECT_NEAR(poissonUpperBound(10, 0.95), 16.96222, 1e-4);          // ½ χ²₂₂(0.95) = 33.92444/2
  EXPECT_NEAR(poissonUpperBound(0, 0.9), 2.302585093, 1e-9);         // −ln 0.1
}

double normal(Rng& rng) {  // Box–Muller
  const double u = 1.0 - rng.uniform(), v = rng.uniform();
  return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
}

// AR(1) streams: mean μ, per-sample σ, lag-1 correlation φ, per motor independent.
std::vector<std::vector<MotorTheta>> ar1Streams(int flights, int samples, double mu, double sigma, double phi, std::uint64_t seed) {
  std::vector<std::vector<MotorTheta>> out;
  Rng rng(seed, 0);
  const double innovation = sigma * std::sqrt(1.0 - phi * phi);
  for (int f = 0; f < flights; ++f) {
    std::vector<MotorTheta> s(static_cast<std::size_t>(samples));
    std::array<double, kMotors> e{};
    for (double& v : e) v = sigma * normal(rng);
    for (auto& t : s)
      for (int k = 0; k < kMotors; ++k) {
        e[static_cast<std::size_t>(k)] = phi * e[static_cast<std::size_t>(k)] + innovation * normal(rng);
        t[static_cast<std::size_t>(k)] = static_cast<float>(mu + e[static_cast<std::size_t>(k)]);
      }
    out.push_back(std::move(s));
  }
  return out;
}

// Threshold crossings of the CUSUM at `level`, restarting from zero after each (the alarms a
// detector with that threshold raises, counting a renewal per alarm).
long crossings(const std::vector<std::vector<MotorTheta>>& streams, double level, double h) {
  long n = 0;
  for (const auto& s : streams)
    for (int k = 0; k < kMotors; ++k) {
      double S = 0.0;
      for (const auto& t : s) {
        S = std::max(0.0, S + level - static_cast<double>(t[static_cast<std::size_t>(k)]));
        if (S >= h) ++n, S = 0.0;
      }
    }
  return n;
}

TEST(Calibration, FitsTheNoiseModelOfAnAr1) {
  const auto streams = ar1Streams(4, 50000, 0.97, 0.02, 0.9, 11);
  const ThetaNoiseModel m = fitNoiseModel(streams);
  EXPECT_NEAR(m.healthy_mean, 0.97, 0.002);
  EXPECT_NEAR(m.sigma, 0.02, 0.001);
  EXPECT_NEAR(m.phi, 0.9, 0.01);
}

TEST(Calibration, TheCalibratedThresholdGivesTheTargetRateOnFreshNoise) {
  // Strongly autocorrelated like Θ̂ at 500 Hz (φ = 0.98), level close to the mean so that alarms
  // are frequent enough to count.
  const double dt = 0.002, level = 0.95, phi = 0.98;
  const auto train = ar1Streams(10, 100000, 0.97, 0.02, phi, 21);  // 0.56 flight hours
  const auto test = ar1Streams(10, 100000, 0.97, 0.02, phi, 22);
  const double hours = 10 * 100000 * dt / 3600.0;
  const ThetaNoiseModel noise = fitNoiseModel(train);
  for (const double target : {60.0, 15.0}) {  // per flight hour; tail fit below the largest maxima seen
    const LevelCalibration c = calibrateLevel(excursionMaxima(train, level), level, hours, target, noise, dt);
    ASSERT_EQ(c.method, "tail");
    const long n = crossings(test, level, c.threshold);
    // The expected count target·hours lies within the two-sided 99 % Garwood interval of the count.
    const double expected = target * hours;
    EXPECT_LE(expected, poissonUpperBound(n, 0.995)) << target << " h = " << c.threshold << " count " << n;
    EXPECT_GE(expected, n > 0 ? poissonUpperBound(n - 1, 0.005) : 0.0) << target << " h = " << c.threshold << " count " << n;
  }
  // Siegmund on the long-run variance is conservative for an AR(1) at moderate h (the CUSUM sees
  // less than the long-run variance over short excursions): higher, but within a factor 2.
  const LevelCalibration fit = calibrateLevel(excursionMaxima(train, level), level, hours, 15.0, noise, dt);
  const double ratio = siegmundThreshold(noise, level, 15.0, dt) / fit.threshold;
  EXPECT_GE(ratio, 1.0);
  EXPECT_LE(ratio, 2.0);
}

// Exponential excursion maxima by inversion: m = −β ln(1 − U) (the random walk's tail).
std::vector<double> exponentialSample(int n, double scale, std::uint64_t seed) {
  Rng rng(seed, 0);
  std::vector<double> y(static_cast<std::size_t>(n));
  for (double& v : y) {
    v = -scale * std::log1p(-rng.uniform(0.0, 1.0));
  }
  return y;
}

// A few excursions far beyond the bulk of the tail (a manoeuvre's transient): when the target
// expects less than one alarm in the data, h stays above all of them; with more, the fit decides.
TEST(Calibration, NoExcursionOfTheDataReachesTheThresholdWhenNoneIsExpected) {
  std::vector<double> maxima = exponentialSample(20000, 1.0, 9);
  maxima.push_back(200.0);  // far beyond anything the exponential bulk extrapolates to
  const ThetaNoiseModel noise;
  const LevelCalibration rare = calibrateLevel(maxima, 0.8, 5.0, 0.05, noise, 0.002);  // 0.25 alarms expected
  EXPECT_GT(rare.threshold, 200.0);
  EXPECT_EQ(rare.alarms_at_threshold, 0);
  const LevelCalibration common = calibrateLevel(maxima, 0.8, 5.0, 2.0, noise, 0.002);  // 10 expected
  EXPECT_LT(common.threshold, 200.0);
  EXPECT_GE(common.alarms_at_threshold, 1);
}

// Expected alarms ≥ 1 (2.5 here): the data may hold at most ⌊2.5⌋ = 2 alarms at h, however light
// the fitted tail says its largest excursions are. Five outliers far above an exponential bulk.
TEST(Calibration, TheDataHoldsNoMoreAlarmsThanTheTargetExpects) {
  std::vector<double> maxima = exponentialSample(20000, 1.0, 9);
  for (double outlier : {200.0, 201.0, 202.0, 203.0, 204.0}) maxima.push_back(outlier);
  const ThetaNoiseModel noise;
  const LevelCalibration c = calibrateLevel(maxima, 0.8, 50.0, 0.05, noise, 0.002);
  EXPECT_EQ(c.alarms_at_threshold, 2);
  EXPECT_GT(c.threshold, 202.0);
  EXPECT_LT(c.threshold, 203.0);
  LevelCalibration tenfold = c;  // 25 expected: the fit decides again
  retarget(tenfold, 50.0, 0.5, noise, 0.002);
  EXPECT_LT(tenfold.threshold, 200.0);
}

// The calibration measures the statistic the rule runs: with a cap, the excursion maxima are those

// A mixture like a real model's maxima: a bulk of 10⁵ small excursions (estimator noise) and 50
// rare large ones (transients, 1 an hour: 1 + Exp(1)) in 50 flight hours. For 0.05 alarms an hour
// the rare cluster alone sets h: 1 + ln(1/0.05) = 4.0. The fit on the maxima near the target finds
// it (±0.9: twice the spread of a 50-sample fit's h); one on the 200 largest, mostly bulk, gives
// about 2.5.
TEST(Calibration, TheTailIsFittedNearTheTargetNotOnTheBulk) {
  std::vector<double> maxima = exponentialSample(100000, 0.1, 31);
  for (double m : exponentialSample(50, 1.0, 32)) maxima.push_back(1.0 + m);
  const ThetaNoiseModel noise;
  const LevelCalibration c = calibrateLevel(maxima, 0.9, 50.0, 0.05, noise, 0.002);
  ASSERT_EQ(c.method, "tail");
  EXPECT_EQ(c.tail_maxima.size(), static_cast<std::size_t>(kMaxTail));  // the stored tail is longer than the fit
  EXPECT_GE(c.tail_start, 1.0);                                         // u among the rare cluster
  EXPECT_NEAR(c.threshold, 4.0, 0.9);
  // Re-targeting keeps the fit and re-solves h on it: lower for a more frequent target, higher for
  // a rarer one (monotone, as detect --false-alarms-per-hour and the trade-off curve need).
  for (const auto& [rate, higher] : {std::pair<double, bool>{0.5, false}, {0.01, true}}) {
    LevelCalibration other = c;
    retarget(other, 50.0, rate, noise, 0.002);
    EXPECT_EQ(other.tail_start, c.tail_start);
    EXPECT_EQ(other.tail_scale, c.tail_scale);
    EXPECT_EQ(other.threshold > c.threshold, higher) << rate;
  }
  LevelCalibration back = c;
  retarget(back, 50.0, 0.05, noise, 0.002);
  EXPECT_EQ(back.threshold, c.threshold);
}
// of the capped CUSUM, and a threshold fitted on them is never reached by the data's own capped
// excursions when none is expected.
TEST(Calibration, ExcursionsOfTheCappedStatistic) {
  std::vector<MotorTheta> dip(200, healthy());
  for (int i = 50; i < 60; ++i) dip[static_cast<std::size_t>(i)][0] = 0.0f;  // 10 samples at 0
  const std::vector<std::vector<MotorTheta>> streams{dip};
  const std::vector<double> plain = excursionMaxima(streams, 0.8, 0), capped = excursionMaxima(streams, 0.8, 0, 0.1);
  ASSERT_EQ(plain.size(), 1u);
  ASSERT_EQ(capped.size(), 1u);
  EXPECT_NEAR(plain[0], 8.0, 1e-6);
  EXPECT_NEAR(capped[0], 1.0, 1e-6);
  const auto train = ar1Streams(4, 50000, 0.97, 0.05, 0.8, 13);
  const ThetaNoiseModel noise = fitNoiseModel(train);
  const double hours = 4 * 50000 * 0.002 / 3600.0;
  const LevelCalibration c = calibrateLevel(excursionMaxima(train, 0.85, 0, 0.05), 0.85, hours, 0.05, noise, 0.002, 0.05);
  EXPECT_EQ(c.method, "tail");
  EXPECT_EQ(c.increment_cap, 0.05);
  SequentialConfig rule;
  rule.degraded_below = 0.85;
  rule.degraded_cap = c.increment_cap;
  rule.degraded_threshold = c.threshold;
  rule.failed_threshold = 1e9;
  for (const auto& s : train) {
    SequentialRule r(rule);
    for (const MotorTheta& t : s) ASSERT_NE(r.update(t, 1), SequentialStatus::kRaised);
  }
}

// The largest excursions are excursionMaxima's largest, and say where they lie: a calibration names
// the flights its threshold stands on.
TEST(Calibration, TheLargestExcursionsNameTheirStreamMotorAndSpan) {
  auto ar1 = ar1Streams(3, 20000, 0.97, 0.03, 0.8, 17);
  // A long shallow dip on stream 1, motor 3 (index 2): 400 samples at 0.85 against level 0.9.
  for (std::size_t i = 5000; i < 5400; ++i) ar1[1][i][2] = 0.85f;
  const std::vector<Excursion> top = largestExcursions(ar1, 0.9, 5, 0, 0.1);
  std::vector<double> all = excursionMaxima(ar1, 0.9, 0, 0.1);
  std::sort(all.rbegin(), all.rend());
  ASSERT_EQ(top.size(), 5u);
  for (std::size_t i = 0; i < top.size(); ++i) EXPECT_DOUBLE_EQ(top[i].peak, all[i]) << i;
  EXPECT_EQ(top[0].stream, 1u);
  EXPECT_EQ(top[0].motor, 2);
  EXPECT_GE(top[0].peak, 400 * 0.05 - 1e-3);  // each sample adds level − 0.85 = 0.05
  EXPECT_LE(top[0].start, 5000);  // it may begin in the noise just before the dip
  EXPECT_GE(top[0].start + top[0].length, 5400);
  EXPECT_LE(top[0].length, 1000);
  // An excursion cut by the stream's end still counts, with its length to the end; none asked: none.
  std::vector<std::vector<MotorTheta>> tail{std::vector<MotorTheta>(100, healthy())};
  for (std::size_t i = 90; i < 100; ++i) tail[0][i][0] = 0.5f;
  const std::vector<Excursion> cut = largestExcursions(tail, 0.8, 2);
  ASSERT_EQ(cut.size(), 1u);
  EXPECT_EQ(cut[0].start, 90);
  EXPECT_EQ(cut[0].length, 10);
  EXPECT_NEAR(cut[0].peak, 3.0, 1e-6);
  EXPECT_TRUE(largestExcursions(ar1, 0.9, 0).empty());
}

// Heavy-tailed estimate errors (95 % within ±0.01, 5 % off by ±0.2), with `noise_sd` the healthy
// noise model's standard deviation of each estimate.
struct SpreadCase {
  std::vector<double> est, truth, var;
  SpreadCase(int n, double noise_sd, std::uint64_t seed) {
    Rng rng(seed, 0);
    for (int i = 0; i < n; ++i) {
      const double t = rng.uniform(0.2, 0.8);
      const double e = rng.uniform(0.0, 1.0) < 0.95 ? rng.uniform(-0.01, 0.01) : (rng.uniform(0.0, 1.0) < 0.5 ? -0.2 : 0.2);
      est.push_back(t + e);
      truth.push_back(t);
      var.push_back(noise_sd * noise_sd);
    }
  }
  double coverage(const EstimateSpread& s) const {
    const double z = normalQuantile(0.95);
    long covered = 0;
    for (std::size_t i = 0; i < est.size(); ++i)
      covered += std::abs(est[i] - truth[i]) <= z * std::sqrt(s.noise_scale * var[i] + s.model_sigma * s.model_sigma);
    return static_cast<double>(covered) / static_cast<double>(est.size());
  }
};

// The fitted intervals hold Θ in 90 % of fresh pairs from the same law, where an RMS fit (σ ≈ 0.045)
// would hold it in all: a noise model narrower than the errors gets a model error on top …
TEST(Calibration, TheEstimateSpreadIsFittedOnCoverage) {
  const SpreadCase fit(2000, 0.001, 41), test(20000, 0.001, 42);
  const EstimateSpread s = fitEstimateSpread(fit.est, fit.truth, fit.var, 0.9);
  EXPECT_EQ(s.noise_scale, 1.0);
  EXPECT_GT(s.model_sigma, 0.0);
  EXPECT_LT(s.model_sigma, 0.02);
  EXPECT_NEAR(test.coverage(s), 0.9, 0.01);
  // … and one wider than them (healthy Θ̂ noisier than a flown-through estimate) is scaled down.
  const SpreadCase wide_fit(2000, 0.05, 43), wide_test(20000, 0.05, 44);
  const EstimateSpread w = fitEstimateSpread(wide_fit.est, wide_fit.truth, wide_fit.var, 0.9);
  EXPECT_LT(w.noise_scale, 0.1);
  EXPECT_EQ(w.model_sigma, 0.0);
  EXPECT_NEAR(wide_test.coverage(w), 0.9, 0.01);
  EXPECT_NEAR(wide_test.coverage(EstimateSpread{1.0, 0.0}), 1.0, 0.06);  // unfitted: far too wide
  // No faulty data: the default noise model's spread.
  const EstimateSpread none = fitEstimateSpread({}, {}, {}, 0.9);
  EXPECT_EQ(none.noise_scale, ThetaNoiseModel{}.noise_scale);
  EXPECT_EQ(none.model_sigma, ThetaNoiseModel{}.model_sigma);
}

// Pairs whose error depends on where the estimate lies, as the networks' do: one-sided and wide
// near Θ = 0 (Θ̂ ≥ 0), narrow above.
struct RangedSpreadCase {
  std::vector<double> est, truth, var;
  RangedSpreadCase(int n, std::uint64_t seed) {
    Rng rng(seed, 0);
    auto gauss = [&rng] { return std::sqrt(-2.0 * std::log(1.0 - rng.uniform())) * std::cos(2.0 * M_PI * rng.uniform()); };  // Box–Muller
    for (int i = 0; i < n; ++i) {
      const double t = rng.uniform(0.0, 0.9);
      const double e = t < 0.1 ? std::abs(gauss()) * 0.03 : gauss() * 0.004;
      est.push_back(t + e);
      truth.push_back(t);
      var.push_back(0.01 * 0.01);
    }
  }
  // Fraction of the pairs with the estimate in [lo, hi) whose interval (the rule's range lookup)
  // holds Θ.
  double coverage(const std::vector<SpreadBin>& bins, double lo, double hi) const {
    const double z = normalQuantile(0.95);
    long in = 0, covered = 0;
    for (std::size_t i = 0; i < est.size(); ++i) {
      if (est[i] < lo || est[i] >= hi) continue;
      std::size_t b = 0;
      while (b + 1 < bins.size() && est[i] >= bins[b].estimate_below) ++b;
      ++in;
      covered += std::abs(est[i] - truth[i]) <= z * std::sqrt(bins[b].noise_scale * var[i] + bins[b].model_sigma * bins[b].model_sigma);
    }
    return static_cast<double>(covered) / static_cast<double>(in);
  }
};

// One spread pooled over Θ covers the wide errors near 0 too rarely and the narrow ones above
// always; a spread per range of the estimate holds Θ at the nominal 90 % in each.
TEST(Calibration, TheEstimateSpreadIsFittedPerRangeOfTheEstimate) {
  const RangedSpreadCase fit(20000, 51), test(60000, 52);
  const std::vector<SpreadBin> bins = fitBinnedEstimateSpread(fit.est, fit.truth, fit.var, 0.9);
  ASSERT_EQ(bins.size(), kSpreadBinEdges.size() + 1);
  for (std::size_t b = 0; b + 1 < bins.size(); ++b) EXPECT_EQ(bins[b].estimate_below, kSpreadBinEdges[b]);
  EXPECT_EQ(bins.back().estimate_below, 1.0);
  long pairs = 0;
  for (const SpreadBin& b : bins) pairs += b.pairs;
  EXPECT_EQ(pairs, 20000);
  const EstimateSpread pooled = fitEstimateSpread(fit.est, fit.truth, fit.var, 0.9);
  const std::vector<SpreadBin> one{{1.0, pooled.noise_scale, pooled.model_sigma, 20000}};
  EXPECT_LT(test.coverage(one, 0.0, 0.05), 0.8);
  EXPECT_GT(test.coverage(one, 0.3, 2.0), 0.97);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    const double lo = b == 0 ? 0.0 : bins[b - 1].estimate_below, hi = b + 1 == bins.size() ? 2.0 : bins[b].estimate_below;
    EXPECT_NEAR(test.coverage(bins, lo, hi), 0.9, 0.03) << "estimates " << lo << " … " << hi;
  }
  // Ranges with too few pairs join the next, the last the one before; none: the default spread.
  const std::vector<SpreadBin> merged = fitBinnedEstimateSpread(fit.est, fit.truth, fit.var, 0.9, {0.3, 0.301, 0.95});
  ASSERT_EQ(merged.size(), 2u);
  EXPECT_EQ(merged[0].estimate_below, 0.3);  // [0.3, 0.301) holds too few: joined [0.301, 0.95) …
  EXPECT_EQ(merged[1].estimate_below, 1.0);  // … and [0.95, ∞) none: joined [0.3, 0.95)
  EXPECT_EQ(merged[0].pairs + merged[1].pairs, 20000);
  const std::vector<SpreadBin> none = fitBinnedEstimateSpread({}, {}, {}, 0.9);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0].noise_scale, ThetaNoiseModel{}.noise_scale);
  EXPECT_EQ(none[0].model_sigma, ThetaNoiseModel{}.model_sigma);
}

// Pairs whose error depends on the true Θ, not on where the estimate lies: wide (σ 0.02) at Θ
// near 0.1, 0.3, 0.5, …, narrow (0.004) near 0, 0.2, 0.4, …, and one-sided at Θ = 0 (Θ̂ ≥ 0). A
// tenth of them are complete failures, as `calibrate --interval belt` flies.
struct BeltCase {
  std::vector<double> est, truth, var;
  static double sigma(double theta) { return static_cast<int>(std::lround(theta * 10.0)) % 2 ? 0.02 : 0.004; }
  static double draw(double theta, Rng& rng) {
    const double g = std::sqrt(-2.0 * std::log(1.0 - rng.uniform())) * std::cos(2.0 * M_PI * rng.uniform());  // Box–Muller
    return theta == 0.0 ? std::abs(g) * 0.01 : theta + 0.005 + sigma(theta) * g;  // a small bias too
  }
  BeltCase(int n, std::uint64_t seed) {
    Rng rng(seed, 0);
    for (int i = 0; i < n; ++i) {
      const double t = i % 10 == 0 ? 0.0 : rng.uniform(0.0, 0.9);
      est.push_back(draw(t, rng));
      truth.push_back(t);
      var.push_back(0.01 * 0.01);
    }
  }
};

// The belt's interval holds Θ at its level for each Θ; a spread per range of the estimate holds it
// on average over a range but not for each Θ, since every range mixes wide- and narrow-error Θ.
TEST(Calibration, TheBeltHoldsThetaAtItsLevelForEachTheta) {
  const BeltCase fit(40000, 61);
  const std::vector<BeltNode> belt = fitThetaBelt(fit.est, fit.truth, 0.9);
  ASSERT_EQ(belt.size(), kBeltNodes.size());
  EXPECT_EQ(belt[0].accept_lo, 0.0);  // the boundary: every estimate up to its quantile
  for (std::size_t i = 1; i < belt.size(); ++i) EXPECT_LT(belt[i].accept_lo, belt[i].accept_hi);
  const std::vector<SpreadBin> bins = fitBinnedEstimateSpread(fit.est, fit.truth, fit.var, 0.9);
  const double z = normalQuantile(0.95);
  Rng rng(62, 0);
  int spread_off = 0;
  for (double theta : kBeltNodes) {
    long belt_in = 0, spread_in = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      const double e = BeltCase::draw(theta, rng);
      double lo, hi;
      invertBelt(belt, e, 0.0, &lo, &hi);
      belt_in += lo <= theta && theta <= hi;
      std::size_t b = 0;
      while (b + 1 < bins.size() && e >= bins[b].estimate_below) ++b;
      const double se = std::sqrt(bins[b].noise_scale * 1e-4 + bins[b].model_sigma * bins[b].model_sigma);
      spread_in += std::max(0.0, e - z * se) <= theta && theta <= e + z * se;
    }
    EXPECT_NEAR(static_cast<double>(belt_in) / n, 0.9, 0.03) << "Θ = " << theta;
    spread_off += std::abs(static_cast<double>(spread_in) / n - 0.9) > 0.05;
  }
  EXPECT_GE(spread_off, 4);  // the spread is off by more than 5 points at several Θ
  // Too few pairs at a node: left out.
  EXPECT_TRUE(fitThetaBelt({0.5}, {0.5}, 0.9).empty());
}

// The interval inverts the belt: every Θ whose acceptance region holds the estimate.
TEST(SequentialRule, TheIntervalInvertsTheBelt) {
  const double kGridStep = 1.5 / kBeltGrid;  // the inversion's resolution: a bound on an edge may fall one grid step either side
  const std::vector<BeltNode> band{{0.0, -0.05, 0.05, 100}, {1.0, 0.95, 1.05, 100}};  // Θ ± 0.05 everywhere
  double lo, hi;
  invertBelt(band, 0.5, 0.0, &lo, &hi);
  EXPECT_NEAR(lo, 0.45, kGridStep);
  EXPECT_NEAR(hi, 0.55, kGridStep);
  invertBelt(band, 0.02, 0.0, &lo, &hi);  // clipped at 0
  EXPECT_EQ(lo, 0.0);
  EXPECT_NEAR(hi, 0.07, kGridStep);
  invertBelt(band, 0.5, 0.02, &lo, &hi);  // widened
  EXPECT_NEAR(lo, 0.43, kGridStep);
  EXPECT_NEAR(hi, 0.57, kGridStep);
  // Beyond the end nodes the region moves with Θ; an estimate no region holds gets the nearest Θ.
  const std::vector<BeltNode> short_belt{{0.2, 0.18, 0.22, 100}, {0.4, 0.38, 0.42, 100}};
  invertBelt(short_belt, 0.7, 0.0, &lo, &hi);
  EXPECT_NEAR(lo, 0.68, kGridStep);
  EXPECT_NEAR(hi, 0.72, kGridStep);
  invertBelt(band, -0.3, 0.0, &lo, &hi);
  EXPECT_EQ(lo, 0.0);
  EXPECT_EQ(hi, 0.0);
  // In the rule: the interval of a full window is the belt's; one of fewer samples is wider.
  SequentialConfig c = handConfig();
  c.noise.belt = band;
  SequentialRule rule(c);
  ASSERT_EQ(updatesUntil(rule, with(2, 0.5f), SequentialStatus::kRaised), 8);  // 0.4 a sample past 2.999
  const double early = rule.state().theta_hi - rule.state().theta_lo;
  for (int i = 0; i < c.estimate_window; ++i) rule.update(with(2, 0.5f), 1);
  EXPECT_NEAR(rule.state().theta_lo, 0.45, kGridStep);
  EXPECT_NEAR(rule.state().theta_hi, 0.55, kGridStep);
  EXPECT_GT(early, 0.1 + 0.01);
}

// The rule states the interval of the range its estimate lies in.
TEST(SequentialRule, TheIntervalComesFromTheEstimatesRange) {
  SequentialConfig c = handConfig();
  c.noise.phi = 0.0;
  c.noise.sigma = 0.0;
  c.noise.spread_bins = {{0.2, 1.0, 0.05, 100}, {1.0, 1.0, 0.01, 100}};
  for (const auto& [theta, sigma] : {std::pair{0.1f, 0.05}, std::pair{0.6f, 0.01}}) {
    SequentialRule rule(c);
    for (int i = 0; i < 100; ++i) rule.update(with(2, theta), 1);
    ASSERT_EQ(rule.state().motor, 2);
    EXPECT_NEAR(rule.state().standard_error, sigma, 1e-12);
    EXPECT_NEAR(rule.state().theta_hi - rule.state().theta_est, rule.z() * sigma, 1e-6);
  }
  for (const auto& [bins, problem] :
       {std::pair{std::vector<SpreadBin>{{0.5, 1.0, 0.0, 0}, {0.4, 1.0, 0.0, 0}}, "estimate_below must be finite and ascending"},
        std::pair{std::vector<SpreadBin>{{0.5, 1.0, 0.0, 0}, {0.9, 1.0, 0.0, 0}}, "the last range must reach 1"},
        std::pair{std::vector<SpreadBin>{{1.0, 0.0, 0.0, 0}}, "spread_bins[0]: noise_scale must be finite and positive"},
        std::pair{std::vector<SpreadBin>{{1.0, 1.0, -0.1, 0}}, "spread_bins[0]: model_sigma must be finite and non-negative"}}) {
    c.noise.spread_bins = bins;
    EXPECT_NE(validate(c).find(problem), std::string::npos) << validate(c);
    EXPECT_THROW(SequentialRule{c}, std::invalid_argument);
  }
}

TEST(Calibration, FallsBackToSiegmundWithoutExcursions) {
  const auto train = ar1Streams(2, 20000, 0.97, 0.02, 0.9, 3);
  const ThetaNoiseModel noise = fitNoiseModel(train);
  const LevelCalibration c = calibrateLevel(excursionMaxima(train, 0.3), 0.3, 0.02, 0.05, noise, 0.002);
  EXPECT_EQ(c.method, "siegmund");
  EXPECT_EQ(c.excursions, 0);
  EXPECT_GE(c.threshold, kMinThreshold);
  // A lower target rate needs a higher threshold.
  EXPECT_GT(siegmundThreshold(noise, 0.9, 0.01, 0.002), siegmundThreshold(noise, 0.9, 1.0, 0.002));
}

// The one-line error calibrationFromJson gives `json` as "cal.json"; a failure (and "") if it is accepted.
std::string rejection(const std::string& json) {
  const std::string refusal = test::configRefusal([&] { calibrationFromJson(json, "cal.json"); });
  if (refusal == test::kAccepted) {
    ADD_FAILURE() << "accepted: " << json.substr(0, 200);
    return {};
  }
  return refusal;
}

// rejection() of `json` with its first `from` replaced by `to`.
std::string rejectionAfterEdit(std::string json, const std::string& from, const std::string& to) {
  const std::size_t at = json.find(from);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no " << from;
    return {};
  }
  return rejection(json.replace(at, from.size(), to));
}

TEST(CalibrationFile, RoundTripsAndNamesTheFileOnBadInput) {
  const auto train = ar1Streams(2, 50000, 0.97, 0.02, 0.9, 5);
  DecisionCalibration c = defaultCalibration(0.9, 0.3, 0.1, 0.002);
  c.noise = fitNoiseModel(train);
  c.flight_hours = 100000 * 0.002 / 3600.0;
  c.degraded = calibrateLevel(excursionMaxima(train, 0.9), 0.9, c.flight_hours, 0.05, c.noise, 0.002);
  c.degraded.increment_cap = 0.1;
  c.noise.noise_scale = 0.25;
  const DecisionCalibration back = calibrationFromJson(calibrationToJson(c), "x.json");
  EXPECT_EQ(calibrationToJson(back), calibrationToJson(c));
  EXPECT_EQ(back.noise.noise_scale, 0.25);
  {  // no key (every file before the fitted spread): the healthy noise unscaled
    std::string json = calibrationToJson(c);
    const std::size_t at = json.find("\"noise_scale\"");
    ASSERT_NE(at, std::string::npos);
    json.replace(at, 13, "\"renamed_key\"");  // an unknown key in its place: ignored
    EXPECT_EQ(calibrationFromJson(json, "old.json").noise.noise_scale, 1.0);
  }
  EXPECT_TRUE(back.noise.spread_bins.empty());  // none fitted: none written, the pooled spread holds
  {                                              // the ranges round-trip; a malformed list names the file
    DecisionCalibration ranged = c;
    ranged.noise.spread_bins = {{0.05, 1.0, 0.021, 159}, {1.0, 0.18, 0.0, 3104}};
    const DecisionCalibration ranged_back = calibrationFromJson(calibrationToJson(ranged), "x.json");
    ASSERT_EQ(ranged_back.noise.spread_bins.size(), 2u);
    EXPECT_EQ(ranged_back.noise.spread_bins[0].model_sigma, 0.021);
    EXPECT_EQ(ranged_back.noise.spread_bins[1].pairs, 3104);
    EXPECT_EQ(calibrationToJson(ranged_back), calibrationToJson(ranged));
    std::string json = calibrationToJson(ranged);
    json.replace(json.find("\"estimate_below\": 0.05"), 22, "\"estimate_below\": 1.05");
    const std::string error = rejection(json);
    EXPECT_NE(error.find("cal.json: bad calibration: noise spread_bins[1]: estimate_below must be finite and ascending"), std::string::npos)
        << error;
    ranged.noise.spread_bins.clear();  // more ranges than a file may hold
    for (std::size_t b = 0; b <= kMaxSpreadBins; ++b) ranged.noise.spread_bins.push_back({1.0 + static_cast<double>(b), 1.0, 0.0, 100});
    const std::string too_many = rejection(calibrationToJson(ranged));
    EXPECT_NE(too_many.find("cal.json: bad calibration: noise spread_bins: at most 16 ranges"), std::string::npos) << too_many;
  }
  {  // the belt round-trips into the rule; absent: none (the spread's interval); malformed: refused
    DecisionCalibration belted = c;
    belted.noise.belt = {{0.0, 0.0, 0.03, 600}, {0.5, 0.47, 0.53, 900}};
    const std::string json = calibrationToJson(belted);
    const DecisionCalibration back_belt = calibrationFromJson(json, "x.json");
    ASSERT_EQ(back_belt.noise.belt.size(), 2u);
    EXPECT_EQ(back_belt.noise.belt[1].accept_hi, 0.53);
    EXPECT_EQ(back_belt.noise.belt[1].pairs, 900);
    EXPECT_EQ(calibrationToJson(back_belt), json);
    EXPECT_EQ(sequentialConfig(back_belt).noise.belt.size(), 2u);
    EXPECT_EQ(calibrationToJson(c).find("\"belt\""), std::string::npos);
    const std::string error = rejectionAfterEdit(json, "\"accept_hi\": 0.53", "\"accept_hi\": 0.43");
    EXPECT_NE(error.find("cal.json: bad calibration: noise belt[1]: accept_lo and accept_hi must be finite with accept_lo <= accept_hi"),
              std::string::npos) << error;
    const std::string order_error = rejectionAfterEdit(json, "\"theta\": 0.5", "\"theta\": 0.0");
    EXPECT_NE(order_error.find("cal.json: bad calibration: noise belt[1]: theta must lie in [0, 1] and ascend"), std::string::npos) << order_error;
  }
  {  // the model's CRC round-trips as 0x + 8 hex digits; absent: not recorded, so not checked; malformed: refused
    DecisionCalibration stamped = c;
    stamped.model_crc32 = 0x0badf00du;
    const std::string json = calibrationToJson(stamped);
    EXPECT_NE(json.find("\"model_crc32\": \"0x0badf00d\""), std::string::npos) << json;
    const DecisionCalibration stamped_back = calibrationFromJson(json, "x.json");
    ASSERT_TRUE(stamped_back.model_crc32.has_value());
    EXPECT_EQ(*stamped_back.model_crc32, 0x0badf00du);
    EXPECT_FALSE(calibrationFromJson(calibrationToJson(c), "x.json").model_crc32.has_value());
    EXPECT_EQ(calibrationModelProblem(stamped_back, 0x0badf00du), "");
    EXPECT_EQ(calibrationModelProblem(c, 0x12345678u), "");             // none recorded
    EXPECT_EQ(calibrationModelProblem(stamped_back, 0), "");            // a model not read from a file
    EXPECT_EQ(calibrationModelProblem(stamped_back, 0x12345678u).rfind("made for another model (weights file CRC-32 0x0badf00d, this model's 0x12345678)", 0), 0u);
    for (const char* bad : {"\"0x0BADF00D\"", "\"0badf00d\"", "\"0x0badf00\"", "\"0x0badf00g\""}) {
      const std::string error = rejectionAfterEdit(json, "\"0x0badf00d\"", bad);
      EXPECT_NE(error.find("cal.json: bad calibration: model_crc32 must be \"0x\" and eight lower-case hex digits"), std::string::npos) << error;
    }
    const std::string not_text = rejectionAfterEdit(json, "\"0x0badf00d\"", "195948557");
    EXPECT_EQ(not_text.rfind("cal.json: bad calibration: ", 0), 0u) << not_text;
  }
  {  // the failed level's command share round-trips into the rule; absent (files before 2026-12-04): none; out of range: refused
    DecisionCalibration gated = c;
    gated.failed.min_command_share = 0.9;
    const std::string json = calibrationToJson(gated);
    EXPECT_NE(json.find("\"min_command_share\": 0.9"), std::string::npos) << json;
    const DecisionCalibration gated_back = calibrationFromJson(json, "x.json");
    EXPECT_EQ(gated_back.failed.min_command_share, 0.9);
    EXPECT_EQ(sequentialConfig(gated_back).failed_min_share, 0.9);
    EXPECT_EQ(calibrationToJson(gated_back), json);
    EXPECT_EQ(calibrationToJson(c).find("min_command_share"), std::string::npos);
    EXPECT_EQ(sequentialConfig(calibrationFromJson(calibrationToJson(c), "x.json")).failed_min_share, 0.0);
    const std::string error = rejectionAfterEdit(json, "\"min_command_share\": 0.9", "\"min_command_share\": 4.5");
    EXPECT_NE(error.find("cal.json: bad calibration: failed min_command_share must lie in [0, 4]"), std::string::npos) << error;
  }
  {  // the degraded level's command share (since 2026-12-05) round-trips into the rule; out of range: refused
    DecisionCalibration gated = c;
    gated.degraded.min_command_share = 0.95;
    const std::string json = calibrationToJson(gated);
    const DecisionCalibration gated_back = calibrationFromJson(json, "x.json");
    EXPECT_EQ(gated_back.degraded.min_command_share, 0.95);
    EXPECT_EQ(gated_back.failed.min_command_share, 0.0);
    EXPECT_EQ(sequentialConfig(gated_back).degraded_min_share, 0.95);
    EXPECT_EQ(sequentialConfig(gated_back).failed_min_share, 0.0);
    EXPECT_EQ(calibrationToJson(gated_back), json);
    const std::string error = rejectionAfterEdit(json, "\"min_command_share\": 0.95", "\"min_command_share\": -0.5");
    EXPECT_NE(error.find("cal.json: bad calibration: degraded min_command_share must lie in [0, 4]"), std::string::npos) << error;
  }
  {  // the reference round-trips; absent (every file before 2026-11-26): absolute; unknown: refused
    DecisionCalibration relative = c;
    relative.reference = ThetaReference::kOthers;
    const std::string json = calibrationToJson(relative);
    EXPECT_EQ(calibrationFromJson(json, "x.json").reference, ThetaReference::kOthers);
    std::string old = json;
    old.replace(old.find("\"reference\""), 11, "\"renamed_k\"");
    EXPECT_EQ(calibrationFromJson(old, "old.json").reference, ThetaReference::kAbsolute);
    std::string bad = json;
    bad.replace(bad.find("\"others\""), 8, "\"median\"");
    const std::string error = rejection(bad);
    EXPECT_NE(error.find("cal.json: bad calibration: reference must be \"absolute\" or \"others\""), std::string::npos) << error;
  }
  {  // the estimate's reference and its own noise model round-trip; absent: the estimate reads what
     // the rule reads; differing without a noise model of its own, or with a bad one: refused
    DecisionCalibration split = c;
    split.reference = ThetaReference::kOthers;
    split.estimate_reference = ThetaReference::kAbsolute;
    split.estimate_noise.sigma = 0.031;
    split.estimate_noise.spread_bins = {{0.5, 0.8, 0.012, 700}, {1.0, 1.3, 0.004, 2100}};
    const std::string json = calibrationToJson(split);
    const DecisionCalibration split_back = calibrationFromJson(json, "x.json");
    EXPECT_EQ(split_back.estimate_reference, ThetaReference::kAbsolute);
    EXPECT_EQ(calibrationToJson(split_back), json);
    const SequentialConfig rule = sequentialConfig(split_back);
    EXPECT_EQ(rule.reference, ThetaReference::kOthers);
    EXPECT_EQ(rule.estimate_reference, ThetaReference::kAbsolute);
    EXPECT_EQ(rule.noise.sigma, 0.031);  // the interval's noise is the estimate's
    ASSERT_EQ(rule.noise.spread_bins.size(), 2u);
    EXPECT_EQ(rule.noise.spread_bins[0].model_sigma, 0.012);
    std::string before = json;  // a file of the morning of 2026-11-26: no estimate_reference
    before.replace(before.find("\"estimate_reference\""), 20, "\"renamed_estimate_r\"");
    const DecisionCalibration follows = calibrationFromJson(before, "old.json");
    EXPECT_EQ(follows.estimate_reference, ThetaReference::kOthers);
    EXPECT_EQ(sequentialConfig(follows).noise.sigma, split.noise.sigma);
    std::string missing = json;
    missing.replace(missing.find("\"estimate_noise\""), 16, "\"estimate_nois_\"");
    const std::string error = rejection(missing);
    EXPECT_NE(error.find("cal.json: bad calibration: estimate_reference differs from reference but there is no estimate_noise"),
              std::string::npos) << error;
    std::string unknown = json;
    unknown.replace(unknown.find("\"estimate_reference\": \"absolute\""), 32, "\"estimate_reference\": \"median\"");
    const std::string unknown_error = rejection(unknown);
    EXPECT_NE(unknown_error.find("cal.json: bad calibration: estimate_reference must be \"absolute\" or \"others\""), std::string::npos)
        << unknown_error;
    split.estimate_noise.phi = 1.5;
    const std::string bad_phi = rejection(calibrationToJson(split));
    EXPECT_NE(bad_phi.find("cal.json: bad calibration: estimate_noise phi must lie in [0, 1)"), std::string::npos) << bad_phi;
  }
  EXPECT_EQ(back.degraded.tail_maxima, c.degraded.tail_maxima);
  EXPECT_EQ(back.degraded.increment_cap, 0.1);
  EXPECT_EQ(back.failed.increment_cap, kNoIncrementCap);  // no key: no cap (every file before the cap)
  EXPECT_EQ(calibrationToJson(back).find("increment_cap", calibrationToJson(back).find("\"failed\"")), std::string::npos);
  {
    std::string json = calibrationToJson(c);
    json.replace(json.find("\"increment_cap\": 0.1"), 20, "\"increment_cap\": -1");
    const std::string error = rejection(json);
    EXPECT_NE(error.find("cal.json: bad calibration: CUSUM increment caps must be positive"), std::string::npos) << error;
  }
  {
    const std::string error = rejection("{\"format\": \"quadfdi-decision-calibration-1\"}");
    EXPECT_EQ(error.rfind("cal.json: bad calibration: ", 0), 0u) << error;
  }
  EXPECT_THROW(calibrationFromJson("{", "cal.json"), ConfigError);
  // A count that is not a whole number (6.7e60 was undefined behaviour in get<long>; fuzz finding).
  for (const char* bad : {"6.66667e+60", "-3", "2.5"}) {
    std::string json = calibrationToJson(c);
    const std::size_t at = json.find("\"flights\": ") + 11;
    json.replace(at, json.find(',', at) - at, bad);
    const std::string error = rejection(json);
    EXPECT_NE(error.find("cal.json: bad calibration: "), std::string::npos) << bad << ": " << error;
    EXPECT_NE(error.find("'flights' must be a whole number >= 0"), std::string::npos) << bad << ": " << error;
  }
}

}  // namespace
}  // namespace quadfdi
