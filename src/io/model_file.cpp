#include "io/model_file.h"

#include <fstream>
#include <iterator>
#include <stdexcept>

#include "io/atomic_file.h"

namespace quadfdi {

namespace {
constexpr std::streamoff kMaxModelBytes = std::streamoff{1} << 31;  // 2 GiB: far beyond any identifier
}

TrainedModel readModelFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(path + ": cannot open for reading");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw ModelError(path + ": cannot read");
  if (size > kMaxModelBytes) throw ModelError(path + ": " + std::to_string(size) + " bytes is too large for a model file");
  in.seekg(0);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), size);
  if (in.gcount() != size) throw ModelError(path + ": read failed");
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
