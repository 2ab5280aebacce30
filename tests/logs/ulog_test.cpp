// PX4 ULog reader: round trips through the test writer, the two real sample logs, and broken
// input (each with its documented status and byte offset; docs/logs/ulog.md).
#include "logs/ulog.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "logs/ulog_writer.h"

namespace quadfdi {
namespace {

using testing::UlogPayload;
using testing::UlogWriter;

ByteSpan span(const std::vector<std::uint8_t>& b) { return ByteSpan{b.data(), b.size()}; }

const LogField& field(const LogTopic& t, const std::string& name) {
  const int i = t.fieldIndex(name);
  EXPECT_GE(i, 0) << name;
  return t.fields.at(static_cast<std::size_t>(i < 0 ? 0 : i));
}
double value(const LogTopic& t, const std::string& name, std::size_t row) {
  const int i = t.fieldIndex(name);
  EXPECT_GE(i, 0) << name;
  return i < 0 ? std::nan("") : t.columns.at(static_cast<std::size_t>(i)).at(row);
}

// A small, valid log: two formats (one nested), two instances of one topic, a second topic.
UlogWriter smallLog() {
  UlogWriter w(1, 1000);
  w.flagBits();
  w.info("sys_name", "PX4");
  w.format("vec3:float x;float y;float z;");
  w.format("sensor:uint64_t timestamp;vec3 accel;int16_t[2] raw;uint8_t[3] _padding0;");
  w.format("vehicle_attitude:uint64_t timestamp;float[4] q;uint8_t[4] _padding0;");
  w.paramFloat("THR_MDL_FAC", 0.3f);
  w.subscribe(0, 0, "vehicle_attitude");
  w.subscribe(0, 1, "sensor");
  w.subscribe(1, 2, "sensor");
  for (std::uint64_t i = 0; i < 5; ++i) {
    w.data(0, UlogPayload().put<std::uint64_t>(10000 + i * 4000).put(1.0f).put(0.0f).put(0.0f).put(static_cast<float>(i)));
    w.data(1, UlogPayload().put<std::uint64_t>(10000 + i * 1000).put(1.5f).put(-2.0f).put(9.81f).put<std::int16_t>(-7).put<std::int16_t>(7));
    w.data(2, UlogPayload().put<std::uint64_t>(20000 + i * 1000).put(0.5f).put(0.25f).put(-9.0f).put<std::int16_t>(1).put<std::int16_t>(2).pad(3));
  }
  return w;
}

TEST(UlogRoundTrip, NestedArraysPaddingAndInstances) {
  const UlogWriter w = smallLog();
  EXPECT_TRUE(looksLikeUlog(span(w.bytes())));
  DecodedLog log;
  const LogIssue issue = readUlog(span(w.bytes()), log);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_EQ(log.format, LogFormat::kUlog);
  EXPECT_TRUE(log.warnings.empty());
  EXPECT_EQ(log.info.at("sys_name"), "PX4");
  EXPECT_EQ(log.info.at("ulog_start_timestamp_us"), "1000");
  EXPECT_FLOAT_EQ(static_cast<float>(log.parameters.at("THR_MDL_FAC")), 0.3f);
  ASSERT_EQ(log.topics.size(), 3u);

  const LogTopic* att = log.find("vehicle_attitude");
  ASSERT_NE(att, nullptr);
  ASSERT_EQ(att->fields.size(), 4u);  // timestamp is in timestamp_us; padding is dropped
  EXPECT_EQ(att->fields[0].name, "q[0]");
  EXPECT_EQ(att->fields[3].name, "q[3]");
  EXPECT_EQ(att->fields[3].type, FieldType::kFloat);
  ASSERT_EQ(att->rows(), 5u);
  EXPECT_EQ(att->timestamp_us[4], 26000);
  EXPECT_EQ(value(*att, "q[3]", 4), 4.0);

  const LogTopic* s0 = log.find("sensor", 0);
  const LogTopic* s1 = log.find("sensor", 1);
  ASSERT_NE(s0, nullptr);
  ASSERT_NE(s1, nullptr);
  EXPECT_EQ(s1->instance, 1);
  ASSERT_EQ(s0->fields.size(), 5u);
  EXPECT_EQ(s0->fields[0].name, "accel.x");
  EXPECT_EQ(s0->fields[2].name, "accel.z");
  EXPECT_EQ(field(*s0, "raw[1]").type, FieldType::kInt16);
  EXPECT_EQ(s0->rows(), 5u);
  EXPECT_EQ(s1->rows(), 5u);
  EXPECT_EQ(value(*s0, "accel.y", 2), -2.0);
  EXPECT_EQ(value(*s0, "raw[0]", 0), -7.0);
  EXPECT_FLOAT_EQ(static_cast<float>(value(*s0, "accel.z", 0)), 9.81f);
  EXPECT_EQ(value(*s1, "accel.z", 3), -9.0);  // written with its trailing padding
  EXPECT_EQ(s0->timestamp_us[1], 11000);       // written without it
  EXPECT_EQ(s1->timestamp_us[1], 21000);
}

TEST(UlogRoundTrip, EveryBasicTypeAndArrayOfNested) {
  UlogWriter w(2);
  w.flagBits();
  w.format("pair:int8_t a;uint16_t b;");
  w.format(
      "all:int8_t i8;uint8_t u8;int16_t i16;uint16_t u16;int32_t i32;uint32_t u32;int64_t i64;uint64_t timestamp;"
      "uint64_t u64;float f;double d;bool flag;char[3] name;pair[2] pairs;");
  w.subscribe(0, 7, "all");
  w.data(7, UlogPayload()
                .put<std::int8_t>(-8)
                .put<std::uint8_t>(200)
                .put<std::int16_t>(-30000)
                .put<std::uint16_t>(60000)
                .put<std::int32_t>(-2000000000)
                .put<std::uint32_t>(4000000000u)
                .put<std::int64_t>(-(std::int64_t{1} << 40))
                .put<std::uint64_t>(123456789012345ull)
                .put<std::uint64_t>(std::uint64_t{1} << 50)
                .put(1.25f)
                .put(-3.5e100)
                .put<std::uint8_t>(7)
                .put('a').put('b').put('c')
                .put<std::int8_t>(-1).put<std::uint16_t>(65535)
                .put<std::int8_t>(5).put<std::uint16_t>(6));
  DecodedLog log;
  ASSERT_TRUE(readUlog(span(w.bytes()), log).ok());
  const LogTopic* t = log.find("all");
  ASSERT_NE(t, nullptr);
  ASSERT_EQ(t->rows(), 1u);
  EXPECT_EQ(t->timestamp_us[0], 123456789012345);
  const std::vector<std::pair<std::string, FieldType>> expected = {
      {"i8", FieldType::kInt8},     {"u8", FieldType::kUInt8},     {"i16", FieldType::kInt16},
      {"u16", FieldType::kUInt16},  {"i32", FieldType::kInt32},    {"u32", FieldType::kUInt32},
      {"i64", FieldType::kInt64},   {"u64", FieldType::kUInt64},   {"f", FieldType::kFloat},
      {"d", FieldType::kDouble},    {"flag", FieldType::kBool},    {"name[0]", FieldType::kChar},
      {"name[1]", FieldType::kChar}, {"name[2]", FieldType::kChar}, {"pairs[0].a", FieldType::kInt8},
      {"pairs[0].b", FieldType::kUInt16}, {"pairs[1].a", FieldType::kInt8}, {"pairs[1].b", FieldType::kUInt16}};
  ASSERT_EQ(t->fields.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(t->fields[i].name, expected[i].first);
    EXPECT_EQ(t->fields[i].type, expected[i].second) << expected[i].first;
  }
  EXPECT_EQ(value(*t, "i8", 0), -8);
  EXPECT_EQ(value(*t, "u8", 0), 200);
  EXPECT_EQ(value(*t, "i16", 0), -30000);
  EXPECT_EQ(value(*t, "u16", 0), 60000);
  EXPECT_EQ(value(*t, "i32", 0), -2000000000);
  EXPECT_EQ(value(*t, "u32", 0), 4000000000.0);
  EXPECT_EQ(value(*t, "i64", 0), -std::ldexp(1.0, 40));
  EXPECT_EQ(value(*t, "u64", 0), std::ldexp(1.0, 50));
  EXPECT_EQ(value(*t, "f", 0), 1.25);
  EXPECT_EQ(value(*t, "d", 0), -3.5e100);
  EXPECT_EQ(value(*t, "flag", 0), 1.0);
  EXPECT_EQ(value(*t, "name[1]", 0), 'b');
  EXPECT_EQ(value(*t, "pairs[0].a", 0), -1);
  EXPECT_EQ(value(*t, "pairs[0].b", 0), 65535);
  EXPECT_EQ(value(*t, "pairs[1].b", 0), 6);
}

TEST(UlogRoundTrip, ParametersInfoMessagesDropouts) {
  UlogWriter w(1);
  w.flagBits(1);
  w.format("t:uint64_t timestamp;float v;");
  w.info("ver_hw", "SITL");
  w.infoUInt32("ver_sw_release", 0x010e00ffu);
  w.multiInfo("perf", "first ", false);
  w.multiInfo("perf", "second", true);
  w.multiInfo("perf", "another", false);
  w.paramInt("SDLOG_PROFILE", 1);
  w.paramFloat("PWM_MAIN_MAX", 1950.0f);
  w.defaultParamInt(1, "SDLOG_PROFILE", 3);
  w.defaultParamFloat(1, "MPC_XY_P", 0.95f);
  w.defaultParamFloat(2, "MPC_XY_P", 0.8f);
  w.subscribe(0, 0, "t");
  w.logging('6', 1500, "Takeoff detected");
  w.data(0, UlogPayload().put<std::uint64_t>(2000).put(1.0f));
  w.dropout(120);
  w.taggedLogging('3', 42, 3000, "ESC failure");
  w.paramInt("SDLOG_PROFILE", 5);  // changed in flight: the last value is kept
  w.defaultParamInt(3, "COM_ARM", 1);
  w.message('X', std::string("an unknown message type"));
  w.sync();
  w.data(0, UlogPayload().put<std::uint64_t>(4000).put(2.0f));
  DecodedLog log;
  const LogIssue issue = readUlog(span(w.bytes()), log);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_EQ(log.info.at("ver_hw"), "SITL");
  EXPECT_EQ(log.info.at("ver_sw_release"), std::to_string(0x010e00ffu));
  EXPECT_EQ(log.info.at("perf"), "first second");
  EXPECT_EQ(log.info.at("perf[1]"), "another");
  EXPECT_EQ(log.parameters.at("SDLOG_PROFILE"), 5);
  EXPECT_EQ(log.parameters.at("PWM_MAIN_MAX"), 1950);
  EXPECT_EQ(log.default_parameters.at("SDLOG_PROFILE"), 3);
  EXPECT_FLOAT_EQ(static_cast<float>(log.default_parameters.at("MPC_XY_P")), 0.8f);  // configuration default wins
  EXPECT_EQ(log.default_parameters.at("COM_ARM"), 1);
  ASSERT_EQ(log.messages.size(), 2u);
  EXPECT_EQ(log.messages[0].level, 6);
  EXPECT_EQ(log.messages[0].tag, -1);
  EXPECT_EQ(log.messages[0].timestamp_us, 1500);
  EXPECT_EQ(log.messages[0].text, "Takeoff detected");
  EXPECT_EQ(log.messages[1].level, 3);
  EXPECT_EQ(log.messages[1].tag, 42);
  EXPECT_EQ(log.messages[1].text, "ESC failure");
  ASSERT_EQ(log.dropouts.size(), 1u);
  EXPECT_EQ(log.dropouts[0].timestamp_us, 2000);
  EXPECT_EQ(log.dropouts[0].duration_us, 120000);
  ASSERT_EQ(log.warnings.size(), 1u);  // the unknown type, skipped
  EXPECT_NE(log.warnings[0].find("unknown type"), std::string::npos);
  EXPECT_EQ(log.find("t")->rows(), 2u);
}

// Info and parameter messages share one body (key length, "type name", value); a broken one is
// skipped — a parameter with a warning naming its byte offset — and the rest of the log is read.
TEST(UlogRoundTrip, BrokenInfoAndParameterMessagesAreSkipped) {
  UlogWriter w(1);
  w.flagBits();
  const std::size_t no_space_at = w.size();
  w.keyed('P', {}, "SDLOG_PROFILE", std::vector<std::uint8_t>(4));  // no type in the key
  const std::size_t short_value_at = w.size();
  w.keyed('P', {}, "float MPC_XY_P", std::vector<std::uint8_t>(2));  // a 2-byte value
  w.message('Q', std::vector<std::uint8_t>{2, 40, 'i', 'n', 't'});  // key longer than the message
  w.keyed('I', {}, "ver_hw", std::vector<std::uint8_t>(4));  // no type in the key
  w.keyed('M', {0}, "char[4] perf", std::string());  // an empty value is still a value
  w.paramInt("COM_ARM", 1);
  w.format("t:uint64_t timestamp;float v;");
  w.subscribe(0, 0, "t");
  w.data(0, UlogPayload().put<std::uint64_t>(2000).put(1.0f));
  DecodedLog log;
  const LogIssue issue = readUlog(span(w.bytes()), log);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_EQ(log.find("t")->rows(), 1u);
  ASSERT_EQ(log.warnings.size(), 2u);
  EXPECT_EQ(log.warnings[0], "byte " + std::to_string(no_space_at) +
                                 ": parameter message without a 4-byte value ('SDLOG_PROFILE'); skipped");
  EXPECT_EQ(log.warnings[1], "byte " + std::to_string(short_value_at) +
                                 ": parameter message without a 4-byte value ('float MPC_XY_P'); skipped");
  EXPECT_EQ(log.parameters.size(), 1u);
  EXPECT_EQ(log.parameters.at("COM_ARM"), 1);
  EXPECT_TRUE(log.default_parameters.empty());
  EXPECT_EQ(log.info.count("ver_hw"), 0u);
  EXPECT_EQ(log.info.at("perf"), "");
}

TEST(UlogRoundTrip, UnsubscribeThenResubscribeContinuesTheTopic) {
  UlogWriter w;
  w.format("t:uint64_t timestamp;float v;");
  w.subscribe(0, 0, "t");
  w.data(0, UlogPayload().put<std::uint64_t>(1).put(1.0f));
  w.unsubscribe(0);
  w.subscribe(0, 3, "t");
  w.data(3, UlogPayload().put<std::uint64_t>(2).put(2.0f));
  DecodedLog log;
  ASSERT_TRUE(readUlog(span(w.bytes()), log).ok());
  ASSERT_EQ(log.topics.size(), 1u);
  EXPECT_EQ(log.topics[0].rows(), 2u);
}

TEST(UlogRoundTrip, AppendedDataIsReadAfterACutMessage) {
  UlogWriter w(2);
  w.flagBits(0, 1, 0);  // the offset is patched below
  w.format("t:uint64_t timestamp;float v;");
  w.subscribe(0, 0, "t");
  w.data(0, UlogPayload().put<std::uint64_t>(100).put(1.0f));
  w.data(0, UlogPayload().put<std::uint64_t>(200).put(2.0f));
  std::vector<std::uint8_t> bytes = w.bytes();
  bytes.resize(bytes.size() - 5);  // the log stopped mid-message (a crash)
  const std::uint64_t appended_at = bytes.size();
  std::memcpy(bytes.data() + 16 + 3 + 16, &appended_at, 8);
  UlogWriter tail;
  tail.data(0, UlogPayload().put<std::uint64_t>(300).put(3.0f));
  bytes.insert(bytes.end(), tail.bytes().begin() + 16, tail.bytes().end());
  DecodedLog log;
  const LogIssue issue = readUlog(span(bytes), log);
  ASSERT_TRUE(issue.ok()) << issue.message;
  const LogTopic* t = log.find("t");
  ASSERT_EQ(t->rows(), 2u);
  EXPECT_EQ(t->timestamp_us[1], 300);
  EXPECT_EQ(value(*t, "v", 1), 3.0);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_NE(log.warnings[0].find("appended"), std::string::npos);
}

// ---- broken input ----

LogIssue readBytes(const std::vector<std::uint8_t>& b, DecodedLog& log) { return readUlog(span(b), log); }

TEST(UlogBadInput, EmptyWrongMagicTruncatedHeader) {
  DecodedLog log;
  LogIssue e = readBytes({}, log);
  EXPECT_EQ(e.status, LogStatus::kTruncated);
  EXPECT_EQ(e.offset, 0u);
  EXPECT_EQ(readUlog(ByteSpan{nullptr, 5}, log).status, LogStatus::kTruncated);

  const std::string csv = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n";
  e = readBytes(std::vector<std::uint8_t>(csv.begin(), csv.end()), log);
  EXPECT_EQ(e.status, LogStatus::kWrongMagic);
  EXPECT_EQ(e.offset, 0u);
  EXPECT_FALSE(looksLikeUlog(ByteSpan{reinterpret_cast<const std::uint8_t*>(csv.data()), csv.size()}));

  std::vector<std::uint8_t> b = smallLog().bytes();
  b.resize(10);
  e = readBytes(b, log);
  EXPECT_EQ(e.status, LogStatus::kTruncated);
  EXPECT_EQ(e.offset, 10u);
}

TEST(UlogBadInput, Versions) {
  std::vector<std::uint8_t> b = smallLog().bytes();
  b[7] = 0;
  DecodedLog log;
  LogIssue e = readBytes(b, log);
  EXPECT_EQ(e.status, LogStatus::kUnsupportedVersion);
  EXPECT_EQ(e.offset, 7u);
  b[7] = 9;  // a future version: read anyway (spec), with a warning
  e = readBytes(b, log);
  EXPECT_TRUE(e.ok());
  ASSERT_FALSE(log.warnings.empty());
  EXPECT_NE(log.warnings[0].find("byte 7"), std::string::npos);
  EXPECT_EQ(log.find("sensor", 1)->rows(), 5u);
}

TEST(UlogBadInput, UnknownIncompatibleFlag) {
  UlogWriter w(2);
  w.flagBits(0, 2);
  w.format("t:uint64_t timestamp;float v;");
  DecodedLog log;
  const LogIssue e = readBytes(w.bytes(), log);
  EXPECT_EQ(e.status, LogStatus::kUnsupportedVersion);
  EXPECT_EQ(e.offset, 16u + 3 + 8);
}

TEST(UlogBadInput, TruncatedDefinitions) {
  UlogWriter w;
  w.flagBits();
  w.format("t:uint64_t timestamp;float v;");
  const std::size_t second_format = w.size();
  w.format("u:uint64_t timestamp;double w;");
  std::vector<std::uint8_t> b = w.bytes();
  b.resize(b.size() - 4);
  DecodedLog log;
  LogIssue e = readBytes(b, log);
  EXPECT_EQ(e.status, LogStatus::kTruncated);
  EXPECT_EQ(e.offset, second_format);
  // Complete messages but no data section at all: also truncated, at the end.
  e = readBytes(w.bytes(), log);
  EXPECT_EQ(e.status, LogStatus::kTruncated);
  EXPECT_EQ(e.offset, w.size());
}

TEST(UlogBadInput, CorruptFormatString) {
  UlogWriter w;
  w.format("t:uint64_t timestamp;float v;");
  const std::size_t bad = w.size();
  w.format("broken:uint64_t timestamp;float[x] v;");
  w.subscribe(0, 0, "t");
  DecodedLog log;
  const LogIssue e = readBytes(w.bytes(), log);
  EXPECT_EQ(e.status, LogStatus::kCorrupt);
  EXPECT_EQ(e.offset, bad);
  EXPECT_EQ(e.topic, "broken");
  for (const char* text : {"nocolon", ":uint8_t a;", "x:uint8_t;", "x:uint8_t[0] a;", "x:uint8_t[99999] a;", "x:", "x:uint8_t a b;"}) {
    UlogWriter v;
    v.format(text);
    EXPECT_EQ(readBytes(v.bytes(), log).status, LogStatus::kCorrupt) << text;
  }
}

TEST(UlogBadInput, DataForAnUnknownMsgId) {
  UlogWriter w;
  w.format("t:uint64_t timestamp;float v;");
  w.subscribe(0, 0, "t");
  w.data(0, UlogPayload().put<std::uint64_t>(1).put(1.0f));
  const std::size_t bad = w.size();
  w.data(5, UlogPayload().put<std::uint64_t>(2).put(2.0f));
  DecodedLog log;
  LogIssue e = readBytes(w.bytes(), log);
  EXPECT_EQ(e.status, LogStatus::kCorrupt);
  EXPECT_EQ(e.offset, bad);
  // With a sync message after it, the reader resyncs there (spec) and warns.
  w.data(0, UlogPayload().put<std::uint64_t>(3).put(3.0f));  // skipped with the bad message
  const std::size_t sync = w.size();
  w.sync();
  w.data(0, UlogPayload().put<std::uint64_t>(4).put(4.0f));
  e = readBytes(w.bytes(), log);
  ASSERT_TRUE(e.ok()) << e.message;
  EXPECT_EQ(log.find("t")->rows(), 2u);
  EXPECT_EQ(log.find("t")->timestamp_us[1], 4);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_NE(log.warnings[0].find("byte " + std::to_string(bad)), std::string::npos);
  EXPECT_NE(log.warnings[0].find("byte " + std::to_string(sync)), std::string::npos);
}

TEST(UlogBadInput, SizeThatContradictsTheFormat) {
  UlogWriter w;
  w.format("t:uint64_t timestamp;float v;");
  w.subscribe(0, 0, "t");
  const std::size_t bad = w.size();
  w.data(0, UlogPayload().put<std::uint64_t>(1));
  DecodedLog log;
  const LogIssue e = readBytes(w.bytes(), log);
  EXPECT_EQ(e.status, LogStatus::kCorrupt);
  EXPECT_EQ(e.offset, bad);
  EXPECT_EQ(e.topic, "t");
}

TEST(UlogBadInput, SubscriptionProblems) {
  DecodedLog log;
  {  // no format for the name
    UlogWriter w;
    w.format("t:uint64_t timestamp;float v;");
    w.subscribe(0, 0, "nothing");
    const LogIssue e = readBytes(w.bytes(), log);
    EXPECT_EQ(e.status, LogStatus::kCorrupt);
    EXPECT_EQ(e.topic, "nothing");
  }
  {  // a nested type that is never defined
    UlogWriter w;
    w.format("t:uint64_t timestamp;ghost g;");
    w.subscribe(0, 0, "t");
    EXPECT_EQ(readBytes(w.bytes(), log).status, LogStatus::kCorrupt);
  }
  {  // circular nesting
    UlogWriter w;
    w.format("a:uint64_t timestamp;b x;");
    w.format("b:a y;");
    w.subscribe(0, 0, "a");
    EXPECT_EQ(readBytes(w.bytes(), log).status, LogStatus::kCorrupt);
  }
  {  // a format larger than any message
    UlogWriter w;
    w.format("big:uint64_t timestamp;double[9000] v;");
    const std::size_t sub = w.size();
    w.subscribe(0, 0, "big");
    const LogIssue e = readBytes(w.bytes(), log);
    EXPECT_EQ(e.status, LogStatus::kTooLarge);
    EXPECT_EQ(e.offset, sub);
  }
  {  // beyond the column limit
    UlogWriter w;
    w.format("wide:uint64_t timestamp;uint8_t[60000] v;");
    for (std::uint16_t i = 0; i < 6; ++i) w.subscribe(static_cast<std::uint8_t>(i), i, "wide");
    const LogIssue e = readBytes(w.bytes(), log);
    EXPECT_EQ(e.status, LogStatus::kTooLarge);
    EXPECT_EQ(e.topic, "wide");
  }
  {  // no timestamp: subscription kept, data skipped, one warning
    UlogWriter w;
    w.format("nots:float v;");
    w.subscribe(0, 0, "nots");
    w.data(0, UlogPayload().put(1.0f));
    ASSERT_TRUE(readBytes(w.bytes(), log).ok());
    EXPECT_EQ(log.find("nots"), nullptr);
    EXPECT_EQ(log.warnings.size(), 1u);
  }
}

TEST(UlogBadInput, TruncatedLastMessageKeepsTheData) {
  const UlogWriter w = smallLog();
  std::vector<std::uint8_t> b = w.bytes();
  b.resize(b.size() - 6);  // the last sensor[1] message loses its end
  DecodedLog log;
  const LogIssue e = readBytes(b, log);
  ASSERT_TRUE(e.ok()) << e.message;
  EXPECT_EQ(log.find("sensor", 1)->rows(), 4u);
  EXPECT_EQ(log.find("sensor", 0)->rows(), 5u);
  ASSERT_EQ(log.warnings.size(), 1u);
  const std::size_t last_message = w.size() - (3 + 2 + 8 + 12 + 4 + 3);
  EXPECT_NE(log.warnings[0].find("byte " + std::to_string(last_message)), std::string::npos) << log.warnings[0];
}

TEST(UlogBadInput, EveryPrefixOfAValidLogIsReadOrRefusedCleanly) {
  const std::vector<std::uint8_t> full = smallLog().bytes();
  for (std::size_t n = 0; n <= full.size(); ++n) {
    const std::vector<std::uint8_t> b(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
    DecodedLog log;
    const LogIssue e = readBytes(b, log);
    EXPECT_TRUE(e.ok() || e.status == LogStatus::kTruncated) << n << ": " << e.message;
    if (!e.ok()) {
      EXPECT_LE(e.offset, n);
    }
  }
}

// ---- the real sample logs (PX4 ulog_cpp, BSD-3-Clause; not in git) ----

std::vector<std::uint8_t> readSharedLog(const std::string& name) {
  std::ifstream in(std::string(QUADFDI_SOURCE_DIR) + "/../shared/logs/px4/" + name, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

double rateHz(const LogTopic& t) {
  if (t.rows() < 2) return 0.0;
  return static_cast<double>(t.rows() - 1) / (static_cast<double>(t.timestamp_us.back() - t.timestamp_us.front()) * 1e-6);
}

void expectWellFormed(const DecodedLog& log) {
  for (const LogTopic& t : log.topics) {
    ASSERT_EQ(t.columns.size(), t.fields.size()) << t.name;
    for (const auto& c : t.columns) ASSERT_EQ(c.size(), t.rows()) << t.name;
    for (std::size_t i = 1; i < t.rows(); ++i) ASSERT_GE(t.timestamp_us[i], t.timestamp_us[i - 1]) << t.name;
  }
}

TEST(UlogRealLogs, SampleLogSmall) {
  const std::vector<std::uint8_t> b = readSharedLog("sample_log_small.ulg");
  if (b.empty()) GTEST_SKIP() << "../shared/logs/px4/sample_log_small.ulg not found";
  DecodedLog log;
  const LogIssue e = readUlog(span(b), log);
  ASSERT_TRUE(e.ok()) << e.offset << ": " << e.message;
  EXPECT_TRUE(log.warnings.empty()) << log.warnings.front();
  expectWellFormed(log);
  EXPECT_EQ(log.info.at("sys_name"), "PX4");

  const LogTopic* att = log.find("vehicle_attitude");
  ASSERT_NE(att, nullptr);
  EXPECT_EQ(field(*att, "q[0]").type, FieldType::kFloat);
  EXPECT_EQ(field(*att, "quat_reset_counter").type, FieldType::kUInt8);
  EXPECT_LT(att->fieldIndex("_padding0[0]"), 0);
  EXPECT_NEAR(rateHz(*att), 200.0, 50.0);
  for (std::size_t i = 0; i < att->rows(); i += 97) {
    double norm2 = 0.0;
    for (const char* q : {"q[0]", "q[1]", "q[2]", "q[3]"}) norm2 += value(*att, q, i) * value(*att, q, i);
    EXPECT_NEAR(norm2, 1.0, 1e-3);  // a unit quaternion: the offsets are right
  }
  const LogTopic* pos = log.find("vehicle_local_position");
  ASSERT_NE(pos, nullptr);
  EXPECT_EQ(field(*pos, "ref_lat").type, FieldType::kDouble);
  EXPECT_EQ(field(*pos, "xy_valid").type, FieldType::kBool);
  EXPECT_NEAR(rateHz(*pos), 100.0, 30.0);
  const LogTopic* out0 = log.find("actuator_outputs", 0);
  const LogTopic* out1 = log.find("actuator_outputs", 1);
  ASSERT_NE(out0, nullptr);
  ASSERT_NE(out1, nullptr);
  EXPECT_EQ(field(*out0, "output[15]").type, FieldType::kFloat);
  EXPECT_NEAR(rateHz(*out0), 10.0, 5.0);
  EXPECT_GT(out1->rows(), 0u);
  EXPECT_NE(log.find("vehicle_land_detected"), nullptr);
  EXPECT_NE(log.find("actuator_controls_0"), nullptr);
  EXPECT_GT(log.parameters.size(), 500u);
  EXPECT_FALSE(log.messages.empty());
}

TEST(UlogRealLogs, TaggedLoggingAndDefaultParameters) {
  const std::vector<std::uint8_t> b = readSharedLog("sample_logging_tagged_and_default_params.ulg");
  if (b.empty()) GTEST_SKIP() << "../shared/logs/px4/sample_logging_tagged_and_default_params.ulg not found";
  DecodedLog log;
  const LogIssue e = readUlog(span(b), log);
  ASSERT_TRUE(e.ok()) << e.offset << ": " << e.message;
  EXPECT_TRUE(log.warnings.empty()) << log.warnings.front();
  expectWellFormed(log);
  int tagged = 0;
  for (const LogText& m : log.messages) tagged += m.tag >= 0 ? 1 : 0;
  EXPECT_EQ(tagged, 3);
  EXPECT_FALSE(log.default_parameters.empty());
  const LogTopic* att = log.find("vehicle_attitude");
  ASSERT_NE(att, nullptr);
  EXPECT_EQ(field(*att, "timestamp_sample").type, FieldType::kUInt64);
  EXPECT_NEAR(rateHz(*att), 176.0, 40.0);
  const LogTopic* pos = log.find("vehicle_local_position");
  ASSERT_NE(pos, nullptr);
  EXPECT_NEAR(rateHz(*pos), 125.0, 35.0);
  ASSERT_NE(log.find("actuator_outputs"), nullptr);
  EXPECT_NEAR(rateHz(*log.find("actuator_outputs")), 10.0, 5.0);
  EXPECT_NE(log.find("vehicle_land_detected"), nullptr);
}

}  // namespace
}  // namespace quadfdi
