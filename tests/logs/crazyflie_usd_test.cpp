// The Crazyflie micro-SD deck log reader (logs/crazyflie_usd.h) and the Crazyflie extractor
// (logs/crazyflie_signals.h): round trips through the test writer, every refusal with its status
// and byte offset, and the four real CrazyPAD logs in ../shared/logs/crazyflie-usd/.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "logs/crazyflie_signals.h"
#include "logs/crazyflie_usd.h"
#include "logs/crazyflie_usd_writer.h"

using namespace quadfdi;
using quadfdi::test::UsdEventType;
using quadfdi::test::UsdWriter;

namespace {

ByteSpan span(const std::vector<std::uint8_t>& v) { return ByteSpan{v.data(), v.size()}; }

// Two event types: the fixed-frequency one with one variable of every type the firmware writes
// (and the wider ones the reader also accepts), and a named event with a payload field.
std::vector<UsdEventType> allTypes() {
  UsdEventType fixed;
  fixed.variables = {{"g.u8", 'B'}, {"g.i8", 'b'}, {"g.u16", 'H'}, {"g.i16", 'h'}, {"g.u32", 'I'},
                     {"g.i32", 'i'}, {"g.f", 'f'},  {"g.half", 'e'}, {"g.i64", 'q'}, {"g.u64", 'Q'},
                     {"g.d", 'd'},   {"g.b", '?'},  {"g.c", 'c'}};
  UsdEventType named;
  named.id = 12;
  named.name = "activeMarkerModeChanged";
  named.variables = {{"mode", 'B'}, {"stateEstimate.z", 'f'}};
  return {fixed, named};
}

std::vector<double> fixedRow(int k) {
  return {static_cast<double>(200 + k), -100.0 - k, 60000.0 + k, -30000.0 + k, 4000000000.0 + k,
          -2000000000.0 + k, 0.25 * k - 3.5, 1.5 - k, -1e12 - k, 1e15 + k, 1.0 / 3.0 + k, static_cast<double>(k % 2),
          static_cast<double>('A' + k)};
}

void expectRoundTrip(int version) {
  UsdWriter w(version, allTypes());
  std::vector<std::int64_t> ts_fixed, ts_named;
  for (int k = 0; k < 5; ++k) {
    const std::uint64_t t = version == 1 ? 1000u + 10u * static_cast<unsigned>(k) : 9836066u + 9897u * static_cast<unsigned>(k);
    w.record(0, t, fixedRow(k));
    ts_fixed.push_back(version == 1 ? static_cast<std::int64_t>(t) * 1000 : static_cast<std::int64_t>(t));
    if (k == 2) {
      w.record(1, t + 3, {7.0, 0.75});
      ts_named.push_back(version == 1 ? static_cast<std::int64_t>(t + 3) * 1000 : static_cast<std::int64_t>(t + 3));
    }
  }
  const std::vector<std::uint8_t> bytes = w.closed();
  EXPECT_TRUE(looksLikeCrazyflieUsd(span(bytes)));
  DecodedLog log;
  const LogIssue issue = readCrazyflieUsd(span(bytes), log);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_EQ(log.format, LogFormat::kCrazyflieUsd);
  EXPECT_TRUE(log.warnings.empty());
  EXPECT_EQ(log.info.at("usd.version"), std::to_string(version));
  EXPECT_NE(log.info.at("usd.crc32").find("verified"), std::string::npos);
  EXPECT_EQ(log.info.at("usd.event.fixedFrequency.id"), "65535");
  EXPECT_EQ(log.info.at("usd.event.activeMarkerModeChanged.id"), "12");
  ASSERT_EQ(log.topics.size(), 2u);

  const LogTopic* fixed = log.find("fixedFrequency");
  ASSERT_NE(fixed, nullptr);
  const std::vector<FieldType> types = {FieldType::kUInt8, FieldType::kInt8,   FieldType::kUInt16, FieldType::kInt16,
                                        FieldType::kUInt32, FieldType::kInt32, FieldType::kFloat,  FieldType::kFloat,
                                        FieldType::kInt64, FieldType::kUInt64, FieldType::kDouble, FieldType::kBool,
                                        FieldType::kChar};
  ASSERT_EQ(fixed->fields.size(), types.size());
  for (std::size_t f = 0; f < types.size(); ++f) {
    EXPECT_EQ(fixed->fields[f].name, allTypes()[0].variables[f].name);
    EXPECT_EQ(fixed->fields[f].type, types[f]) << fixed->fields[f].name;
  }
  EXPECT_EQ(fixed->timestamp_us, ts_fixed);
  for (int k = 0; k < 5; ++k) {
    const std::vector<double> want = fixedRow(k);
    for (std::size_t f = 0; f < want.size(); ++f) {
      const double expected = f == 6 ? static_cast<double>(static_cast<float>(want[f])) : want[f];
      EXPECT_EQ(fixed->columns[f][static_cast<std::size_t>(k)], expected) << fixed->fields[f].name << " row " << k;
    }
  }
  const LogTopic* named = log.find("activeMarkerModeChanged");
  ASSERT_NE(named, nullptr);
  ASSERT_EQ(named->fields.size(), 2u);
  EXPECT_EQ(named->fields[0].name, "mode");
  EXPECT_EQ(named->fields[1].type, FieldType::kFloat);
  EXPECT_EQ(named->timestamp_us, ts_named);
  EXPECT_EQ(named->columns[0], std::vector<double>{7.0});
  EXPECT_EQ(named->columns[1], std::vector<double>{0.75});
}

// A small valid version 2 log: one fixed-frequency event of two variables, three records.
UsdWriter smallLog() {
  UsdEventType fixed;
  fixed.variables = {{"stateEstimate.x", 'f'}, {"motor.m1", 'I'}};
  UsdWriter w(2, {fixed});
  for (unsigned k = 0; k < 3; ++k) w.record(0, 1000000u + 2000u * k, {0.5 * k, 1000.0 * k});
  return w;
}

LogIssue read(const std::vector<std::uint8_t>& bytes, DecodedLog& log) { return readCrazyflieUsd(span(bytes), log); }

}  // namespace

TEST(CrazyflieUsd, Crc32IsZlibs) {
  const std::string check = "123456789";  // the CRC-32 check value of the catalogue
  EXPECT_EQ(crc32Ieee(reinterpret_cast<const std::uint8_t*>(check.data()), check.size()), 0xCBF43926u);
}

TEST(CrazyflieUsd, RoundTripVersion2) { expectRoundTrip(2); }
TEST(CrazyflieUsd, RoundTripVersion1MillisecondsBecomeMicroseconds) { expectRoundTrip(1); }

TEST(CrazyflieUsd, EmptyInputIsTruncatedAtZero) {
  DecodedLog log;
  const LogIssue i = read({}, log);
  EXPECT_EQ(i.status, LogStatus::kTruncated);
  EXPECT_EQ(i.offset, 0u);
  EXPECT_FALSE(looksLikeCrazyflieUsd(ByteSpan{}));
}

TEST(CrazyflieUsd, WrongMagic) {
  std::vector<std::uint8_t> bytes = smallLog().closed();
  bytes[0] = 'U';  // a ULog starts "ULog"
  DecodedLog log;
  const LogIssue i = read(bytes, log);
  EXPECT_EQ(i.status, LogStatus::kWrongMagic);
  EXPECT_EQ(i.offset, 0u);
  EXPECT_NE(i.message.find("0x55"), std::string::npos) << i.message;
  EXPECT_FALSE(looksLikeCrazyflieUsd(span(bytes)));
}

TEST(CrazyflieUsd, UnknownVersion) {
  std::vector<std::uint8_t> bytes = smallLog().closed();
  bytes[1] = 3;
  DecodedLog log;
  const LogIssue i = read(bytes, log);
  EXPECT_EQ(i.status, LogStatus::kUnsupportedVersion);
  EXPECT_EQ(i.offset, 1u);
  EXPECT_NE(i.message.find("version 3"), std::string::npos) << i.message;
  EXPECT_FALSE(looksLikeCrazyflieUsd(span(bytes)));
}

TEST(CrazyflieUsd, TruncatedHeader) {
  std::vector<std::uint8_t> bytes = smallLog().closed();
  bytes.resize(3);
  DecodedLog log;
  const LogIssue i = read(bytes, log);
  EXPECT_EQ(i.status, LogStatus::kTruncated);
  EXPECT_EQ(i.offset, 3u);
}

TEST(CrazyflieUsd, TruncatedVariableTable) {
  const UsdWriter w = smallLog();
  // Inside "motor.m1(I)": the header is 5 + 2 + 15 ("fixedFrequency\0") + 2 + 19 + 12 bytes.
  for (std::size_t cut : {std::size_t{6}, std::size_t{10}, std::size_t{23}, std::size_t{30}, w.headerBytes() - 1}) {
    std::vector<std::uint8_t> bytes = w.closed();
    bytes.resize(cut);
    DecodedLog log;
    const LogIssue i = read(bytes, log);
    EXPECT_EQ(i.status, LogStatus::kTruncated) << "cut at " << cut << ": " << i.message;
    EXPECT_EQ(i.offset, cut) << i.message;
  }
}

TEST(CrazyflieUsd, FlippedDataByteFailsTheCrc) {
  const UsdWriter w = smallLog();
  std::vector<std::uint8_t> bytes = w.closed();
  bytes[w.headerBytes() + w.recordBytes(0) + 12] ^= 0x10;  // a value of the second record
  DecodedLog log;
  const LogIssue i = read(bytes, log);
  EXPECT_EQ(i.status, LogStatus::kCorrupt);
  EXPECT_EQ(i.offset, bytes.size() - 4);
  EXPECT_NE(i.message.find("CRC-32 mismatch"), std::string::npos) << i.message;
}

TEST(CrazyflieUsd, FlippedEventIdIsCorruptAtTheRecord) {
  const UsdWriter w = smallLog();
  std::vector<std::uint8_t> bytes = w.closed();
  const std::size_t second = w.headerBytes() + w.recordBytes(0);
  bytes[second] ^= 0x01;  // event id 0xFFFF → 0xFFFE
  DecodedLog log;
  const LogIssue i = read(bytes, log);
  EXPECT_EQ(i.status, LogStatus::kCorrupt);
  EXPECT_EQ(i.offset, second);
  EXPECT_NE(i.message.find("unknown event id 65534"), std::string::npos) << i.message;
}

TEST(CrazyflieUsd, TruncatedLastRecordKeepsTheCompleteOnes) {
  const UsdWriter w = smallLog();
  std::vector<std::uint8_t> bytes = w.unclosed();
  bytes.resize(bytes.size() - 5);  // no CRC, last record cut 5 bytes short
  DecodedLog log;
  const LogIssue i = read(bytes, log);
  ASSERT_TRUE(i.ok()) << i.message;
  ASSERT_EQ(log.topics.size(), 1u);
  EXPECT_EQ(log.topics[0].rows(), 2u);
  ASSERT_EQ(log.warnings.size(), 1u);
  const std::size_t last = w.headerBytes() + 2 * w.recordBytes(0);
  EXPECT_EQ(log.warnings[0].rfind("byte " + std::to_string(last) + ":", 0), 0u) << log.warnings[0];
  EXPECT_NE(log.warnings[0].find("truncated"), std::string::npos);
  EXPECT_EQ(log.info.at("usd.crc32"), "absent (log not closed)");
}

TEST(CrazyflieUsd, UnclosedLogWithoutCrcIsAWarning) {
  const UsdWriter w = smallLog();
  DecodedLog log;
  const LogIssue i = read(w.unclosed(), log);
  ASSERT_TRUE(i.ok()) << i.message;
  EXPECT_EQ(log.topics[0].rows(), 3u);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_NE(log.warnings[0].find("without a CRC-32"), std::string::npos) << log.warnings[0];
}

TEST(CrazyflieUsd, HeaderOnlyClosedLogHasNoRows) {
  UsdEventType fixed;
  fixed.variables = {{"a.b", 'f'}};
  DecodedLog log;
  const LogIssue i = read(UsdWriter(2, {fixed}).closed(), log);
  ASSERT_TRUE(i.ok()) << i.message;
  EXPECT_EQ(log.topics[0].rows(), 0u);
  EXPECT_TRUE(log.warnings.empty());
}

TEST(CrazyflieUsd, DeclaredCountsAreCapped) {
  std::vector<std::uint8_t> bytes = smallLog().closed();
  bytes[3] = 0xE8;  // 1000 event types
  bytes[4] = 0x03;
  DecodedLog log;
  LogIssue i = read(bytes, log);
  EXPECT_EQ(i.status, LogStatus::kTooLarge);
  EXPECT_EQ(i.offset, 3u);

  bytes = smallLog().closed();
  const std::size_t count_at = 5 + 2 + 15;  // after the id and "fixedFrequency\0"
  bytes[count_at] = 0xFF;
  bytes[count_at + 1] = 0xFF;
  i = read(bytes, log);
  EXPECT_EQ(i.status, LogStatus::kTooLarge);
  EXPECT_EQ(i.offset, count_at);
  EXPECT_EQ(i.topic, "fixedFrequency");
}

TEST(CrazyflieUsd, BadVariableDeclarations) {
  for (const char* decl : {"x(Z)", "()", "noparen", "x(f"}) {
    UsdEventType fixed;
    fixed.variables = {{"a.b", 'f'}};
    std::vector<std::uint8_t> bytes = UsdWriter(2, {fixed}).closed();
    // Replace "a.b(f)" by the bad declaration (the CRC no longer matters: the header fails first).
    const std::size_t at = 5 + 2 + 15 + 2;
    std::vector<std::uint8_t> bad(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(at));
    for (const char* p = decl; *p; ++p) bad.push_back(static_cast<std::uint8_t>(*p));
    bad.push_back(0);
    DecodedLog log;
    const LogIssue i = read(bad, log);
    EXPECT_EQ(i.status, LogStatus::kCorrupt) << decl << ": " << i.message;
    EXPECT_EQ(i.offset, at) << decl;
  }
}

TEST(CrazyflieUsd, DuplicateEventIdIsCorrupt) {
  UsdEventType a, b;
  b.name = "again";
  DecodedLog log;
  const LogIssue i = read(UsdWriter(2, {a, b}).closed(), log);
  EXPECT_EQ(i.status, LogStatus::kCorrupt);
  EXPECT_EQ(i.offset, 5u + 2 + 15 + 2);
}

// --- The real logs (CrazyPAD, Crazyflie 2.1, format version 2). ---

namespace {

const std::string kRealDir = std::string(QUADFDI_SOURCE_DIR) + "/../shared/logs/crazyflie-usd/";

std::vector<std::uint8_t> slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

// The variables the deck's config.txt puts under "on:fixedFrequency" (after frequency and mode).
std::vector<std::string> configVariables(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::string> vars;
  std::string line;
  int state = 0;  // 0 before on:fixedFrequency, 1-2 frequency and mode lines, 3 variables
  while (std::getline(f, line)) {
    line = line.substr(0, line.find('#'));
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (line.empty()) continue;
    if (line.rfind("on:", 0) == 0) {
      state = line == "on:fixedFrequency" ? 1 : 4;
      continue;
    }
    if (state == 1 || state == 2) ++state;
    else if (state == 3) vars.push_back(line);
  }
  return vars;
}

struct RealLog {
  const char* file;
  const char* config;
  std::size_t rows;
};
// The CRC-verified record counts (cross-checked with a throwaway script); the tape log was
// recorded with the controller configuration.
const RealLog kRealLogs[] = {
    {"motor_normal_flight_E8_log00", "config_E8_motor.txt", 2604},
    {"normal_flight_E8_log00", "config_E8_controller.txt", 2606},
    {"normal_flight_E9_log00", "config_E9_controller.txt", 2596},
    {"tape_on_propeller_M1_M3_E9_log00", "config_E9_controller.txt", 2595},
};

bool readReal(const RealLog& r, DecodedLog& log) {
  const std::vector<std::uint8_t> bytes = slurp(kRealDir + r.file);
  if (bytes.empty()) return false;
  const LogIssue i = readCrazyflieUsd(span(bytes), log);
  EXPECT_TRUE(i.ok()) << r.file << ": byte " << i.offset << ": " << i.message;
  return i.ok();
}

}  // namespace

TEST(CrazyflieUsdReal, AllFourLogsParseCompletely) {
  for (const RealLog& r : kRealLogs) {
    SCOPED_TRACE(r.file);
    DecodedLog log;
    if (!readReal(r, log)) {
      if (slurp(kRealDir + r.file).empty()) GTEST_SKIP() << "no " << kRealDir << r.file;
      continue;
    }
    EXPECT_TRUE(log.warnings.empty());
    EXPECT_EQ(log.info.at("usd.version"), "2");
    EXPECT_NE(log.info.at("usd.crc32").find("verified"), std::string::npos);
    const LogTopic* fixed = log.find("fixedFrequency");
    ASSERT_NE(fixed, nullptr);
    EXPECT_EQ(fixed->rows(), r.rows);
    // The variables match the deck's configuration file, in order.
    std::vector<std::string> names;
    for (const LogField& f : fixed->fields) names.push_back(f.name);
    EXPECT_EQ(names, configVariables(kRealDir + r.config));
    for (const auto& column : fixed->columns) EXPECT_EQ(column.size(), fixed->rows());
    // ~100 Hz for ~26 s, timestamps increasing.
    const double span_s = static_cast<double>(fixed->timestamp_us.back() - fixed->timestamp_us.front()) * 1e-6;
    EXPECT_NEAR(span_s, 25.7, 0.3);
    EXPECT_NEAR(static_cast<double>(fixed->rows() - 1) / span_s, 101.0, 1.5);
    for (std::size_t k = 1; k < fixed->rows(); ++k) {
      const std::int64_t dt = fixed->timestamp_us[k] - fixed->timestamp_us[k - 1];
      ASSERT_TRUE(dt > 9000 && dt < 11000) << "row " << k << ": " << dt << " µs";
    }
    // Of the four named events in the configs only activeMarkerModeChanged exists in that
    // firmware (the deck skips unknown events); it never fired.
    const LogTopic* marker = log.find("activeMarkerModeChanged");
    ASSERT_NE(marker, nullptr);
    ASSERT_EQ(marker->fields.size(), 1u);
    EXPECT_EQ(marker->fields[0].name, "mode");
    EXPECT_EQ(marker->fields[0].type, FieldType::kUInt8);
    EXPECT_EQ(marker->rows(), 0u);
    EXPECT_EQ(log.topics.size(), 2u);
    // Types as the firmware declares them.
    EXPECT_EQ(fixed->fields[static_cast<std::size_t>(fixed->fieldIndex("stateEstimate.x"))].type, FieldType::kFloat);
    if (fixed->fieldIndex("motor.m1") >= 0) {
      EXPECT_EQ(fixed->fields[static_cast<std::size_t>(fixed->fieldIndex("motor.m1"))].type, FieldType::kUInt32);
      EXPECT_EQ(fixed->fields[static_cast<std::size_t>(fixed->fieldIndex("pm.vbatMV"))].type, FieldType::kUInt16);
    } else {
      EXPECT_EQ(fixed->fields[static_cast<std::size_t>(fixed->fieldIndex("controller.ctr_yaw"))].type,
                FieldType::kInt16);
    }
  }
}

// --- The extractor. ---

namespace {

// A synthetic 500 Hz log with every signal the extractor reads; attitude in degrees.
struct Synthetic {
  std::vector<std::uint8_t> bytes;
  static constexpr int kRows = 50;
};

std::vector<std::uint8_t> syntheticLog(bool with_pitch = true, bool battery = false) {
  UsdEventType fixed;
  fixed.variables = {{"stateEstimate.x", 'f'}, {"stateEstimate.y", 'f'}, {"stateEstimate.z", 'f'},
                     {"stateEstimate.roll", 'f'}, {"stateEstimate.yaw", 'f'},
                     {"motor.m1", 'I'}, {"motor.m2", 'I'}, {"motor.m3", 'I'}, {"motor.m4", 'I'}};
  if (with_pitch) fixed.variables.push_back({"stateEstimate.pitch", 'f'});
  if (battery)
    fixed.variables.insert(fixed.variables.end(), {{"pwm.m1_pwm", 'f'}, {"pwm.m2_pwm", 'f'}, {"pwm.m3_pwm", 'f'},
                                                   {"pwm.m4_pwm", 'f'}, {"pm.vbatMV", 'H'}});
  UsdEventType other;
  other.id = 3;
  other.name = "early";
  UsdWriter w(2, {fixed, other});
  w.record(1, 5000000, {});  // the log's first record: the time origin
  for (int k = 0; k < Synthetic::kRows; ++k) {
    std::vector<double> row = {0.5, -1.25, 0.75 + 0.001 * k, 5.0, 90.0, 0.0, 65535.0, 32768.0, 16384.0};
    if (with_pitch) row.push_back(10.0);
    if (battery) {
      // 40 g of total thrust at 4.0 V: V = -0.0006239·40² + 0.088·40 = 2.52176 V, duty 0.63044.
      const double pwm = 2.52176 / 4.0 * 65535.0;
      row.insert(row.end(), {pwm, pwm, 0.0, pwm, 4000.0});
    }
    w.record(0, 5000000u + 1000u + 2000u * static_cast<unsigned>(k), row);
  }
  return w.closed();
}

LogIssue extract(const std::vector<std::uint8_t>& bytes, FlightSignals& s,
                 const CrazyflieSignalOptions& o = CrazyflieSignalOptions{}) {
  DecodedLog log;
  const LogIssue i = readCrazyflieUsd(span(bytes), log);
  if (!i.ok()) return i;
  return extractCrazyflieSignals(log, o, s);
}

bool mentions(const std::vector<std::string>& lines, const std::string& what) {
  for (const std::string& l : lines)
    if (l.find(what) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(CrazyflieSignals, KnownValuesInExpectedSignalsOut) {
  FlightSignals s;
  const LogIssue i = extract(syntheticLog(), s);
  ASSERT_TRUE(i.ok()) << i.message;
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  ASSERT_EQ(s.position.t.size(), static_cast<std::size_t>(Synthetic::kRows));
  EXPECT_NEAR(s.position.t[0], 0.001, 1e-12);  // 1 ms after the first record of the log
  EXPECT_NEAR(s.position.t[1] - s.position.t[0], 0.002, 1e-12);
  EXPECT_NEAR(s.position.v[3][0], 0.5, 1e-7);
  EXPECT_NEAR(s.position.v[3][1], -1.25, 1e-7);
  EXPECT_NEAR(s.position.v[3][2], 0.753, 1e-7);
  EXPECT_NEAR(s.attitude.v[0][0], 5.0 * kDeg, 1e-9);    // roll as logged
  EXPECT_NEAR(s.attitude.v[0][1], -10.0 * kDeg, 1e-9);  // the firmware's +10° pitch (nose up) is −10° here
  EXPECT_NEAR(s.attitude.v[0][2], 90.0 * kDeg, 1e-9);
  EXPECT_EQ(s.command_kind, CommandKind::kThrustNewton);
  // The firmware's map f = a·r² + b·r, motors in the same order.
  const double a = 0.091492681, b = 0.067673604;
  EXPECT_NEAR(s.command.v[0][0], 0.0, 1e-12);
  EXPECT_NEAR(s.command.v[0][1], a + b, 1e-12);
  const double r2 = 32768.0 / 65535.0, r3 = 16384.0 / 65535.0;
  EXPECT_NEAR(s.command.v[0][2], a * r2 * r2 + b * r2, 1e-12);
  EXPECT_NEAR(s.command.v[0][3], a * r3 * r3 + b * r3, 1e-12);
  EXPECT_EQ(s.attitude.source.topic, "fixedFrequency");
  EXPECT_TRUE(mentions(s.conventions, "pitch negated"));
  EXPECT_TRUE(mentions(s.conventions, "M1 front-right"));
  EXPECT_TRUE(mentions(s.conventions, "pwmToThrustA/B"));
  EXPECT_TRUE(mentions(s.conventions, "time:"));
  EXPECT_TRUE(s.states.empty());
}

TEST(CrazyflieSignals, BatteryVoltageModelWhenPwmAndVbatAreLogged) {
  FlightSignals s;
  const LogIssue i = extract(syntheticLog(true, true), s);
  ASSERT_TRUE(i.ok()) << i.message;
  const double per_motor = 40.0 / 4.0 * 1e-3 * 9.81;  // [N] 10 g
  EXPECT_NEAR(s.command.v[0][0], per_motor, 1e-6);
  EXPECT_NEAR(s.command.v[0][1], per_motor, 1e-6);
  EXPECT_NEAR(s.command.v[0][2], 0.0, 1e-12);
  EXPECT_NEAR(s.command.v[0][3], per_motor, 1e-6);
  EXPECT_TRUE(mentions(s.conventions, "battery-voltage model"));

  CrazyflieSignalOptions duty;
  duty.thrust_map = CrazyflieThrustMap::kQuadraticDuty;
  ASSERT_TRUE(extract(syntheticLog(true, true), s, duty).ok());
  EXPECT_NEAR(s.command.v[0][1], 0.091492681 + 0.067673604, 1e-12);  // motor.m2 = 65535 again
  EXPECT_TRUE(mentions(s.conventions, "pm.vbatMV is logged"));
}

TEST(CrazyflieSignals, MissingPitchIsNamed) {
  FlightSignals s;
  const LogIssue i = extract(syntheticLog(false), s);
  ASSERT_FALSE(i.ok());
  EXPECT_EQ(i.status, LogStatus::kMissingSignal);
  EXPECT_EQ(i.topic, "stateEstimate.pitch");
  EXPECT_EQ(i.message.rfind("the log has no stateEstimate.pitch (nor stabilizer.roll/pitch/yaw, "
                            "stateEstimate.qw/qx/qy/qz or stateEstimateZ.quat)",
                            0),
            0u)
      << i.message;
  EXPECT_EQ(i.message.find("stateEstimate.roll"), i.message.find("stateEstimate.roll/pitch/yaw")) << i.message;
}

TEST(CrazyflieSignals, StabilizerAttitudeAsFallback) {
  UsdEventType fixed;
  fixed.variables = {{"stateEstimate.x", 'f'}, {"stateEstimate.y", 'f'}, {"stateEstimate.z", 'f'},
                     {"stabilizer.roll", 'f'}, {"stabilizer.pitch", 'f'}, {"stabilizer.yaw", 'f'},
                     {"motor.m1", 'I'},        {"motor.m2", 'I'},         {"motor.m3", 'I'},
                     {"motor.m4", 'I'}};
  UsdWriter w(2, {fixed});
  w.record(0, 100, {0, 0, 1, 0, -30, 0, 0, 0, 0, 0});
  w.record(0, 2100, {0, 0, 1, 0, -30, 0, 0, 0, 0, 0});
  FlightSignals s;
  ASSERT_TRUE(extract(w.closed(), s).ok());
  EXPECT_NEAR(s.attitude.v[1][1], 30.0 * 3.14159265358979323846 / 180.0, 1e-9);
  EXPECT_TRUE(mentions(s.conventions, "stabilizer.roll/pitch/yaw used instead"));
  CrazyflieSignalOptions strict;
  strict.stabilizer_fallback = false;
  const LogIssue i = extract(w.closed(), s, strict);
  EXPECT_FALSE(i.ok());
  EXPECT_NE(i.message.find("stateEstimate.roll, stateEstimate.pitch, stateEstimate.yaw"), std::string::npos);
}

// --- The attitude as a quaternion: stateEstimate.qw..qz and the compressed stateEstimateZ.quat. ---

namespace {

constexpr double kPi = 3.14159265358979323846;

// The angle of the rotation between two quaternions (w, x, y, z) [rad].
double angleBetween(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  const double dot = std::fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
  return 2.0 * std::acos(std::min(1.0, dot));
}

// A 500 Hz log of a vehicle holding roll 5°, pitch 10° nose up and yaw 90°, its attitude given by
// `attitude` (and its values per row by `values`), position and motors as in syntheticLog.
std::vector<std::uint8_t> attitudeLog(const std::vector<quadfdi::test::UsdVariable>& attitude,
                                      const std::vector<double>& values, bool compressed_position = false) {
  UsdEventType fixed;
  if (compressed_position)
    fixed.variables = {{"stateEstimateZ.x", 'h'}, {"stateEstimateZ.y", 'h'}, {"stateEstimateZ.z", 'h'}};
  else
    fixed.variables = {{"stateEstimate.x", 'f'}, {"stateEstimate.y", 'f'}, {"stateEstimate.z", 'f'}};
  fixed.variables.insert(fixed.variables.end(), attitude.begin(), attitude.end());
  fixed.variables.insert(fixed.variables.end(), {{"motor.m1", 'I'}, {"motor.m2", 'I'}, {"motor.m3", 'I'},
                                                 {"motor.m4", 'I'}});
  UsdWriter w(2, {fixed});
  for (int k = 0; k < 4; ++k) {
    std::vector<double> row;
    if (compressed_position)
      row = {500.0, -1250.0, 750.0 + k};
    else
      row = {0.5, -1.25, 0.75 + 0.001 * k};
    for (double v : values) row.push_back(v);
    for (int m = 0; m < 4; ++m) row.push_back(32768.0);
    w.record(0, 1000u + 2000u * static_cast<unsigned>(k), row);
  }
  return w.closed();
}

}  // namespace

TEST(CrazyflieSignals, DecompressesTheFirmwaresQuaternionEncoding) {
  std::array<double, 4> q{};
  // Identity: w largest (index 3), the other three zero.
  ASSERT_TRUE(decompressCrazyflieQuaternion(0xC0000000u, q));
  EXPECT_EQ(q, (std::array<double, 4>{0.0, 0.0, 0.0, 1.0}));
  // w largest, x at full magnitude 511 (= 1/√2), positive: 90° of roll.
  ASSERT_TRUE(decompressCrazyflieQuaternion((3u << 30) | (511u << 20), q));
  EXPECT_NEAR(q[0], std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(q[3], std::sqrt(0.5), 1e-15);
  // z largest (index 2), w = −1/√2 stored with its sign bit (the last, lowest group): −90° of yaw.
  ASSERT_TRUE(decompressCrazyflieQuaternion((2u << 30) | (1u << 9) | 511u, q));
  EXPECT_NEAR(q[2], std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(q[3], -std::sqrt(0.5), 1e-15);
  EXPECT_EQ(q[0], 0.0);
  EXPECT_EQ(q[1], 0.0);
  // Three components of 1/√2 are longer than a unit quaternion.
  EXPECT_FALSE(decompressCrazyflieQuaternion((3u << 30) | (511u << 20) | (511u << 10) | 511u, q));

  // Random rotations (seeded): compressed and decompressed, within the encoding's resolution
  // (components to ±0.0007, so the rotation to a few mrad).
  std::uint64_t state = 12345;
  auto uniform = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  double worst = 0.0;
  for (int n = 0; n < 2000; ++n) {
    const std::array<double, 4> truth = test::usdQuaternionOfEuler((2 * uniform() - 1) * kPi, (uniform() - 0.5) * kPi,
                                                     (2 * uniform() - 1) * kPi);
    ASSERT_TRUE(decompressCrazyflieQuaternion(test::usdCompressQuaternion(truth), q));
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-12);
    worst = std::max(worst, angleBetween(truth, {q[3], q[0], q[1], q[2]}));
  }
  EXPECT_LT(worst, 0.006) << "rad";
  EXPECT_GT(worst, 1e-4) << "9 bits cannot be exact";
}

TEST(CrazyflieSignals, QuaternionAttitudeAgreesWithTheLoggedEulerAngles) {
  constexpr double kDeg = kPi / 180.0;
  // The firmware logs this attitude's Euler angles as roll 5°, pitch +10° (legacy: nose up), yaw 90°;
  // its quaternion has quadfdi's pitch, −10° (nose down positive).
  const std::array<double, 4> q = test::usdQuaternionOfEuler(5 * kDeg, -10 * kDeg, 90 * kDeg);
  FlightSignals euler, full, compressed;
  ASSERT_TRUE(extract(attitudeLog({{"stateEstimate.roll", 'f'}, {"stateEstimate.pitch", 'f'}, {"stateEstimate.yaw", 'f'}},
                                  {5.0, 10.0, 90.0}),
                      euler)
                  .ok());
  ASSERT_TRUE(extract(attitudeLog({{"stateEstimate.qx", 'f'}, {"stateEstimate.qy", 'f'}, {"stateEstimate.qz", 'f'},
                                   {"stateEstimate.qw", 'f'}},
                                  {q[1], q[2], q[3], q[0]}),
                      full)
                  .ok());
  const LogIssue i = extract(attitudeLog({{"stateEstimateZ.quat", 'I'}}, {static_cast<double>(test::usdCompressQuaternion(q))}, true),
                             compressed);
  ASSERT_TRUE(i.ok()) << i.message;
  ASSERT_EQ(full.attitude.t.size(), 4u);
  ASSERT_EQ(compressed.attitude.t.size(), 4u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(full.attitude.v[0][static_cast<std::size_t>(k)], euler.attitude.v[0][static_cast<std::size_t>(k)],
                1e-6)
        << "axis " << k;  // float quaternion against float degrees
    EXPECT_NEAR(compressed.attitude.v[0][static_cast<std::size_t>(k)], euler.attitude.v[0][static_cast<std::size_t>(k)],
                0.005)
        << "axis " << k;  // 9-bit components
  }
  EXPECT_NEAR(full.attitude.v[0][1], -10 * kDeg, 1e-6);
  EXPECT_EQ(full.attitude.source.fields, "stateEstimate.qw,qx,qy,qz");
  EXPECT_TRUE(mentions(full.conventions, "stateEstimate.qw/qx/qy/qz (state.attitudeQuaternion"));
  EXPECT_FALSE(mentions(full.conventions, "pitch negated"));
  EXPECT_EQ(compressed.attitude.source.fields, "stateEstimateZ.quat");
  EXPECT_TRUE(mentions(compressed.conventions, "quatcompress.h"));
  // stateEstimateZ position: millimetres.
  EXPECT_EQ(compressed.position.source.fields, "stateEstimateZ.x,y,z");
  EXPECT_NEAR(compressed.position.v[0][0], 0.5, 1e-12);
  EXPECT_NEAR(compressed.position.v[0][1], -1.25, 1e-12);
  EXPECT_NEAR(compressed.position.v[3][2], 0.753, 1e-12);
  EXPECT_TRUE(mentions(compressed.conventions, "[mm] → [m]"));
}

TEST(CrazyflieSignals, NoRotationAndSaturatedPositionRowsAreSkippedAndCounted) {
  // A zero quaternion (an estimator not yet started) and a position at the int16 limit.
  UsdEventType fixed;
  fixed.variables = {{"stateEstimateZ.x", 'h'}, {"stateEstimateZ.y", 'h'}, {"stateEstimateZ.z", 'h'},
                     {"stateEstimate.qw", 'f'}, {"stateEstimate.qx", 'f'}, {"stateEstimate.qy", 'f'},
                     {"stateEstimate.qz", 'f'}, {"motor.m1", 'I'},         {"motor.m2", 'I'},
                     {"motor.m3", 'I'},         {"motor.m4", 'I'}};
  UsdWriter w(2, {fixed});
  w.record(0, 1000, {0, 0, 32767, 0, 0, 0, 0, 0, 0, 0, 0});
  w.record(0, 3000, {0, 0, 500, 1, 0, 0, 0, 0, 0, 0, 0});
  w.record(0, 5000, {0, 0, 502, 2, 0, 0, 0, 0, 0, 0, 0});  // not normalised: read as the identity
  FlightSignals s;
  const LogIssue i = extract(w.closed(), s);
  ASSERT_TRUE(i.ok()) << i.message;
  EXPECT_EQ(s.position.t.size(), 2u);
  EXPECT_EQ(s.attitude.t.size(), 2u);
  EXPECT_TRUE(mentions(s.conventions, "position: 1 rows at the int16 limit"));
  EXPECT_TRUE(mentions(s.conventions, "attitude: 1 rows whose quaternion is no rotation"));
  EXPECT_EQ(s.attitude.v[1], (std::array<double, 3>{0.0, 0.0, 0.0}));
}

TEST(CrazyflieSignals, TimeMustIncrease) {
  UsdEventType fixed;
  fixed.variables = {{"stateEstimate.x", 'f'}, {"stateEstimate.y", 'f'}, {"stateEstimate.z", 'f'},
                     {"stateEstimate.roll", 'f'}, {"stateEstimate.pitch", 'f'}, {"stateEstimate.yaw", 'f'},
                     {"motor.m1", 'I'}, {"motor.m2", 'I'}, {"motor.m3", 'I'}, {"motor.m4", 'I'}};
  UsdWriter w(2, {fixed});
  const std::vector<double> row(10, 0.0);
  w.record(0, 5000, row);
  w.record(0, 5000, row);
  FlightSignals s;
  const LogIssue i = extract(w.closed(), s);
  EXPECT_FALSE(i.ok());
  EXPECT_NE(i.message.find("time does not increase at row 1"), std::string::npos) << i.message;
}

TEST(CrazyflieSignalsReal, MotorLogsRefuseNamingTheMissingPitch) {
  DecodedLog log;
  if (!readReal(kRealLogs[0], log)) GTEST_SKIP() << "no real logs in " << kRealDir;
  FlightSignals s;
  const LogIssue i = extractCrazyflieSignals(log, CrazyflieSignalOptions{}, s);
  ASSERT_FALSE(i.ok());
  EXPECT_EQ(i.topic, "stateEstimate.pitch");
  EXPECT_EQ(i.message.rfind("the log has no stateEstimate.pitch (", 0), 0u) << i.message;
  EXPECT_EQ(i.message.find("motor.m1,"), std::string::npos) << i.message;  // the motors are there

  // With a pitch column added (level), everything else the log holds converts: ~101 Hz signals,
  // and the battery-voltage model gives a hover thrust of a ~35 g Crazyflie 2.1 with decks.
  LogTopic& fixed = log.topics[0];
  fixed.fields.push_back(LogField{"stateEstimate.pitch", FieldType::kFloat, "", 1.0});
  fixed.columns.emplace_back(fixed.rows(), 0.0);
  ASSERT_TRUE(extractCrazyflieSignals(log, CrazyflieSignalOptions{}, s).ok());
  EXPECT_EQ(s.command.t.size(), fixed.rows());
  EXPECT_TRUE(mentions(s.conventions, "battery-voltage model"));
  double sum = 0.0;
  int flying = 0;
  for (const auto& f : s.command.v) {
    const double total = f[0] + f[1] + f[2] + f[3];
    if (total > 0.1) {
      sum += total;
      ++flying;
    }
  }
  ASSERT_GT(flying, 1000);
  EXPECT_NEAR(sum / flying / 9.81 * 1000.0, 37.0, 5.0) << "mean thrust in flight [g]";
}

TEST(CrazyflieSignalsReal, ControllerLogsRefuseNamingAttitudeAndMotors) {
  for (std::size_t k = 1; k < 4; ++k) {
    DecodedLog log;
    if (!readReal(kRealLogs[k], log)) GTEST_SKIP() << "no real logs in " << kRealDir;
    FlightSignals s;
    const LogIssue i = extractCrazyflieSignals(log, CrazyflieSignalOptions{}, s);
    ASSERT_FALSE(i.ok());
    EXPECT_EQ(i.message.rfind("the log has no stateEstimate.roll, stateEstimate.pitch, stateEstimate.yaw, motor.m1, "
                              "motor.m2, motor.m3, motor.m4 (",
                              0),
              0u)
        << kRealLogs[k].file << ": " << i.message;
  }
}
