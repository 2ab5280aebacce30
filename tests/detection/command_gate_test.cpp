// The command gate (detection/command_gate.h) and what the sequential rule and the calibration do
// with its mask, on hand-made commands and Θ̂.
#include <gtest/gtest.h>

#include <vector>

#include "detection/calibration.h"
#include "detection/command_gate.h"
#include "detection/sequential.h"

namespace quadfdi {
namespace {

CommandGateConfig gateConfig(int hold) {
  CommandGateConfig c;
  c.min_share = 0.3;
  c.hold = hold;
  return c;
}

TEST(CommandGate, AMotorBelowItsShareIsHiddenForTheHoldThenSeenAgain) {
  CommandGate gate(gateConfig(5));
  EXPECT_EQ(gate.step({1.0, 1.0, 1.0, 1.0}), kAllMotorsObservable);  // nothing seen against any motor
  // Motor 3 at 0.2 of a mean of 0.8: below 0.3 of it.
  EXPECT_EQ(gate.step({1.0, 1.0, 0.2, 1.0}), 0x0B);
  // Back up: hidden while the low sample is inside the last 5, seen from the 5th sample after it.
  for (int i = 1; i < 5; ++i) EXPECT_EQ(gate.step({1.0, 1.0, 1.0, 1.0}), 0x0B) << i;
  EXPECT_EQ(gate.step({1.0, 1.0, 1.0, 1.0}), kAllMotorsObservable);
  // At the share exactly: seen. No thrust at all (on the ground): nothing is observable.
  EXPECT_EQ(gate.step({0.3 * 0.825, 1.0, 1.0, 1.0}), kAllMotorsObservable);
  EXPECT_EQ(gate.step({0.0, 0.0, 0.0, 0.0}), 0x00);
  gate.reset();
  EXPECT_EQ(gate.step({1.0, 1.0, 1.0, 1.0}), kAllMotorsObservable);
}

TEST(CommandGate, AZeroShareTurnsItOff) {
  CommandGateConfig c = gateConfig(5);
  c.min_share = 0.0;
  CommandGate gate(c);
  EXPECT_EQ(gate.step({0.0, 1.0, 0.0, 1.0}), kAllMotorsObservable);
  EXPECT_EQ(gate.step({0.0, 0.0, 0.0, 0.0}), kAllMotorsObservable);
}

TEST(CommandGate, AHiddenMotorTakesNoEvidenceButLosesWhatItHad) {
  SequentialConfig c;
  c.degraded_below = 0.8;
  c.degraded_threshold = 2.999;
  c.failed_threshold = 2.999;
  SequentialRule gated(c), plain(c);
  const MotorTheta dip{0.0f, 0.97f, 0.97f, 0.97f};
  const std::uint8_t motor1_hidden = 0x0E;
  // Motor 1 reads 0 while it is hidden: no evidence, no alarm, however long.
  for (int i = 0; i < 50; ++i) EXPECT_EQ(gated.update(dip, 1, motor1_hidden), SequentialStatus::kHealthy);
  EXPECT_EQ(gated.degradedStatistic(0), 0.0);
  EXPECT_EQ(gated.failedStatistic(0), 0.0);
  // Unmasked, the same reading raises an alarm.
  int raised = 0;
  for (int i = 1; i <= 10 && !raised; ++i)
    if (plain.update(dip, 1) == SequentialStatus::kRaised) raised = i;
  EXPECT_EQ(raised, 4);  // the degraded statistic (0.8 a sample) passes 2.999 first
  // Evidence gathered while observable still drains while hidden, and does not grow.
  SequentialRule drain(c);
  drain.update({0.5f, 0.97f, 0.97f, 0.97f}, 1);  // +0.3 on motor 1
  drain.update({0.97f, 0.97f, 0.97f, 0.97f}, 1, motor1_hidden);
  EXPECT_NEAR(drain.degradedStatistic(0), 0.3 - 0.17, 1e-6);  // a healthy reading still counts against it
  drain.update({0.5f, 0.97f, 0.97f, 0.97f}, 1, motor1_hidden);
  EXPECT_NEAR(drain.degradedStatistic(0), 0.13, 1e-6);  // hidden: held, not grown
  drain.update({0.5f, 0.97f, 0.97f, 0.97f}, 1);
  EXPECT_NEAR(drain.degradedStatistic(0), 0.43, 1e-6);  // seen again: grows
}

TEST(CommandGate, TwoMotorsLeftToReadThatBothReadWeakGainNoEvidence) {
  // Every mask: read against the siblings, emptied only when exactly two motors are seen and both
  // read below kMinOthersMedian; kept whenever one of the two reads strong, and with one, three or
  // four motors seen. The absolute reading keeps every mask as the gate gave it.
  const MotorTheta weak{0.1f, 0.1f, 0.1f, 0.1f}, strong{0.9f, 0.9f, 0.9f, 0.9f};
  for (int mask = 0; mask < 16; ++mask) {
    const auto m = static_cast<std::uint8_t>(mask);
    const int seen = (mask & 1) + ((mask >> 1) & 1) + ((mask >> 2) & 1) + ((mask >> 3) & 1);
    EXPECT_EQ(evidenceMask(m, weak, ThetaReference::kOthers), seen == 2 ? 0 : m) << mask;
    EXPECT_EQ(evidenceMask(m, strong, ThetaReference::kOthers), m) << mask;
    EXPECT_EQ(evidenceMask(m, weak, ThetaReference::kAbsolute), m) << mask;
  }
  EXPECT_EQ(evidenceMask(0x06, MotorTheta{0.1f, 0.1f, kMinOthersMedian, 0.1f}, ThetaReference::kOthers), 0x06);  // at the bound: strong

  // Motors 1 and 4 (the front pair) hidden at their lower limit while motors 2 and 3 read 0: a
  // saturated pitch demand, not a fault (what the CBF-QP's tilt limit in wind gave the X500).
  SequentialConfig c;
  c.degraded_below = 0.8;
  c.degraded_threshold = 2.999;
  c.failed_threshold = 2.999;
  c.reference = ThetaReference::kOthers;
  const auto raisedAt = [](SequentialRule& rule, const MotorTheta& theta, std::uint8_t mask) {
    for (int i = 1; i <= 50; ++i)
      if (rule.update(theta, 1, mask) == SequentialStatus::kRaised) return i;
    return 0;
  };
  SequentialRule rear_pair(c);
  EXPECT_EQ(raisedAt(rear_pair, {0.97f, 0.0f, 0.0f, 0.97f}, 0x06), 0);
  for (int k = 0; k < kMotors; ++k) EXPECT_EQ(rear_pair.failedStatistic(k), 0.0) << k;
  // The same two seen, one of them strong: the other's dip is a fault's, named on it (the degraded
  // statistic, 0.8 a sample, passes 2.999 first). So is the dip of the only motor seen, and a dip
  // of two motors with a third one seen (the median of its siblings then stands for a seen motor).
  SequentialRule one_weak(c), one_seen(c), three_seen(c);
  EXPECT_EQ(raisedAt(one_weak, {0.97f, 0.0f, 0.97f, 0.97f}, 0x06), 4);
  EXPECT_EQ(one_weak.state().motor, 2);
  EXPECT_EQ(raisedAt(one_seen, {0.97f, 0.0f, 0.97f, 0.97f}, 0x02), 4);
  EXPECT_EQ(one_seen.state().motor, 2);
  EXPECT_EQ(raisedAt(three_seen, {0.97f, 0.0f, 0.0f, 0.97f}, 0x07), 4);
  // The absolute reading keeps the pair's evidence: motor 2 (ties go to the lower motor) is named.
  c.reference = ThetaReference::kAbsolute;
  SequentialRule absolute(c);
  EXPECT_EQ(raisedAt(absolute, {0.97f, 0.0f, 0.0f, 0.97f}, 0x06), 4);
  EXPECT_EQ(absolute.state().motor, 2);
}

TEST(CommandGate, TheCalibrationCountsNoExcursionOfAHiddenMotor) {
  // One stream: motor 2 dips to 0.5 for 20 samples; the mask hides it for the first 15 of them.
  std::vector<std::vector<MotorTheta>> streams(1, std::vector<MotorTheta>(200, MotorTheta{0.97f, 0.97f, 0.97f, 0.97f}));
  std::vector<std::vector<std::uint8_t>> masks(1, std::vector<std::uint8_t>(200, kAllMotorsObservable));
  for (int i = 100; i < 120; ++i) streams[0][static_cast<std::size_t>(i)][1] = 0.5f;
  for (int i = 100; i < 115; ++i) masks[0][static_cast<std::size_t>(i)] = 0x0D;
  const std::vector<double> plain = excursionMaxima(streams, 0.8, 0);
  const std::vector<double> gated = excursionMaxima(streams, 0.8, 0, kNoIncrementCap, &masks);
  ASSERT_EQ(plain.size(), 1U);
  ASSERT_EQ(gated.size(), 1U);
  EXPECT_NEAR(plain[0], 20 * 0.3, 1e-5);
  EXPECT_NEAR(gated[0], 5 * 0.3, 1e-5);
}

TEST(CommandGate, AFailedShareWithholdsFailedEvidenceFromAMotorCommandedBelowIt) {
  CommandGateConfig c = gateConfig(5);
  c.failed_min_share = 1.0;
  CommandGate gate(c);
  // Mean 1.0: motors 2 and 3 below it are withheld at the failed level (bits 5 and 6), every motor
  // observable; at the mean exactly, not withheld.
  EXPECT_EQ(gate.step({1.3, 0.8, 0.9, 1.0}), kAllMotorsObservable | 0x60);
  EXPECT_TRUE(takesFailedEvidence(kAllMotorsObservable | 0x60, 0));
  EXPECT_FALSE(takesFailedEvidence(kAllMotorsObservable | 0x60, 1));
  EXPECT_TRUE(takesFailedEvidence(kAllMotorsObservable | 0x60, 3));
  // Instantaneous: the next sample's commands decide alone (the failed motor is commanded up at once
  // when the controller sees the loss); observability keeps its hold.
  EXPECT_EQ(gate.step({0.8, 1.3, 1.0, 0.9}), kAllMotorsObservable | 0x90);
  EXPECT_EQ(gate.step({1.0, 1.0, 0.2, 1.0}), 0x0B | 0x40);
  EXPECT_FALSE(takesFailedEvidence(0x0B, 2));  // hidden: no evidence at either level
  // No thrust at all: nothing observable, everything withheld.
  EXPECT_EQ(gate.step({0.0, 0.0, 0.0, 0.0}), 0xF0);
  // Observability off, the failed share on: every motor observable, the low one withheld.
  c.min_share = 0.0;
  CommandGate failed_only(c);
  EXPECT_EQ(failed_only.step({0.0, 1.0, 1.0, 1.0}), kAllMotorsObservable | 0x10);
  // The share off (every calibration before it): nothing withheld, as before.
  CommandGate plain(gateConfig(5));
  EXPECT_EQ(plain.step({1.3, 0.8, 0.9, 1.0}), kAllMotorsObservable);
}

TEST(CommandGate, ADegradedShareHidesAMotorCommandedBelowItFromBothLevels) {
  CommandGateConfig c = gateConfig(5);
  c.degraded_min_share = 1.0;
  CommandGate gate(c);
  // Mean 1.0: motors 2 and 3 below it are not observable now; at the mean exactly, observable.
  EXPECT_EQ(gate.step({1.3, 0.8, 0.9, 1.0}), 0x09);
  EXPECT_FALSE(takesEvidence(0x09, 1));
  EXPECT_FALSE(takesFailedEvidence(0x09, 2));
  // Instantaneous, unlike the observability hold: commanded up again, observable at once.
  EXPECT_EQ(gate.step({0.8, 1.3, 1.0, 0.9}), 0x06);
  // With the failed share too: the failed bits are set as without the degraded share.
  c.failed_min_share = 1.1;
  CommandGate both(c);
  EXPECT_EQ(both.step({1.3, 0.8, 0.9, 1.0}), 0x09 | 0xE0);
  EXPECT_TRUE(takesFailedEvidence(0x09 | 0xE0, 0));
  // A steady fault at Θ = 0.9, the others at 1.0: commanded 1/0.9 of them, 1.08 of the mean: observable.
  c.failed_min_share = 1.0;
  CommandGate steady(c);
  EXPECT_EQ(steady.step({1.0 / 0.9, 1.0, 1.0, 1.0}), 0x01 | 0xE0);
  // The share off: as before.
  CommandGate plain(gateConfig(5));
  EXPECT_EQ(plain.step({1.3, 0.8, 0.9, 1.0}), kAllMotorsObservable);
}

TEST(CommandGate, AWithheldMotorGainsDegradedButNotFailedEvidence) {
  SequentialConfig c;
  c.degraded_below = 0.8;
  c.degraded_threshold = 100.0;  // out of reach: only the statistics are watched
  c.failed_threshold = 100.0;
  SequentialRule rule(c);
  const MotorTheta dip{0.0f, 0.97f, 0.97f, 0.97f};
  const auto withheld1 = static_cast<std::uint8_t>(kAllMotorsObservable | (1u << kFailedWithheldShift));
  for (int i = 0; i < 5; ++i) rule.update(dip, 1, withheld1);
  EXPECT_NEAR(rule.degradedStatistic(0), 5 * 0.8, 1e-6);
  EXPECT_EQ(rule.failedStatistic(0), 0.0);
  // Commanded up again: the failed statistic grows from where it was.
  for (int i = 0; i < 3; ++i) rule.update(dip, 1, kAllMotorsObservable);
  EXPECT_NEAR(rule.failedStatistic(0), 3 * 0.3, 1e-6);
  EXPECT_NEAR(rule.degradedStatistic(0), 8 * 0.8, 1e-6);
  // Withheld again with a healthy reading: the failed statistic still drains.
  rule.update({0.97f, 0.97f, 0.97f, 0.97f}, 1, withheld1);
  EXPECT_NEAR(rule.failedStatistic(0), 0.9 - 0.67, 1e-6);
  // Read against the siblings, the withheld bits pass through evidenceMask untouched.
  EXPECT_EQ(evidenceMask(withheld1, MotorTheta{0.1f, 0.97f, 0.97f, 0.97f}, ThetaReference::kOthers), withheld1);
}

TEST(CommandGate, TheFailedCalibrationCountsNoWithheldSample) {
  // Motor 2 dips to 0.1 for 20 samples, withheld at the failed level for the first 15: the failed
  // excursion holds the last 5 samples' deficits only; the degraded one all 20.
  std::vector<std::vector<MotorTheta>> streams(1, std::vector<MotorTheta>(200, MotorTheta{0.97f, 0.97f, 0.97f, 0.97f}));
  std::vector<std::vector<std::uint8_t>> masks(1, std::vector<std::uint8_t>(200, kAllMotorsObservable));
  for (int i = 100; i < 120; ++i) streams[0][static_cast<std::size_t>(i)][1] = 0.1f;
  for (int i = 100; i < 115; ++i) masks[0][static_cast<std::size_t>(i)] = kAllMotorsObservable | (1u << (kFailedWithheldShift + 1));
  const std::vector<double> failed = excursionMaxima(streams, 0.3, 0, kNoIncrementCap, &masks, EvidenceLevel::kFailed);
  const std::vector<double> degraded = excursionMaxima(streams, 0.8, 0, kNoIncrementCap, &masks, EvidenceLevel::kDegraded);
  ASSERT_EQ(failed.size(), 1U);
  ASSERT_EQ(degraded.size(), 1U);
  EXPECT_NEAR(failed[0], 5 * 0.2, 1e-5);
  EXPECT_NEAR(degraded[0], 20 * 0.7, 1e-5);
}

}  // namespace
}  // namespace quadfdi
