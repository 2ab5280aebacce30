// Dense (sequence) training of the causal TCN (docs/networks.md, "Dense training"): one forward
// pass over a whole trajectory gives, at every position k, the windowed network's output for the
// window ending at k; a tiny dense run learns; its held-out score means what the windowed one does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "networks/model.h"
#include "networks/trainer.h"
#include "networks/tiny_training.h"

namespace quadfdi {
namespace {

TEST(DenseTraining, SequenceOutputEqualsTheWindowedForward) {
  for (FeatureSet features : {FeatureSet::kModelFreeHeading, FeatureSet::kScaleFree}) {
    ModelMetadata m;
    m.architecture = Architecture::kTcn;
    m.features = features;
    m.window = 100;
    for (int j = 0; j < m.channels(); ++j) {  // a normalisation that is not the identity
      m.feature_mean.push_back(0.01f * static_cast<float>(j));
      m.feature_std.push_back(0.5f + 0.1f * static_cast<float>(j));
    }
    const FaultIdentifier model = FaultIdentifier::create(m, 11);

    RolloutConfig rc;
    rc.window = m.window;
    rc.seed = 9;
    TrajectoryBatch b;
    RolloutEngine(rc).run(algorithm1Jobs(0, 1, {0.0, 0.6}, {2}), 1, b);
    const int samples = b.samples, c = m.channels(), first = m.tcn.receptiveField() - 1;
    for (int i = 0; i < b.count; ++i) {
      std::vector<float> sequence(static_cast<std::size_t>(samples * c));
      gatherWindowFeatures(b, {i, samples - 1}, samples, features, m.output, nullptr, sequence.data());
      std::vector<float> dense(static_cast<std::size_t>(samples - first) * 4);
      model.predictSequences(sequence.data(), 1, samples, dense.data());
      for (int k : {m.window - 1, m.window, m.window + 1, 150, samples - 1}) {
        std::vector<float> window(static_cast<std::size_t>(m.window * c));
        gatherWindowFeatures(b, {i, k}, m.window, features, m.output, nullptr, window.data());
        float windowed[4];
        model.predict(window.data(), 1, windowed);
        for (int j = 0; j < 4; ++j)
          EXPECT_NEAR(dense[static_cast<std::size_t>((k - first) * 4 + j)], windowed[j], 2e-6)
              << toString(features) << " trajectory " << i << " k " << k << " output " << j;
      }
    }
  }
}

TEST(DenseTraining, RefusesNonCausalNetworks) {
  TrainConfig c;
  c.data.scale = {"unit", 1, 100};
  EXPECT_EQ(validate(c), "");
  c.mode = TrainingMode::kSequences;
  c.model.architecture = Architecture::kLstm;
  EXPECT_NE(validate(c).find("causal"), std::string::npos);
  TrainingMode mode = TrainingMode::kWindows;
  EXPECT_TRUE(parseTrainingMode("sequences", mode));
  EXPECT_EQ(mode, TrainingMode::kSequences);
  EXPECT_STREQ(toString(mode), "sequences");
  EXPECT_FALSE(parseTrainingMode("dense", mode));
}


TEST(DenseTraining, ReducesTheLossAndScoresTheHeldOutWindowsAsTheWindowedForwardDoes) {
  const TrainConfig c = test::tinyDenseTcn(FeatureSet::kModelFreeHeading);
  std::vector<IterationReport> reports;
  const TrainResult r = train(c, [&](const IterationReport& it) { reports.push_back(it); });
  ASSERT_EQ(reports.size(), 6u);
  EXPECT_LT(reports.back().loss, 0.7 * reports.front().loss);
  EXPECT_LT(reports.back().heldout_loss, reports.front().heldout_loss);
  EXPECT_GT(reports.back().windows_per_second, 0.0);

  // The held-out score again, window by window through the windowed forward pass.
  TrajectoryBatch heldout;
  RolloutEngine(c.data.rollout)
      .run(algorithm1Jobs(1ull << 40, c.heldout_initial_conditions, c.data.thetas, c.data.motors), 1, heldout);
  std::vector<WindowRef> refs;
  enumerateWindows(heldout, c.model.window, refs);
  const ModelMetadata& m = r.model.metadata();
  const std::size_t per = static_cast<std::size_t>(m.window * m.channels());
  std::vector<float> windows(refs.size() * per), theta(refs.size() * 4);
  for (std::size_t i = 0; i < refs.size(); ++i)
    gatherWindowFeatures(heldout, refs[i], m.window, m.features, m.output, nullptr, &windows[i * per]);
  r.model.predict(windows.data(), static_cast<int>(refs.size()), theta.data());
  double loss = 0.0;
  int correct = 0;
  for (std::size_t i = 0; i < refs.size(); ++i) {
    const Input label = windowLabel(heldout, refs[i]);
    double norm2 = 0.0, worst = 0.0;
    for (int j = 0; j < 4; ++j) {
      const double e = std::abs(static_cast<double>(theta[i * 4 + static_cast<std::size_t>(j)]) - label(j));
      norm2 += e * e;
      worst = std::max(worst, e);
    }
    loss += std::max(0.0, std::sqrt(norm2) - c.epsilon);
    correct += worst <= 0.05 ? 1 : 0;
  }
  const auto n = static_cast<double>(refs.size());
  EXPECT_NEAR(m.heldout_loss, loss / n, 1e-6);
  EXPECT_NEAR(m.heldout_accuracy, correct / n, 1.0 / n);  // a window may sit on the 0.05 boundary
  EXPECT_GT(m.heldout_accuracy, 0.0);
}

}  // namespace
}  // namespace quadfdi
