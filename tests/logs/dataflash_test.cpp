// The DataFlash reader (src/logs/dataflash.h) against logs made by tests/logs/dataflash_writer.h.
#include "logs/dataflash.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "logs/dataflash_writer.h"

using namespace quadfdi;
using quadfdi::test::centi;
using quadfdi::test::DataflashWriter;
using quadfdi::test::e7;

namespace {

ByteSpan span(const std::vector<std::uint8_t>& b) { return ByteSpan{b.data(), b.size()}; }

LogIssue read(const std::vector<std::uint8_t>& b, DecodedLog& log) { return readDataflash(span(b), log); }

double value(const LogTopic& t, const std::string& field, std::size_t row) {
  const int i = t.fieldIndex(field);
  EXPECT_GE(i, 0) << field;
  if (i < 0) return NAN;
  return t.columns[static_cast<std::size_t>(i)].at(row);
}

const LogField& fieldOf(const LogTopic& t, const std::string& name) {
  const int i = t.fieldIndex(name);
  EXPECT_GE(i, 0) << name;
  return t.fields.at(static_cast<std::size_t>(i < 0 ? 0 : i));
}

bool hasWarning(const DecodedLog& log, const std::string& prefix, const std::string& part) {
  for (const std::string& w : log.warnings)
    if (w.rfind(prefix, 0) == 0 && w.find(part) != std::string::npos) return true;
  return false;
}

std::string allWarnings(const DecodedLog& log) {
  std::string s;
  for (const std::string& w : log.warnings) s += w + "\n";
  return s;
}

// A log with one data type "TST" (type 200, "Qhf": TimeUS, A, B) and `rows` rows.
DataflashWriter simpleLog(int rows) {
  DataflashWriter w;
  w.fmt(200, "TST", "Qhf", "TimeUS,A,B");
  for (int r = 0; r < rows; ++r) w.write(200, {1000ull * static_cast<unsigned long long>(r + 1), r, 0.5 * r});
  return w;
}

}  // namespace

TEST(DataflashReader, LooksLikeDataflash) {
  const DataflashWriter w;
  EXPECT_TRUE(looksLikeDataflash(span(w.bytes)));
  const std::vector<std::uint8_t> ulog = {'U', 'L', 'o', 'g', 0x01, 0x12, 0x35};
  EXPECT_FALSE(looksLikeDataflash(span(ulog)));
  const std::vector<std::uint8_t> data_first = {0xA3, 0x95, 0x40};
  EXPECT_FALSE(looksLikeDataflash(span(data_first)));
  EXPECT_FALSE(looksLikeDataflash(ByteSpan{}));
}

TEST(DataflashReader, RoundTripsEveryNumericFormatCharacter) {
  DataflashWriter w;
  // 16 characters, the FMT maximum: every numeric type but a.
  w.fmt(200, "ALL", "QbBhHiIfdcCeELMq", "TimeUS,b,B,h,H,i,I,f,d,c,C,e,E,L,M,q");
  w.write(200, {123456789012ull, -128, 255, -32768, 65535, -2147483647 - 1, 4294967295u, 0.25, -1.0e300, -12345,
                60000, -123456789, 3000000000u, e7(-35.3632621), 6, -(1ll << 53)});
  w.write(200, {123456789013ull, 127, 0, 32767, 0, 2147483647, 0u, -3.5, 1.0 / 3.0, 17999, 0, 99, 1u, e7(149.1652374), 0,
                (1ll << 53)});
  DecodedLog log;
  const LogIssue issue = read(w.bytes, log);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_TRUE(log.warnings.empty()) << allWarnings(log);
  EXPECT_EQ(log.format, LogFormat::kDataflash);
  const LogTopic* t = log.find("ALL");
  ASSERT_NE(t, nullptr);
  ASSERT_EQ(t->rows(), 2u);
  EXPECT_EQ(t->timestamp_us[0], 123456789012);
  EXPECT_EQ(t->timestamp_us[1], 123456789013);
  EXPECT_EQ(t->fieldIndex("TimeUS"), -1);  // kept exactly in timestamp_us, not as a column
  ASSERT_EQ(t->fields.size(), 15u);

  const struct {
    const char* name;
    FieldType type;
    double multiplier;
    double v0, v1;
  } expect[] = {
      {"b", FieldType::kInt8, 1, -128, 127},
      {"B", FieldType::kUInt8, 1, 255, 0},
      {"h", FieldType::kInt16, 1, -32768, 32767},
      {"H", FieldType::kUInt16, 1, 65535, 0},
      {"i", FieldType::kInt32, 1, -2147483648.0, 2147483647.0},
      {"I", FieldType::kUInt32, 1, 4294967295.0, 0},
      {"f", FieldType::kFloat, 1, 0.25, -3.5},
      {"d", FieldType::kDouble, 1, -1.0e300, 1.0 / 3.0},
      {"c", FieldType::kInt16, 0.01, -12345 * 0.01, 17999 * 0.01},
      {"C", FieldType::kUInt16, 0.01, 60000 * 0.01, 0},
      {"e", FieldType::kInt32, 0.01, -123456789 * 0.01, 99 * 0.01},
      {"E", FieldType::kUInt32, 0.01, 3000000000.0 * 0.01, 0.01},
      {"L", FieldType::kInt32, 1e-7, static_cast<double>(e7(-35.3632621)) * 1e-7, static_cast<double>(e7(149.1652374)) * 1e-7},
      {"M", FieldType::kUInt8, 1, 6, 0},
      {"q", FieldType::kInt64, 1, -9007199254740992.0, 9007199254740992.0},
  };
  for (const auto& e : expect) {
    SCOPED_TRACE(e.name);
    const LogField& f = fieldOf(*t, e.name);
    EXPECT_EQ(f.type, e.type);
    EXPECT_EQ(f.multiplier, e.multiplier);
    EXPECT_EQ(value(*t, e.name, 0), e.v0);
    EXPECT_EQ(value(*t, e.name, 1), e.v1);
  }
  EXPECT_NEAR(value(*t, "L", 0), -35.3632621, 1e-12);
}

TEST(DataflashReader, ArraysAndStrings) {
  DataflashWriter w;
  w.fmt(201, "ARR", "QanNZ", "TimeUS,Arr,Sh,Md,Lg");
  std::array<std::int16_t, 32> a{};
  for (std::size_t k = 0; k < a.size(); ++k) a[k] = static_cast<std::int16_t>(1000 - 77 * static_cast<int>(k));
  w.write(201, {5ull, a, "abcd", "sixteen chars!!!", std::string(64, 'z')});
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  const LogTopic* t = log.find("ARR");
  ASSERT_NE(t, nullptr);
  // a → Arr[0..31]; the strings n, N, Z make no column.
  ASSERT_EQ(t->fields.size(), 32u);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(t->fields[k].name, "Arr[" + std::to_string(k) + "]");
    EXPECT_EQ(t->fields[k].type, FieldType::kInt16);
    EXPECT_EQ(t->columns[k][0], a[k]);
  }
  EXPECT_EQ(t->timestamp_us[0], 5);
}

TEST(DataflashReader, UnitsAndMultipliersFromFmtu) {
  DataflashWriter w;
  w.unit(0, 's', "s");
  w.unit(0, 'd', "deg");
  w.unit(0, 'm', "m");
  w.unit(0, 'A', "A");
  w.unit(0, '-', "");
  w.mult(0, 'F', 1e-6);
  w.mult(0, 'B', 1e-2);
  w.mult(0, '0', 1.0);
  w.mult(0, '-', 0.0);  // ArduPilot's "no multiplier" is 0: must not zero the values
  w.mult(0, 'C', 1e-3);
  w.fmt(202, "UNT", "QchfH", "TimeUS,Ang,Cur,Dist,Raw");
  // A row before its FMTU: units and multipliers apply to every row of the type.
  w.write(202, {1000ull, centi(12.34), 1500, 2.5, 7});
  w.fmtu(0, 202, "sdAm-", "FBC0-");
  w.write(202, {2000ull, centi(-5.0), -250, -1.25, 9});
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  const LogTopic* t = log.find("UNT");
  ASSERT_NE(t, nullptr);
  ASSERT_EQ(t->rows(), 2u);
  EXPECT_EQ(fieldOf(*t, "Ang").unit, "deg");
  EXPECT_EQ(fieldOf(*t, "Cur").unit, "A");
  EXPECT_EQ(fieldOf(*t, "Dist").unit, "m");
  EXPECT_EQ(fieldOf(*t, "Raw").unit, "");
  // 'c' carries ×0.01 itself; FMTU's 'B' restates it and is not applied twice.
  EXPECT_DOUBLE_EQ(value(*t, "Ang", 0), 12.34);
  EXPECT_DOUBLE_EQ(value(*t, "Ang", 1), -5.0);
  EXPECT_EQ(fieldOf(*t, "Ang").multiplier, 0.01);
  // 'h' with multiplier C (1e-3): applied, recorded.
  EXPECT_DOUBLE_EQ(value(*t, "Cur", 0), 1.5);
  EXPECT_DOUBLE_EQ(value(*t, "Cur", 1), -0.25);
  EXPECT_EQ(fieldOf(*t, "Cur").multiplier, 1e-3);
  EXPECT_EQ(value(*t, "Dist", 0), 2.5);
  EXPECT_EQ(fieldOf(*t, "Dist").multiplier, 1.0);
  EXPECT_EQ(value(*t, "Raw", 1), 9);
  EXPECT_EQ(fieldOf(*t, "Raw").multiplier, 1.0);
}

TEST(DataflashReader, InstancesFromFmtuHashUnit) {
  DataflashWriter w;
  w.unit(0, '#', "instance");
  w.unit(0, 'm', "m");
  w.fmt(203, "XKF1", "QBfff", "TimeUS,C,PN,PE,PD");
  w.fmtu(0, 203, "s#mmm", "F-000");
  for (int r = 0; r < 5; ++r)
    for (unsigned core = 0; core < 2; ++core)
      w.write(203, {static_cast<unsigned long long>(10000 * (r + 1) + core), core, 1.0 * r + 100.0 * core, 2.0, -3.0});
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok()) << allWarnings(log);
  const LogTopic* c0 = log.find("XKF1", 0);
  const LogTopic* c1 = log.find("XKF1", 1);
  ASSERT_NE(c0, nullptr);
  ASSERT_NE(c1, nullptr);
  ASSERT_EQ(c0->rows(), 5u);
  ASSERT_EQ(c1->rows(), 5u);
  EXPECT_EQ(c0->timestamp_us[2], 30000);
  EXPECT_EQ(c1->timestamp_us[2], 30001);
  EXPECT_EQ(value(*c0, "PN", 3), 3.0);
  EXPECT_EQ(value(*c1, "PN", 3), 103.0);
  EXPECT_EQ(value(*c1, "C", 0), 1.0);
  EXPECT_EQ(fieldOf(*c1, "C").unit, "instance");
  EXPECT_EQ(fieldOf(*c1, "PN").unit, "m");
}

TEST(DataflashReader, BadInstanceValueIsNotSplit) {
  DataflashWriter w;
  w.fmt(203, "INS", "Qff", "TimeUS,I,V");
  w.fmtu(0, 203, "s#-", "F--");
  w.write(203, {1ull, 0.0, 1.0});
  w.write(203, {2ull, 1.5, 2.0});
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  const LogTopic* t = log.find("INS", 0);
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->rows(), 2u);
  EXPECT_TRUE(hasWarning(log, "INS", "not an instance number")) << allWarnings(log);
}

TEST(DataflashReader, ParametersMessagesAndVersion) {
  DataflashWriter w;
  w.fmt(204, "VER", "QBHBBBBIZH", "TimeUS,BT,BST,Maj,Min,Pat,FWT,GH,FWS,APJ");
  w.msg(100, "ArduCopter V4.5.1 (abcdef12)");
  w.parm(200, "MOT_THST_EXPO", 0.65);
  w.parm(300, "MOT_SPIN_MIN", 0.15);
  w.parm(400, "MOT_THST_EXPO", 0.5);  // later value wins
  w.write(204, {500ull, 3, 0, 4, 5, 1, 255, 0xabcdef12u, "ArduCopter V4.5.1", 140});
  w.msg(600, "Frame: QUAD/X");
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  EXPECT_EQ(log.parameters.at("MOT_THST_EXPO"), static_cast<double>(0.5f));
  EXPECT_EQ(log.parameters.at("MOT_SPIN_MIN"), static_cast<double>(0.15f));
  ASSERT_EQ(log.messages.size(), 2u);
  EXPECT_EQ(log.messages[0].timestamp_us, 100);
  EXPECT_EQ(log.messages[0].text, "ArduCopter V4.5.1 (abcdef12)");
  EXPECT_EQ(log.messages[1].text, "Frame: QUAD/X");
  EXPECT_EQ(log.info.at("firmware"), "ArduCopter V4.5.1");  // VER's FWS wins over MSG
  EXPECT_EQ(log.info.at("VER.Maj"), "4");
  EXPECT_EQ(log.info.at("VER.GH"), std::to_string(0xabcdef12u));
  EXPECT_EQ(log.find("PARM"), nullptr);
  EXPECT_EQ(log.find("MSG"), nullptr);
  EXPECT_EQ(log.find("VER"), nullptr);
}

TEST(DataflashReader, TimeMsAndUntimedMessages) {
  DataflashWriter w;
  w.fmt(205, "OLD", "Ih", "TimeMS,V");
  w.fmt(206, "NOT", "h", "V");
  w.write(206, {1});             // before any timed message: time 0
  w.write(205, {1234u, 7});      // TimeMS → µs
  w.write(206, {2});             // the latest timed message's time
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  const LogTopic* old_t = log.find("OLD");
  const LogTopic* not_t = log.find("NOT");
  ASSERT_NE(old_t, nullptr);
  ASSERT_NE(not_t, nullptr);
  EXPECT_EQ(old_t->timestamp_us[0], 1234000);
  EXPECT_EQ(old_t->fieldIndex("TimeMS"), -1);
  ASSERT_EQ(not_t->rows(), 2u);
  EXPECT_EQ(not_t->timestamp_us[0], 0);
  EXPECT_EQ(not_t->timestamp_us[1], 1234000);
}

// --- bad input -------------------------------------------------------------------------------

TEST(DataflashReader, EmptyIsTruncated) {
  DecodedLog log;
  const std::vector<std::uint8_t> empty;
  const LogIssue issue = read(empty, log);
  EXPECT_EQ(issue.status, LogStatus::kTruncated);
  EXPECT_EQ(issue.offset, 0u);
}

TEST(DataflashReader, WrongMagic) {
  DecodedLog log;
  const std::vector<std::uint8_t> ulog = {'U', 'L', 'o', 'g', 0x01, 0x12, 0x35, 0x01};
  LogIssue issue = read(ulog, log);
  EXPECT_EQ(issue.status, LogStatus::kWrongMagic);
  EXPECT_EQ(issue.offset, 0u);
  // The header, but a data message first: not a log ArduPilot writes.
  const std::vector<std::uint8_t> data_first = {0xA3, 0x95, 0x40, 1, 2, 3};
  issue = read(data_first, log);
  EXPECT_EQ(issue.status, LogStatus::kWrongMagic);
  EXPECT_NE(issue.message.find("not FMT"), std::string::npos);
}

TEST(DataflashReader, TruncatedFirstFmt) {
  const DataflashWriter w(false);
  for (std::size_t cut : {1u, 2u, 3u, 50u, 88u}) {
    const std::vector<std::uint8_t> b(w.bytes.begin(), w.bytes.begin() + static_cast<std::ptrdiff_t>(cut));
    DecodedLog log;
    const LogIssue issue = read(b, log);
    EXPECT_EQ(issue.status, LogStatus::kTruncated) << cut;
    EXPECT_EQ(issue.offset, 0u);
  }
}

TEST(DataflashReader, FirstFmtWithImpossibleLengthIsCorrupt) {
  DataflashWriter w(false);
  w.bytes[4] = 90;  // FMT's own length: 89
  DecodedLog log;
  const LogIssue issue = read(w.bytes, log);
  EXPECT_EQ(issue.status, LogStatus::kCorrupt);
  EXPECT_EQ(issue.offset, 0u);
  EXPECT_EQ(issue.topic, "FMT");
}

TEST(DataflashReader, LaterFmtWithImpossibleLengthIsSkippedWithItsOffset) {
  DataflashWriter w;
  const std::size_t bad_at = w.bytes.size();
  w.fmtRaw(200, 2, "BAD", "Qh", "TimeUS,V");                 // shorter than its header
  const std::size_t bad2_at = w.bytes.size();
  w.fmtRaw(201, 20, "BD2", "Qh", "TimeUS,V");                // Qh needs 3 + 10 = 13
  w.fmt(202, "OK", "Qh", "TimeUS,V");
  w.write(202, {1ull, 5});
  DecodedLog log;
  const LogIssue issue = read(w.bytes, log);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_TRUE(hasWarning(log, "byte " + std::to_string(bad_at) + ":", "impossible length 2")) << allWarnings(log);
  EXPECT_TRUE(hasWarning(log, "byte " + std::to_string(bad2_at) + ":", "declares length 20 but its format \"Qh\" needs 13"))
      << allWarnings(log);
  ASSERT_NE(log.find("OK"), nullptr);
  EXPECT_EQ(log.find("OK")->rows(), 1u);
}

TEST(DataflashReader, GarbageInTheMiddleResyncsWithOffsetAndCount) {
  DataflashWriter w = simpleLog(3);
  const std::size_t garbage_at = w.bytes.size();
  // 37 bytes with a false header (0xA3 0x95 of an undefined type) inside.
  std::vector<std::uint8_t> garbage(37, 0x55);
  garbage[10] = 0xA3;
  garbage[11] = 0x95;
  garbage[12] = 17;
  w.raw(garbage);
  w.write(200, {9000ull, 42, 1.0});
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  ASSERT_EQ(log.warnings.size(), 1u) << allWarnings(log);
  EXPECT_EQ(log.warnings[0], "byte " + std::to_string(garbage_at) + ": not a message header; skipped 37 bytes to the next message at byte " +
                                 std::to_string(garbage_at + 37));
  const LogTopic* t = log.find("TST");
  ASSERT_NE(t, nullptr);
  ASSERT_EQ(t->rows(), 4u);
  EXPECT_EQ(t->timestamp_us[3], 9000);
  EXPECT_EQ(value(*t, "A", 3), 42);
}

TEST(DataflashReader, TruncatedLastMessageKeepsTheRest) {
  DataflashWriter w = simpleLog(4);
  const std::size_t last_at = w.bytes.size() - DataflashWriter::lengthOf("Qhf");
  w.bytes.resize(w.bytes.size() - 5);
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  ASSERT_EQ(log.warnings.size(), 1u) << allWarnings(log);
  EXPECT_TRUE(hasWarning(log, "byte " + std::to_string(last_at) + ":", "log ends inside a TST message (12 of 17 bytes)"))
      << allWarnings(log);
  ASSERT_NE(log.find("TST"), nullptr);
  EXPECT_EQ(log.find("TST")->rows(), 3u);
  // Cut inside the header too.
  w.bytes.resize(last_at + 2);
  ASSERT_TRUE(read(w.bytes, log).ok());
  EXPECT_TRUE(hasWarning(log, "byte " + std::to_string(last_at) + ":", "inside a message header")) << allWarnings(log);
  EXPECT_EQ(log.find("TST")->rows(), 3u);
}

TEST(DataflashReader, DataMessageBeforeItsFmtIsSkipped) {
  DataflashWriter w;
  DataflashWriter other;  // to make the bytes of a type-200 message before its FMT
  other.fmt(200, "TST", "Qhf", "TimeUS,A,B");
  other.bytes.clear();
  other.write(200, {1ull, 1, 1.0});
  const std::size_t early_at = w.bytes.size();
  w.raw(other.bytes);
  w.fmt(200, "TST", "Qhf", "TimeUS,A,B");
  w.write(200, {2ull, 2, 2.0});
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  ASSERT_EQ(log.warnings.size(), 1u) << allWarnings(log);
  EXPECT_EQ(log.warnings[0], "byte " + std::to_string(early_at) + ": message type 200 has no FMT before it; skipped 17 bytes to the next message at byte " +
                                 std::to_string(early_at + 17));
  ASSERT_NE(log.find("TST"), nullptr);
  EXPECT_EQ(log.find("TST")->rows(), 1u);
  EXPECT_EQ(log.find("TST")->timestamp_us[0], 2);
}

TEST(DataflashReader, RedefinitionKeepsTheFirst) {
  DataflashWriter w = simpleLog(1);
  const std::size_t redef_at = w.bytes.size();
  w.fmtRaw(200, 7, "TS2", "I", "V");  // a valid FMT, but type 200 is TST already
  w.write(200, {5ull, 3, 1.5});
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  EXPECT_TRUE(hasWarning(log, "byte " + std::to_string(redef_at) + ":", "kept the first definition")) << allWarnings(log);
  ASSERT_NE(log.find("TST"), nullptr);
  EXPECT_EQ(log.find("TST")->rows(), 2u);
}

TEST(DataflashReader, WarningsAreCapped) {
  DataflashWriter w = simpleLog(1);
  for (int k = 0; k < 300; ++k) {
    w.raw({0x00, 0x01});
    w.write(200, {1ull, 1, 1.0});
  }
  DecodedLog log;
  ASSERT_TRUE(read(w.bytes, log).ok());
  EXPECT_EQ(log.warnings.size(), kDataflashMaxWarnings + 1);
  EXPECT_EQ(log.warnings.back(), "200 further warnings not shown");
  EXPECT_EQ(log.find("TST")->rows(), 301u);
}

TEST(DataflashReader, TooLargeIsRefusedBeforeReading) {
  const std::uint8_t byte = 0xA3;
  DecodedLog log;
  const LogIssue issue = readDataflash(ByteSpan{&byte, static_cast<std::size_t>(kDataflashMaxBytes) + 1}, log);
  EXPECT_EQ(issue.status, LogStatus::kTooLarge);
}
