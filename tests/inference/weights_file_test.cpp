// The weights file (docs/weights-format.md): exact round trips for every architecture, and a
// one-line ModelError naming the file and the problem for every kind of damage. The TCN's
// streaming form equals its windowed form bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "estimation/motor_estimator.h"
#include "inference/engine.h"
#include "inference/weights_file.h"
#include "networks/model.h"

namespace quadfdi {
namespace {

TrainedModel makeModel(Architecture arch, std::uint64_t seed, FeatureSet tcn_features = FeatureSet::kModelFreeHeading) {
  ModelMetadata m;
  m.architecture = arch;
  m.window = 100;
  m.hidden = 16;
  if (arch == Architecture::kTcn) m.features = tcn_features;
  m.feature_mean.assign(static_cast<std::size_t>(m.channels()), 0.1f);
  m.feature_std.assign(static_cast<std::size_t>(m.channels()), 2.0f);
  m.command = "test";
  const FaultIdentifier net = FaultIdentifier::create(m, seed);
  return {net.metadata(), exportWeights(net)};
}

std::string encode(const TrainedModel& t) { return encodeWeightsFile(t.metadata, t.weights); }

std::string errorOf(const std::string& bytes) {
  try {
    decodeWeightsFile(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "m.qfdw");
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(WeightsFile, RoundTripsEveryArchitectureExactly) {
  for (Architecture arch : {Architecture::kLstm, Architecture::kMlp, Architecture::kTcn}) {
    TrainedModel a = makeModel(arch, 3);
    if (arch == Architecture::kTcn) a.metadata.started_from = "models/base.qfdw (360 iterations, 1200 s)";  // fine-tuned
    const std::string bytes = encode(a);
    const TrainedModel b = decodeWeightsFile(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "x");
    EXPECT_EQ(metadataToJson(a.metadata), metadataToJson(b.metadata)) << toString(arch);
    EXPECT_EQ(a.metadata.started_from, b.metadata.started_from);
    EXPECT_EQ(a.weights.mean, b.weights.mean);
    EXPECT_EQ(a.weights.gates.weight, b.weights.gates.weight);
    ASSERT_EQ(a.weights.head.size(), b.weights.head.size());
    for (std::size_t i = 0; i < a.weights.head.size(); ++i) EXPECT_EQ(a.weights.head[i].weight, b.weights.head[i].weight);
    ASSERT_EQ(a.weights.convs.size(), b.weights.convs.size());
    for (std::size_t i = 0; i < a.weights.convs.size(); ++i) {
      EXPECT_EQ(a.weights.convs[i].weight, b.weights.convs[i].weight);
      EXPECT_EQ(a.weights.convs[i].dilation, b.weights.convs[i].dilation);
    }
    EXPECT_EQ(encode(b), bytes);  // and the bytes are a fixed point
  }
}

// A decoded model carries its file's CRC-32 (what a calibration records): the CRC of every byte
// before it, and another one for another network.
TEST(WeightsFile, ADecodedModelKnowsItsFilesCrc) {
  const std::string bytes = encode(makeModel(Architecture::kTcn, 3));
  const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
  const TrainedModel a = decodeWeightsFile(data, bytes.size(), "a");
  EXPECT_EQ(a.file_crc32, crc32(data, bytes.size() - 4));
  const std::string other = encode(makeModel(Architecture::kTcn, 4));
  EXPECT_NE(decodeWeightsFile(reinterpret_cast<const std::uint8_t*>(other.data()), other.size(), "b").file_crc32, a.file_crc32);
  EXPECT_EQ(makeModel(Architecture::kTcn, 3).file_crc32, 0u);  // not read from a file
}

TEST(WeightsFile, EveryKindOfDamageIsAOneLineError) {
  const std::string good = encode(makeModel(Architecture::kTcn, 1));
  EXPECT_EQ(errorOf(""), "m.qfdw: empty file, not a quadfdi weights file");
  EXPECT_EQ(errorOf("t,x,y\n1,2,3\n"), "m.qfdw: not a quadfdi weights file (bad magic at byte 0)");
  EXPECT_NE(errorOf("quadfdi-model 1\n{}\n").find("convert it with 'quadfdi convert-model"), std::string::npos);
  std::string v = good;
  v[8] = 9;
  EXPECT_NE(errorOf(v).find("version 9 is not supported"), std::string::npos) << errorOf(v);
  for (std::size_t cut : {std::size_t{10}, std::size_t{20}, good.size() / 2, good.size() - 1})
    EXPECT_FALSE(errorOf(good.substr(0, cut)).empty()) << cut;
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 0x10);
  EXPECT_NE(errorOf(flipped).find("CRC-32 check failed"), std::string::npos) << errorOf(flipped);
  std::string huge = good;
  huge[12] = huge[13] = huge[14] = static_cast<char>(0x7f);
  EXPECT_NE(errorOf(huge).find("declares"), std::string::npos) << errorOf(huge);
}

TEST(WeightsFile, RefusesNonFiniteAndMismatchedWeights) {
  TrainedModel t = makeModel(Architecture::kLstm, 2);
  t.weights.head[0].weight[5] = std::nanf("");
  EXPECT_THROW(encodeWeightsFile(t.metadata, t.weights), ModelError);
  t = makeModel(Architecture::kLstm, 2);
  t.weights.gates.bias.pop_back();
  EXPECT_THROW(encodeWeightsFile(t.metadata, t.weights), ModelError);
  t = makeModel(Architecture::kTcn, 2);
  t.metadata.tcn.dilations = {64, 64};  // receptive field 257 > T − 1
  EXPECT_THROW(metadataFromJson(metadataToJson(t.metadata), "x"), ModelError);
}

// The TCN on a stream gives, at every sample from T on, exactly the windowed network's estimate
// on the last T samples — through the estimation core, with the four symmetry maps.
TEST(WeightsFile, RecordsTheScaleFreeFeatureSet) {
  const TrainedModel a = makeModel(Architecture::kTcn, 4, FeatureSet::kScaleFree);
  const std::string bytes = encode(a);
  const TrainedModel b = decodeWeightsFile(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "x");
  EXPECT_EQ(b.metadata.features, FeatureSet::kScaleFree);
  EXPECT_EQ(b.metadata.channels(), 11);
  EXPECT_EQ(b.weights.channels, 11);
  EXPECT_EQ(b.weights.convs.front().in, 11);
  EXPECT_NE(bytes.find("\"scale-free\""), std::string::npos);
  EXPECT_EQ(encode(b), bytes);
  EXPECT_TRUE(StreamingMotorEstimator::canStream(b.metadata));
}

class StreamingEstimator : public ::testing::TestWithParam<FeatureSet> {};

TEST_P(StreamingEstimator, EqualsTheWindowedEstimateBitForBit) {
  const TrainedModel model = makeModel(Architecture::kTcn, 5, GetParam());
  StreamingMotorEstimator stream(model, SymmetryMode::kExactGroup);
  MotorEstimator windows(model, SymmetryMode::kExactGroup);
  const int t_len = model.metadata.window, n = 260;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<float> y(static_cast<std::size_t>(n) * kOutputDim), u(static_cast<std::size_t>(n) * kInputDim),
      w(static_cast<std::size_t>(n) * kRateDim);
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < kOutputDim; ++i) y[static_cast<std::size_t>(k * kOutputDim + i)] = static_cast<float>(0.3 * std::sin(0.05 * k + i) + 0.01 * noise(rng));
    y[static_cast<std::size_t>(k * kOutputDim + 5)] = static_cast<float>(3.0 * std::sin(0.01 * k));  // yaw through ±π
    for (int i = 0; i < kInputDim; ++i) u[static_cast<std::size_t>(k * kInputDim + i)] = static_cast<float>(0.07 + 0.01 * noise(rng));
    for (int i = 0; i < kRateDim; ++i) w[static_cast<std::size_t>(k * kRateDim + i)] = static_cast<float>(2.0 * std::sin(0.03 * k + i) + 0.05 * noise(rng));
  }
  std::vector<float> features(kMotors * windows.featuresPerWindow());
  int compared = 0;
  for (int k = 0; k < n; ++k) {
    Output yk;
    Input uk;
    for (int i = 0; i < kOutputDim; ++i) yk(i) = y[static_cast<std::size_t>(k * kOutputDim + i)];
    for (int i = 0; i < kInputDim; ++i) uk(i) = u[static_cast<std::size_t>(k * kInputDim + i)];
    const Vec3 wk(w[static_cast<std::size_t>(k * kRateDim)], w[static_cast<std::size_t>(k * kRateDim + 1)],
                  w[static_cast<std::size_t>(k * kRateDim + 2)]);
    MotorTheta streamed{};
    const bool ready = featuresReadRates(GetParam()) ? stream.push(yk, uk, wk, streamed) : stream.push(yk, uk, streamed);
    EXPECT_EQ(ready, k >= t_len - 1) << k;
    if (!ready) continue;
    const int first = k - t_len + 1;
    windows.gather(&y[static_cast<std::size_t>(first * kOutputDim)], &u[static_cast<std::size_t>(first * kInputDim)], nullptr,
                   &w[static_cast<std::size_t>(first * kRateDim)], features.data());
    MotorTheta windowed{};
    windows.estimate(features.data(), 1, &windowed);
    EXPECT_EQ(streamed, windowed) << "sample " << k;
    ++compared;
  }
  EXPECT_EQ(compared, n - t_len + 1);
  if (featuresReadRates(GetParam())) {
    MotorTheta theta{};
    EXPECT_THROW(stream.push(Output::Zero(), Input::Ones(), theta), std::logic_error);
  }
}

INSTANTIATE_TEST_SUITE_P(StreamingFeatureSets, StreamingEstimator,
                         ::testing::Values(FeatureSet::kModelFreeHeading, FeatureSet::kScaleFree, FeatureSet::kScaleFreeRates),
                         [](const ::testing::TestParamInfo<FeatureSet>& param) {
                           return param.param == FeatureSet::kScaleFree        ? std::string("ScaleFree")
                                  : param.param == FeatureSet::kScaleFreeRates ? std::string("ScaleFreeRates")
                                                                               : std::string("ModelFreeHeading");
                         });

}  // namespace
}  // namespace quadfdi
