// LibTorch model archives (training checkpoints and format-1 models; networks/model.h,
// docs/model-format.md): any bytes give a model that runs, or
// one ModelError naming the file. An accepted model must export to the inference engine
// (`quadfdi detect`) and predict through LibTorch (`quadfdi evaluate`) without complaint.
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_support.h"
#include "inference/engine.h"
#include "networks/model.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  configureCpu(1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = fuzz::writeTempFile(data, size, ".qfdi");
  try {
    const FaultIdentifier model = FaultIdentifier::load(path);
    const ModelMetadata& m = model.metadata();
    const std::size_t per_window = static_cast<std::size_t>(m.window) * static_cast<std::size_t>(m.channels());
    const std::vector<float> window(per_window, 0.5f);
    float theta[4];
    model.predict(window.data(), 1, theta);
    InferenceEngine engine(exportWeights(model));  // throws std::invalid_argument: not caught, a finding
    QUADFDI_FUZZ_CHECK(engine.window() == m.window && engine.channels() == m.channels());
    engine.predict(window.data(), 1, theta);
  } catch (const ModelError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind(path, 0) == 0);
  }
  return 0;
}
