// Polyak averaging (TrainConfig::average_last, docs/networks.md#weight-averaging): the model a run
// writes is the mean of its last iterations' weights, scored on its own, and a window longer than
// the run is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "networks/model.h"
#include "networks/trainer.h"
#include "networks/tiny_training.h"

namespace quadfdi {
namespace {

// Every weight and bias of a network in one flat list (TCN: convolutions, then the head).
std::vector<float> flatWeights(const FaultIdentifier& model) {
  const NetworkWeights w = exportWeights(model);
  std::vector<float> flat;
  for (const ConvWeights& c : w.convs) {
    flat.insert(flat.end(), c.weight.begin(), c.weight.end());
    flat.insert(flat.end(), c.bias.begin(), c.bias.end());
  }
  for (const DenseWeights& d : w.head) {
    flat.insert(flat.end(), d.weight.begin(), d.weight.end());
    flat.insert(flat.end(), d.bias.begin(), d.bias.end());
  }
  return flat;
}

TrainConfig tinyRun(int iterations, int average_last) {
  TrainConfig c = test::tinyDenseTcn(FeatureSet::kScaleFree, iterations);
  c.average_last = average_last;
  return c;
}

TEST(WeightAveraging, TheWrittenModelIsTheMeanOfTheLastIterationsWeights) {
  // A run is a function of its iteration index alone (data, shuffling, learning rate), so the first
  // two iterations of a three-iteration run are a two-iteration run.
  const TrainResult two = train(tinyRun(2, 0));
  const TrainResult three = train(tinyRun(3, 0));
  const TrainResult averaged = train(tinyRun(3, 2));
  const std::vector<float> w2 = flatWeights(two.model), w3 = flatWeights(three.model), mean = flatWeights(averaged.model);
  ASSERT_EQ(w2.size(), mean.size());
  ASSERT_EQ(w3.size(), mean.size());
  double largest_step = 0.0;
  for (std::size_t i = 0; i < mean.size(); ++i) {
    EXPECT_NEAR(mean[i], 0.5f * (w2[i] + w3[i]), 1e-6f) << "weight " << i;
    largest_step = std::max(largest_step, static_cast<double>(std::abs(w3[i] - w2[i])));
  }
  EXPECT_GT(largest_step, 1e-4);  // the last iteration moved the weights: the mean is not either end
  EXPECT_EQ(averaged.averaged_iterations, 2);
  EXPECT_EQ(averaged.iterations, 3);
  // The held-out score written is the averaged network's own; the last weights' is kept beside it.
  EXPECT_DOUBLE_EQ(averaged.last_heldout_accuracy, three.model.metadata().heldout_accuracy);
  EXPECT_EQ(three.averaged_iterations, 0);
}

TEST(WeightAveraging, OneIterationIsTheLastWeightsAndALongerWindowThanTheRunIsRefused) {
  const TrainResult last = train(tinyRun(2, 0)), one = train(tinyRun(2, 1));
  EXPECT_EQ(flatWeights(last.model), flatWeights(one.model));
  try {
    train(tinyRun(2, 3));
    FAIL() << "a window of 3 iterations in a run of 2 was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("iterations averaged"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace quadfdi
