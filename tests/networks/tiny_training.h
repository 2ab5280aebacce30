// The tiny but real Algorithm 1 runs the network tests train: T = 10, 4 initial conditions × Θ ∈
// {0, 0.5, 1} (12 trajectories an iteration), 2 held-out initial conditions, one thread, seed 5.
#pragma once

#include "networks/trainer.h"

namespace quadfdi::test {

// What every tiny run shares; the architecture and minibatching are the caller's.
inline TrainConfig tinyTraining(int iterations = 6) {
  TrainConfig c;
  c.data.rollout.window = 10;
  c.data.rollout.seed = 3;
  c.data.scale = {"unit", 4, 2000};
  c.data.thetas = {0.0, 0.5, 1.0};
  c.data.threads = 1;
  c.model.window = 10;
  c.passes = 2;
  c.min_iterations = iterations;
  c.max_iterations = iterations;
  c.heldout_initial_conditions = 2;
  c.learning_rate = 5e-3;
  c.threads = 1;
  c.seed = 5;
  return c;
}

// Dense training of a two-layer TCN (16 channels, dilations 1 and 2: receptive field 7),
// 8 trajectories a minibatch.
inline TrainConfig tinyDenseTcn(FeatureSet features, int iterations = 6) {
  TrainConfig c = tinyTraining(iterations);
  c.model.architecture = Architecture::kTcn;
  c.model.features = features;
  c.model.tcn.channels = 16;
  c.model.tcn.dilations = {1, 2};
  c.mode = TrainingMode::kSequences;
  c.batch_trajectories = 8;
  return c;
}

}  // namespace quadfdi::test
