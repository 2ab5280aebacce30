// Crazyflie micro-SD deck event logs; the format and the policies: docs/logs/crazyflie-usd.md.
#include "logs/crazyflie_usd.h"

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace quadfdi {
namespace {

constexpr std::uint8_t kMagic = 0xBC;          // usddeck.c: first byte of every log
constexpr std::size_t kHeaderFixedBytes = 5;   // magic (1) + version (2) + event type count (2)
constexpr std::size_t kCrcBytes = 4;           // trailing CRC-32, written when logging stops

// The CRC-32 table (reflected polynomial 0xEDB88320), built at compile time.
constexpr std::array<std::uint32_t, 256> makeCrcTable() {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? (0xEDB88320u ^ (c >> 1)) : (c >> 1);
    t[i] = c;
  }
  return t;
}
constexpr std::array<std::uint32_t, 256> kCrcTable = makeCrcTable();

std::uint16_t readU16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t readU32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
std::uint64_t readU64(const std::uint8_t* p) {
  return static_cast<std::uint64_t>(readU32(p)) | (static_cast<std::uint64_t>(readU32(p + 4)) << 32);
}

// IEEE 754 binary16 → double (exact).
double halfToDouble(std::uint16_t h) {
  const int sign = (h & 0x8000) ? -1 : 1;
  const int exponent = (h >> 10) & 0x1F;
  const int mantissa = h & 0x3FF;
  if (exponent == 0) return sign * std::ldexp(static_cast<double>(mantissa), -24);
  if (exponent == 31)
    return mantissa == 0 ? sign * std::numeric_limits<double>::infinity()
                         : std::numeric_limits<double>::quiet_NaN();
  return sign * std::ldexp(static_cast<double>(mantissa + 1024), exponent - 25);
}

// A variable's type character (Python struct format characters; usddeck.c writes B b H h I i f,
// and e (fp16) for event payloads) → quadfdi type and size in bytes. False if unknown.
bool typeOf(char c, FieldType& type, std::size_t& size) {
  switch (c) {
    case 'B': type = FieldType::kUInt8; size = 1; return true;
    case 'b': type = FieldType::kInt8; size = 1; return true;
    case 'H': type = FieldType::kUInt16; size = 2; return true;
    case 'h': type = FieldType::kInt16; size = 2; return true;
    case 'I': type = FieldType::kUInt32; size = 4; return true;
    case 'i': type = FieldType::kInt32; size = 4; return true;
    case 'f': type = FieldType::kFloat; size = 4; return true;
    case 'e': type = FieldType::kFloat; size = 2; return true;  // half precision, stored as float
    case 'q': type = FieldType::kInt64; size = 8; return true;
    case 'Q': type = FieldType::kUInt64; size = 8; return true;
    case 'd': type = FieldType::kDouble; size = 8; return true;
    case '?': type = FieldType::kBool; size = 1; return true;
    case 'c': type = FieldType::kChar; size = 1; return true;
    default: return false;
  }
}

struct Variable {
  char code = 'f';    // type character
  std::size_t size = 0;  // [bytes]
};

struct EventType {
  std::uint16_t id = 0;
  std::size_t topic = 0;           // index in DecodedLog::topics
  std::vector<Variable> vars;
  std::size_t payload_bytes = 0;   // [bytes] sum of the variables' sizes
};

double decodeValue(const Variable& v, const std::uint8_t* p) {
  switch (v.code) {
    case 'B': return p[0];
    case 'b': return static_cast<std::int8_t>(p[0]);
    case '?': return p[0] != 0 ? 1.0 : 0.0;
    case 'c': return p[0];
    case 'H': return readU16(p);
    case 'h': return static_cast<std::int16_t>(readU16(p));
    case 'I': return readU32(p);
    case 'i': return static_cast<std::int32_t>(readU32(p));
    case 'e': return halfToDouble(readU16(p));
    case 'f': {
      const std::uint32_t bits = readU32(p);
      float f = 0.0f;
      std::memcpy(&f, &bits, sizeof f);
      return static_cast<double>(f);
    }
    case 'q': return static_cast<double>(static_cast<std::int64_t>(readU64(p)));
    case 'Q': return static_cast<double>(readU64(p));
    case 'd': {
      const std::uint64_t bits = readU64(p);
      double d = 0.0;
      std::memcpy(&d, &bits, sizeof d);
      return d;
    }
    default: return 0.0;
  }
}

LogIssue issue(LogStatus status, std::size_t offset, std::string topic, std::string message) {
  return LogIssue{status, offset, std::move(topic), std::move(message)};
}

std::string hex32(std::uint32_t v) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s = "0x";
  for (int shift = 28; shift >= 0; shift -= 4) s += kDigits[(v >> shift) & 0xF];
  return s;
}

// Reads a NUL-terminated name at `pos` (advanced past the NUL). `what` names it in messages.
LogIssue readName(ByteSpan b, std::size_t& pos, std::size_t max_bytes, const char* what, std::string& name) {
  const std::size_t start = pos;
  const std::size_t limit = std::min(b.size, start + max_bytes + 1);  // the name and its NUL
  const void* nul = std::memchr(b.data + start, 0, limit - start);
  if (nul == nullptr) {
    if (limit == b.size)
      return issue(LogStatus::kTruncated, b.size, "",
                   std::string("the file ends inside ") + what + " starting at byte " + std::to_string(start));
    return issue(LogStatus::kTooLarge, start, "",
                 std::string(what) + " is longer than " + std::to_string(max_bytes) + " bytes (no NUL)");
  }
  const std::size_t len = static_cast<std::size_t>(static_cast<const std::uint8_t*>(nul) - (b.data + start));
  name.assign(reinterpret_cast<const char*>(b.data + start), len);
  pos = start + len + 1;
  return {};
}

}  // namespace

std::uint32_t crc32Ieee(const std::uint8_t* data, std::size_t size) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) c = kCrcTable[(c ^ data[i]) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

bool looksLikeCrazyflieUsd(ByteSpan bytes) {
  if (bytes.data == nullptr || bytes.size < kHeaderFixedBytes || bytes.data[0] != kMagic) return false;
  const std::uint16_t version = readU16(bytes.data + 1);
  return version == 1 || version == 2;
}

LogIssue readCrazyflieUsd(ByteSpan bytes, DecodedLog& out) {
  return readCrazyflieUsd(bytes, out, CrazyflieUsdLimits{});
}

LogIssue readCrazyflieUsd(ByteSpan b, DecodedLog& out, const CrazyflieUsdLimits& limits) {
  out = DecodedLog{};
  out.format = LogFormat::kCrazyflieUsd;
  if (b.data == nullptr || b.size == 0)
    return issue(LogStatus::kTruncated, 0, "", "empty input: no Crazyflie micro-SD header");
  if (b.data[0] != kMagic)
    return issue(LogStatus::kWrongMagic, 0, "",
                 "first byte is " + hex32(b.data[0]).replace(2, 6, "") + ", not the Crazyflie micro-SD magic 0xbc");
  if (b.size < kHeaderFixedBytes)
    return issue(LogStatus::kTruncated, b.size, "",
                 "header truncated: " + std::to_string(b.size) + " of 5 bytes (magic, version, event type count)");
  const std::uint16_t version = readU16(b.data + 1);
  if (version != 1 && version != 2)
    return issue(LogStatus::kUnsupportedVersion, 1, "",
                 "file format version " + std::to_string(version) + " (this reader knows versions 1 and 2)");
  const std::size_t num_types = readU16(b.data + 3);
  if (num_types > limits.max_event_types)
    return issue(LogStatus::kTooLarge, 3, "",
                 std::to_string(num_types) + " event types declared (at most " +
                     std::to_string(limits.max_event_types) + " accepted)");

  out.info["usd.version"] = std::to_string(version);
  out.info["usd.event_types"] = std::to_string(num_types);
  out.info["usd.timestamp"] = version == 1 ? "uint32 milliseconds (converted to microseconds)" : "uint64 microseconds";

  // --- The event type table. ---
  std::vector<EventType> types;
  types.reserve(num_types);
  std::size_t pos = kHeaderFixedBytes;
  for (std::size_t e = 0; e < num_types; ++e) {
    const std::size_t event_start = pos;
    if (b.size - pos < 2)
      return issue(LogStatus::kTruncated, b.size, "",
                   "the file ends inside the event type table (event type " + std::to_string(e + 1) + " of " +
                       std::to_string(num_types) + ")");
    EventType et;
    et.id = readU16(b.data + pos);
    pos += 2;
    for (const EventType& other : types)
      if (other.id == et.id)
        return issue(LogStatus::kCorrupt, event_start, "", "event id " + std::to_string(et.id) + " is declared twice");
    std::string name;
    if (LogIssue i = readName(b, pos, limits.max_name_bytes, "an event name", name); !i.ok()) return i;
    if (b.size - pos < 2)
      return issue(LogStatus::kTruncated, b.size, name, "the file ends before event '" + name + "' gives its variable count");
    const std::size_t num_vars = readU16(b.data + pos);
    if (num_vars > limits.max_variables_per_event)
      return issue(LogStatus::kTooLarge, pos, name,
                   "event '" + name + "' declares " + std::to_string(num_vars) + " variables (at most " +
                       std::to_string(limits.max_variables_per_event) + " accepted)");
    pos += 2;
    LogTopic topic;
    topic.name = name;
    for (const LogTopic& t : out.topics)
      if (t.name == name) ++topic.instance;
    for (std::size_t v = 0; v < num_vars; ++v) {
      const std::size_t var_start = pos;
      std::string decl;
      if (LogIssue i = readName(b, pos, limits.max_name_bytes, "a variable declaration", decl); !i.ok()) {
        i.topic = name;
        return i;
      }
      // "group.name(T)": at least one character of name, then '(', the type, ')'.
      FieldType type = FieldType::kFloat;
      std::size_t size = 0;
      if (decl.size() < 4 || decl[decl.size() - 3] != '(' || decl.back() != ')' ||
          !typeOf(decl[decl.size() - 2], type, size))
        return issue(LogStatus::kCorrupt, var_start, name,
                     "variable declaration '" + decl + "' of event '" + name +
                         "' is not NAME(T) with a known type character T");
      LogField field;
      field.name = decl.substr(0, decl.size() - 3);
      field.type = type;
      topic.fields.push_back(std::move(field));
      et.vars.push_back(Variable{decl[decl.size() - 2], size});
      et.payload_bytes += size;
    }
    topic.columns.resize(topic.fields.size());
    out.info["usd.event." + name + ".id"] = std::to_string(et.id);
    et.topic = out.topics.size();
    out.topics.push_back(std::move(topic));
    types.push_back(std::move(et));
  }
  const std::size_t data_start = pos;
  out.info["usd.header_bytes"] = std::to_string(data_start);

  // Event id → index + 1 into `types` (0 = unknown id); a real log has a handful of types.
  auto slotOf = [&types](std::uint16_t id) -> std::size_t {
    for (std::size_t i = 0; i < types.size(); ++i)
      if (types[i].id == id) return i + 1;
    return 0;
  };

  // --- The records: walk them as far as whole records go. ---
  const std::size_t record_head = version == 1 ? 6 : 10;  // id (2) + timestamp (4 or 8)
  std::size_t partial_at = 0, partial_have = 0, partial_need = 0;
  bool partial = false;
  std::vector<std::size_t> backwards(types.size(), 0);
  while (pos < b.size) {
    const std::size_t left = b.size - pos;
    if (left < 2) {
      partial = true;
      partial_at = pos;
      partial_have = left;
      partial_need = record_head;
      break;
    }
    const std::uint16_t id = readU16(b.data + pos);
    const std::size_t k = slotOf(id);
    if (k == 0) {
      if (left <= kCrcBytes) {  // possibly the CRC: decided below
        partial = true;
        partial_at = pos;
        partial_have = left;
        partial_need = record_head;
        break;
      }
      return issue(LogStatus::kCorrupt, pos, "", "record with unknown event id " + std::to_string(id));
    }
    EventType& et = types[k - 1];
    const std::size_t need = record_head + et.payload_bytes;
    LogTopic& topic = out.topics[et.topic];
    if (left < need) {
      partial = true;
      partial_at = pos;
      partial_have = left;
      partial_need = need;
      break;
    }
    std::int64_t ts = 0;
    if (version == 1) {
      ts = static_cast<std::int64_t>(readU32(b.data + pos + 2)) * 1000;  // [ms] → [µs]
    } else {
      const std::uint64_t raw = readU64(b.data + pos + 2);
      if (raw > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
        return issue(LogStatus::kCorrupt, pos + 2, topic.name, "timestamp " + std::to_string(raw) + " µs is beyond 2^63");
      ts = static_cast<std::int64_t>(raw);
    }
    if (!topic.timestamp_us.empty() && ts < topic.timestamp_us.back()) ++backwards[k - 1];
    topic.timestamp_us.push_back(ts);
    const std::uint8_t* p = b.data + pos + record_head;
    for (std::size_t v = 0; v < et.vars.size(); ++v) {
      topic.columns[v].push_back(decodeValue(et.vars[v], p));
      p += et.vars[v].size;
    }
    pos += need;
  }

  // --- The end: a CRC-32 over everything before it, or a log that was never closed. ---
  std::size_t records = 0;
  for (const LogTopic& t : out.topics) records += t.rows();
  if (partial && partial_have == kCrcBytes && partial_at == b.size - kCrcBytes) {
    const std::uint32_t stored = readU32(b.data + partial_at);
    const std::uint32_t computed = crc32Ieee(b.data, partial_at);
    if (stored != computed)
      return issue(LogStatus::kCorrupt, partial_at, "",
                   "CRC-32 mismatch: stored " + hex32(stored) + ", computed " + hex32(computed) + " over bytes 0.." +
                       std::to_string(partial_at - 1) + " (corrupt file)");
    out.info["usd.crc32"] = hex32(stored) + " (verified)";
  } else if (b.size >= data_start + kCrcBytes &&
             readU32(b.data + b.size - kCrcBytes) == crc32Ieee(b.data, b.size - kCrcBytes)) {
    // The CRC matches, but the records do not end where it begins.
    const std::size_t at = partial ? partial_at : b.size;
    return issue(LogStatus::kCorrupt, at, "",
                 "the records do not end where the CRC-32 begins (byte " + std::to_string(b.size - kCrcBytes) + ")");
  } else if (partial) {
    out.info["usd.crc32"] = "absent (log not closed)";
    out.warnings.push_back("byte " + std::to_string(partial_at) + ": the log ends inside a record (" +
                           std::to_string(partial_have) + " of " + std::to_string(partial_need) +
                           " bytes): truncated mid-write, the record is dropped; no CRC-32, " +
                           std::to_string(records) + " complete records kept unverified");
  } else {
    out.info["usd.crc32"] = "absent (log not closed)";
    out.warnings.push_back("byte " + std::to_string(b.size) +
                           ": the log ends after a whole record without a CRC-32 (logging was not stopped with "
                           "usd.logging = 0, or power was lost); " +
                           std::to_string(records) + " records kept unverified");
  }
  for (std::size_t i = 0; i < types.size(); ++i)
    if (backwards[i] > 0)
      out.warnings.push_back("event '" + out.topics[types[i].topic].name + "': the timestamp goes backwards " +
                             std::to_string(backwards[i]) + " times");
  out.info["usd.records"] = std::to_string(records);
  return {};
}

}  // namespace quadfdi
