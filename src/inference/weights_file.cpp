#include "inference/weights_file.h"

#include <array>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace quadfdi {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the weights file stores little-endian floats");

namespace {

struct TensorSpec {
  std::string name;
  std::vector<int> shape;
  std::vector<float>* data;  // where it lives in NetworkWeights
  std::size_t count() const {
    std::size_t n = 1;
    for (int d : shape) n *= static_cast<std::size_t>(d);
    return n;
  }
};

// The tensors an architecture has, in file order, bound to the fields of `w` (whose dense/conv
// shapes are set from the metadata here).
std::vector<TensorSpec> layoutOf(const ModelMetadata& m, NetworkWeights& w) {
  const int n = m.channels(), h = m.hidden, t = m.window;
  w.architecture = m.architecture;
  w.window = t;
  w.channels = n;
  w.hidden = h;
  std::vector<TensorSpec> specs{{"mean", {n}, &w.mean}, {"scale", {n}, &w.scale}};
  auto dense = [&](const std::string& name, DenseWeights& d, int in, int out) {
    d.in = in;
    d.out = out;
    specs.push_back({name + ".weight", {out, in}, &d.weight});
    specs.push_back({name + ".bias", {out}, &d.bias});
  };
  std::vector<std::pair<int, int>> head;  // (in, out) per head layer
  if (m.architecture == Architecture::kLstm) {
    dense("gates", w.gates, n + h, 4 * h);
    head = {{h, 64}, {64, 4}};
  } else if (m.architecture == Architecture::kMlp) {
    head = {{n * t, h}, {h, h}, {h, h}, {h, h}, {h, 64}, {64, 4}};
  } else {
    const TcnShape& s = m.tcn;
    w.convs.resize(s.dilations.size());
    for (std::size_t i = 0; i < s.dilations.size(); ++i) {
      ConvWeights& c = w.convs[i];
      c.in = i == 0 ? n : s.channels;
      c.out = s.channels;
      c.kernel = s.kernel;
      c.dilation = s.dilations[i];
      const std::string name = "conv." + std::to_string(i);
      specs.push_back({name + ".weight", {c.out, c.in, c.kernel}, &c.weight});
      specs.push_back({name + ".bias", {c.out}, &c.bias});
    }
    head = {{s.channels, 64}, {64, 4}};
  }
  w.head.resize(head.size());
  for (std::size_t i = 0; i < head.size(); ++i) dense("head." + std::to_string(i), w.head[i], head[i].first, head[i].second);
  return specs;
}

void putU32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}
std::uint32_t getU32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 | static_cast<std::uint32_t>(p[2]) << 16 |
         static_cast<std::uint32_t>(p[3]) << 24;
}

constexpr std::size_t kHeaderBytes = sizeof(kWeightsMagic) + 4 + 4;  // magic, version, JSON length
constexpr std::uint32_t kMaxJsonBytes = 1u << 24;                   // 16 MiB of metadata is already absurd

}  // namespace

std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) != 0 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) c = table[(c ^ data[i]) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

bool looksLikeWeightsFile(const std::uint8_t* data, std::size_t size) {
  return size >= sizeof(kWeightsMagic) && std::memcmp(data, kWeightsMagic, sizeof(kWeightsMagic)) == 0;
}

void checkWeightsMatch(const ModelMetadata& metadata, const NetworkWeights& weights, const std::string& where) {
  NetworkWeights expected;
  NetworkWeights copy = weights;
  const std::vector<TensorSpec> want = layoutOf(metadata, expected);
  const std::vector<TensorSpec> have = layoutOf(metadata, copy);  // same order, bound to the given data
  for (std::size_t i = 0; i < want.size(); ++i) {
    if (have[i].data->size() != want[i].count())
      throw ModelError(where + ": tensor '" + want[i].name + "' has " + std::to_string(have[i].data->size()) +
                       " values, the architecture needs " + std::to_string(want[i].count()));
    for (float v : *have[i].data)
      if (!std::isfinite(v)) throw ModelError(where + ": tensor '" + want[i].name + "' holds non-finite values");
  }
  if (weights.architecture != metadata.architecture || weights.convs.size() != copy.convs.size() ||
      weights.head.size() != copy.head.size())
    throw ModelError(where + ": the weights' layers do not match the metadata's architecture");
}

std::string encodeWeightsFile(const ModelMetadata& metadata, const NetworkWeights& weights) {
  checkWeightsMatch(metadata, weights, "encodeWeightsFile");
  NetworkWeights bound = weights;
  const std::vector<TensorSpec> specs = layoutOf(metadata, bound);
  nlohmann::json directory = nlohmann::json::array();
  for (const TensorSpec& s : specs) directory.push_back({{"name", s.name}, {"shape", s.shape}});
  nlohmann::json header = {{"metadata", nlohmann::json::parse(metadataToJson(metadata))}, {"tensors", directory}};
  std::string json = header.dump();
  while ((kHeaderBytes + json.size()) % 4 != 0) json.push_back(' ');  // float blocks 4-byte aligned
  std::string out(kWeightsMagic, sizeof(kWeightsMagic));
  putU32(out, kWeightsVersion);
  putU32(out, static_cast<std::uint32_t>(json.size()));
  out += json;
  for (const TensorSpec& s : specs)
    out.append(reinterpret_cast<const char*>(s.data->data()), s.data->size() * sizeof(float));
  putU32(out, crc32(reinterpret_cast<const std::uint8_t*>(out.data()), out.size()));
  return out;
}

TrainedModel decodeWeightsFile(const std::uint8_t* data, std::size_t size, const std::string& where) {
  auto fail = [&](const std::string& problem) { return ModelError(where + ": " + problem); };
  if (size == 0) throw fail("empty file, not a quadfdi weights file");
  if (!looksLikeWeightsFile(data, size)) {
    if (size >= 13 && std::memcmp(data, "quadfdi-model", 13) == 0)
      throw fail("a LibTorch model archive (format 1): convert it with 'quadfdi convert-model " + where + " OUT.qfdw'");
    throw fail("not a quadfdi weights file (bad magic at byte 0)");
  }
  if (size < kHeaderBytes + 4) throw fail("truncated (" + std::to_string(size) + " bytes, header incomplete)");
  const std::uint32_t version = getU32(data + 8);
  if (version != kWeightsVersion)
    throw fail("weights format version " + std::to_string(version) + " is not supported (this build reads " +
               std::to_string(kWeightsVersion) + ")");
  const std::uint32_t json_bytes = getU32(data + 12);
  if (json_bytes > kMaxJsonBytes || kHeaderBytes + json_bytes + 4 > size)
    throw fail("truncated or corrupt: byte 12 declares " + std::to_string(json_bytes) + " bytes of metadata in a " +
               std::to_string(size) + "-byte file");
  if (crc32(data, size - 4) != getU32(data + size - 4))
    throw fail("CRC-32 check failed at byte " + std::to_string(size - 4) + " (corrupt or truncated file)");
  const std::string json(reinterpret_cast<const char*>(data + kHeaderBytes), json_bytes);
  nlohmann::json header;
  try {
    header = nlohmann::json::parse(json);
  } catch (const nlohmann::json::exception&) {
    throw fail("byte 16: metadata is not valid JSON");
  }
  if (!header.is_object() || !header.contains("metadata") || !header.contains("tensors") || !header["tensors"].is_array())
    throw fail("byte 16: the header lacks 'metadata' or 'tensors'");
  TrainedModel model;
  model.file_crc32 = getU32(data + size - 4);
  model.metadata = metadataFromJson(header["metadata"].dump(), where);
  const std::vector<TensorSpec> specs = layoutOf(model.metadata, model.weights);
  const nlohmann::json& directory = header["tensors"];
  if (directory.size() != specs.size())
    throw fail("the file has " + std::to_string(directory.size()) + " tensors, a " + toString(model.metadata.architecture) +
               " of this shape has " + std::to_string(specs.size()));
  std::size_t at = kHeaderBytes + json_bytes;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const TensorSpec& s = specs[i];
    const nlohmann::json& d = directory[i];
    std::vector<int> shape;
    try {
      if (d.at("name").get<std::string>() != s.name) throw fail("tensor " + std::to_string(i) + " is '" + d.at("name").get<std::string>() + "', expected '" + s.name + "'");
      for (const auto& x : d.at("shape")) {
        if (!x.is_number_integer()) throw fail("tensor '" + s.name + "': shape must be integers");
        shape.push_back(static_cast<int>(x.get<std::int64_t>()));
      }
    } catch (const nlohmann::json::exception&) {
      throw fail("tensor directory entry " + std::to_string(i) + " is malformed");
    }
    if (shape != s.shape) throw fail("tensor '" + s.name + "' has the wrong shape for the metadata's architecture");
    const std::size_t bytes = s.count() * sizeof(float);
    if (bytes > size - 4 - at) throw fail("truncated: tensor '" + s.name + "' at byte " + std::to_string(at) + " runs past the end");
    s.data->resize(s.count());
    std::memcpy(s.data->data(), data + at, bytes);
    for (float v : *s.data)
      if (!std::isfinite(v)) throw fail("tensor '" + s.name + "' (byte " + std::to_string(at) + ") holds non-finite values");
    at += bytes;
  }
  if (at != size - 4) throw fail("byte " + std::to_string(at) + ": " + std::to_string(size - 4 - at) + " bytes of trailing data before the CRC");
  for (float s : model.weights.scale)
    if (!(s > 0.0f)) throw fail("tensor 'scale' must be > 0");
  return model;
}

}  // namespace quadfdi
