#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <fstream>
#include <sstream>

#include "inference/engine.h"
#include "networks/model.h"
#include "networks/trainer.h"
#include "scratch_path.h"
#include "wavy_windows.h"
#include "networks/tiny_training.h"

namespace quadfdi {
namespace {

// Per process: two builds' suites (test, asan) may run at once.
std::string temp(const std::string& name) {
  return quadfdi::test::scratchPath("nn", name);
}

// A tiny but real Algorithm 1 run (tiny_training.h), hidden 16, minibatches of 32 windows.
TrainConfig tinyConfig(Architecture arch = Architecture::kLstm, FeatureSet features = FeatureSet::kModelFree) {
  TrainConfig c = test::tinyTraining();
  c.model.architecture = arch;
  c.model.features = features;
  c.model.hidden = 16;
  c.batch_size = 32;
  return c;
}

TEST(Training, ReducesTheLossOnAFixedSeed) {
  for (Architecture arch : {Architecture::kLstm, Architecture::kMlp}) {
    std::vector<IterationReport> reports;
    const TrainResult r = train(tinyConfig(arch), [&](const IterationReport& it) { reports.push_back(it); });
    ASSERT_EQ(reports.size(), 6u);
    EXPECT_LT(reports.back().loss, 0.7 * reports.front().loss) << toString(arch);
    EXPECT_LT(reports.back().heldout_loss, reports.front().heldout_loss) << toString(arch);
    EXPECT_EQ(r.model.metadata().iterations, 6);
    EXPECT_EQ(r.model.metadata().feature_mean.size(), 10u);
  }
}

std::vector<float> someWindows(const ModelMetadata& m, int count, double offset = 0.0) {
  RolloutConfig rc;
  rc.window = m.window;
  rc.seed = 9;
  TrajectoryBatch b;
  RolloutEngine(rc).run(algorithm1Jobs(0, 2, {0.0, 1.0}, {2}), 1, b);
  // Positions on a 2⁻¹⁶ m grid, so that adding a whole offset below 128 m is exact in float32:
  // then any difference in the output would come from the network, not from storage rounding.
  for (int i = 0; i < b.count; ++i)
    for (int k = 0; k < b.samples; ++k)
      for (int c = 0; c < 3; ++c) {
        float& p = b.outputs[b.sampleOffset(i, k) * kOutputDim + static_cast<std::size_t>(c)];
        p = std::ldexp(std::round(std::ldexp(p, 16)), -16) + static_cast<float>(offset);
      }
  std::vector<WindowRef> refs;
  enumerateWindows(b, m.window, refs);
  const std::size_t per = static_cast<std::size_t>(m.window * m.channels());
  std::vector<float> out(static_cast<std::size_t>(count) * per);
  for (int i = 0; i < count; ++i)
    gatherWindowFeatures(b, refs[static_cast<std::size_t>(i) % refs.size()], m.window, m.features, m.output, nullptr,
                         &out[static_cast<std::size_t>(i) * per]);
  return out;
}

TEST(ModelFile, SaveLoadGivesIdenticalOutputsAndMetadata) {
  for (Architecture arch : {Architecture::kLstm, Architecture::kMlp}) {
    ModelMetadata m;
    m.architecture = arch;
    m.features = FeatureSet::kModelBased;
    m.window = 10;
    m.hidden = 16;
    m.feature_mean.assign(16, 0.1f);
    m.feature_std.assign(16, 2.0f);
    m.heldout_accuracy = 0.75;
    m.command = "quadfdi train --test";
    const FaultIdentifier model = FaultIdentifier::create(m, 3);
    const std::string path = temp(std::string("model_") + toString(arch) + ".qfdi");
    model.save(path);
    const FaultIdentifier back = FaultIdentifier::load(path);
    EXPECT_EQ(back.metadata().architecture, arch);
    EXPECT_EQ(back.metadata().features, FeatureSet::kModelBased);
    EXPECT_EQ(back.metadata().command, "quadfdi train --test");
    EXPECT_EQ(back.metadata().heldout_accuracy, 0.75);
    const std::vector<float> w = someWindows(m, 7);
    std::vector<float> a(28), b(28);
    model.predict(w.data(), 7, a.data());
    back.predict(w.data(), 7, b.data());
    EXPECT_EQ(a, b);
    for (float t : a) EXPECT_TRUE(t > 0.0f && t < 1.0f);
  }
}

using test::wavyWindows;

// The LibTorch-free engine agrees with LibTorch to float round-off, and — unlike LibTorch, whose
// GEMM changes its summation order with the batch size — gives a window the same bits alone or
// in any batch, which the detector's file and stream modes rely on.
TEST(InferenceEngine, MatchesLibTorchAndIsIndependentOfTheBatch) {
  int kernels_run = 0;
  for (const char* kernel : {"generic", "avx2", "avx512"}) {
    setenv("QUADFDI_KERNEL", kernel, 1);
    for (Architecture arch : {Architecture::kLstm, Architecture::kMlp, Architecture::kTcn}) {
      ModelMetadata m;
      m.architecture = arch;
      if (arch == Architecture::kTcn) m.features = FeatureSet::kModelFreeHeading;
      m.window = 100;
      m.hidden = 128;
      m.feature_mean.assign(10, 0.05f);
      m.feature_std.assign(10, 1.5f);
      const FaultIdentifier model = FaultIdentifier::create(m, 4);
      std::unique_ptr<InferenceEngine> engine;
      try {
        engine = std::make_unique<InferenceEngine>(exportWeights(model));
      } catch (const std::invalid_argument&) {
        break;  // this CPU lacks the instruction set
      }
      EXPECT_STREQ(engine->kernel(), kernel);
      const int n = 2 * engine->lanes() + 3;
      const std::vector<float> w = wavyWindows(m, n);
      std::vector<float> reference(4 * n), batched(4 * n), single(4 * n);
      model.predict(w.data(), n, reference.data());
      engine->predict(w.data(), n, batched.data());
      const std::size_t per = static_cast<std::size_t>(m.window * m.channels());
      for (int first = 0; first < n; first += 3)
        engine->predict(w.data() + per * static_cast<std::size_t>(first), std::min(3, n - first), single.data() + 4 * first);
      EXPECT_EQ(batched, single) << kernel << " " << toString(arch);
      float worst = 0.0f;
      for (int i = 0; i < 4 * n; ++i) worst = std::max(worst, std::abs(batched[i] - reference[i]));
      EXPECT_LT(worst, 2e-6f) << kernel << " " << toString(arch);
      if (arch == Architecture::kTcn) ++kernels_run;
    }
  }
  unsetenv("QUADFDI_KERNEL");
  EXPECT_GE(kernels_run, 1);
  setenv("QUADFDI_KERNEL", "sse9", 1);
  ModelMetadata m;
  EXPECT_THROW(InferenceEngine{exportWeights(FaultIdentifier::create(m, 1))}, std::invalid_argument);
  unsetenv("QUADFDI_KERNEL");
}

TEST(InferenceEngine, MatchesATrainedNetwork) {
  const TrainResult r = train(tinyConfig());
  const std::vector<float> w = wavyWindows(r.model.metadata(), 11);
  std::vector<float> reference(44), fast(44);
  r.model.predict(w.data(), 11, reference.data());
  InferenceEngine engine(exportWeights(r.model));
  engine.predict(w.data(), 11, fast.data());
  for (int i = 0; i < 44; ++i) EXPECT_NEAR(fast[i], reference[i], 2e-6f);
}

// A diverging run stops with a message rather than saving a NaN network (issue 7).
TEST(Training, StopsWithAClearMessageOnANonFiniteLoss) {
  TrainConfig c = tinyConfig();
  c.learning_rate = 1e30;  // finite, accepted, and enough to overflow the weights
  c.max_iterations = c.min_iterations = 2;
  try {
    train(c);
    FAIL() << "training with a 1e30 learning rate did not diverge";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("training diverged: non-finite loss"), std::string::npos) << e.what();
  }
  c.learning_rate = std::numeric_limits<double>::infinity();
  EXPECT_NE(validate(c).find("bad optimiser settings"), std::string::npos);
}

TEST(InferenceEngine, RefusesInconsistentWeights) {
  ModelMetadata m;
  m.window = 10;
  m.hidden = 16;
  NetworkWeights w = exportWeights(FaultIdentifier::create(m, 1));
  w.head.pop_back();
  EXPECT_THROW(InferenceEngine{w}, std::invalid_argument);
  w = exportWeights(FaultIdentifier::create(m, 1));
  w.gates.bias.pop_back();
  EXPECT_THROW(InferenceEngine{w}, std::invalid_argument);
}

TEST(ModelFile, OutputIsInvariantToAConstantPositionOffset) {
  const TrainResult r = train(tinyConfig());
  const ModelMetadata& m = r.model.metadata();
  const std::vector<float> here = someWindows(m, 20), there = someWindows(m, 20, 37.0);
  EXPECT_EQ(here, there);  // features are relative to the window's first position
  std::vector<float> a(80), b(80);
  r.model.predict(here.data(), 20, a.data());
  r.model.predict(there.data(), 20, b.data());
  EXPECT_EQ(a, b);
}

TEST(ModelFile, RefusesWrongTruncatedAndForeignFiles) {
  ModelMetadata m;
  m.window = 10;
  m.hidden = 16;
  const std::string good = temp("good.qfdi");
  FaultIdentifier::create(m, 1).save(good);
  std::ifstream in(good, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string bytes = ss.str();
  auto errorOf = [](const std::string& path) {
    try {
      FaultIdentifier::load(path);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  auto write = [](const std::string& path, const std::string& data) {
    std::ofstream(path, std::ios::binary) << data;
    return path;
  };
  EXPECT_EQ(errorOf(temp("none.qfdi")), temp("none.qfdi") + ": cannot open for reading");
  EXPECT_EQ(errorOf("/dev/zero"), "/dev/zero: is not a regular file, not a model file");  // not one endless line
  EXPECT_EQ(errorOf(::testing::TempDir()), ::testing::TempDir() + ": is a folder, not a model file");
  EXPECT_EQ(errorOf(write(temp("empty.qfdi"), "")), temp("empty.qfdi") + ": empty file, not a quadfdi model");
  EXPECT_EQ(errorOf(write(temp("csv.qfdi"), "t,x,y\n")), temp("csv.qfdi") + ": not a quadfdi model file (bad first line)");
  EXPECT_EQ(errorOf(write(temp("v9.qfdi"), "quadfdi-model 9\n{}\n")),
            temp("v9.qfdi") + ": model format '9' is not supported (expected 1)");
  for (std::size_t cut : {bytes.size() / 2, bytes.size() - 10, bytes.find('\n') + 40}) {
    const std::string path = write(temp("cut.qfdi"), bytes.substr(0, cut));
    const std::string e = errorOf(path);
    EXPECT_EQ(e.rfind(path + ":", 0), 0u) << e;
  }
  std::string wrong_arch = bytes;
  wrong_arch.replace(wrong_arch.find("\"lstm\""), 6, "\"mlp\" ");
  EXPECT_NE(errorOf(write(temp("arch.qfdi"), wrong_arch)).find("do not match the architecture"), std::string::npos);
}

TEST(Training, ResumeContinuesFromTheCheckpoint) {
  TrainConfig c = tinyConfig();
  c.checkpoint_path = temp("resume.ckpt");
  c.log_path = temp("resume.csv");
  std::remove(c.checkpoint_path.c_str());
  // An "interrupted" run: 3 of 6 iterations.
  TrainConfig first = c;
  first.max_iterations = 3;
  first.min_iterations = 3;
  train(first);
  // Resume to 6 and compare with an uninterrupted run to 6.
  c.resume = true;
  const TrainResult resumed = train(c);
  EXPECT_TRUE(resumed.resumed);
  EXPECT_EQ(resumed.model.metadata().iterations, 6);
  TrainConfig straight = tinyConfig();
  const TrainResult full = train(straight);
  const std::vector<float> w = someWindows(full.model.metadata(), 10);
  std::vector<float> a(40), b(40);
  resumed.model.predict(w.data(), 10, a.data());
  full.model.predict(w.data(), 10, b.data());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-4f);
  // The log holds one row per iteration, 1 … 6.
  std::ifstream log(c.log_path);
  std::string line;
  int rows = 0;
  std::getline(log, line);
  while (std::getline(log, line)) EXPECT_EQ(std::atoi(line.c_str()), ++rows);
  EXPECT_EQ(rows, 6);
}

TEST(Training, RejectsBadSettingsAndMissingCuda) {
  TrainConfig c = tinyConfig();
  c.batch_size = 0;
  EXPECT_THROW(train(c), std::runtime_error);
  c = tinyConfig();
  c.model.window = 20;
  EXPECT_THROW(train(c), std::runtime_error);
  if (!cudaAvailable()) {
    c = tinyConfig();
    c.device = "cuda";
    try {
      train(c);
      FAIL();
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("no CUDA device"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace quadfdi
