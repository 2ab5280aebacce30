// The DataFlash text reader (src/logs/dataflash_text.h): a log printed as text (Mission Planner's
// .log, here by tests/logs/dataflash_writer.h) must read as the binary log it was printed from,
// whatever the line endings and separators; a line it cannot read is named by its number.
#include "logs/dataflash_text.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "logs/dataflash.h"
#include "logs/dataflash_writer.h"
#include "logs/mission_writers.h"
#include "logs/sim_flights.h"

using namespace quadfdi;
using quadfdi::test::DataflashWriter;

namespace {

ByteSpan span(const std::string& s) { return ByteSpan{reinterpret_cast<const std::uint8_t*>(s.data()), s.size()}; }
ByteSpan span(const std::vector<std::uint8_t>& b) { return ByteSpan{b.data(), b.size()}; }

std::string allWarnings(const DecodedLog& log) {
  std::string s;
  for (const std::string& w : log.warnings) s += w + "\n";
  return s;
}

bool sameValue(double a, double b) { return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0; }

// Every topic, field, row and value the same, bit for bit; a flight-mode field (M) may be kFloat in `text`.
void expectSameLog(const DecodedLog& binary, const DecodedLog& text) {
  EXPECT_EQ(text.format, binary.format);
  ASSERT_EQ(text.topics.size(), binary.topics.size());
  for (std::size_t i = 0; i < binary.topics.size(); ++i) {
    const LogTopic& b = binary.topics[i];
    const LogTopic& t = text.topics[i];
    SCOPED_TRACE(b.name + "[" + std::to_string(b.instance) + "]");
    EXPECT_EQ(t.name, b.name);
    EXPECT_EQ(t.instance, b.instance);
    EXPECT_EQ(t.timestamp_us, b.timestamp_us);
    ASSERT_EQ(t.fields.size(), b.fields.size());
    ASSERT_EQ(t.columns.size(), b.columns.size());
    for (std::size_t f = 0; f < b.fields.size(); ++f) {
      SCOPED_TRACE(b.fields[f].name);
      EXPECT_EQ(t.fields[f].name, b.fields[f].name);
      EXPECT_EQ(t.fields[f].unit, b.fields[f].unit);
      EXPECT_EQ(t.fields[f].multiplier, b.fields[f].multiplier);
      if (b.fields[f].type != FieldType::kUInt8 || t.fields[f].type != FieldType::kFloat) {
        EXPECT_EQ(t.fields[f].type, b.fields[f].type);
      }
      ASSERT_EQ(t.columns[f].size(), b.columns[f].size());
      for (std::size_t r = 0; r < b.columns[f].size(); ++r)
        if (!sameValue(t.columns[f][r], b.columns[f][r])) {
          ADD_FAILURE() << "row " << r << ": text " << t.columns[f][r] << ", binary " << b.columns[f][r];
          break;
        }
    }
  }
  EXPECT_EQ(text.parameters, binary.parameters);
  EXPECT_EQ(text.info, binary.info);
  ASSERT_EQ(text.messages.size(), binary.messages.size());
  for (std::size_t i = 0; i < binary.messages.size(); ++i) {
    EXPECT_EQ(text.messages[i].timestamp_us, binary.messages[i].timestamp_us);
    EXPECT_EQ(text.messages[i].text, binary.messages[i].text);
  }
}

// Both forms of one writer's log, read and compared; the text also with CRLF, "," and a BOM.
void expectTextReadsAsBinary(const DataflashWriter& w) {
  DecodedLog binary;
  ASSERT_TRUE(readDataflash(span(w.bytes), binary).ok());
  std::string crlf, tight;
  for (char c : w.text) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  // "," between fields (some tools write it); a MSG's own ", " stays.
  bool in_msg = false;
  for (std::size_t k = 0; k < w.text.size(); ++k) {
    if (k == 0 || w.text[k - 1] == '\n') in_msg = w.text.compare(k, 4, "MSG,") == 0;
    if (!(w.text[k] == ' ' && k > 0 && w.text[k - 1] == ',' && !in_msg)) tight += w.text[k];
  }
  const std::string variants[] = {w.text, crlf, "\xEF\xBB\xBF" + w.text, tight};
  for (const std::string& text : variants) {
    SCOPED_TRACE(text.substr(0, 70));
    EXPECT_TRUE(looksLikeDataflashText(span(text)));
    EXPECT_FALSE(looksLikeDataflash(span(text)));
    DecodedLog read;
    const LogIssue issue = readDataflashText(span(text), read);
    ASSERT_TRUE(issue.ok()) << issue.message;
    EXPECT_EQ(allWarnings(read), allWarnings(binary));
    expectSameLog(binary, read);
  }
}

}  // namespace

// Every format character (c, C, e, E and L printed in physical units), TimeMS, VER, an int16[32].
TEST(DataflashText, EveryFormatCharacterReadsAsInTheBinaryLog) { expectTextReadsAsBinary(test::everyFormatCharacterLog()); }

// Units, multipliers (FMTU, UNIT, MULT) and instances split as in the binary log: a whole
// ArduPilot flight with two IMUs and two EKF cores.
TEST(DataflashText, AFlightWithUnitsMultipliersAndInstancesReadsAsInTheBinaryLog) {
  const test::Mission m = test::simulateMission(2, 0.0, 4.0);
  DataflashWriter w = test::ardupilotMissionLog(m, 400.0, 25.0, test::ApRates::kImu);
  w.unit(0, 'E', "rad/s");
  w.mult(0, 'F', 1e-6);
  w.fmtu(0, test::kApImu, "s#EEEnnn--O----", "F-000000--0----");
  for (unsigned core = 0; core < 2; ++core)
    w.write(test::kApXkf1, {10000000ull, core, 0, 0, 0, 0.0, 0.0, 0.0, 0.0, 1.0, 2.0, -3.0, 0, 0, 0, 0});
  expectTextReadsAsBinary(w);
  DecodedLog log;
  ASSERT_TRUE(readDataflashText(span(w.text), log).ok());
  ASSERT_NE(log.find("IMU", 1), nullptr);
  ASSERT_NE(log.find("XKF1", 1), nullptr);
  const LogTopic& imu = *log.find("IMU", 0);
  EXPECT_EQ(imu.fields.at(static_cast<std::size_t>(imu.fieldIndex("GyrX"))).unit, "rad/s");
}

// A flight mode printed by its name reads as NaN (MODE's ModeNum holds the number).
TEST(DataflashText, AFlightModeNameReadsAsNaN) {
  const std::string text =
      "FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns\n"
      "FMT, 140, 14, MODE, QMBB, TimeUS,Mode,ModeNum,Rsn\n"
      "MODE, 1000, Stabilize, 0, 1\n"
      "MODE, 2000, 5, 5, 2\n";
  DecodedLog log;
  ASSERT_TRUE(readDataflashText(span(text), log).ok());
  EXPECT_EQ(allWarnings(log), "");
  const LogTopic* mode = log.find("MODE");
  ASSERT_NE(mode, nullptr);
  ASSERT_EQ(mode->rows(), 2u);
  EXPECT_TRUE(std::isnan(mode->columns[0][0]));
  EXPECT_EQ(mode->columns[0][1], 5.0);
  EXPECT_EQ(mode->columns[1][0], 0.0);
  EXPECT_EQ(mode->fields[0].type, FieldType::kFloat);
}

// UNIT's and MULT's Id, a character stored as int8, reads the same printed as its code or as itself.
TEST(DataflashText, UnitAndMultIdsReadAsCodesOrCharacters) {
  const std::string head =
      "FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns\n"
      "FMT, 177, 76, UNIT, QbZ, TimeUS,Id,Label\n"
      "FMT, 179, 20, MULT, Qbd, TimeUS,Id,Mult\n"
      "FMT, 178, 44, FMTU, QBNN, TimeUS,FmtType,UnitIds,MultIds\n"
      "FMT, 200, 17, TST, Qhf, TimeUS,A,B\n";
  const std::string tail = "FMTU, 0, 200, sdm, F?B\nTST, 1000, 150, 2.5\n";
  DecodedLog as_codes, as_characters;
  ASSERT_TRUE(readDataflashText(span(head + "UNIT, 0, 100, deg\nUNIT, 0, 109, m\nMULT, 0, 66, 0.01\n" + tail), as_codes).ok());
  ASSERT_TRUE(readDataflashText(span(head + "UNIT, 0, d, deg\nUNIT, 0, m, m\nMULT, 0, B, 0.01\n" + tail), as_characters).ok());
  EXPECT_EQ(allWarnings(as_characters), "");
  expectSameLog(as_codes, as_characters);
  const LogTopic* tst = as_characters.find("TST");
  ASSERT_NE(tst, nullptr);
  EXPECT_EQ(tst->fields[0].unit, "deg");
  EXPECT_EQ(tst->fields[1].unit, "m");
  EXPECT_DOUBLE_EQ(tst->columns[1][0], 0.025);  // B × 0.01
}

// A line that cannot be read is skipped and named by its line (the first of each kind; the rest
// counted); every other line still reads.
TEST(DataflashText, LinesThatCannotBeReadAreSkippedAndNamedByTheirLine) {
  const std::string text =
      "FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns\n"       // 1
      "FMT, 200, 15, TST, Qhc, TimeUS,A,B\n"                              // 2
      "TST, 1000, 1, 0.5\n"                                               // 3
      "TST, 2000, 70000, 0.5\n"                                           // 4: h out of range
      "TST, 3000, x, 0.5\n"                                               // 5: not a number
      "TST, 4000, 2\n"                                                    // 6: too few fields
      "TST, 5000, 3, 400.0\n"                                             // 7: 40000 > int16
      "GPS, 6000, 1, 2\n"                                                 // 8: no FMT
      "GPS, 6100, 1, 2\n"                                                 // 9: no FMT again
      "FMT, 201, 99, BAD, Qh, TimeUS\n"                                   // 10: 1 label for 2 characters
      "BAD, 1, 2\n"                                                       // 11: its FMT was skipped
      "FMT, 202, 9, BIG, Qj, TimeUS,J\n"                                  // 12: unknown character
      "FMT, 203, 12, LEN, Qf, TimeUS,F\n"                                 // 13: declares 12, needs 15
      "LEN, 7000, 2.5\n"                                                  // 14: read by its format
      "FMT, 200, 15, TS2, Qhc, TimeUS,A,B\n"                              // 15: type 200 again
      "\n"                                                                // 16: blank
      "TST, 8000, 4, -0.25\n";                                            // 17
  DecodedLog log;
  const LogIssue issue = readDataflashText(span(text), log);
  ASSERT_TRUE(issue.ok()) << issue.message;
  const std::string warnings = allWarnings(log);
  EXPECT_EQ(warnings,
            "line 4: TST.A: '70000' is outside the range of its type; line skipped\n"
            "line 5: TST.A: 'x' is not an integer; line skipped\n"
            "line 6: TST line with 2 fields, its FMT has 3; skipped\n"
            "line 7: TST.B: '400.0' is outside the range of its stored type; line skipped\n"
            "line 8: message 'GPS' has no FMT line before it; skipped (and 1 more line like it)\n"
            "line 10: FMT line for BAD: 1 labels for 2 format characters; skipped, and its messages with it\n"
            "line 11: message 'BAD' has no FMT line before it; skipped\n"
            "line 12: FMT line for BIG: the format \"Qj\" is not up to 16 DataFlash format characters with up to 64 characters of "
            "labels; skipped, and its messages with it\n"
            "line 13: FMT line for LEN declares length 12 but its format \"Qf\" needs 15 bytes; read by its format\n"
            "line 15: FMT line redefines type 200 (TST → TS2); kept the first definition\n");
  const LogTopic* tst = log.find("TST");
  ASSERT_NE(tst, nullptr);
  EXPECT_EQ(tst->timestamp_us, (std::vector<std::int64_t>{1000, 8000}));
  EXPECT_EQ(tst->columns[1], (std::vector<double>{0.5, -0.25}));
  ASSERT_NE(log.find("LEN"), nullptr);
  EXPECT_EQ(log.find("LEN")->columns[0], std::vector<double>{2.5});
}

// Older firmware printed a banner before the first FMT line: skipped with one warning.
TEST(DataflashText, ABannerBeforeTheFirstFmtLineIsSkipped) {
  const std::string text =
      "ArduCopter V3.1.5 (3c57e771)\r\n"
      "Free RAM: 990\r\n"
      "\r\n"
      "APM 2\r\n"
      "FMT, 1, 23, PARM, Nf, Name,Value\r\n"
      "PARM, RATE_RLL_P, 0.15\r\n";
  EXPECT_TRUE(looksLikeDataflashText(span(text)));
  DecodedLog log;
  const LogIssue issue = readDataflashText(span(text), log);
  ASSERT_TRUE(issue.ok()) << issue.message;
  EXPECT_EQ(allWarnings(log), "line 1: 3 lines of text before the first FMT line skipped (\"ArduCopter V3.1.5 (3c57e771)\")\n");
  EXPECT_FLOAT_EQ(static_cast<float>(log.parameters.at("RATE_RLL_P")), 0.15f);
}

// What is not a text DataFlash log is refused with its line; the binary reader names the text form.
TEST(DataflashText, WhatIsNoTextLogIsRefusedWithItsLine) {
  DecodedLog log;
  LogIssue issue = readDataflashText(span(std::string()), log);
  EXPECT_EQ(issue.status, LogStatus::kTruncated);
  issue = readDataflashText(span(std::string("\n \r\n\n")), log);
  EXPECT_EQ(issue.status, LogStatus::kTruncated);
  EXPECT_EQ(issue.message, "empty log (no line of text)");
  // A CSV: no FMT line in its first 16 lines (nor anywhere): refused at the 17th, or at line 1 when shorter.
  std::string csv = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n";
  for (int k = 0; k < 20; ++k) csv += "0,0,0,0,0,0,0,0.1,0.1,0.1,0.1\n";
  EXPECT_FALSE(looksLikeDataflashText(span(csv)));
  issue = readDataflashText(span("\n\n" + csv + "FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns\n"), log);
  EXPECT_EQ(issue.status, LogStatus::kWrongMagic);
  EXPECT_EQ(issue.line, 19u);
  EXPECT_EQ(issue.message, "not an ArduPilot DataFlash log as text: no FMT line (\"FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,"
                           "Columns\") in its first 16 lines of text");
  issue = readDataflashText(span(std::string("t,x\n0,1\n")), log);
  EXPECT_EQ(issue.status, LogStatus::kWrongMagic);
  EXPECT_EQ(issue.line, 1u);
  EXPECT_FALSE(looksLikeDataflashText(span(std::string("t,FMT,x\n"))));
  EXPECT_TRUE(looksLikeDataflashText(span(std::string("\r\n  FMT, 129, 23, PARM, QNf, TimeUS,Name,Value\n"))));
  // A text log given to the binary reader: its refusal names the text form.
  issue = readDataflash(span(std::string("FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns\n")), log);
  EXPECT_EQ(issue.status, LogStatus::kWrongMagic);
  EXPECT_NE(issue.message.find("\"FMT, …\" of the log as text"), std::string::npos) << issue.message;
}
