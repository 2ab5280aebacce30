// What every flight-log reader produces (PX4 ULog, Crazyflie micro-SD, ArduPilot DataFlash):
// one format-neutral table per logged message type, so that the conventions layer (frames,
// motor numbering, thrust) reads topics by name and never sees a byte format. Readers are
// pure functions of a byte span: no files, no exceptions; problems come back as a LogIssue.
// The formats themselves: docs/log-formats.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace quadfdi {

// A read-only view of a whole log in memory (the CLI maps or reads the file).
struct ByteSpan {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
};

// kMergedCsv: a telemetry CSV merging signals sampled at different times (io/merged_telemetry.h),
// which reaches the conventions layer as a log does.
enum class LogFormat { kUnknown, kUlog, kCrazyflieUsd, kDataflash, kMergedCsv };
const char* toString(LogFormat f);

// The type a field had in the log; values are stored as double whatever the type (64-bit
// integers beyond 2^53 lose precision: timestamps are kept separately, exactly).
enum class FieldType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kInt64, kUInt64, kFloat, kDouble, kBool, kChar };
const char* toString(FieldType t);

// A parameter or field value in a message, printed the shortest way ("%g": 1, 0.15, 1e+06).
std::string shortNumber(double v);

struct LogField {
  std::string name;        // arrays are flattened: "q[0]" … "q[3]"
  FieldType type = FieldType::kFloat;
  std::string unit;        // where the format says (DataFlash FMTU, …); empty otherwise
  double multiplier = 1.0; // already applied to the stored values (DataFlash MULT); 1 otherwise
};

// One logged message type (ULog topic instance, DataFlash message type + instance, Crazyflie
// event type), as columns.
struct LogTopic {
  std::string name;        // "vehicle_attitude", "ATT", "fixedFrequency"
  int instance = 0;        // ULog multi_id, DataFlash instance field; 0 otherwise
  std::vector<LogField> fields;
  std::vector<std::int64_t> timestamp_us;       // [µs] one per row, in the log's own time base
  std::vector<std::vector<double>> columns;     // columns[field][row]
  std::size_t rows() const { return timestamp_us.size(); }
  int fieldIndex(const std::string& field) const;  // −1 if absent
};

// A gap the logger itself reported (ULog dropout), or a reader-detected one.
struct LogDropout {
  std::int64_t timestamp_us = 0;  // [µs] when it was noticed
  std::int64_t duration_us = 0;   // [µs] data lost
};

// A text message of the autopilot (ULog logging/tagged logging, DataFlash MSG).
struct LogText {
  std::int64_t timestamp_us = 0;  // [µs]
  int level = 0;                  // format's own severity (ULog: '0'..'7'); 0 if none
  int tag = -1;                   // ULog tagged logging; −1 otherwise
  std::string text;
};

struct DecodedLog {
  LogFormat format = LogFormat::kUnknown;
  std::vector<LogTopic> topics;
  std::map<std::string, double> parameters;        // last value of each (ULog, DataFlash PARM)
  std::map<std::string, double> default_parameters; // ULog default-parameter messages
  std::map<std::string, std::string> info;         // ULog info, Crazyflie header facts, DataFlash VER/MSG firmware
  std::vector<LogText> messages;
  std::vector<LogDropout> dropouts;
  std::vector<std::string> warnings;               // problems read past (e.g. a truncated last message)
  const LogTopic* find(const std::string& name, int instance = 0) const;  // nullptr if absent
};

enum class LogStatus {
  kOk,
  kWrongMagic,          // not this format
  kUnsupportedVersion,  // this format, a version we do not read
  kTruncated,           // ends before a required part (header, definitions) is complete
  kCorrupt,             // a message contradicts the format (bad size, unknown id where one is required, bad checksum)
  kTooLarge,            // a declared size beyond what the reader accepts (protects memory)
  kMissingSignal,       // well-formed, but a topic/field the extractor needs is not logged (extractors only)
};
const char* toString(LogStatus s);

// The one error convention of the readers: status, where, and a sentence; the CLI prints
// "FILE: byte OFFSET[, topic T]: message" ("FILE: line N[, …]" for a text log).
struct LogIssue {
  LogStatus status = LogStatus::kOk;
  std::uint64_t offset = 0;  // [bytes] from the start of the log
  std::string topic;         // the message type involved, if any
  std::string message;
  std::uint64_t line = 0;    // [1-based] the line, in a log that is text (DataFlash as text); 0 where `offset` says it
  bool ok() const { return status == LogStatus::kOk; }
};

}  // namespace quadfdi
