// HDF5 dataset files (io/hdf5_dataset.h, docs/dataset-format.md): any bytes give a validated
// TrajectoryBatch or one DatasetError naming the file. An accepted batch must be safe for its
// consumers: every window enumerateWindows lists gathers its features within bounds.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

#include "data/features.h"
#include "data/trajectory_batch.h"
#include "fuzz_support.h"
#include "io/hdf5_dataset.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = fuzz::writeTempFile(data, size, ".h5");
  try {
    DatasetMetadata meta;
    const TrajectoryBatch b = readDataset(path, &meta);
    const auto samples = static_cast<std::size_t>(b.count) * static_cast<std::size_t>(b.samples);
    QUADFDI_FUZZ_CHECK(b.outputs.size() == samples * kOutputDim && b.inputs.size() == samples * kInputDim &&
                       b.states.size() == samples * kStateDim && b.residuals.size() == samples * kOutputDim);
    std::vector<WindowRef> windows;
    enumerateWindows(b, meta.window, windows);
    const OutputKind output = meta.output == "position-rates" ? OutputKind::kPositionRates : OutputKind::kPositionEuler;
    std::vector<float> features;
    if (!windows.empty()) features.resize(static_cast<std::size_t>(meta.window) * featureChannels(FeatureSet::kModelBased));
    for (std::size_t i = 0; i < windows.size() && i < 64; ++i) {
      QUADFDI_FUZZ_CHECK(windows[i].trajectory >= 0 && windows[i].trajectory < b.count);
      QUADFDI_FUZZ_CHECK(windows[i].end_sample >= meta.window - 1 && windows[i].end_sample < b.samples);
      gatherWindowFeatures(b, windows[i], meta.window, FeatureSet::kModelBased, output, nullptr, features.data());
      (void)windowLabel(b, windows[i]);
    }
  } catch (const DatasetError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind(path, 0) == 0);
  }
  // Every identifier the reader opened is closed again, on success and on every error path.
  QUADFDI_FUZZ_CHECK(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL) == 0);
  return 0;
}
