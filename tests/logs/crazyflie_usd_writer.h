// Test and benchmark support: writes Crazyflie micro-SD deck event logs (file format versions 1
// and 2, docs/logs/crazyflie-usd.md) from known values, so that tests can round-trip
// write → readCrazyflieUsd → the same values, types and timestamps. Header only.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace quadfdi::test {

struct UsdVariable {
  std::string name;  // "group.name" for log variables, bare for event payload fields
  char type = 'f';   // B b H h I i f e (what the firmware writes) or q Q d ? c
};

struct UsdEventType {
  std::uint16_t id = 0xFFFF;               // 0xFFFF = fixedFrequency in the firmware
  std::string name = "fixedFrequency";
  std::vector<UsdVariable> variables;
};

// An independent bitwise CRC-32 (IEEE, reflected 0xEDB88320, zlib's), to check the reader's.
inline std::uint32_t usdCrc32(const std::vector<std::uint8_t>& bytes, std::size_t size) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) {
    c ^= bytes[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

inline std::size_t usdTypeSize(char t) {
  switch (t) {
    case 'B': case 'b': case '?': case 'c': return 1;
    case 'H': case 'h': case 'e': return 2;
    case 'I': case 'i': case 'f': return 4;
    case 'q': case 'Q': case 'd': return 8;
    default: throw std::invalid_argument(std::string("usd writer: unknown type ") + t);
  }
}

// float → IEEE binary16 for values exactly representable in it (tests pick such values).
inline std::uint16_t usdFloatToHalf(double v) {
  if (v == 0.0) return std::signbit(v) ? 0x8000 : 0;
  const std::uint16_t sign = v < 0 ? 0x8000 : 0;
  int exp = 0;
  const double m = std::frexp(std::fabs(v), &exp);  // |v| = m · 2^exp, m in [0.5, 1)
  const int e = exp - 1 + 15;                       // biased exponent of 1.xxx · 2^(exp-1)
  if (e <= 0 || e >= 31) throw std::invalid_argument("usd writer: value outside normal fp16 range");
  const auto mant = static_cast<std::uint16_t>(std::lround((m * 2.0 - 1.0) * 1024.0));
  return static_cast<std::uint16_t>(sign | (e << 10) | mant);
}

// The Hamilton quaternion (w, x, y, z) of ZYX Euler angles: qz(ψ)·qy(θ)·qx(φ).
inline std::array<double, 4> usdQuaternionOfEuler(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll / 2), sr = std::sin(roll / 2), cp = std::cos(pitch / 2), sp = std::sin(pitch / 2),
               cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
  return {cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
          cr * cp * sy - sr * sp * cy};
}

// stateEstimateZ.quat: the firmware's "smallest three" encoding (quatcompress.h), written here
// from its description (docs/logs/crazyflie-usd.md): the largest component's index (x, y, z, w
// order) in the top two bits, made positive by negating the whole quaternion; each other
// component, in index order, as a sign bit over round(|q|·√2·511).
inline std::uint32_t usdCompressQuaternion(const std::array<double, 4>& wxyz) {
  const double q[4] = {wxyz[1], wxyz[2], wxyz[3], wxyz[0]};
  unsigned largest = 0;
  for (unsigned i = 1; i < 4; ++i)
    if (std::fabs(q[i]) > std::fabs(q[largest])) largest = i;
  const bool negate = q[largest] < 0;
  std::uint32_t packed = largest;
  for (unsigned i = 0; i < 4; ++i) {
    if (i == largest) continue;
    const unsigned sign = (q[i] < 0) != negate ? 1u : 0u;
    const auto magnitude = static_cast<std::uint32_t>(std::lround(511.0 * std::fabs(q[i]) * std::sqrt(2.0)));
    packed = (packed << 10) | (sign << 9) | magnitude;
  }
  return packed;
}

class UsdWriter {
 public:
  // version 1: uint32 timestamps [ms]; version 2: uint64 timestamps [µs].
  UsdWriter(int version, std::vector<UsdEventType> types) : version_(version), types_(std::move(types)) {
    put8(0xBC);
    put16(static_cast<std::uint16_t>(version_));
    put16(static_cast<std::uint16_t>(types_.size()));
    for (const UsdEventType& t : types_) {
      put16(t.id);
      putName(t.name);
      put16(static_cast<std::uint16_t>(t.variables.size()));
      for (const UsdVariable& v : t.variables) putName(v.name + "(" + v.type + ")");
    }
    header_bytes_ = bytes_.size();
  }

  std::size_t headerBytes() const { return header_bytes_; }
  std::size_t recordBytes(std::size_t type_index) const {
    std::size_t n = version_ == 1 ? 6 : 10;
    for (const UsdVariable& v : types_.at(type_index).variables) n += usdTypeSize(v.type);
    return n;
  }

  // One record of event type `type_index`; `timestamp` in the version's unit (ms or µs).
  void record(std::size_t type_index, std::uint64_t timestamp, const std::vector<double>& values) {
    const UsdEventType& t = types_.at(type_index);
    if (values.size() != t.variables.size()) throw std::invalid_argument("usd writer: value count");
    put16(t.id);
    if (version_ == 1) put32(static_cast<std::uint32_t>(timestamp));
    else put64(timestamp);
    for (std::size_t i = 0; i < values.size(); ++i) putValue(t.variables[i].type, values[i]);
  }

  // The bytes written so far (no CRC: a log that was never closed).
  const std::vector<std::uint8_t>& unclosed() const { return bytes_; }

  // The whole file as the deck closes it: records, then the CRC-32 of everything before it.
  std::vector<std::uint8_t> closed() const {
    std::vector<std::uint8_t> out = bytes_;
    const std::uint32_t crc = usdCrc32(out, out.size());
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<std::uint8_t>(crc >> (8 * k)));
    return out;
  }

 private:
  void put8(std::uint8_t v) { bytes_.push_back(v); }
  void put16(std::uint16_t v) { put8(static_cast<std::uint8_t>(v)); put8(static_cast<std::uint8_t>(v >> 8)); }
  void put32(std::uint32_t v) { put16(static_cast<std::uint16_t>(v)); put16(static_cast<std::uint16_t>(v >> 16)); }
  void put64(std::uint64_t v) { put32(static_cast<std::uint32_t>(v)); put32(static_cast<std::uint32_t>(v >> 32)); }
  void putName(const std::string& s) {
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    put8(0);
  }
  void putValue(char type, double v) {
    switch (type) {
      case 'B': case '?': case 'c': put8(static_cast<std::uint8_t>(v)); break;
      case 'b': put8(static_cast<std::uint8_t>(static_cast<std::int8_t>(v))); break;
      case 'H': put16(static_cast<std::uint16_t>(v)); break;
      case 'h': put16(static_cast<std::uint16_t>(static_cast<std::int16_t>(v))); break;
      case 'I': put32(static_cast<std::uint32_t>(v)); break;
      case 'i': put32(static_cast<std::uint32_t>(static_cast<std::int32_t>(v))); break;
      case 'e': put16(usdFloatToHalf(v)); break;
      case 'f': {
        const auto f = static_cast<float>(v);
        std::uint32_t bits = 0;
        std::memcpy(&bits, &f, sizeof bits);
        put32(bits);
        break;
      }
      case 'q': put64(static_cast<std::uint64_t>(static_cast<std::int64_t>(v))); break;
      case 'Q': put64(static_cast<std::uint64_t>(v)); break;
      case 'd': {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &v, sizeof bits);
        put64(bits);
        break;
      }
      default: throw std::invalid_argument(std::string("usd writer: unknown type ") + type);
    }
  }

  int version_;
  std::vector<UsdEventType> types_;
  std::vector<std::uint8_t> bytes_;
  std::size_t header_bytes_ = 0;
};

}  // namespace quadfdi::test
