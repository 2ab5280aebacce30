// Feature rows (docs/networks.md): the scale-free set's invariances (to scaling every command by
// one constant, to position and heading offsets), its guard for no thrust, and the dense labels
// of whole trajectories at the fault boundary.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "data/features.h"

namespace quadfdi {
namespace {

constexpr int kLength = 40;
constexpr int kScaleFreeChannels = kOutputDim + kInputDim + 1;

// A wandering flight: positions, attitude with the yaw through ±π, uneven commands around 0.07 N.
void flight(std::vector<float>& y, std::vector<float>& u) {
  y.assign(kLength * kOutputDim, 0.0f);
  u.assign(kLength * kInputDim, 0.0f);
  for (int k = 0; k < kLength; ++k) {
    const double t = 0.1 * k;
    float* yk = &y[static_cast<std::size_t>(k * kOutputDim)];
    yk[0] = static_cast<float>(0.5 * std::sin(t));
    yk[1] = static_cast<float>(0.3 * std::cos(1.3 * t));
    yk[2] = static_cast<float>(1.0 + 0.1 * t);
    yk[3] = static_cast<float>(0.1 * std::sin(2.0 * t));
    yk[4] = static_cast<float>(-0.08 * std::cos(t));
    yk[5] = static_cast<float>(3.1 + 0.02 * k);  // crosses π
    for (int i = 0; i < kInputDim; ++i)
      u[static_cast<std::size_t>(k * kInputDim + i)] = static_cast<float>(0.07 * (1.0 + 0.2 * std::sin(t + i)));
  }
}

std::vector<float> scaleFreeRows(const std::vector<float>& y, const std::vector<float>& u) {
  std::vector<float> out(kLength * kScaleFreeChannels);
  gatherFeatures(y.data(), u.data(), nullptr, nullptr, kLength, FeatureSet::kScaleFree, OutputKind::kPositionEuler, nullptr,
                 out.data());
  return out;
}

TEST(ScaleFreeFeatures, AreNamedAndCounted) {
  FeatureSet f = FeatureSet::kModelFree;
  ASSERT_TRUE(parseFeatureSet("scale-free", f));
  EXPECT_EQ(f, FeatureSet::kScaleFree);
  EXPECT_STREQ(toString(f), "scale-free");
  EXPECT_EQ(featureChannels(f), kScaleFreeChannels);
  EXPECT_TRUE(isStreamingFeatureSet(f));
  EXPECT_TRUE(isStreamingFeatureSet(FeatureSet::kModelFreeHeading));
  EXPECT_FALSE(isStreamingFeatureSet(FeatureSet::kModelFree));
}

TEST(ScaleFreeFeatures, AreSharesOfTheCollectiveAndItsLogChange) {
  const Output y = Output::Zero();
  float row[kScaleFreeChannels];
  streamingFeatureRow(FeatureSet::kScaleFree, y, Input(1.0, 1.0, 1.0, 1.0), y, Input(1.0, 2.0, 3.0, 4.0), row);
  EXPECT_FLOAT_EQ(row[6], 0.4f);  // ū = 2.5
  EXPECT_FLOAT_EQ(row[7], 0.8f);
  EXPECT_FLOAT_EQ(row[8], 1.2f);
  EXPECT_FLOAT_EQ(row[9], 1.6f);
  EXPECT_FLOAT_EQ(row[10], static_cast<float>(std::log(2.5)));
}

TEST(ScaleFreeFeatures, AreInvariantToScalingEveryCommand) {
  std::vector<float> y, u;
  flight(y, u);
  const std::vector<float> a = scaleFreeRows(y, u);
  for (double c : {0.01, 3.7, 250.0}) {  // a toy drone to a heavy lifter
    std::vector<float> scaled = u;
    for (float& v : scaled) v = static_cast<float>(static_cast<double>(v) * c);
    const std::vector<float> b = scaleFreeRows(y, scaled);
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-6) << "c " << c << " value " << i;
  }
  // The command channels carry information (not all ones): shares vary, and so does Δ ln ū.
  EXPECT_GT(std::abs(a[kScaleFreeChannels * 10 + 6] - 1.0f), 1e-3f);
  EXPECT_GT(std::abs(a[kScaleFreeChannels * 10 + 10]), 1e-4f);
}

TEST(ScaleFreeFeatures, AreInvariantToPositionAndHeadingOffsets) {
  std::vector<float> y, u;
  flight(y, u);
  const std::vector<float> a = scaleFreeRows(y, u);
  const double alpha = 2.0, c = std::cos(alpha), s = std::sin(alpha);
  std::vector<float> moved = y;
  for (int k = 0; k < kLength; ++k) {
    float* m = &moved[static_cast<std::size_t>(k * kOutputDim)];
    const double px = static_cast<double>(m[0]), py = static_cast<double>(m[1]);
    m[0] = static_cast<float>(c * px - s * py + 12.0);
    m[1] = static_cast<float>(s * px + c * py - 7.0);
    m[2] = static_cast<float>(static_cast<double>(m[2]) + 3.0);
    m[5] = static_cast<float>(static_cast<double>(m[5]) + alpha);
  }
  const std::vector<float> b = scaleFreeRows(moved, u);
  // float storage of the moved positions (≈ 12 m: 1e-6 m steps) bounds the agreement.
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 5e-6) << "value " << i;
}

TEST(ScaleFreeFeatures, NoThrustGivesEvenSharesAndNoChange) {
  const Output y = Output::Zero();
  const Input zero = Input::Zero(), hover(0.07, 0.07, 0.07, 0.07);
  float row[kScaleFreeChannels];
  streamingFeatureRow(FeatureSet::kScaleFree, y, zero, y, zero, row);
  for (int i = 6; i < 10; ++i) EXPECT_EQ(row[i], 1.0f);
  EXPECT_EQ(row[10], 0.0f);
  streamingFeatureRow(FeatureSet::kScaleFree, y, zero, y, hover, row);  // motors spin up: no finite log change
  for (int i = 6; i < 10; ++i) EXPECT_FLOAT_EQ(row[i], 1.0f);
  EXPECT_EQ(row[10], 0.0f);
  streamingFeatureRow(FeatureSet::kScaleFree, y, hover, y, zero, row);  // and stop
  for (int i = 6; i < 11; ++i) EXPECT_TRUE(std::isfinite(row[i]));
  EXPECT_EQ(row[10], 0.0f);
}

TEST(DenseLabels, SwitchToThetaAfterTheFaultAndMaskInvalidSamples) {
  TrajectoryBatch b;
  b.resize(2, 21);
  b.fault_step = {10, 10};
  b.length = {19, 21};  // the first flight was cut after 19 samples
  const float theta[] = {1.0f, 0.3f, 1.0f, 1.0f};
  std::copy(theta, theta + 4, b.theta.begin());
  const int first = 5, positions = 21 - first;
  std::vector<float> labels(static_cast<std::size_t>(positions) * 4), mask(static_cast<std::size_t>(positions));
  positionLabels(b, 0, first, labels.data(), mask.data());
  for (int k = first; k < 21; ++k) {
    const auto p = static_cast<std::size_t>(k - first);
    // Window ending at k: labelled Θ once it holds a faulty sample (k > F), as windowLabel.
    EXPECT_EQ(labels[p * 4 + 1], k > 10 ? 0.3f : 1.0f) << k;
    EXPECT_EQ(labels[p * 4 + 0], 1.0f) << k;
    EXPECT_EQ(labels[p * 4 + 1], static_cast<float>(windowLabel(b, {0, k})(1))) << k;
    EXPECT_EQ(mask[p], k < 19 ? 1.0f : 0.0f) << k;
  }
  positionLabels(b, 1, first, labels.data(), mask.data());
  for (int p = 0; p < positions; ++p) {
    EXPECT_EQ(mask[static_cast<std::size_t>(p)], 1.0f);
    EXPECT_EQ(labels[static_cast<std::size_t>(p) * 4 + 1], 1.0f);  // healthy flight (Θ = 1)
  }
}

// scale-free-rates: the scale-free row, then the measured body rates; a symmetry map sends the rates
// as it sends the state's rate block, ω → det(S)·S·ω (docs/symmetry.md), e.g. (p, −q, −r) for the
// reflection x → −x that sends motor 1 to motor 2.
TEST(ScaleFreeRatesFeatures, AreTheScaleFreeRowThenTheRatesMappedLikeTheState) {
  FeatureSet f = FeatureSet::kModelFree;
  ASSERT_TRUE(parseFeatureSet("scale-free-rates", f));
  EXPECT_EQ(f, FeatureSet::kScaleFreeRates);
  EXPECT_STREQ(toString(f), "scale-free-rates");
  constexpr int kChannels = kScaleFreeChannels + kRateDim;
  EXPECT_EQ(featureChannels(f), kChannels);
  EXPECT_TRUE(isStreamingFeatureSet(f));
  EXPECT_TRUE(featuresReadRates(f));
  EXPECT_FALSE(featuresReadRates(FeatureSet::kScaleFree));

  std::vector<float> y, u;
  flight(y, u);
  std::vector<float> rates(kLength * kRateDim);
  for (int k = 0; k < kLength; ++k)
    for (int i = 0; i < kRateDim; ++i) rates[static_cast<std::size_t>(k * kRateDim + i)] = static_cast<float>(0.1 * (i + 1) * std::sin(0.2 * k + i));
  for (int motor = 0; motor <= 4; ++motor) {  // 0: no map
    const SymmetryMap map = mapMotorToMotor2(motor == 0 ? 2 : motor, SymmetryMode::kExactGroup);
    const SymmetryMap* m = motor == 0 ? nullptr : &map;
    std::vector<float> with(kLength * kChannels), without(kLength * kScaleFreeChannels);
    gatherFeatures(y.data(), u.data(), nullptr, rates.data(), kLength, f, OutputKind::kPositionEuler, m, with.data());
    gatherFeatures(y.data(), u.data(), nullptr, nullptr, kLength, FeatureSet::kScaleFree, OutputKind::kPositionEuler, m,
                   without.data());
    for (int k = 0; k < kLength; ++k) {
      for (int c = 0; c < kScaleFreeChannels; ++c)
        EXPECT_EQ(with[static_cast<std::size_t>(k * kChannels + c)], without[static_cast<std::size_t>(k * kScaleFreeChannels + c)]);
      State x = State::Zero();
      for (int i = 0; i < kRateDim; ++i) x(idx::kRate + i) = rates[static_cast<std::size_t>(k * kRateDim + i)];
      const State mapped = m ? m->applyToState(x) : x;
      for (int i = 0; i < kRateDim; ++i)
        EXPECT_FLOAT_EQ(with[static_cast<std::size_t>(k * kChannels + kScaleFreeChannels + i)], static_cast<float>(mapped(idx::kRate + i)))
            << "motor " << motor << " sample " << k;
    }
    if (motor == 1) {  // x → −x: (p, −q, −r)
      EXPECT_FLOAT_EQ(with[kScaleFreeChannels + 0], rates[0]);
      EXPECT_FLOAT_EQ(with[kScaleFreeChannels + 1], -rates[1]);
      EXPECT_FLOAT_EQ(with[kScaleFreeChannels + 2], -rates[2]);
    }
  }
}

}  // namespace
}  // namespace quadfdi
