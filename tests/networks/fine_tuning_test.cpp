// Fine-tuning (docs/networks.md#fine-tuning): a finished model's plain weights go back into a
// trainable network unchanged, training started from them begins exactly where the model ended
// (its held-out score, its normalisation), and a model whose network differs is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "networks/model.h"
#include "networks/trainer.h"
#include "networks/tiny_training.h"

namespace quadfdi {
namespace {

ModelMetadata smallNetwork(Architecture arch) {
  ModelMetadata m;
  m.architecture = arch;
  m.features = arch == Architecture::kTcn ? FeatureSet::kScaleFree : FeatureSet::kModelFree;
  m.window = 10;
  m.hidden = 16;
  m.tcn.channels = 8;
  m.tcn.dilations = {1, 2};
  for (int j = 0; j < m.channels(); ++j) {  // a normalisation that is not the identity
    m.feature_mean.push_back(0.02f * static_cast<float>(j) - 0.1f);
    m.feature_std.push_back(0.4f + 0.15f * static_cast<float>(j));
  }
  return m;
}

std::vector<float> wavy(const ModelMetadata& m, int count) {
  std::vector<float> w(static_cast<std::size_t>(count * m.window * m.channels()));
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = static_cast<float>(std::sin(0.29 * static_cast<double>(i)) * 2.0);
  return w;
}

TEST(FineTuning, ImportedWeightsGiveTheExportedNetworksOutputs) {
  for (Architecture arch : {Architecture::kLstm, Architecture::kMlp, Architecture::kTcn}) {
    const ModelMetadata m = smallNetwork(arch);
    const FaultIdentifier original = FaultIdentifier::create(m, 21);
    ModelMetadata blank = m;  // the normalisation must come from the weights, not the metadata
    blank.feature_mean.clear();
    blank.feature_std.clear();
    const FaultIdentifier back = importWeights(blank, exportWeights(original));
    const std::vector<float> w = wavy(m, 6);
    std::vector<float> a(24), b(24);
    original.predict(w.data(), 6, a.data());
    back.predict(w.data(), 6, b.data());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-6f) << toString(arch) << " output " << i;
    EXPECT_EQ(back.metadata().feature_mean, m.feature_mean) << toString(arch);
    EXPECT_EQ(back.metadata().feature_std, m.feature_std) << toString(arch);
  }
}

TEST(FineTuning, RefusesWeightsOfAnotherNetwork) {
  const ModelMetadata m = smallNetwork(Architecture::kTcn);
  NetworkWeights w = exportWeights(FaultIdentifier::create(m, 2));
  NetworkWeights fewer = w;
  fewer.convs.pop_back();
  EXPECT_THROW(importWeights(m, fewer), ModelError);
  NetworkWeights narrower = w;
  narrower.head[0].weight.pop_back();
  try {
    importWeights(m, narrower);
    FAIL() << "a head with a missing weight was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("head1.weight"), std::string::npos) << e.what();
  }
  ModelMetadata lstm = smallNetwork(Architecture::kLstm);
  EXPECT_THROW(importWeights(lstm, w), ModelError);
}

// A tiny dense TCN run on scale-free features (tiny_training.h).
TrainConfig tinyTcnConfig(int iterations) { return test::tinyDenseTcn(FeatureSet::kScaleFree, iterations); }

std::shared_ptr<const TrainedModel> finished(const TrainResult& r) {
  return std::make_shared<const TrainedModel>(TrainedModel{r.model.metadata(), exportWeights(r.model)});
}

TEST(FineTuning, StartsWhereTheStartingModelEndedAndKeepsItsNormalisation) {
  const TrainResult base = train(tinyTcnConfig(3));

  // Same held-out flights: iteration 0 scores the starting model as its own training last did.
  TrainConfig c = tinyTcnConfig(2);
  c.start_from = finished(base);
  c.start_from_name = "base.qfdw";
  std::vector<IterationReport> reports;
  const TrainResult tuned = train(c, [&](const IterationReport& it) { reports.push_back(it); });
  ASSERT_EQ(reports.size(), 3u);
  EXPECT_EQ(reports[0].iteration, 0);
  EXPECT_TRUE(std::isnan(reports[0].loss));
  EXPECT_NEAR(reports[0].heldout_loss, base.model.metadata().heldout_loss, 1e-6);
  EXPECT_DOUBLE_EQ(reports[0].heldout_accuracy, base.model.metadata().heldout_accuracy);
  EXPECT_EQ(reports[2].iteration, 2);
  EXPECT_LT(reports[2].heldout_loss, reports[0].heldout_loss);  // it went on learning, not from scratch
  const ModelMetadata& m = tuned.model.metadata();
  EXPECT_EQ(m.iterations, 2);
  EXPECT_EQ(m.started_from.rfind("base.qfdw (3 iterations", 0), 0u) << m.started_from;
  EXPECT_EQ(m.feature_mean, base.model.metadata().feature_mean);

  // Other flights (another data seed, other thetas): the network keeps the scale it learnt.
  TrainConfig other = tinyTcnConfig(1);
  other.data.rollout.seed = 17;
  other.data.thetas = {0.2, 0.9};
  other.start_from = finished(base);
  const TrainResult moved = train(other);
  EXPECT_EQ(moved.model.metadata().feature_mean, base.model.metadata().feature_mean);
  EXPECT_EQ(moved.model.metadata().feature_std, base.model.metadata().feature_std);
  const TrainResult fresh = train([] {
    TrainConfig f = tinyTcnConfig(1);
    f.data.rollout.seed = 17;
    f.data.thetas = {0.2, 0.9};
    return f;
  }());
  EXPECT_NE(fresh.model.metadata().feature_mean, base.model.metadata().feature_mean);  // the check can fail
}

TEST(FineTuning, RefusesAStartingModelWhoseNetworkDiffers) {
  const TrainResult base = train(tinyTcnConfig(1));
  struct Case {
    const char* what;
    void (*change)(TrainConfig&);
  };
  const Case cases[] = {
      {"features are scale-free, this training's model-free-heading",
       [](TrainConfig& c) { c.model.features = FeatureSet::kModelFreeHeading; }},
      {"TCN has 16 channels", [](TrainConfig& c) { c.model.tcn.channels = 32; }},
      {"architecture is tcn", [](TrainConfig& c) {
         c.model.architecture = Architecture::kLstm;
         c.mode = TrainingMode::kWindows;
       }},
  };
  for (const Case& k : cases) {
    TrainConfig c = tinyTcnConfig(1);
    k.change(c);
    c.start_from = finished(base);
    EXPECT_NE(startingModelProblem(c).find(k.what), std::string::npos) << startingModelProblem(c);
    EXPECT_THROW(train(c), std::runtime_error) << k.what;
  }
  TrainConfig same = tinyTcnConfig(1);
  same.start_from = finished(base);
  EXPECT_EQ(startingModelProblem(same), "");
}

}  // namespace
}  // namespace quadfdi
