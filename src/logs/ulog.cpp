#include "logs/ulog.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

// ULog is little endian; values are copied straight out of the buffer.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the ULog reader assumes a little-endian host");

namespace quadfdi {
namespace {

constexpr std::uint8_t kMagic[7] = {0x55, 0x4c, 0x6f, 0x67, 0x01, 0x12, 0x35};
constexpr std::uint8_t kSyncMagic[8] = {0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12};
constexpr std::size_t kHeaderSize = 16;           // [bytes] magic, version, timestamp
constexpr std::size_t kMessageHeaderSize = 3;     // [bytes] uint16 msg_size, uint8 msg_type
constexpr std::size_t kFlagBitsSize = 40;         // [bytes] compat[8], incompat[8], appended_offsets[3]
constexpr std::size_t kMaxDataPayload = 65535 - 2;  // [bytes] a 'D' message's data after its msg_id
constexpr int kNewestKnownVersion = 2;
constexpr std::size_t kMaxIdentifier = 255;       // [chars] message, field, parameter names

template <class T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The body INFO, INFO_MULTIPLE, PARAMETER and PARAMETER_DEFAULT messages share, after the flag
// byte the multi and default kinds lead with (skip): uint8 key_len, the key "type name", the value.
struct KeyedValue {
  std::string key;
  bool typed = false;      // the key has a space: "type name"
  std::string type, name;  // empty unless typed
  const std::uint8_t* value = nullptr;
  std::size_t value_len = 0;  // [bytes]
};

// False when the message is too short for its key.
bool readKeyedValue(const std::uint8_t* p, std::size_t n, std::size_t skip, KeyedValue& kv) {
  if (n < skip + 1) return false;
  const std::size_t key_len = p[skip];
  if (n < skip + 1 + key_len) return false;
  kv.key.assign(reinterpret_cast<const char*>(p + skip + 1), key_len);
  kv.value = p + skip + 1 + key_len;
  kv.value_len = n - skip - 1 - key_len;
  const std::size_t space = kv.key.find(' ');
  kv.typed = space != std::string::npos;
  if (kv.typed) {
    kv.type = kv.key.substr(0, space);
    kv.name = kv.key.substr(space + 1);
  }
  return true;
}

struct BasicType {
  const char* name;
  FieldType type;
  std::uint32_t size;  // [bytes]
};
constexpr BasicType kBasicTypes[] = {
    {"int8_t", FieldType::kInt8, 1},     {"uint8_t", FieldType::kUInt8, 1},   {"int16_t", FieldType::kInt16, 2},
    {"uint16_t", FieldType::kUInt16, 2}, {"int32_t", FieldType::kInt32, 4},   {"uint32_t", FieldType::kUInt32, 4},
    {"int64_t", FieldType::kInt64, 8},   {"uint64_t", FieldType::kUInt64, 8}, {"float", FieldType::kFloat, 4},
    {"double", FieldType::kDouble, 8},   {"bool", FieldType::kBool, 1},       {"char", FieldType::kChar, 1},
};

const BasicType* findBasicType(const std::string& name) {
  for (const BasicType& b : kBasicTypes)
    if (name == b.name) return &b;
  return nullptr;
}

bool isFieldNameChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}
bool isMessageNameChar(char c) { return isFieldNameChar(c) || c == '-' || c == '/'; }

bool validName(const std::string& s, bool message_name) {
  if (s.empty() || s.size() > kMaxIdentifier) return false;
  for (char c : s)
    if (!(message_name ? isMessageNameChar(c) : isFieldNameChar(c))) return false;
  return true;
}

// One field of an 'F' format as written: a basic type or another format, maybe an array.
struct FormatField {
  std::string type_name;
  const BasicType* basic = nullptr;  // nullptr: a nested format, resolved on subscription
  std::uint32_t count = 1;           // array length; 1 for a scalar
  bool is_array = false;
  std::string name;
  bool padding = false;              // "_padding…": bytes to skip, never shown
};

// A format flattened to what one data message decodes to: a column per basic element.
struct FieldPlan {
  std::uint32_t offset;  // [bytes] in the message data
  FieldType type;
};
struct FlatFormat {
  std::vector<LogField> fields;  // without padding and without the top-level timestamp
  std::vector<FieldPlan> plan;   // parallel to fields
  std::uint32_t size = 0;        // [bytes] of a full message
  std::uint32_t min_size = 0;    // [bytes] without a trailing padding field (writers may leave it out)
  std::int64_t timestamp_offset = -1;  // [bytes] of the top-level uint64_t timestamp; −1 if none
};

struct Format {
  std::vector<FormatField> fields;
  int sizing_state = 0;         // 0 not sized, 1 being sized (a cycle if met again), 2 sized
  std::uint64_t size = 0;       // [bytes] valid when sizing_state == 2
  std::shared_ptr<const FlatFormat> flat;  // built on first subscription
};

// Parses "name:type field;type[N] field;…" (spec: 'F' message). Empty string = ok.
std::string parseFormat(const std::string& text, std::string& name, Format& format) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) return "format has no ':' after the message name";
  name = text.substr(0, colon);
  if (!validName(name, true)) return "bad message name in format";
  if (findBasicType(name)) return "format name is a basic type";
  std::size_t pos = colon + 1;
  while (pos < text.size()) {
    std::size_t end = text.find(';', pos);
    if (end == std::string::npos) end = text.size();
    const std::string field = text.substr(pos, end - pos);
    pos = end + 1;
    if (field.empty()) continue;  // a trailing ';' (PX4 writes one) or ";;"
    const std::size_t space = field.find(' ');
    if (space == std::string::npos || space == 0) return "field '" + field + "' is not 'type name'";
    FormatField f;
    std::string type = field.substr(0, space);
    f.name = field.substr(space + 1);
    if (!validName(f.name, false)) return "bad field name '" + f.name + "'";
    const std::size_t bracket = type.find('[');
    if (bracket != std::string::npos) {
      if (type.back() != ']' || bracket + 2 >= type.size()) return "bad array type '" + type + "'";
      std::uint64_t n = 0;
      for (std::size_t i = bracket + 1; i + 1 < type.size(); ++i) {
        const char c = type[i];
        if (c < '0' || c > '9') return "bad array length in '" + type + "'";
        n = n * 10 + static_cast<std::uint64_t>(c - '0');
        if (n > kMaxDataPayload) return "array length in '" + type + "' exceeds any message";
      }
      if (n == 0) return "zero array length in '" + type + "'";
      f.count = static_cast<std::uint32_t>(n);
      f.is_array = true;
      type.resize(bracket);
    }
    if (!validName(type, true)) return "bad type '" + type + "'";
    f.type_name = type;
    f.basic = findBasicType(type);
    f.padding = f.name.rfind("_padding", 0) == 0;
    format.fields.push_back(std::move(f));
  }
  if (format.fields.empty()) return "format has no fields";
  return {};
}

class UlogReader {
 public:
  UlogReader(ByteSpan bytes, DecodedLog& out, const UlogLimits& limits)
      : data_(bytes.data), size_(bytes.size), out_(out), limits_(limits) {}

  LogIssue read();

 private:
  // How parsing a segment ended.
  enum class Outcome { kEnd, kCut, kFailed };

  LogIssue fail(LogStatus status, std::uint64_t offset, std::string topic, std::string message) {
    issue_ = LogIssue{status, offset, std::move(topic), std::move(message)};
    return issue_;
  }
  void warn(std::string text) {
    if (out_.warnings.size() < limits_.max_stored_warnings)
      out_.warnings.push_back(std::move(text));
    else
      ++dropped_warnings_;
  }
  static std::string at(std::size_t offset) { return "byte " + std::to_string(offset) + ": "; }

  LogIssue readHeader();
  LogIssue readFlagBits(std::size_t& pos);
  Outcome parseSegment(std::size_t begin, std::size_t end, bool appended);
  // A contradiction in the data section: resync at the next sync message, or fail with kCorrupt.
  bool recover(std::size_t offset, const std::string& topic, const std::string& problem, std::size_t end,
               std::size_t& pos);
  std::size_t findSync(std::size_t from, std::size_t end);

  bool handleFormat(std::size_t offset, const std::uint8_t* p, std::size_t n);
  void handleInfo(const std::uint8_t* p, std::size_t n, bool multi);
  void handleParameter(std::size_t offset, const std::uint8_t* p, std::size_t n, bool is_default);
  bool handleAdd(std::size_t offset, const std::uint8_t* p, std::size_t n, std::size_t end, std::size_t& next);
  bool handleData(std::size_t offset, const std::uint8_t* p, std::size_t n, std::size_t end, std::size_t& next);
  void handleLogging(const std::uint8_t* p, std::size_t n, bool tagged);

  // Sizes and flattens a format; empty string = ok, else the problem (status in `status`).
  std::string sizeOf(const std::string& name, int depth, std::uint64_t& size, LogStatus& status);
  std::string flatten(const Format& f, std::uint32_t base, const std::string& prefix, int depth, bool top,
                      FlatFormat& flat, LogStatus& status);
  std::string flatFormat(const std::string& name, std::shared_ptr<const FlatFormat>& flat, LogStatus& status);

  const std::uint8_t* data_;
  std::size_t size_;
  DecodedLog& out_;
  const UlogLimits& limits_;
  LogIssue issue_;
  int version_ = 0;
  bool in_data_section_ = false;
  std::vector<std::uint64_t> appended_offsets_;
  std::map<std::string, Format> formats_;

  struct Subscription {
    std::shared_ptr<const FlatFormat> flat;
    int topic = -1;               // index in out_.topics
    std::string name;
    int multi_id = 0;
    std::int64_t last_timestamp = 0;
    bool warned_backwards = false;
  };
  std::vector<Subscription> subscriptions_;
  std::vector<std::int32_t> subscription_by_id_;  // by msg_id, −1: none; grows with the largest msg_id subscribed
  std::int32_t subscriptionIndex(std::uint16_t id) const { return id < subscription_by_id_.size() ? subscription_by_id_[id] : -1; }
  std::map<std::pair<std::string, int>, int> topic_by_key_;

  // Data messages per msg_id (and their bytes), counted ahead on large logs to reserve columns.
  std::vector<std::uint32_t> data_count_by_id_;
  std::vector<std::uint64_t> data_bytes_by_id_;
  void countDataMessages(std::size_t from);

  std::size_t columns_used_ = 0;
  std::size_t name_bytes_used_ = 0;
  std::size_t no_sync_from_ = static_cast<std::size_t>(-1);  // no sync message at or after this offset
  std::int64_t last_timestamp_ = 0;  // [µs] latest seen, for dropouts
  std::map<std::string, int> multi_info_count_;
  std::string last_multi_key_;
  std::size_t unknown_messages_ = 0;
  std::string unknown_types_;
  std::size_t dropped_warnings_ = 0;
};

LogIssue UlogReader::read() {
  out_ = DecodedLog{};
  out_.format = LogFormat::kUlog;
  if (LogIssue h = readHeader(); !h.ok()) return h;
  std::size_t pos = kHeaderSize;
  if (LogIssue b = readFlagBits(pos); !b.ok()) return b;

  countDataMessages(pos);

  // The regular data runs up to the first appended offset (it may stop mid-message there); each
  // appended block up to the next one or the end of the file.
  std::vector<std::uint64_t> bounds;
  for (std::uint64_t o : appended_offsets_) {
    if (o < pos) return fail(LogStatus::kCorrupt, 16, "", "appended-data offset " + std::to_string(o) + " lies before the end of the flag-bits message");
    if (o >= size_) {
      warn(at(16) + "appended-data offset " + std::to_string(o) + " lies past the end of the file; ignored");
      continue;
    }
    bounds.push_back(o);
  }
  std::sort(bounds.begin(), bounds.end());
  bounds.erase(std::unique(bounds.begin(), bounds.end()), bounds.end());
  std::size_t begin = pos;
  for (std::size_t i = 0; i <= bounds.size(); ++i) {
    const std::size_t end = i < bounds.size() ? static_cast<std::size_t>(bounds[i]) : size_;
    if (parseSegment(begin, end, i > 0) == Outcome::kFailed) return issue_;
    if (!in_data_section_)
      return fail(LogStatus::kTruncated, end, "", "the log ends before its data section (no subscription or logged message)");
    begin = end;
  }
  if (unknown_messages_ > 0)
    warn(std::to_string(unknown_messages_) + " message(s) of unknown type skipped (types: " + unknown_types_ + ")");
  if (dropped_warnings_ > 0) out_.warnings.push_back("… and " + std::to_string(dropped_warnings_) + " more warnings");
  return {};
}

LogIssue UlogReader::readHeader() {
  const std::size_t have = std::min(size_, sizeof kMagic);
  if (std::memcmp(data_, kMagic, have) != 0)
    return fail(LogStatus::kWrongMagic, 0, "", "not a ULog file (no 'ULog' magic)");
  if (size_ < kHeaderSize)
    return fail(LogStatus::kTruncated, size_, "", size_ == 0 ? "empty input" : "the file ends inside the 16-byte ULog header");
  version_ = data_[7];
  if (version_ == 0) return fail(LogStatus::kUnsupportedVersion, 7, "", "ULog version 0 does not exist (expected 1 or 2)");
  if (version_ > kNewestKnownVersion)
    warn(at(7) + "ULog version " + std::to_string(version_) + " is newer than " + std::to_string(kNewestKnownVersion) +
         "; read as version 2 (the spec asks readers to try)");
  out_.info["ulog_version"] = std::to_string(version_);
  out_.info["ulog_start_timestamp_us"] = std::to_string(load<std::uint64_t>(data_ + 8));
  return {};
}

LogIssue UlogReader::readFlagBits(std::size_t& pos) {
  // Optional (version 1 logs may lack it), but when present it is the first message.
  if (size_ < pos + kMessageHeaderSize || data_[pos + 2] != 'B') return {};
  const std::size_t n = load<std::uint16_t>(data_ + pos);
  if (pos + kMessageHeaderSize + n > size_)
    return fail(LogStatus::kTruncated, pos, "", "the file ends inside the flag-bits message");
  if (n < kFlagBitsSize)
    return fail(LogStatus::kCorrupt, pos, "", "flag-bits message of " + std::to_string(n) + " bytes (expected at least 40)");
  const std::uint8_t* p = data_ + pos + kMessageHeaderSize;
  const std::uint8_t* incompat = p + 8;
  for (std::size_t i = 0; i < 8; ++i) {
    const std::uint8_t unknown = i == 0 ? static_cast<std::uint8_t>(incompat[0] & ~1u) : incompat[i];
    if (unknown != 0)
      return fail(LogStatus::kUnsupportedVersion, pos + kMessageHeaderSize + 8 + i, "",
                  "unknown incompatible flag bits set (value " + std::to_string(unknown) + " in byte " + std::to_string(i) +
                      "): the log uses a format change this reader does not know");
  }
  if (incompat[0] & 1u) {
    for (std::size_t i = 0; i < 3; ++i) {
      const std::uint64_t o = load<std::uint64_t>(p + 16 + 8 * i);
      if (o != 0) appended_offsets_.push_back(o);
    }
    if (appended_offsets_.empty()) warn(at(pos) + "DATA_APPENDED flag set but every appended offset is 0");
  }
  pos += kMessageHeaderSize + n;
  return {};
}

void UlogReader::countDataMessages(std::size_t from) {
  // Only worth its two tables on large logs: growing a column by doubling copies it again and
  // touches twice the memory.
  constexpr std::size_t kWorthFrom = std::size_t{1} << 20;  // [bytes]
  if (size_ < kWorthFrom) return;
  data_count_by_id_.assign(65536, 0);
  data_bytes_by_id_.assign(65536, 0);
  for (std::size_t pos = from; size_ - pos >= kMessageHeaderSize + 2;) {
    const std::size_t n = load<std::uint16_t>(data_ + pos);
    if (size_ - pos - kMessageHeaderSize < n) break;
    if (data_[pos + 2] == 'D' && n >= 2) {
      const std::uint16_t id = load<std::uint16_t>(data_ + pos + kMessageHeaderSize);
      ++data_count_by_id_[id];
      data_bytes_by_id_[id] += n - 2;
    }
    pos += kMessageHeaderSize + n;
  }
}

std::size_t UlogReader::findSync(std::size_t from, std::size_t end) {
  if (from >= no_sync_from_) return end;
  const std::uint8_t* first = data_ + from;
  const std::uint8_t* last = data_ + end;
  while (true) {
    const std::uint8_t* hit = std::search(first, last, std::begin(kSyncMagic), std::end(kSyncMagic));
    if (hit == last) {
      no_sync_from_ = std::min(no_sync_from_, from);
      return end;
    }
    const std::size_t magic_at = static_cast<std::size_t>(hit - data_);
    // The magic must be the body of an 'S' message: header right before it.
    if (magic_at >= from + kMessageHeaderSize && data_[magic_at - 1] == 'S' &&
        load<std::uint16_t>(data_ + magic_at - 3) >= sizeof kSyncMagic)
      return magic_at - kMessageHeaderSize;
    first = hit + 1;
  }
}

bool UlogReader::recover(std::size_t offset, const std::string& topic, const std::string& problem, std::size_t end,
                         std::size_t& pos) {
  const std::size_t sync = findSync(offset + kMessageHeaderSize, end);
  if (sync >= end) {
    fail(LogStatus::kCorrupt, offset, topic, problem + " (no sync message follows to recover at)");
    return false;
  }
  warn(at(offset) + (topic.empty() ? "" : topic + ": ") + problem + "; skipped " + std::to_string(sync - offset) +
       " bytes to the sync message at byte " + std::to_string(sync));
  pos = sync;
  return true;
}

UlogReader::Outcome UlogReader::parseSegment(std::size_t begin, std::size_t end, bool appended) {
  std::size_t pos = begin;
  if (appended) in_data_section_ = true;  // appended data belongs to the data section (spec)
  while (pos < end) {
    if (end - pos < kMessageHeaderSize) {
      warn(at(pos) + "the log ends inside a message header; the last " + std::to_string(end - pos) + " bytes are dropped");
      return Outcome::kCut;
    }
    const std::size_t n = load<std::uint16_t>(data_ + pos);
    const char type = static_cast<char>(data_[pos + 2]);
    const std::uint8_t* p = data_ + pos + kMessageHeaderSize;
    if (end - pos - kMessageHeaderSize < n) {
      if (!in_data_section_) {
        fail(LogStatus::kTruncated, pos, "", "the log ends inside a definitions message ('" + std::string(1, type) + "', " +
                                                 std::to_string(n) + " bytes)");
        return Outcome::kFailed;
      }
      warn(at(pos) + (end < size_ ? "message cut at the start of appended data" : "the log ends inside a message") +
           " ('" + std::string(1, type) + "', " + std::to_string(n) + " bytes, " +
           std::to_string(end - pos - kMessageHeaderSize) + " present); everything before it is kept");
      return Outcome::kCut;
    }
    std::size_t next = pos + kMessageHeaderSize + n;
    switch (type) {
      case 'D':
        if (!handleData(pos, p, n, end, next)) return Outcome::kFailed;
        break;
      case 'F':
        if (!handleFormat(pos, p, n)) return Outcome::kFailed;
        break;
      case 'A':
        in_data_section_ = true;
        if (!handleAdd(pos, p, n, end, next)) return Outcome::kFailed;
        break;
      case 'I': handleInfo(p, n, false); break;
      case 'M': handleInfo(p, n, true); break;
      case 'P': handleParameter(pos, p, n, false); break;
      case 'Q': handleParameter(pos, p, n, true); break;
      case 'L':
      case 'C':
        in_data_section_ = true;
        handleLogging(p, n, type == 'C');
        break;
      case 'R':
        if (n >= 2) {
          const std::uint16_t id = load<std::uint16_t>(p);
          if (id < subscription_by_id_.size()) subscription_by_id_[id] = -1;
        }
        break;
      case 'O':
        if (n >= 2) out_.dropouts.push_back(LogDropout{last_timestamp_, std::int64_t{load<std::uint16_t>(p)} * 1000});
        break;
      case 'S':
        break;  // only a landmark for recovery
      case 'B':
        warn(at(pos) + "flag-bits message not at the start of the log; ignored");
        break;
      default:
        // Forward compatibility (spec): unknown message types are skipped.
        if (unknown_types_.find(type) == std::string::npos && unknown_types_.size() < 32) {
          if (type >= 0x21 && type <= 0x7e)
            unknown_types_ += type;
          else
            unknown_types_ += '?';
        }
        ++unknown_messages_;
        break;
    }
    pos = next;
  }
  return Outcome::kEnd;
}

bool UlogReader::handleFormat(std::size_t offset, const std::uint8_t* p, std::size_t n) {
  const std::string text(reinterpret_cast<const char*>(p), n);
  std::string name;
  Format format;
  const std::string problem = parseFormat(text, name, format);
  if (!problem.empty()) {
    fail(LogStatus::kCorrupt, offset, name, "format definition does not parse: " + problem);
    return false;
  }
  auto [it, inserted] = formats_.emplace(name, std::move(format));
  if (!inserted) {
    // A second definition of a name: allowed only if nothing was built from the first.
    if (it->second.flat || it->second.sizing_state != 0) {
      warn(at(offset) + "format '" + name + "' defined again after use; the first definition is kept");
    } else {
      it->second = std::move(format);
    }
  }
  return true;
}

void UlogReader::handleInfo(const std::uint8_t* p, std::size_t n, bool multi) {
  KeyedValue kv;
  if (!readKeyedValue(p, n, multi ? 1 : 0, kv) || !kv.typed) return;
  const bool continued = multi && p[0] != 0;
  std::string text;
  if (kv.type.rfind("char[", 0) == 0) {
    text.assign(reinterpret_cast<const char*>(kv.value), kv.value_len);
  } else if (const BasicType* b = findBasicType(kv.type); b && kv.value_len >= b->size) {
    switch (b->type) {
      case FieldType::kInt32: text = std::to_string(load<std::int32_t>(kv.value)); break;
      case FieldType::kUInt32: text = std::to_string(load<std::uint32_t>(kv.value)); break;
      case FieldType::kInt64: text = std::to_string(load<std::int64_t>(kv.value)); break;
      case FieldType::kUInt64: text = std::to_string(load<std::uint64_t>(kv.value)); break;
      case FieldType::kInt8: text = std::to_string(load<std::int8_t>(kv.value)); break;
      case FieldType::kUInt8: text = std::to_string(load<std::uint8_t>(kv.value)); break;
      case FieldType::kInt16: text = std::to_string(load<std::int16_t>(kv.value)); break;
      case FieldType::kUInt16: text = std::to_string(load<std::uint16_t>(kv.value)); break;
      case FieldType::kFloat: text = std::to_string(load<float>(kv.value)); break;
      case FieldType::kDouble: text = std::to_string(load<double>(kv.value)); break;
      case FieldType::kBool: text = kv.value[0] ? "true" : "false"; break;
      case FieldType::kChar: text.assign(1, static_cast<char>(kv.value[0])); break;
    }
  } else {
    // Another type (an array of numbers, …): kept as raw bytes.
    text.assign(reinterpret_cast<const char*>(kv.value), kv.value_len);
  }
  if (!multi) {
    out_.info[kv.name] = std::move(text);
    return;
  }
  // Multi info: continued parts are appended to the previous entry of the key; a new entry of a
  // key already seen is stored as "key[1]", "key[2]", ….
  int& count = multi_info_count_[kv.name];
  if (continued && count > 0 && last_multi_key_ == kv.name) {
    out_.info[count == 1 ? kv.name : kv.name + "[" + std::to_string(count - 1) + "]"] += text;
    return;
  }
  out_.info[count == 0 ? kv.name : kv.name + "[" + std::to_string(count) + "]"] = std::move(text);
  ++count;
  last_multi_key_ = kv.name;
}

void UlogReader::handleParameter(std::size_t offset, const std::uint8_t* p, std::size_t n, bool is_default) {
  KeyedValue kv;
  if (!readKeyedValue(p, n, is_default ? 1 : 0, kv)) return;
  const std::uint8_t default_types = is_default ? p[0] : 0;
  if (!kv.typed || kv.value_len < 4) {
    warn(at(offset) + "parameter message without a 4-byte value ('" + kv.key + "'); skipped");
    return;
  }
  double v = 0.0;
  if (kv.type == "float")
    v = static_cast<double>(load<float>(kv.value));
  else if (kv.type == "int32_t")
    v = load<std::int32_t>(kv.value);
  else {
    warn(at(offset) + "parameter '" + kv.name + "' of type '" + kv.type + "' (the spec allows float and int32_t); skipped");
    return;
  }
  if (!is_default) {
    out_.parameters[kv.name] = v;
    return;
  }
  // The configuration (airframe) default (bit 1) is what applies to this vehicle; the system-wide
  // one (bit 0) is kept only where no configuration default was logged.
  if (default_types & 2u)
    out_.default_parameters[kv.name] = v;
  else if (default_types & 1u)
    out_.default_parameters.emplace(kv.name, v);
}

void UlogReader::handleLogging(const std::uint8_t* p, std::size_t n, bool tagged) {
  const std::size_t head = tagged ? 11 : 9;
  if (n < head) return;
  LogText t;
  const std::uint8_t level = p[0];
  t.level = level >= '0' && level <= '7' ? level - '0' : level;
  if (tagged) t.tag = load<std::uint16_t>(p + 1);
  const std::uint64_t ts = load<std::uint64_t>(p + (tagged ? 3 : 1));
  t.timestamp_us = static_cast<std::int64_t>(std::min<std::uint64_t>(ts, std::numeric_limits<std::int64_t>::max()));
  t.text.assign(reinterpret_cast<const char*>(p + head), n - head);
  out_.messages.push_back(std::move(t));
}

std::string UlogReader::sizeOf(const std::string& name, int depth, std::uint64_t& size, LogStatus& status) {
  if (depth > limits_.max_nesting_depth) {
    status = LogStatus::kTooLarge;
    return "formats nested deeper than " + std::to_string(limits_.max_nesting_depth) + " levels";
  }
  auto it = formats_.find(name);
  if (it == formats_.end()) {
    status = LogStatus::kCorrupt;
    return "type '" + name + "' is not defined";
  }
  Format& f = it->second;
  if (f.sizing_state == 1) {
    status = LogStatus::kCorrupt;
    return "format '" + name + "' contains itself";
  }
  if (f.sizing_state == 2) {
    size = f.size;
    return {};
  }
  f.sizing_state = 1;
  std::uint64_t total = 0;
  for (const FormatField& field : f.fields) {
    std::uint64_t element = 0;
    if (field.basic) {
      element = field.basic->size;
    } else if (std::string problem = sizeOf(field.type_name, depth + 1, element, status); !problem.empty()) {
      f.sizing_state = 0;
      return problem;
    }
    total += element * field.count;
    if (total > (std::uint64_t{1} << 32)) break;  // far beyond any message; no overflow either
  }
  f.sizing_state = 2;
  f.size = total;
  size = total;
  return {};
}

std::string UlogReader::flatten(const Format& f, std::uint32_t base, const std::string& prefix, int depth, bool top,
                                FlatFormat& flat, LogStatus& status) {
  std::uint32_t offset = base;
  for (const FormatField& field : f.fields) {
    std::uint32_t element = 0;
    const Format* nested = nullptr;
    if (field.basic) {
      element = field.basic->size;
    } else {
      nested = &formats_.at(field.type_name);  // sized already, so it exists
      element = static_cast<std::uint32_t>(nested->size);
    }
    if (field.padding) {
      offset += element * field.count;
      continue;
    }
    if (top && field.name == "timestamp" && !field.is_array && field.basic && field.basic->type == FieldType::kUInt64) {
      flat.timestamp_offset = offset;
      offset += element;
      continue;
    }
    for (std::uint32_t i = 0; i < field.count; ++i, offset += element) {
      std::string name = prefix + field.name;
      if (field.is_array) name += "[" + std::to_string(i) + "]";
      if (nested) {
        if (std::string problem = flatten(*nested, offset, name + ".", depth + 1, false, flat, status); !problem.empty())
          return problem;
        continue;
      }
      name_bytes_used_ += name.size();
      if (++columns_used_ > limits_.max_columns || name_bytes_used_ > limits_.max_name_bytes) {
        status = LogStatus::kTooLarge;
        return "more fields than the reader accepts (" + std::to_string(limits_.max_columns) + " columns, " +
               std::to_string(limits_.max_name_bytes) + " bytes of names, all topics together)";
      }
      LogField lf;
      lf.name = std::move(name);
      lf.type = field.basic->type;
      flat.fields.push_back(std::move(lf));
      flat.plan.push_back(FieldPlan{offset, field.basic->type});
    }
  }
  return {};
}

std::string UlogReader::flatFormat(const std::string& name, std::shared_ptr<const FlatFormat>& flat, LogStatus& status) {
  std::uint64_t size = 0;
  if (std::string problem = sizeOf(name, 0, size, status); !problem.empty()) return problem;
  Format& f = formats_.at(name);
  if (f.flat) {
    flat = f.flat;
    return {};
  }
  std::uint64_t trailing_padding = 0;
  if (const FormatField& last = f.fields.back(); last.padding) {
    std::uint64_t element = 0;
    if (last.basic)
      element = last.basic->size;
    else
      element = formats_.at(last.type_name).size;
    trailing_padding = element * last.count;
  }
  if (size - trailing_padding > kMaxDataPayload) {
    status = LogStatus::kTooLarge;
    return "format of " + std::to_string(size) + " bytes, more than a data message can hold";
  }
  auto built = std::make_shared<FlatFormat>();
  built->size = static_cast<std::uint32_t>(std::min<std::uint64_t>(size, std::uint64_t{1} << 31));
  built->min_size = static_cast<std::uint32_t>(size - trailing_padding);
  if (std::string problem = flatten(f, 0, "", 0, true, *built, status); !problem.empty()) return problem;
  f.flat = built;
  flat = std::move(built);
  return {};
}

bool UlogReader::handleAdd(std::size_t offset, const std::uint8_t* p, std::size_t n, std::size_t end, std::size_t& next) {
  if (n < 4) return recover(offset, "", "subscription message of " + std::to_string(n) + " bytes", end, next);
  const int multi_id = p[0];
  const std::uint16_t msg_id = load<std::uint16_t>(p + 1);
  const std::string name(reinterpret_cast<const char*>(p + 3), n - 3);
  if (subscriptionIndex(msg_id) >= 0) {
    const Subscription& old = subscriptions_[static_cast<std::size_t>(subscriptionIndex(msg_id))];
    if (old.name == name && old.multi_id == multi_id) return true;  // repeated, harmless
    return recover(offset, name, "msg_id " + std::to_string(msg_id) + " already subscribed to " + old.name, end, next);
  }
  if (formats_.find(name) == formats_.end())
    return recover(offset, name, "subscription to a message with no format definition", end, next);
  Subscription sub;
  sub.name = name;
  sub.multi_id = multi_id;
  LogStatus status = LogStatus::kCorrupt;
  const std::size_t columns_before = columns_used_;
  if (std::string problem = flatFormat(name, sub.flat, status); !problem.empty()) {
    if (status == LogStatus::kTooLarge) {
      fail(status, offset, name, problem);
      return false;
    }
    return recover(offset, name, problem, end, next);
  }
  if (sub.flat->timestamp_offset < 0) {
    // Spec: every subscribed format has a uint64_t timestamp. Without it no row can be placed.
    warn(at(offset) + name + ": format has no uint64_t 'timestamp' field; its data is skipped");
  } else {
    auto key = std::make_pair(name, multi_id);
    auto it = topic_by_key_.find(key);
    if (it != topic_by_key_.end()) {
      sub.topic = it->second;
    } else {
      // A flattened format built for an earlier topic is shared; its columns count again here.
      if (columns_before == columns_used_) {
        columns_used_ += sub.flat->fields.size();
        for (const LogField& lf : sub.flat->fields) name_bytes_used_ += lf.name.size();
        if (columns_used_ > limits_.max_columns || name_bytes_used_ > limits_.max_name_bytes) {
          fail(LogStatus::kTooLarge, offset, name, "more fields than the reader accepts (all topics together)");
          return false;
        }
      }
      LogTopic topic;
      topic.name = name;
      topic.instance = multi_id;
      topic.fields = sub.flat->fields;
      topic.columns.resize(topic.fields.size());
      if (!data_count_by_id_.empty()) {
        // At most as many rows as messages, and as the bytes allow: memory stays below 8× the file.
        const std::size_t rows = std::min<std::uint64_t>(data_count_by_id_[msg_id],
                                                         data_bytes_by_id_[msg_id] / std::max<std::uint32_t>(1, sub.flat->min_size));
        topic.timestamp_us.reserve(rows);
        for (auto& c : topic.columns) c.reserve(rows);
      }
      sub.topic = static_cast<int>(out_.topics.size());
      out_.topics.push_back(std::move(topic));
      topic_by_key_.emplace(std::move(key), sub.topic);
    }
  }
  if (msg_id >= subscription_by_id_.size()) subscription_by_id_.resize(std::size_t{msg_id} + 1, -1);
  subscription_by_id_[msg_id] = static_cast<std::int32_t>(subscriptions_.size());
  subscriptions_.push_back(std::move(sub));
  return true;
}

bool UlogReader::handleData(std::size_t offset, const std::uint8_t* p, std::size_t n, std::size_t end, std::size_t& next) {
  if (n < 2) return recover(offset, "", "data message of " + std::to_string(n) + " bytes", end, next);
  const std::uint16_t msg_id = load<std::uint16_t>(p);
  const std::int32_t index = subscriptionIndex(msg_id);
  if (index < 0) return recover(offset, "", "data for msg_id " + std::to_string(msg_id) + ", which is not subscribed", end, next);
  Subscription& sub = subscriptions_[static_cast<std::size_t>(index)];
  if (sub.topic < 0) return true;  // a format without timestamp: warned at subscription
  const FlatFormat& flat = *sub.flat;
  const std::uint8_t* d = p + 2;
  const std::size_t len = n - 2;
  if (len < flat.min_size || len > flat.size)
    return recover(offset, sub.name,
                   "data message of " + std::to_string(len) + " bytes, the format needs " +
                       (flat.min_size == flat.size ? std::to_string(flat.size)
                                                   : std::to_string(flat.min_size) + " to " + std::to_string(flat.size)),
                   end, next);
  LogTopic& topic = out_.topics[static_cast<std::size_t>(sub.topic)];
  const std::uint64_t raw_ts = load<std::uint64_t>(d + flat.timestamp_offset);
  const std::int64_t ts = static_cast<std::int64_t>(std::min<std::uint64_t>(raw_ts, std::numeric_limits<std::int64_t>::max()));
  if (ts < sub.last_timestamp && !sub.warned_backwards) {
    warn(at(offset) + sub.name + "[" + std::to_string(sub.multi_id) + "]: timestamp goes backwards (" +
         std::to_string(ts) + " after " + std::to_string(sub.last_timestamp) + " µs); rows kept in log order");
    sub.warned_backwards = true;
  }
  sub.last_timestamp = ts;
  last_timestamp_ = std::max(last_timestamp_, ts);
  topic.timestamp_us.push_back(ts);
  std::vector<double>* columns = topic.columns.data();
  const std::size_t count = flat.plan.size();
  for (std::size_t i = 0; i < count; ++i) {
    const FieldPlan& f = flat.plan[i];
    const std::uint8_t* v = d + f.offset;
    double x = 0.0;
    switch (f.type) {
      case FieldType::kFloat: x = static_cast<double>(load<float>(v)); break;
      case FieldType::kDouble: x = load<double>(v); break;
      case FieldType::kUInt8:
      case FieldType::kChar: x = *v; break;
      case FieldType::kBool: x = *v != 0 ? 1.0 : 0.0; break;
      case FieldType::kInt8: x = static_cast<std::int8_t>(*v); break;
      case FieldType::kInt16: x = load<std::int16_t>(v); break;
      case FieldType::kUInt16: x = load<std::uint16_t>(v); break;
      case FieldType::kInt32: x = load<std::int32_t>(v); break;
      case FieldType::kUInt32: x = load<std::uint32_t>(v); break;
      case FieldType::kInt64: x = static_cast<double>(load<std::int64_t>(v)); break;
      case FieldType::kUInt64: x = static_cast<double>(load<std::uint64_t>(v)); break;
    }
    columns[i].push_back(x);
  }
  return true;
}

}  // namespace

bool looksLikeUlog(ByteSpan bytes) {
  return bytes.data && bytes.size >= sizeof kMagic && std::memcmp(bytes.data, kMagic, sizeof kMagic) == 0;
}

LogIssue readUlog(ByteSpan bytes, DecodedLog& out, const UlogLimits& limits) {
  if (bytes.data == nullptr) bytes.size = 0;
  static const std::uint8_t kNothing = 0;
  if (bytes.size == 0) bytes.data = &kNothing;  // memcmp of 0 bytes still wants a valid pointer
  UlogReader reader(bytes, out, limits);
  return reader.read();
}

}  // namespace quadfdi
