#include "logs/dataflash.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace quadfdi {
namespace {

// LogStructure.h: LOG_PACKET_HEADER_LEN and sizeof(log_Format) = 3 + 1 + 1 + 4 + 16 + 64.
constexpr std::size_t kHeaderLen = 3;
constexpr std::size_t kFmtLen = 89;

// How one field is read from the message bytes.
enum class Op : std::uint8_t { kI8, kU8, kI16, kU16, kI32, kU32, kI64, kU64, kF32, kF64, kString };

struct CharInfo {
  Op op = Op::kString;
  std::size_t size = 0;    // [bytes] of one element
  std::size_t count = 1;   // elements (32 for 'a')
  double scale = 1.0;      // implied by the character (c/C/e/E ×0.01, L ×1e-7)
  FieldType type = FieldType::kChar;
  bool ok = false;
};

// The format characters of LogStructure.h.
CharInfo charInfo(char c) {
  CharInfo i;
  i.ok = true;
  switch (c) {
    case 'b': i.op = Op::kI8; i.size = 1; i.type = FieldType::kInt8; break;
    case 'B': case 'M': i.op = Op::kU8; i.size = 1; i.type = FieldType::kUInt8; break;
    case 'h': i.op = Op::kI16; i.size = 2; i.type = FieldType::kInt16; break;
    case 'H': i.op = Op::kU16; i.size = 2; i.type = FieldType::kUInt16; break;
    case 'i': i.op = Op::kI32; i.size = 4; i.type = FieldType::kInt32; break;
    case 'I': i.op = Op::kU32; i.size = 4; i.type = FieldType::kUInt32; break;
    case 'q': i.op = Op::kI64; i.size = 8; i.type = FieldType::kInt64; break;
    case 'Q': i.op = Op::kU64; i.size = 8; i.type = FieldType::kUInt64; break;
    case 'f': i.op = Op::kF32; i.size = 4; i.type = FieldType::kFloat; break;
    case 'd': i.op = Op::kF64; i.size = 8; i.type = FieldType::kDouble; break;
    case 'c': i.op = Op::kI16; i.size = 2; i.type = FieldType::kInt16; i.scale = 0.01; break;
    case 'C': i.op = Op::kU16; i.size = 2; i.type = FieldType::kUInt16; i.scale = 0.01; break;
    case 'e': i.op = Op::kI32; i.size = 4; i.type = FieldType::kInt32; i.scale = 0.01; break;
    case 'E': i.op = Op::kU32; i.size = 4; i.type = FieldType::kUInt32; i.scale = 0.01; break;
    case 'L': i.op = Op::kI32; i.size = 4; i.type = FieldType::kInt32; i.scale = 1e-7; break;
    case 'a': i.op = Op::kI16; i.size = 2; i.count = kDataflashArrayLen; i.type = FieldType::kInt16; break;
    case 'n': i.op = Op::kString; i.size = 4; break;
    case 'N': i.op = Op::kString; i.size = 16; break;
    case 'Z': i.op = Op::kString; i.size = 64; break;
    default: i.ok = false; break;
  }
  return i;
}

template <typename T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);  // DataFlash is little-endian, as every host we build for
  return v;
}

double readOp(Op op, const std::uint8_t* p) {
  switch (op) {
    case Op::kI8: return static_cast<double>(load<std::int8_t>(p));
    case Op::kU8: return static_cast<double>(load<std::uint8_t>(p));
    case Op::kI16: return static_cast<double>(load<std::int16_t>(p));
    case Op::kU16: return static_cast<double>(load<std::uint16_t>(p));
    case Op::kI32: return static_cast<double>(load<std::int32_t>(p));
    case Op::kU32: return static_cast<double>(load<std::uint32_t>(p));
    case Op::kI64: return static_cast<double>(load<std::int64_t>(p));
    case Op::kU64: return static_cast<double>(load<std::uint64_t>(p));
    case Op::kF32: return static_cast<double>(load<float>(p));
    case Op::kF64: return load<double>(p);
    case Op::kString: return 0.0;
  }
  return 0.0;
}

// A fixed-size, NUL-padded char array as a string (up to the first NUL).
std::string fixedString(const std::uint8_t* p, std::size_t n) {
  std::size_t len = 0;
  while (len < n && p[len] != 0) ++len;
  return std::string(reinterpret_cast<const char*>(p), len);
}

// What the reader does with a type besides (or instead of) making it a topic.
enum class Kind : std::uint8_t { kData, kFmtu, kUnit, kMult, kParm, kMsg, kVer };

struct Column {       // one decoded column: where it is and how it is read
  std::uint16_t offset;  // [bytes] from the start of the message (header included)
  Op op;
  double scale;
};

struct FieldSlot {    // one format character
  char c = 0;
  std::uint16_t offset = 0;  // [bytes] from the start of the message
  int first_column = -1;     // −1 for strings
  int columns = 0;
};

enum class TimeKind : std::uint8_t { kNone, kMicros, kMillis };

// A type's decode plan, built once from its FMT.
struct Definition {
  bool defined = false;
  std::uint8_t length = 0;  // [bytes] header included
  std::string name, format, labels_text;
  std::vector<std::string> labels;
  std::vector<FieldSlot> slots;     // per format character
  std::vector<Column> columns;      // per stored column
  std::vector<LogField> fields;     // per stored column
  TimeKind time = TimeKind::kNone;
  std::uint16_t time_offset = 0;
  Op time_op = Op::kU64;
  Kind kind = Kind::kData;
  int table = -1;                   // index into Reader::tables_, once it has rows
};

// The rows of one type before the instance split.
struct Table {
  std::uint8_t type = 0;
  std::vector<std::int64_t> t;
  std::vector<std::vector<double>> cols;
};

std::vector<std::string> splitLabels(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = s.find(',', start);
    out.push_back(s.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

bool printableName(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < 0x21 || c > 0x7e) return false;
  return true;
}

std::string formatNumber(double v) {
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15) return std::to_string(static_cast<long long>(v));
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

class Reader {
 public:
  Reader(ByteSpan bytes, DecodedLog& out) : p_(bytes.data), n_(bytes.size), out_(out) {}

  LogIssue run();

 private:
  // FMT at pos_ (kFmtLen bytes available): defines a type; empty string or a reason.
  std::string parseFmt(const std::uint8_t* m, bool first);
  void decodeData(Definition& d, const std::uint8_t* m);
  void special(const Definition& d, const std::uint8_t* m, std::int64_t t);
  std::int64_t timeOf(const Definition& d, const std::uint8_t* m);
  bool known(std::size_t at) const;
  void resync(std::size_t from, const std::string& why);
  void warn(std::uint64_t offset, const std::string& text) { warnAt("byte " + std::to_string(offset) + ": " + text); }
  void warnAt(const std::string& text);
  void finish();

  int slotIndex(const Definition& d, const char* label) const {
    for (std::size_t i = 0; i < d.labels.size() && i < d.slots.size(); ++i)
      if (d.labels[i] == label) return static_cast<int>(i);
    return -1;
  }
  double number(const Definition& d, const std::uint8_t* m, int slot) const {
    const FieldSlot& s = d.slots[static_cast<std::size_t>(slot)];
    const CharInfo ci = charInfo(s.c);
    return readOp(ci.op, m + s.offset) * ci.scale;
  }
  std::string text(const Definition& d, const std::uint8_t* m, int slot) const {
    const FieldSlot& s = d.slots[static_cast<std::size_t>(slot)];
    return fixedString(m + s.offset, charInfo(s.c).size);
  }

  const std::uint8_t* p_;
  std::size_t n_;
  DecodedLog& out_;
  std::size_t pos_ = 0;
  std::array<Definition, 256> defs_{};
  std::vector<Table> tables_;
  std::int64_t last_time_us_ = 0;
  std::size_t suppressed_ = 0;
  std::map<std::uint8_t, std::pair<std::string, std::string>> fmtu_;  // type → (unit ids, mult ids)
  std::map<char, std::string> units_;
  std::map<char, double> mults_;
  bool firmware_from_ver_ = false;
};

void Reader::warnAt(const std::string& text) {
  if (out_.warnings.size() >= kDataflashMaxWarnings) {
    ++suppressed_;
    return;
  }
  out_.warnings.push_back(text);
}

bool Reader::known(std::size_t at) const {
  if (n_ - at < kHeaderLen) return false;
  if (p_[at] != kDataflashHead1 || p_[at + 1] != kDataflashHead2) return false;
  const std::uint8_t type = p_[at + 2];
  return type == kDataflashFmtType || defs_[type].defined;
}

// Skips from `from` to the next header of a known type (or the end), with one warning.
void Reader::resync(std::size_t from, const std::string& why) {
  std::size_t at = from + 1;
  while (at < n_) {
    const void* hit = std::memchr(p_ + at, kDataflashHead1, n_ - at);
    if (!hit) {
      at = n_;
      break;
    }
    at = static_cast<std::size_t>(static_cast<const std::uint8_t*>(hit) - p_);
    if (known(at)) break;
    ++at;
  }
  if (at > n_) at = n_;
  warn(from, why + "; skipped " + std::to_string(at - from) + " bytes" +
                 (at < n_ ? " to the next message at byte " + std::to_string(at) : " to the end of the log"));
  pos_ = at;
}

std::string Reader::parseFmt(const std::uint8_t* m, bool first) {
  const std::uint8_t type = m[3];
  const std::uint8_t length = m[4];
  const std::string name = fixedString(m + 5, kDataflashNameLen);
  const std::string format = fixedString(m + 5 + kDataflashNameLen, kDataflashFormatLen);
  const std::string labels_text = fixedString(m + 5 + kDataflashNameLen + kDataflashFormatLen, kDataflashLabelsLen);

  if (!printableName(name)) return "FMT for type " + std::to_string(type) + " has no printable name";
  if (length < kHeaderLen) return "FMT " + name + " declares an impossible length " + std::to_string(length);
  for (char c : format)
    if (!charInfo(c).ok) return "FMT " + name + " has an unknown format character '" + std::string(1, c) + "'";
  const std::size_t size = dataflashMessageLength(format);
  if (size != length)
    return "FMT " + name + " declares length " + std::to_string(length) + " but its format \"" + format + "\" needs " +
           std::to_string(size) + " bytes";
  const std::vector<std::string> labels = format.empty() ? std::vector<std::string>{} : splitLabels(labels_text);
  if (labels.size() != format.size())
    return "FMT " + name + " has " + std::to_string(labels.size()) + " labels for " + std::to_string(format.size()) +
           " format characters";

  if (type == kDataflashFmtType) {
    // The FMT of FMT itself: the reader knows its layout; it must agree.
    if (length != kFmtLen || format != "BBnNZ") return "FMT describes FMT (128) with a layout other than BBnNZ, 89 bytes";
    return {};
  }
  if (first) return "the first FMT describes type " + std::to_string(type) + ", not FMT itself";

  Definition& d = defs_[type];
  if (d.defined) {
    if (d.length != length || d.name != name || d.format != format || d.labels_text != labels_text)
      warn(pos_, "FMT redefines type " + std::to_string(type) + " (" + d.name + " → " + name + "); kept the first definition");
    return {};
  }
  d = Definition{};
  d.defined = true;
  d.length = length;
  d.name = name;
  d.format = format;
  d.labels_text = labels_text;
  d.labels = labels;
  std::size_t offset = kHeaderLen;
  for (std::size_t i = 0; i < format.size(); ++i) {
    const CharInfo ci = charInfo(format[i]);
    FieldSlot s;
    s.c = format[i];
    s.offset = static_cast<std::uint16_t>(offset);
    const bool is_time = (labels[i] == "TimeUS" || labels[i] == "TimeMS") && ci.op != Op::kString && ci.count == 1 &&
                         ci.op != Op::kF32 && ci.op != Op::kF64 && d.time == TimeKind::kNone;
    if (is_time) {
      d.time = labels[i] == "TimeUS" ? TimeKind::kMicros : TimeKind::kMillis;
      d.time_offset = s.offset;
      d.time_op = ci.op;
    } else if (ci.op != Op::kString) {
      s.first_column = static_cast<int>(d.columns.size());
      s.columns = static_cast<int>(ci.count);
      for (std::size_t k = 0; k < ci.count; ++k) {
        d.columns.push_back(Column{static_cast<std::uint16_t>(offset + k * ci.size), ci.op, ci.scale});
        LogField f;
        f.name = ci.count == 1 ? labels[i] : labels[i] + "[" + std::to_string(k) + "]";
        f.type = ci.type;
        f.multiplier = ci.scale;
        d.fields.push_back(std::move(f));
      }
    }
    d.slots.push_back(s);
    offset += ci.size * ci.count;
  }
  // The self-description and text messages (LogStructure.h: FMTU, UNIT, MULT, PARM, MSG, VER).
  if (name == "FMTU" && slotIndex(d, "FmtType") >= 0) d.kind = Kind::kFmtu;
  else if (name == "UNIT" && slotIndex(d, "Id") >= 0 && slotIndex(d, "Label") >= 0) d.kind = Kind::kUnit;
  else if (name == "MULT" && slotIndex(d, "Id") >= 0 && slotIndex(d, "Mult") >= 0) d.kind = Kind::kMult;
  else if (name == "PARM" && slotIndex(d, "Name") >= 0 && slotIndex(d, "Value") >= 0) d.kind = Kind::kParm;
  else if (name == "MSG" && slotIndex(d, "Message") >= 0) d.kind = Kind::kMsg;
  else if (name == "VER") d.kind = Kind::kVer;
  return {};
}

std::int64_t Reader::timeOf(const Definition& d, const std::uint8_t* m) {
  if (d.time == TimeKind::kNone) return last_time_us_;
  std::int64_t t = 0;
  switch (d.time_op) {
    case Op::kU64: {
      const std::uint64_t v = load<std::uint64_t>(m + d.time_offset);
      t = v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) ? std::numeric_limits<std::int64_t>::max()
                                                                                  : static_cast<std::int64_t>(v);
      break;
    }
    case Op::kI64: t = load<std::int64_t>(m + d.time_offset); break;
    default: t = static_cast<std::int64_t>(readOp(d.time_op, m + d.time_offset)); break;  // ≤ 32-bit integers: exact
  }
  if (d.time == TimeKind::kMillis) {
    constexpr std::int64_t kLimit = std::numeric_limits<std::int64_t>::max() / 1000;
    t = std::clamp(t, -kLimit, kLimit) * 1000;
  }
  last_time_us_ = t;
  return t;
}

void Reader::decodeData(Definition& d, const std::uint8_t* m) {
  const std::int64_t t = timeOf(d, m);
  if (d.kind != Kind::kData) {
    special(d, m, t);
    return;
  }
  if (d.table < 0) {
    d.table = static_cast<int>(tables_.size());
    Table tab;
    tab.type = static_cast<std::uint8_t>(&d - defs_.data());
    tab.cols.resize(d.columns.size());
    tables_.push_back(std::move(tab));
  }
  Table& tab = tables_[static_cast<std::size_t>(d.table)];
  tab.t.push_back(t);
  const std::size_t nc = d.columns.size();
  for (std::size_t c = 0; c < nc; ++c) {
    const Column& col = d.columns[c];
    tab.cols[c].push_back(readOp(col.op, m + col.offset) * col.scale);
  }
}

void Reader::special(const Definition& d, const std::uint8_t* m, std::int64_t t) {
  switch (d.kind) {
    case Kind::kData: break;
    case Kind::kFmtu: {
      const double type = number(d, m, slotIndex(d, "FmtType"));
      const int u = slotIndex(d, "UnitIds");
      const int mu = slotIndex(d, "MultIds");
      if (type >= 0 && type <= 255)
        fmtu_[static_cast<std::uint8_t>(type)] = {u >= 0 ? text(d, m, u) : std::string{}, mu >= 0 ? text(d, m, mu) : std::string{}};
      break;
    }
    case Kind::kUnit: {
      const int id = slotIndex(d, "Id");
      const std::uint8_t c = m[d.slots[static_cast<std::size_t>(id)].offset];
      units_[static_cast<char>(c)] = text(d, m, slotIndex(d, "Label"));
      break;
    }
    case Kind::kMult: {
      const int id = slotIndex(d, "Id");
      const std::uint8_t c = m[d.slots[static_cast<std::size_t>(id)].offset];
      mults_[static_cast<char>(c)] = number(d, m, slotIndex(d, "Mult"));
      break;
    }
    case Kind::kParm: {
      const std::string name = text(d, m, slotIndex(d, "Name"));
      if (!name.empty()) out_.parameters[name] = number(d, m, slotIndex(d, "Value"));
      break;
    }
    case Kind::kMsg: {
      LogText lt;
      lt.timestamp_us = t;
      lt.text = text(d, m, slotIndex(d, "Message"));
      if (!firmware_from_ver_ && out_.info.count("firmware") == 0) {
        static constexpr const char* kPrefixes[] = {"ArduCopter", "ArduPlane", "ArduRover", "ArduSub", "APM:", "Blimp", "AntennaTracker"};
        for (const char* prefix : kPrefixes)
          if (lt.text.rfind(prefix, 0) == 0) out_.info["firmware"] = lt.text;
      }
      out_.messages.push_back(std::move(lt));
      break;
    }
    case Kind::kVer: {
      for (std::size_t i = 0; i < d.slots.size() && i < d.labels.size(); ++i) {
        if (d.labels[i] == "TimeUS") continue;
        const CharInfo ci = charInfo(d.slots[i].c);
        if (ci.count != 1) continue;
        const int slot = static_cast<int>(i);
        out_.info["VER." + d.labels[i]] = ci.op == Op::kString ? text(d, m, slot) : formatNumber(number(d, m, slot));
        if (d.labels[i] == "FWS" && ci.op == Op::kString) {
          out_.info["firmware"] = text(d, m, slot);
          firmware_from_ver_ = true;
        }
      }
      break;
    }
  }
}

LogIssue Reader::run() {
  out_ = DecodedLog{};
  out_.format = LogFormat::kDataflash;
  LogIssue issue;
  if (n_ == 0 || p_ == nullptr) return LogIssue{LogStatus::kTruncated, 0, "", "empty log"};
  if (static_cast<std::uint64_t>(n_) > kDataflashMaxBytes)
    return LogIssue{LogStatus::kTooLarge, 0, "", "log of " + std::to_string(n_) + " bytes; the reader accepts up to " +
                                                    std::to_string(kDataflashMaxBytes)};
  if (p_[0] != kDataflashHead1 || (n_ >= 2 && p_[1] != kDataflashHead2))
    return LogIssue{LogStatus::kWrongMagic, 0, "", "not a DataFlash log: no 0xA3 0x95 header, nor a first line \"FMT, …\" of the log as text"};
  if (n_ < kHeaderLen) return LogIssue{LogStatus::kTruncated, 0, "", "log ends inside the first message header"};
  if (p_[2] != kDataflashFmtType)
    return LogIssue{LogStatus::kWrongMagic, 0, "", "the first message is type " + std::to_string(p_[2]) + ", not FMT (128)"};
  if (n_ < kFmtLen)
    return LogIssue{LogStatus::kTruncated, 0, "FMT", "log ends at byte " + std::to_string(n_) + " inside the first FMT (89 bytes)"};
  {
    const std::string why = parseFmt(p_, true);
    if (!why.empty()) return LogIssue{LogStatus::kCorrupt, 0, "FMT", why};
    pos_ = kFmtLen;
  }

  while (pos_ < n_) {
    const std::size_t left = n_ - pos_;
    if (left < kHeaderLen) {
      if (p_[pos_] == kDataflashHead1 && (left < 2 || p_[pos_ + 1] == kDataflashHead2))
        warn(pos_, "log ends inside a message header (" + std::to_string(left) + " bytes); dropped");
      else
        warn(pos_, "not a message header; skipped " + std::to_string(left) + " bytes to the end of the log");
      break;
    }
    const std::uint8_t* m = p_ + pos_;
    if (m[0] != kDataflashHead1 || m[1] != kDataflashHead2) {
      resync(pos_, "not a message header");
      continue;
    }
    const std::uint8_t type = m[2];
    if (type == kDataflashFmtType) {
      if (left < kFmtLen) {
        warn(pos_, "log ends inside a FMT (" + std::to_string(left) + " of 89 bytes); dropped");
        break;
      }
      const std::string why = parseFmt(m, false);
      if (!why.empty()) {
        resync(pos_, why);
        continue;
      }
      pos_ += kFmtLen;
      continue;
    }
    Definition& d = defs_[type];
    if (!d.defined) {
      resync(pos_, "message type " + std::to_string(type) + " has no FMT before it");
      continue;
    }
    if (left < d.length) {
      warn(pos_, "log ends inside a " + d.name + " message (" + std::to_string(left) + " of " + std::to_string(d.length) +
                     " bytes); dropped");
      break;
    }
    decodeData(d, m);
    pos_ += d.length;
  }
  finish();
  return issue;
}

// Units, multipliers and the instance split: FMTU may come after the first rows of its type, so
// they are applied once at the end.
void Reader::finish() {
  for (Table& tab : tables_) {
    const Definition& d = defs_[tab.type];
    std::vector<LogField> fields = d.fields;
    int instance_col = -1;
    const auto fu = fmtu_.find(tab.type);
    if (fu != fmtu_.end()) {
      const std::string& unit_ids = fu->second.first;
      const std::string& mult_ids = fu->second.second;
      for (std::size_t i = 0; i < d.slots.size(); ++i) {
        const FieldSlot& s = d.slots[i];
        if (s.first_column < 0) continue;
        const char uid = i < unit_ids.size() ? unit_ids[i] : '-';
        const char mid = i < mult_ids.size() ? mult_ids[i] : '-';
        std::string unit;
        if (uid == '#') {
          if (s.columns == 1 && instance_col < 0) instance_col = s.first_column;
          unit = "instance";
        } else if (const auto u = units_.find(uid); u != units_.end() && uid != '-') {
          unit = u->second;
        }
        double mult = 1.0;
        const CharInfo ci = charInfo(s.c);
        // c, C, e, E and L carry their scale in the character; their FMTU multiplier restates it
        // (ATT Roll is 'c' with multiplier 'B' = 1e-2) and is not applied twice.
        if (ci.scale == 1.0 && mid != '-' && mid != '?') {
          const auto mm = mults_.find(mid);
          if (mm != mults_.end() && std::isfinite(mm->second) && mm->second != 0.0) mult = mm->second;
        }
        for (int k = 0; k < s.columns; ++k) {
          const std::size_t c = static_cast<std::size_t>(s.first_column + k);
          fields[c].unit = unit;
          if (mult != 1.0) {
            fields[c].multiplier = mult;
            for (double& v : tab.cols[c]) v *= mult;
          }
        }
      }
    }

    // The instance split: every value of the instance field an integer 0..255, or no split.
    std::vector<int> inst;
    if (instance_col >= 0) {
      const std::vector<double>& ic = tab.cols[static_cast<std::size_t>(instance_col)];
      inst.reserve(ic.size());
      for (std::size_t r = 0; r < ic.size(); ++r) {
        const double v = ic[r];
        if (!(v >= 0.0 && v <= 255.0 && v == std::floor(v))) {
          warnAt(d.name + ": instance field " + fields[static_cast<std::size_t>(instance_col)].name + " holds " +
                      formatNumber(v) + ", not an instance number 0..255; rows not split by instance");
          inst.clear();
          break;
        }
        inst.push_back(static_cast<int>(v));
      }
    }
    const bool split = !inst.empty() && std::any_of(inst.begin(), inst.end(), [&](int v) { return v != inst[0]; });
    if (!split) {
      LogTopic topic;
      topic.name = d.name;
      topic.instance = inst.empty() ? 0 : inst[0];
      topic.fields = std::move(fields);
      topic.timestamp_us = std::move(tab.t);
      topic.columns = std::move(tab.cols);
      out_.topics.push_back(std::move(topic));
      continue;
    }
    std::array<std::size_t, 256> count{};
    for (int v : inst) ++count[static_cast<std::size_t>(v)];
    std::array<int, 256> topic_of{};
    topic_of.fill(-1);
    for (std::size_t v = 0; v < count.size(); ++v) {
      if (count[v] == 0) continue;
      topic_of[v] = static_cast<int>(out_.topics.size());
      LogTopic topic;
      topic.name = d.name;
      topic.instance = static_cast<int>(v);
      topic.fields = fields;
      topic.timestamp_us.reserve(count[v]);
      topic.columns.resize(fields.size());
      for (auto& col : topic.columns) col.reserve(count[v]);
      out_.topics.push_back(std::move(topic));
    }
    for (std::size_t r = 0; r < inst.size(); ++r) {
      LogTopic& topic = out_.topics[static_cast<std::size_t>(topic_of[static_cast<std::size_t>(inst[r])])];
      topic.timestamp_us.push_back(tab.t[r]);
      for (std::size_t c = 0; c < tab.cols.size(); ++c) topic.columns[c].push_back(tab.cols[c][r]);
    }
    tab = Table{};
  }
  if (suppressed_ > 0) out_.warnings.push_back(std::to_string(suppressed_) + " further warnings not shown");
}

}  // namespace

bool looksLikeDataflash(ByteSpan bytes) {
  return bytes.data != nullptr && bytes.size >= kHeaderLen && bytes.data[0] == kDataflashHead1 && bytes.data[1] == kDataflashHead2 &&
         bytes.data[2] == kDataflashFmtType;
}

std::size_t dataflashMessageLength(const std::string& format) {
  std::size_t size = kHeaderLen;
  for (char c : format) {
    const CharInfo ci = charInfo(c);
    if (!ci.ok) return 0;
    size += ci.size * ci.count;
  }
  return size;
}

LogIssue readDataflash(ByteSpan bytes, DecodedLog& out) {
  // Definitions of 256 types and the reading state: one Reader per call, no globals.
  auto reader = std::make_unique<Reader>(bytes, out);
  return reader->run();
}

}  // namespace quadfdi
