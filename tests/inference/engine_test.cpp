// The inference engine's packing: subnormal weights are packed as zero (they cost a microcode
// assist per multiply-add on x86, docs/benchmarks.md), and no output moves for it.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "inference/engine.h"
#include "inference/kernel.h"
#include "networks/model.h"
#include "wavy_windows.h"

namespace quadfdi {
namespace {

using inference::kRowBlock;

float packedWeight(const PackedDense& p, int row, int k) {
  const int blk = row / kRowBlock, i = row % kRowBlock;
  return p.w[(static_cast<std::size_t>(blk) * p.in + static_cast<std::size_t>(k)) * kRowBlock + static_cast<std::size_t>(i)];
}

TEST(Packing, SubnormalWeightsAndBiasesArePackedAsZeroAndNothingElseChanges) {
  const float subnormal = FLT_MIN / 4.0f;
  ASSERT_EQ(std::fpclassify(subnormal), FP_SUBNORMAL);
  const std::vector<float> values{subnormal, -subnormal, FLT_TRUE_MIN, FLT_MIN, -FLT_MIN, 1e-30f, 0.0f, -0.5f, 3.0f};
  DenseWeights d;
  d.in = 2;
  d.out = static_cast<int>(values.size());  // 9 rows: two blocks, the second part-filled
  for (float v : values) {
    d.weight.push_back(v);
    d.weight.push_back(-v);
    d.bias.push_back(v);
  }
  const PackedDense p = packDense(d);
  ASSERT_EQ(p.blocks, 2);
  for (int r = 0; r < d.out; ++r) {
    const float v = values[static_cast<std::size_t>(r)];
    const float expected = std::fpclassify(v) == FP_SUBNORMAL ? 0.0f : v;
    EXPECT_EQ(packedWeight(p, r, 0), expected) << "row " << r;
    EXPECT_EQ(packedWeight(p, r, 1), -expected) << "row " << r;
    EXPECT_EQ(p.b[static_cast<std::size_t>(r)], expected) << "row " << r;
  }
}

// Each weight of every layer set to a subnormal with probability 1/5, as training's weight decay
// leaves dead units' weights (models/tcn-randomised.qfdw: 206 of 19 k).
NetworkWeights withSubnormals(NetworkWeights w, bool as_zero) {
  unsigned state = 12345;
  auto touch = [&](std::vector<float>& v) {
    for (float& x : v) {
      state = state * 1664525u + 1013904223u;
      if ((state >> 16) % 5 == 0) x = as_zero ? 0.0f : (((state >> 8) & 1) ? 1.0f : -1.0f) * FLT_MIN * 0.01f * static_cast<float>(1 + (state >> 24) % 90);
    }
  };
  for (ConvWeights& c : w.convs) {
    touch(c.weight);
    touch(c.bias);
  }
  for (DenseWeights& d : w.head) {
    touch(d.weight);
    touch(d.bias);
  }
  touch(w.gates.weight);
  touch(w.gates.bias);
  return w;
}

// LibTorch computes with the subnormals as they are; the engine, which packs them as zero, agrees
// with it to float round-off and gives exactly what the same network with zeros gives.
TEST(Packing, SubnormalWeightsMoveNoOutput) {
  for (Architecture arch : {Architecture::kTcn, Architecture::kLstm}) {
    ModelMetadata m;
    m.architecture = arch;
    if (arch == Architecture::kTcn) m.features = FeatureSet::kModelFreeHeading;
    m.window = 100;
    m.hidden = 16;
    m.feature_mean.assign(static_cast<std::size_t>(m.channels()), 0.05f);
    m.feature_std.assign(static_cast<std::size_t>(m.channels()), 1.5f);
    const NetworkWeights exported = exportWeights(FaultIdentifier::create(m, 3));
    const NetworkWeights subnormal = withSubnormals(exported, false), zeroed = withSubnormals(exported, true);
    const FaultIdentifier reference = importWeights(m, subnormal);
    const int n = 7;
    const std::vector<float> windows = test::wavyWindows(m, n);
    std::vector<float> exact(4 * n), with_subnormals(4 * n), with_zeros(4 * n);
    reference.predict(windows.data(), n, exact.data());
    InferenceEngine(subnormal).predict(windows.data(), n, with_subnormals.data());
    InferenceEngine(zeroed).predict(windows.data(), n, with_zeros.data());
    EXPECT_EQ(with_subnormals, with_zeros) << toString(arch);
    for (int i = 0; i < 4 * n; ++i) EXPECT_NEAR(with_subnormals[i], exact[i], 2e-6f) << toString(arch) << " output " << i;
  }
}

}  // namespace
}  // namespace quadfdi
