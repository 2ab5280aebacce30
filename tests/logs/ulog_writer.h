// A small PX4 ULog writer for tests, benchmarks and fuzz seeds (header only): builds a log in
// memory message by message, following the PX4 docs "ULog File Format". It writes what it is
// told — including broken logs on purpose (raw messages, cut buffers) — and checks nothing.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace quadfdi::testing {

// The bytes of one 'D' message's data, field after field in format order (little endian).
class UlogPayload {
 public:
  template <class T>
  UlogPayload& put(T value) {
    const std::size_t at = bytes_.size();
    bytes_.resize(at + sizeof value);
    std::memcpy(bytes_.data() + at, &value, sizeof value);
    return *this;
  }
  UlogPayload& pad(std::size_t n) {
    bytes_.resize(bytes_.size() + n, 0);
    return *this;
  }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

class UlogWriter {
 public:
  // Header: magic, version, timestamp [µs].
  explicit UlogWriter(std::uint8_t version = 1, std::uint64_t start_us = 0) {
    const std::uint8_t magic[7] = {0x55, 0x4c, 0x6f, 0x67, 0x01, 0x12, 0x35};
    bytes_.assign(magic, magic + 7);
    bytes_.push_back(version);
    putLe(start_us);
  }

  // 'B': must come right after the header.
  UlogWriter& flagBits(std::uint8_t compat0 = 0, std::uint8_t incompat0 = 0, std::uint64_t appended0 = 0,
                       std::uint64_t appended1 = 0, std::uint64_t appended2 = 0) {
    std::vector<std::uint8_t> b(40, 0);
    b[0] = compat0;
    b[8] = incompat0;
    std::memcpy(b.data() + 16, &appended0, 8);
    std::memcpy(b.data() + 24, &appended1, 8);
    std::memcpy(b.data() + 32, &appended2, 8);
    return message('B', b);
  }
  // 'F': "name:type field;…".
  UlogWriter& format(const std::string& text) { return message('F', text); }
  // 'I' with a string value: key "char[len] name".
  UlogWriter& info(const std::string& name, const std::string& value) {
    return keyed('I', {}, "char[" + std::to_string(value.size()) + "] " + name, value);
  }
  // 'I' with a uint32_t / int32_t value.
  UlogWriter& infoUInt32(const std::string& name, std::uint32_t value) { return keyed('I', {}, "uint32_t " + name, raw(value)); }
  // 'M': multi information, continued parts set is_continued.
  UlogWriter& multiInfo(const std::string& name, const std::string& value, bool continued) {
    return keyed('M', {static_cast<std::uint8_t>(continued ? 1 : 0)}, "char[" + std::to_string(value.size()) + "] " + name, value);
  }
  // 'P' (definitions or data section).
  UlogWriter& paramFloat(const std::string& name, float value) { return keyed('P', {}, "float " + name, raw(value)); }
  UlogWriter& paramInt(const std::string& name, std::int32_t value) { return keyed('P', {}, "int32_t " + name, raw(value)); }
  // 'Q': default_types bit 0 system-wide, bit 1 configuration.
  UlogWriter& defaultParamFloat(std::uint8_t default_types, const std::string& name, float value) {
    return keyed('Q', {default_types}, "float " + name, raw(value));
  }
  UlogWriter& defaultParamInt(std::uint8_t default_types, const std::string& name, std::int32_t value) {
    return keyed('Q', {default_types}, "int32_t " + name, raw(value));
  }
  // 'A'.
  UlogWriter& subscribe(std::uint8_t multi_id, std::uint16_t msg_id, const std::string& name) {
    std::vector<std::uint8_t> b{multi_id};
    append(b, raw(msg_id));
    append(b, name);
    return message('A', b);
  }
  // 'R'.
  UlogWriter& unsubscribe(std::uint16_t msg_id) { return message('R', raw(msg_id)); }
  // 'D'.
  UlogWriter& data(std::uint16_t msg_id, const UlogPayload& payload) {
    std::vector<std::uint8_t> b = raw(msg_id);
    append(b, payload.bytes());
    return message('D', b);
  }
  // 'L': level '0'..'7' as PX4 writes it (ASCII).
  UlogWriter& logging(char level, std::uint64_t timestamp_us, const std::string& text) {
    std::vector<std::uint8_t> b{static_cast<std::uint8_t>(level)};
    append(b, raw(timestamp_us));
    append(b, text);
    return message('L', b);
  }
  // 'C'.
  UlogWriter& taggedLogging(char level, std::uint16_t tag, std::uint64_t timestamp_us, const std::string& text) {
    std::vector<std::uint8_t> b{static_cast<std::uint8_t>(level)};
    append(b, raw(tag));
    append(b, raw(timestamp_us));
    append(b, text);
    return message('C', b);
  }
  // 'S'.
  UlogWriter& sync() { return message('S', std::vector<std::uint8_t>{0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12}); }
  // 'O': dropout of `duration_ms`.
  UlogWriter& dropout(std::uint16_t duration_ms) { return message('O', raw(duration_ms)); }

  // Any message, for unknown types and broken ones.
  UlogWriter& message(char type, const std::vector<std::uint8_t>& body) {
    putLe(static_cast<std::uint16_t>(body.size()));
    bytes_.push_back(static_cast<std::uint8_t>(type));
    append(bytes_, body);
    return *this;
  }
  UlogWriter& message(char type, const std::string& body) {
    return message(type, std::vector<std::uint8_t>(body.begin(), body.end()));
  }

  // An info or parameter message: the head (flag byte, if any), key length, key, value bytes.
  UlogWriter& keyed(char type, std::vector<std::uint8_t> head, const std::string& key, const std::vector<std::uint8_t>& value) {
    head.push_back(static_cast<std::uint8_t>(key.size()));
    append(head, key);
    append(head, value);
    return message(type, head);
  }
  UlogWriter& keyed(char type, std::vector<std::uint8_t> head, const std::string& key, const std::string& value) {
    return keyed(type, std::move(head), key, std::vector<std::uint8_t>(value.begin(), value.end()));
  }

  std::size_t size() const { return bytes_.size(); }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }
  std::vector<std::uint8_t>& mutableBytes() { return bytes_; }
  void reserve(std::size_t n) { bytes_.reserve(n); }

 private:
  template <class T>
  static std::vector<std::uint8_t> raw(T value) {
    std::vector<std::uint8_t> b(sizeof value);
    std::memcpy(b.data(), &value, sizeof value);
    return b;
  }
  template <class T>
  void putLe(T value) {
    append(bytes_, raw(value));
  }
  static void append(std::vector<std::uint8_t>& to, const std::vector<std::uint8_t>& from) {
    to.insert(to.end(), from.begin(), from.end());
  }
  static void append(std::vector<std::uint8_t>& to, const std::string& from) { to.insert(to.end(), from.begin(), from.end()); }

  std::vector<std::uint8_t> bytes_;
};

// PX4's vehicle_local_position and vehicle_attitude formats as the tests write them: with
// `with_resets`, EKF2's validity flags, reset shifts and counters (PX4 ≥ 1.10) — x, y, z,
// delta_xy[2], delta_z, xy_valid, z_valid, xy_reset_counter, z_reset_counter and q[4],
// delta_q_reset[4], quat_reset_counter; else x, y, z, xy_valid (+3 padding bytes) and q[4].
inline void formatPx4Estimates(UlogWriter& w, bool with_resets) {
  if (with_resets) {
    w.format("vehicle_local_position:uint64_t timestamp;float x;float y;float z;float[2] delta_xy;float delta_z;"
             "bool xy_valid;bool z_valid;uint8_t xy_reset_counter;uint8_t z_reset_counter;");
    w.format("vehicle_attitude:uint64_t timestamp;float[4] q;float[4] delta_q_reset;uint8_t quat_reset_counter;");
  } else {
    w.format("vehicle_local_position:uint64_t timestamp;float x;float y;float z;bool xy_valid;uint8_t[3] _padding0;");
    w.format("vehicle_attitude:uint64_t timestamp;float[4] q;");
  }
}

}  // namespace quadfdi::testing
