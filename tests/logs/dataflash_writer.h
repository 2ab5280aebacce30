// A DataFlash (.BIN) writer for tests, benchmarks and fuzz seeds (header only): FMT, FMTU, UNIT,
// MULT, PARM, MSG and data messages with any format characters, byte for byte as ArduPilot's
// AP_Logger lays them out (libraries/AP_Logger/LogStructure.h: packed little-endian structs
// behind the 0xA3 0x95 type header). Values are given as stored: c/C/e/E in hundredths, L in
// 1e-7 degrees (use centi() and e7() for physical values).
// Every message is also printed into `text`, the log as text the way Mission Planner writes its
// .log: "NAME, v1, v2, …", values in physical units (c/C/e/E ÷ 100, L ÷ 1e7), floats with the
// digits that give the float back, strings unpadded, an int16[32] as "[a0 a1 … a31]".
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace quadfdi::test {

// One field's value: a number (integers up to 64 bits exact), a string, or an int16[32].
struct DfValue {
  enum class Kind { kInt, kUInt, kReal, kString, kArray } kind = Kind::kInt;
  std::int64_t i = 0;
  std::uint64_t u = 0;
  double d = 0.0;
  std::string s;
  std::array<std::int16_t, 32> a{};
  DfValue(int v) : kind(Kind::kInt), i(v) {}                    // NOLINT: implicit on purpose
  DfValue(long v) : kind(Kind::kInt), i(v) {}                   // NOLINT
  DfValue(long long v) : kind(Kind::kInt), i(v) {}              // NOLINT
  DfValue(unsigned v) : kind(Kind::kUInt), u(v) {}              // NOLINT
  DfValue(unsigned long v) : kind(Kind::kUInt), u(v) {}         // NOLINT
  DfValue(unsigned long long v) : kind(Kind::kUInt), u(v) {}    // NOLINT
  DfValue(double v) : kind(Kind::kReal), d(v) {}                // NOLINT
  DfValue(const char* v) : kind(Kind::kString), s(v) {}        // NOLINT
  DfValue(std::string v) : kind(Kind::kString), s(std::move(v)) {}  // NOLINT
  DfValue(const std::array<std::int16_t, 32>& v) : kind(Kind::kArray), a(v) {}  // NOLINT
  std::int64_t asInt() const {
    return kind == Kind::kInt ? i : kind == Kind::kUInt ? static_cast<std::int64_t>(u) : static_cast<std::int64_t>(std::llround(d));
  }
  std::uint64_t asUInt() const {
    return kind == Kind::kUInt ? u : kind == Kind::kInt ? static_cast<std::uint64_t>(i) : static_cast<std::uint64_t>(std::llround(d));
  }
  double asReal() const {
    return kind == Kind::kReal ? d : kind == Kind::kInt ? static_cast<double>(i) : static_cast<double>(u);
  }
};

inline long long centi(double v) { return std::llround(v * 100.0); }  // for c, C, e, E
inline long long e7(double deg) { return std::llround(deg * 1e7); }   // for L

// Bytes of one field of format character c (0 for an unknown one).
inline std::size_t dfCharSize(char c) {
  switch (c) {
    case 'b': case 'B': case 'M': return 1;
    case 'h': case 'H': case 'c': case 'C': return 2;
    case 'i': case 'I': case 'e': case 'E': case 'L': case 'f': case 'n': return 4;
    case 'q': case 'Q': case 'd': return 8;
    case 'N': return 16;
    case 'Z': case 'a': return 64;
    default: return 0;
  }
}

class DataflashWriter {
 public:
  static constexpr std::uint8_t kFmt = 128;  // LOG_FORMAT_MSG
  // Type ids for the self-description (any free ids do: the reader recognises these messages by name).
  static constexpr std::uint8_t kParm = 64, kUnit = 177, kFmtu = 178, kMult = 179, kMsg = 91;

  // Starts with the FMT that describes FMT (ArduPilot's first message); `standard` also defines
  // PARM, MSG, UNIT, MULT and FMTU as ArduPilot 4.x does.
  explicit DataflashWriter(bool standard = true) {
    fmt(kFmt, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");
    if (standard) {
      fmt(kParm, "PARM", "QNf", "TimeUS,Name,Value");
      fmt(kMsg, "MSG", "QZ", "TimeUS,Message");
      fmt(kUnit, "UNIT", "QbZ", "TimeUS,Id,Label");
      fmt(kMult, "MULT", "Qbd", "TimeUS,Id,Mult");
      fmt(kFmtu, "FMTU", "QBNN", "TimeUS,FmtType,UnitIds,MultIds");
    }
  }

  static std::size_t lengthOf(const std::string& format) {
    std::size_t n = 3;
    for (char c : format) n += dfCharSize(c);
    return n;
  }

  // A FMT with the length its format needs.
  void fmt(std::uint8_t type, const std::string& name, const std::string& format, const std::string& labels) {
    fmtRaw(type, static_cast<std::uint8_t>(lengthOf(format)), name, format, labels);
    formats_[type] = format;
  }
  // A FMT with any length (for bad inputs); does not register the format.
  void fmtRaw(std::uint8_t type, std::uint8_t length, const std::string& name, const std::string& format, const std::string& labels) {
    header(kFmt);
    put<std::uint8_t>(type);
    put<std::uint8_t>(length);
    chars(name, 4);
    chars(format, 16);
    chars(labels, 64);
    text += "FMT, " + std::to_string(type) + ", " + std::to_string(length) + ", " + name + ", " + format + ", " + labels + "\n";
    names_[type] = name;
  }
  void fmtu(std::uint64_t t, std::uint8_t type, const std::string& units, const std::string& mults) {
    write(kFmtu, {t, static_cast<unsigned>(type), units, mults});
  }
  void unit(std::uint64_t t, char id, const std::string& label) { write(kUnit, {t, static_cast<int>(id), label}); }
  void mult(std::uint64_t t, char id, double m) { write(kMult, {t, static_cast<int>(id), m}); }
  void parm(std::uint64_t t, const std::string& name, double value) { write(kParm, {t, name, value}); }
  void msg(std::uint64_t t, const std::string& message) { write(kMsg, {t, message}); }

  // A data message of a type defined with fmt(): one value per format character.
  void write(std::uint8_t type, const std::vector<DfValue>& values) {
    const auto it = formats_.find(type);
    if (it == formats_.end()) throw std::logic_error("DataflashWriter: type without fmt()");
    const std::string& format = it->second;
    if (values.size() != format.size()) throw std::logic_error("DataflashWriter: value count differs from the format");
    header(type);
    text += names_[type];
    for (std::size_t k = 0; k < format.size(); ++k) {
      field(format[k], values[k]);
      text += ", " + printed(format[k], values[k]);
    }
    text += "\n";
  }

  void raw(const std::vector<std::uint8_t>& b) { bytes.insert(bytes.end(), b.begin(), b.end()); }

  std::vector<std::uint8_t> bytes;
  std::string text;

 private:
  static std::string number(int digits, double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
  }
  // One value as Mission Planner prints it: physical units, no padding.
  static std::string printed(char c, const DfValue& v) {
    switch (c) {
      case 'b': case 'h': case 'i': case 'q': return std::to_string(v.asInt());
      case 'B': case 'M': case 'H': case 'I': case 'Q': return std::to_string(v.asUInt());
      case 'c': case 'e': return number(10, static_cast<double>(v.asInt()) / 100.0);
      case 'C': case 'E': return number(10, static_cast<double>(v.asUInt()) / 100.0);
      case 'L': return number(10, static_cast<double>(v.asInt()) / 1e7);
      case 'f': return number(9, static_cast<double>(static_cast<float>(v.asReal())));
      case 'd': return number(17, v.asReal());
      case 'n': case 'N': case 'Z': return v.s.substr(0, dfCharSize(c));
      case 'a': {
        std::string s = "[";
        for (std::size_t k = 0; k < v.a.size(); ++k) s += (k ? " " : "") + std::to_string(v.a[k]);
        return s + "]";
      }
      default: return "?";
    }
  }
  template <typename T>
  void put(T v) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    bytes.insert(bytes.end(), b, b + sizeof(T));
  }
  void chars(const std::string& s, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) bytes.push_back(k < s.size() ? static_cast<std::uint8_t>(s[k]) : 0);
  }
  void header(std::uint8_t type) {
    bytes.push_back(0xA3);
    bytes.push_back(0x95);
    bytes.push_back(type);
  }
  void field(char c, const DfValue& v) {
    switch (c) {
      case 'b': put(static_cast<std::int8_t>(v.asInt())); break;
      case 'B': case 'M': put(static_cast<std::uint8_t>(v.asUInt())); break;
      case 'h': case 'c': put(static_cast<std::int16_t>(v.asInt())); break;
      case 'H': case 'C': put(static_cast<std::uint16_t>(v.asUInt())); break;
      case 'i': case 'e': case 'L': put(static_cast<std::int32_t>(v.asInt())); break;
      case 'I': case 'E': put(static_cast<std::uint32_t>(v.asUInt())); break;
      case 'q': put(static_cast<std::int64_t>(v.asInt())); break;
      case 'Q': put(static_cast<std::uint64_t>(v.asUInt())); break;
      case 'f': put(static_cast<float>(v.asReal())); break;
      case 'd': put(v.asReal()); break;
      case 'n': chars(v.s, 4); break;
      case 'N': chars(v.s, 16); break;
      case 'Z': chars(v.s, 64); break;
      case 'a': for (std::int16_t x : v.a) put(x); break;
      default: throw std::logic_error("DataflashWriter: unknown format character");
    }
  }
  std::map<std::uint8_t, std::string> formats_;
  std::map<std::uint8_t, std::string> names_;
};

// Every format character, at its extremes where it has them (the integer limits, NaN, −0, a
// TimeUS beyond int64), an int16[32] and the three string sizes, a TimeMS type, VER, PARM and a
// MSG with commas: for the readers' tests and the fuzz seeds.
inline DataflashWriter everyFormatCharacterLog() {
  DataflashWriter w;
  w.fmt(200, "ALL", "QbBhHiIfdcCeELMq", "TimeUS,b,B,h,H,i,I,f,d,c,C,e,E,L,M,q");
  w.write(200, {1ull, -1, 2, -3, 4, -5, 6u, 0.1, 0.25, -7, 8, -9, 10u, e7(47.1234567), 6, -11});
  w.write(200, {2ull, -128, 255, -32768, 65535, -2147483647 - 1, 4294967295u, std::nan(""), 1e300, -32768, 65535, -2147483647 - 1,
                4294967295u, e7(-179.9999999), 255, -9223372036854775807LL});
  w.write(200, {18446744073709551615ull, 127, 0, 32767, 0, 2147483647, 0u, -3.4e38, -0.0, 32767, 0, 2147483647, 0u, e7(0.0000001), 0,
                9223372036854775807LL});
  w.fmt(201, "ARR", "QanNZ", "TimeUS,Arr,Sh,Md,Lg");
  std::array<std::int16_t, 32> a{};
  a[0] = -32768;
  a[3] = 77;
  a[31] = 32767;
  w.write(201, {2ull, a, "abcd", "sixteen chars!!!", "long"});
  w.fmt(202, "OLD", "Ih", "TimeMS,V");
  w.write(202, {5u, 1});
  w.fmt(203, "VER", "QBHBBBBIZH", "TimeUS,BT,BST,Maj,Min,Pat,FWT,GH,FWS,APJ");
  w.write(203, {3ull, 3, 0, 4, 5, 1, 255, 1u, "ArduCopter V4.5.1", 140});
  w.parm(4, "MOT_THST_EXPO", 0.65);
  w.msg(6, "PreArm: Gyros inconsistent, check IMU, 2 and 3");  // commas in the last field
  return w;
}

}  // namespace quadfdi::test
