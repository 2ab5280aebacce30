#include "logs/dataflash_text.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "logs/dataflash.h"

namespace quadfdi {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// The fields of a line after its name: split at every comma, each trimmed. `starts` keeps where
// each began, so that a string field holding commas (a MSG) can be taken whole.
void splitFields(std::string_view rest, std::vector<std::string_view>& fields, std::vector<std::size_t>& starts) {
  fields.clear();
  starts.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = rest.find(',', start);
    const std::size_t end = comma == std::string_view::npos ? rest.size() : comma;
    fields.push_back(trim(rest.substr(start, end - start)));
    starts.push_back(start);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

// A number as printed: decimal, optionally signed ('+' too), "nan"/"inf"/"infinity" in any case,
// pymavlink's "qnan". False when anything is left over.
bool parseReal(std::string_view s, double& v) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s == "qnan" || s == "-qnan") {
    v = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (s.empty()) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// An integer as printed, exact to 64 bits; an integral decimal ("3.0", "1e3") is accepted too.
// False when it is no number or not integral; `in_range` false when it lies outside [lo, hi].
bool parseInteger(std::string_view s, std::int64_t lo, std::uint64_t hi, std::uint64_t& bits, bool& in_range) {
  in_range = true;
  std::string_view body = s;
  if (!body.empty() && body.front() == '+') body.remove_prefix(1);
  const bool negative = !body.empty() && body.front() == '-';
  if (negative) {
    std::int64_t v = 0;
    const auto r = std::from_chars(body.data(), body.data() + body.size(), v);
    if (r.ec == std::errc() && r.ptr == body.data() + body.size()) {
      in_range = v >= lo;
      bits = static_cast<std::uint64_t>(v);
      return true;
    }
    if (r.ec == std::errc::result_out_of_range) {
      in_range = false;
      return true;
    }
  } else {
    std::uint64_t v = 0;
    const auto r = std::from_chars(body.data(), body.data() + body.size(), v);
    if (r.ec == std::errc() && r.ptr == body.data() + body.size()) {
      in_range = v <= hi;
      bits = v;
      return true;
    }
    if (r.ec == std::errc::result_out_of_range) {
      in_range = false;
      return true;
    }
  }
  double d = 0.0;
  if (!parseReal(s, d) || !std::isfinite(d) || d != std::floor(d)) return false;
  // Beyond ±2^63 no double is an exact 64-bit integer; within, the cast is exact.
  if (d < static_cast<double>(lo) || d > static_cast<double>(hi) || std::fabs(d) >= 9.2e18) {
    in_range = false;
    return true;
  }
  bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(d));
  return true;
}

struct IntegerType {
  std::int64_t lo;
  std::uint64_t hi;
  std::size_t bytes;
};

// The integer a format character stores (c, C, e, E and L included: their stored integers).
bool integerType(char c, IntegerType& t) {
  switch (c) {
    case 'b': t = {-128, 127, 1}; return true;
    case 'B': t = {0, 255, 1}; return true;
    case 'h': case 'c': t = {-32768, 32767, 2}; return true;
    case 'H': case 'C': t = {0, 65535, 2}; return true;
    case 'i': case 'e': case 'L': t = {std::numeric_limits<std::int32_t>::min(), 2147483647u, 4}; return true;
    case 'I': case 'E': t = {0, 4294967295u, 4}; return true;
    case 'q': t = {std::numeric_limits<std::int64_t>::min(), 9223372036854775807u, 8}; return true;
    case 'Q': t = {0, std::numeric_limits<std::uint64_t>::max(), 8}; return true;
    default: return false;
  }
}

// The factor a printed value of c, C, e, E (×100) or L (×1e7) takes back to its stored integer;
// 0 for the other characters.
double storedFactor(char c) {
  switch (c) {
    case 'c': case 'C': case 'e': case 'E': return 100.0;
    case 'L': return 1e7;
    default: return 0.0;
  }
}

std::size_t stringBytes(char c) { return c == 'n' ? 4 : c == 'N' ? 16 : c == 'Z' ? 64 : 0; }  // char[4], [16], [64]

bool printableName(std::string_view s) {
  if (s.empty() || s.size() > kDataflashNameLen) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return c >= 0x21 && c <= 0x7e; });
}

// A message type as its FMT line defined it.
struct TextType {
  std::string name;
  std::uint8_t type = 0;
  std::string format;  // as printed (re-encoded with a flight mode, M, as a float, to hold a NaN)
  std::string labels_text;
};

class TextReader {
 public:
  TextReader(ByteSpan bytes, DecodedLog& out) : p_(reinterpret_cast<const char*>(bytes.data)), n_(bytes.size), out_(out) {}
  LogIssue run();

 private:
  void readFmt(std::uint64_t line);
  void readData(std::uint64_t line, const TextType& t, std::string_view rest);
  bool encodeField(std::uint64_t line, const TextType& t, std::size_t k, std::string_view value);
  void problem(std::uint64_t line, const std::string& key, const std::string& text);
  void header(std::uint64_t line, std::uint8_t type);
  void emitFmt(std::uint64_t line, std::uint8_t type, const std::string& name, const std::string& format, const std::string& labels);
  template <typename T>
  void put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    bin_.insert(bin_.end(), b, b + sizeof(T));
  }
  void putInteger(std::uint64_t bits, std::size_t bytes) {  // little-endian, as DataFlash
    for (std::size_t k = 0; k < bytes; ++k) bin_.push_back(static_cast<char>((bits >> (8 * k)) & 0xFF));
  }
  void putChars(std::string_view s, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) bin_.push_back(k < s.size() ? s[k] : '\0');
  }
  std::uint64_t lineOfOffset(std::uint64_t offset) const;
  void collectWarnings(std::vector<std::string> binary_warnings);

  const char* p_;
  std::size_t n_;
  DecodedLog& out_;
  std::vector<char> bin_;  // the binary log the text was printed from
  std::vector<std::pair<std::uint64_t, std::uint64_t>> line_of_;  // (first byte of a message in bin_, its line)
  std::vector<std::unique_ptr<TextType>> definitions_;
  std::map<std::string, const TextType*, std::less<>> by_name_;  // the latest FMT of each name
  std::array<const TextType*, 256> by_id_{};                     // the first FMT of each type id
  struct Problem {
    std::uint64_t line;  // its first line
    std::size_t count;   // lines like it
    std::string text;
  };
  std::vector<Problem> problems_;
  std::map<std::string, std::size_t> problem_index_;  // key → problems_ index
  std::vector<std::string_view> fields_;
  std::vector<std::size_t> starts_;
};

void TextReader::problem(std::uint64_t line, const std::string& key, const std::string& text) {
  const auto [it, added] = problem_index_.emplace(key, problems_.size());
  if (added) problems_.push_back(Problem{line, 1, text});
  else ++problems_[it->second].count;
}

void TextReader::header(std::uint64_t line, std::uint8_t type) {
  line_of_.emplace_back(bin_.size(), line);
  bin_.push_back(static_cast<char>(kDataflashHead1));
  bin_.push_back(static_cast<char>(kDataflashHead2));
  bin_.push_back(static_cast<char>(type));
}

// The binary FMT message that defines `type`, its length the one `format` needs.
void TextReader::emitFmt(std::uint64_t line, std::uint8_t type, const std::string& name, const std::string& format,
                         const std::string& labels) {
  header(line, kDataflashFmtType);
  put<std::uint8_t>(type);
  put<std::uint8_t>(static_cast<std::uint8_t>(dataflashMessageLength(format)));
  putChars(name, kDataflashNameLen);
  putChars(format, kDataflashFormatLen);
  putChars(labels, kDataflashLabelsLen);
}

std::uint64_t TextReader::lineOfOffset(std::uint64_t offset) const {
  const auto it = std::upper_bound(line_of_.begin(), line_of_.end(), offset,
                                   [](std::uint64_t o, const std::pair<std::uint64_t, std::uint64_t>& m) { return o < m.first; });
  return it == line_of_.begin() ? 1 : std::prev(it)->second;
}

// "FMT, Type, Length, Name, Format, Columns" (fields_ after the name): the columns hold commas of their own.
void TextReader::readFmt(std::uint64_t line) {
  const std::vector<std::string_view>& f = fields_;
  if (f.size() < 4) {
    problem(line, "fmt-short", "FMT line with " + std::to_string(f.size()) + " fields, not Type, Length, Name, Format, Columns; skipped");
    return;
  }
  std::uint64_t type = 0, length = 0;
  bool type_in_range = false, length_in_range = false;
  if (!parseInteger(f[0], 0, 255, type, type_in_range) || !type_in_range || !parseInteger(f[1], 0, 255, length, length_in_range) ||
      !length_in_range) {
    problem(line, "fmt-numbers", "FMT line: Type and Length must be integers 0..255, not '" + std::string(f[0]) + "' and '" +
                                     std::string(f[1]) + "'; skipped");
    return;
  }
  const std::string name(f[2]);
  const std::string format(f[3]);
  std::string labels;
  std::size_t label_count = 0;
  for (std::size_t k = 4; k < f.size(); ++k, ++label_count) labels += (k > 4 ? "," : "") + std::string(f[k]);
  if (format.empty() && labels.empty()) label_count = 0;
  if (!printableName(name)) {
    problem(line, "fmt-name", "FMT line: the name '" + name + "' is not 1 to 4 printable characters; skipped");
    return;
  }
  if (type == kDataflashFmtType || name == "FMT") {
    // The text form's own layout: FMT lines are read by position whatever this line says.
    if (type != kDataflashFmtType || name != "FMT" || format != "BBnNZ")
      problem(line, "fmt-fmt", "FMT line describes FMT as type " + std::to_string(type) + " " + name + " \"" + format +
                                   "\", not type 128 FMT \"BBnNZ\" (the text form's own layout); ignored");
    return;
  }
  std::string stored = format;
  std::replace(stored.begin(), stored.end(), 'M', 'f');
  const std::size_t needed = dataflashMessageLength(format);
  if (format.size() > kDataflashFormatLen || labels.size() > kDataflashLabelsLen || needed == 0 || dataflashMessageLength(stored) > 255) {
    problem(line, "fmt-format " + name, "FMT line for " + name + ": the format \"" + format +
                                            "\" is not up to 16 DataFlash format characters with up to 64 characters of labels; "
                                            "skipped, and its messages with it");
    return;
  }
  if (label_count != format.size()) {
    problem(line, "fmt-labels " + name, "FMT line for " + name + ": " + std::to_string(label_count) + " labels for " +
                                            std::to_string(format.size()) + " format characters; skipped, and its messages with it");
    return;
  }
  const TextType*& first = by_id_[static_cast<std::size_t>(type)];
  if (first) {
    // The binary reader keeps a type's first FMT; a repeated identical line changes nothing.
    if (first->name != name || first->format != format || first->labels_text != labels)
      problem(line, "fmt-redefined " + std::to_string(type), "FMT line redefines type " + std::to_string(type) + " (" + first->name +
                                                                 " → " + name + "); kept the first definition");
    return;
  }
  if (needed != length)
    problem(line, "fmt-length " + name, "FMT line for " + name + " declares length " + std::to_string(length) + " but its format \"" +
                                            format + "\" needs " + std::to_string(needed) + " bytes; read by its format");
  auto t = std::make_unique<TextType>();
  t->name = name;
  t->type = static_cast<std::uint8_t>(type);
  t->format = format;
  t->labels_text = labels;
  first = t.get();
  by_name_[name] = t.get();
  definitions_.push_back(std::move(t));
  emitFmt(line, first->type, name, stored, labels);
}

bool TextReader::encodeField(std::uint64_t line, const TextType& t, std::size_t k, std::string_view value) {
  const char c = t.format[k];
  // "NAME.Label" of this field, for a warning (built only then: this runs for every field of every line).
  const auto what = [&] {
    std::size_t start = 0;
    for (std::size_t i = 0; i < k; ++i) start = t.labels_text.find(',', start) + 1;  // the FMT line has a label per field
    return t.name + "." + t.labels_text.substr(start, t.labels_text.find(',', start) - start);
  };
  auto refuse = [&](const std::string& why) {
    problem(line, "field " + what() + why.substr(0, 12), what() + ": '" + std::string(value.substr(0, 40)) + "' " + why + "; line skipped");
    return false;
  };
  if (const std::size_t n = stringBytes(c); n > 0) {
    if (value.size() > n) problem(line, "long " + what(), what() + ": " + std::to_string(value.size()) + " characters, kept the first " + std::to_string(n));
    putChars(value, n);
    return true;
  }
  // UNIT's and MULT's Id is a character stored as int8: printed as its code (100) or as itself (d).
  if ((t.name == "UNIT" || t.name == "MULT") && k == 1 && c == 'b' && value.size() == 1 && !(value[0] >= '0' && value[0] <= '9')) {
    bin_.push_back(value[0]);
    return true;
  }
  if (c == 'f' || c == 'd' || c == 'M') {
    double v = 0.0;
    if (!parseReal(value, v)) {
      if (c != 'M') return refuse("is not a number");
      v = std::numeric_limits<double>::quiet_NaN();  // a mode printed by its name
    }
    if (c == 'd') put(v);
    else if (std::isfinite(v) && std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max())) return refuse("is outside a float's range");
    else put(static_cast<float>(v));
    return true;
  }
  if (c == 'a') {  // 32 integers, separated by spaces, optionally in brackets
    std::string_view list = value;
    if (!list.empty() && list.front() == '[') list.remove_prefix(1);
    if (!list.empty() && list.back() == ']') list.remove_suffix(1);
    std::size_t count = 0;
    std::array<std::int16_t, kDataflashArrayLen> a{};
    while (true) {
      while (!list.empty() && list.front() == ' ') list.remove_prefix(1);
      if (list.empty()) break;
      const std::size_t end = std::min(list.find(' '), list.size());
      std::uint64_t bits = 0;
      bool in_range = false;
      if (count == kDataflashArrayLen || !parseInteger(list.substr(0, end), -32768, 32767, bits, in_range) || !in_range)
        return refuse("is not 32 integers of int16 separated by spaces");
      a[count++] = static_cast<std::int16_t>(static_cast<std::int64_t>(bits));
      list.remove_prefix(end);
    }
    if (count != kDataflashArrayLen) return refuse("is not 32 integers of int16 separated by spaces");
    for (std::int16_t x : a) put(x);
    return true;
  }
  IntegerType it{};
  if (!integerType(c, it)) return refuse("has a format character the reader does not know");  // checked at the FMT
  std::uint64_t bits = 0;
  bool in_range = false;
  if (const double factor = storedFactor(c); factor > 0.0) {
    double v = 0.0;
    if (!parseReal(value, v) || !std::isfinite(v)) return refuse("is not a number");
    const double stored = std::round(v * factor);
    if (stored < static_cast<double>(it.lo) || stored > static_cast<double>(it.hi))
      return refuse("is outside the range of its stored type");
    bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(stored));
  } else {
    if (!parseInteger(value, it.lo, it.hi, bits, in_range)) return refuse("is not an integer");
    if (!in_range) return refuse("is outside the range of its type");
  }
  putInteger(bits, it.bytes);
  return true;
}

void TextReader::readData(std::uint64_t line, const TextType& t, std::string_view rest) {
  const std::size_t k = t.format.size();
  std::size_t given = fields_.size();
  if (k == 0 && given == 1 && fields_[0].empty()) given = 0;
  // A string last (MSG's text) may hold commas: the rest of the line is its value.
  const bool string_last = k > 0 && stringBytes(t.format.back()) > 0;
  if (given < k || (given > k && !string_last)) {
    problem(line, "count " + t.name, t.name + " line with " + std::to_string(given) + " fields, its FMT has " + std::to_string(k) +
                                         "; skipped");
    return;
  }
  const std::size_t size_before = bin_.size();
  const std::size_t lines_before = line_of_.size();
  header(line, t.type);
  for (std::size_t i = 0; i < k; ++i) {
    const std::string_view value = (i + 1 == k && given > k) ? trim(rest.substr(starts_[i])) : fields_[i];
    if (!encodeField(line, t, i, value)) {
      bin_.resize(size_before);
      line_of_.resize(lines_before);
      return;
    }
  }
}

void TextReader::collectWarnings(std::vector<std::string> binary_warnings) {
  std::vector<std::string> all;
  std::stable_sort(problems_.begin(), problems_.end(), [](const Problem& a, const Problem& b) { return a.line < b.line; });
  for (const Problem& p : problems_)
    all.push_back("line " + std::to_string(p.line) + ": " + p.text +
                  (p.count > 1 ? " (and " + std::to_string(p.count - 1) + " more line" + (p.count > 2 ? "s" : "") + " like it)" : ""));
  // The binary reader's "byte N: …" names a byte of the re-encoded log: said as the line it came from.
  for (std::string& w : binary_warnings) {
    std::uint64_t offset = 0;
    const auto r = w.rfind("byte ", 0) == 0 ? std::from_chars(w.data() + 5, w.data() + w.size(), offset) : std::from_chars_result{};
    if (r.ptr != nullptr && r.ec == std::errc() && std::string_view(r.ptr).rfind(": ", 0) == 0)
      w = "line " + std::to_string(lineOfOffset(offset)) + std::string(r.ptr);
    all.push_back(std::move(w));
  }
  if (all.size() > kDataflashMaxWarnings + 1) {
    const std::size_t hidden = all.size() - kDataflashMaxWarnings;
    all.resize(kDataflashMaxWarnings);
    all.push_back(std::to_string(hidden) + " further warnings not shown");
  }
  out_.warnings = std::move(all);
}

LogIssue TextReader::run() {
  out_ = DecodedLog{};
  out_.format = LogFormat::kDataflash;
  if (n_ == 0 || p_ == nullptr) return LogIssue{LogStatus::kTruncated, 0, "", "empty log", 1};
  if (static_cast<std::uint64_t>(n_) > kDataflashMaxBytes)
    return LogIssue{LogStatus::kTooLarge, 0, "", "log of " + std::to_string(n_) + " bytes; the reader accepts up to " +
                                                    std::to_string(kDataflashMaxBytes), 1};
  bin_.reserve(n_ / 2);
  // The FMT of FMT, as every binary log starts: the text form's own FMT lines need no definition.
  emitFmt(1, kDataflashFmtType, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");

  std::size_t pos = n_ >= 3 && std::memcmp(p_, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;  // a UTF-8 byte-order mark
  std::uint64_t line = 0;
  bool first = true;            // no FMT line yet
  std::size_t preamble_lines = 0;  // non-blank lines before it
  std::string preamble;            // the first of them, for the warning
  while (pos < n_) {
    ++line;
    const void* nl = std::memchr(p_ + pos, '\n', n_ - pos);
    const std::size_t end = nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - p_) : n_;
    const std::string_view text = trim(std::string_view(p_ + pos, end - pos));
    pos = end + 1;
    if (text.empty()) continue;
    const std::size_t comma = text.find(',');
    const std::string_view name = trim(text.substr(0, comma));
    const std::string_view rest = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
    if (first) {
      if (name != "FMT" || comma == std::string_view::npos) {
        // Older firmware printed a banner first ("ArduCopter V3.1.5 (3c57e771)", "Free RAM: 990").
        if (preamble.empty()) preamble = std::string(text.substr(0, 60));
        if (++preamble_lines > kDataflashTextPreambleLines)
          return LogIssue{LogStatus::kWrongMagic, 0, "",
                          "not an ArduPilot DataFlash log as text: no FMT line (\"FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,"
                          "Columns\") in its first " + std::to_string(kDataflashTextPreambleLines) + " lines of text", line};
        continue;
      }
      if (preamble_lines > 0)
        problem(1, "preamble", std::to_string(preamble_lines) + " line" + (preamble_lines > 1 ? "s" : "") +
                                   " of text before the first FMT line skipped (\"" + preamble + "\")");
      first = false;
    }
    if (comma == std::string_view::npos) {
      fields_.clear();
      starts_.clear();
    } else {
      splitFields(rest, fields_, starts_);
    }
    if (name == "FMT") {
      readFmt(line);
      continue;
    }
    const auto t = by_name_.find(name);
    if (t == by_name_.end()) {
      problem(line, "undefined " + std::string(name.substr(0, 16)),
              "message '" + std::string(name.substr(0, 16)) + "' has no FMT line before it; skipped");
      continue;
    }
    readData(line, *t->second, rest);
  }
  if (first && preamble_lines > 0)
    return LogIssue{LogStatus::kWrongMagic, 0, "", "not an ArduPilot DataFlash log as text: no FMT line (\"FMT, 128, 89, FMT, BBnNZ, "
                                                    "Type,Length,Name,Format,Columns\")", 1};
  if (first) return LogIssue{LogStatus::kTruncated, 0, "", "empty log (no line of text)", 1};

  const ByteSpan encoded{reinterpret_cast<const std::uint8_t*>(bin_.data()), bin_.size()};
  LogIssue issue = readDataflash(encoded, out_);
  if (!issue.ok()) {  // the re-encoded log always starts with a good FMT: not expected, said by its line
    issue.line = lineOfOffset(issue.offset);
    issue.offset = 0;
  }
  collectWarnings(std::move(out_.warnings));
  return issue;
}

}  // namespace

bool looksLikeDataflashText(ByteSpan bytes) {
  if (bytes.data == nullptr) return false;
  std::string_view s(reinterpret_cast<const char*>(bytes.data), bytes.size);
  if (s.rfind("\xEF\xBB\xBF", 0) == 0) s.remove_prefix(3);
  // A FMT line among the first lines (after a banner of older firmware, if any).
  for (std::size_t lines = 0; !s.empty() && lines <= kDataflashTextPreambleLines;) {
    const std::size_t end = std::min(s.find('\n'), s.size());
    const std::string_view text = trim(s.substr(0, end));
    if (text.rfind("FMT,", 0) == 0) return true;
    if (!text.empty()) ++lines;
    s.remove_prefix(std::min(end + 1, s.size()));
  }
  return false;
}

LogIssue readDataflashText(ByteSpan bytes, DecodedLog& out) {
  auto reader = std::make_unique<TextReader>(bytes, out);
  return reader->run();
}

}  // namespace quadfdi
