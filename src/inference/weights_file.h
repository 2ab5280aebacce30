// The weights file (.qfdw): a plain, versioned, documented container for a trained identifier
// that needs no unpickler — magic, version, JSON metadata with a tensor directory, raw
// little-endian float32 blocks, CRC-32. Layout: docs/weights-format.md. Bytes in and out only:
// the caller reads and writes the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "inference/network_weights.h"

namespace quadfdi {

inline constexpr char kWeightsMagic[8] = {'Q', 'F', 'D', 'I', 'W', 'G', 'T', '\0'};
inline constexpr std::uint32_t kWeightsVersion = 1;

struct TrainedModel {
  ModelMetadata metadata;
  NetworkWeights weights;
  // The CRC-32 its weights file ends with (checked on decoding): the file's identity, which a
  // calibration records so that it is not run with another network. 0 for a model not read from a file.
  std::uint32_t file_crc32 = 0;
};

// Serialises; throws std::invalid_argument if the weights do not match the metadata's architecture.
std::string encodeWeightsFile(const ModelMetadata& metadata, const NetworkWeights& weights);

// Parses and checks everything (magic, version, CRC, metadata, every tensor's name, shape and
// finiteness against the architecture). Throws ModelError("WHERE: problem"), never crashes, and
// never allocates more than the input's size implies.
TrainedModel decodeWeightsFile(const std::uint8_t* data, std::size_t size, const std::string& where);

// True if the bytes start like a weights file (for a clear message on an old LibTorch .qfdi).
bool looksLikeWeightsFile(const std::uint8_t* data, std::size_t size);

// The network's weights with the metadata's shapes, for tests and the converter: checks that
// `weights` matches `metadata` (same rules as decoding). Throws ModelError.
void checkWeightsMatch(const ModelMetadata& metadata, const NetworkWeights& weights, const std::string& where);

std::uint32_t crc32(const std::uint8_t* data, std::size_t size);  // IEEE 802.3, as zip and PNG use

}  // namespace quadfdi
