#include "io/model_file.h"

#include <stdexcept>

#include "io/atomic_file.h"
#include "io/file_bytes.h"

namespace quadfdi {

namespace {
constexpr std::uintmax_t kMaxModelBytes = std::uintmax_t{1} << 31;  // 2 GiB: far beyond any identifier
}

TrainedModel readModelFile(const std::string& path) {
  std::string bytes;
  try {
    bytes = readFileBounded(path, kMaxModelBytes, "a model file", PipeReading::kRefuse);
  } catch (const FileReadError& e) {
    throw ModelError(e.what());
  }
  return decodeWeightsFile(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), path);
}

void writeModelFile(const std::string& path, const ModelMetadata& metadata, const NetworkWeights& weights) {
  std::string bytes;
  try {
    bytes = encodeWeightsFile(metadata, weights);
  } catch (const std::exception& e) {
    throw ModelError(path + ": " + e.what());
  }
  try {
    AtomicFileWriter out(path);
    out.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.commit();
  } catch (const std::runtime_error& e) {
    throw ModelError(e.what());
  }
}

}  // namespace quadfdi
