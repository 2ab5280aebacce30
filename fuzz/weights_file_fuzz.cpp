// Weights files (inference/weights_file.h, docs/weights-format.md) — what `quadfdi detect` and
// `evaluate` load: any bytes give a model that runs through the estimation core, or one
// ModelError naming the file. No LibTorch anywhere on this path.
#include <cstdint>
#include <string>
#include <vector>

#include "estimation/motor_estimator.h"
#include "fuzz_support.h"
#include "inference/weights_file.h"

using namespace quadfdi;

namespace {

void decodeAndRun(const std::uint8_t* data, std::size_t size) {
  try {
    const TrainedModel model = decodeWeightsFile(data, size, "fuzz.qfdw");
    const ModelMetadata& m = model.metadata;
    // An accepted file is a network the engine runs: anything it refuses is a finding.
    if (m.features == FeatureSet::kModelBased || m.features == FeatureSet::kResidualOnly) return;
    if (static_cast<long>(m.window) * m.channels() * (m.architecture == Architecture::kMlp ? m.hidden : 1) > 4000000) return;
    MotorEstimator estimator(model, m.symmetry);
    const std::vector<float> outputs(static_cast<std::size_t>(m.window) * kOutputDim, 0.25f);
    const std::vector<float> inputs(static_cast<std::size_t>(m.window) * kInputDim, 0.07f);
    const std::vector<float> rates(static_cast<std::size_t>(m.window) * kRateDim, 0.1f);  // read by scale-free-rates models
    std::vector<float> features(kMotors * estimator.featuresPerWindow());
    estimator.gather(outputs.data(), inputs.data(), nullptr, rates.data(), features.data());
    MotorTheta theta{};
    estimator.estimate(features.data(), 1, &theta);
    for (float t : theta) QUADFDI_FUZZ_CHECK(t >= 0.0f && t <= 1.0f);
  } catch (const ModelError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz.qfdw", 0) == 0);
  } catch (const std::invalid_argument& e) {  // trained motor ≠ 2: refused by the estimation core
    fuzz::report(e);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  decodeAndRun(data, size);
  // The same bytes with a correct CRC, so that mutations also reach the JSON and the tensors
  // (a random change almost never keeps the CRC right).
  if (size >= 20) {
    std::vector<std::uint8_t> fixed(data, data + size);
    const std::uint32_t crc = crc32(fixed.data(), size - 4);
    for (int i = 0; i < 4; ++i) fixed[size - 4 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(crc >> (8 * i));
    decodeAndRun(fixed.data(), fixed.size());
  }
  return 0;
}
