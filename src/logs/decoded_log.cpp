#include "logs/decoded_log.h"

#include <cstdio>

namespace quadfdi {

const char* toString(LogFormat f) {
  switch (f) {
    case LogFormat::kUnknown: return "unknown";
    case LogFormat::kUlog: return "PX4 ULog";
    case LogFormat::kCrazyflieUsd: return "Crazyflie micro-SD";
    case LogFormat::kDataflash: return "ArduPilot DataFlash";
    case LogFormat::kMergedCsv: return "merged telemetry CSV";
  }
  return "?";
}

const char* toString(FieldType t) {
  switch (t) {
    case FieldType::kInt8: return "int8";
    case FieldType::kUInt8: return "uint8";
    case FieldType::kInt16: return "int16";
    case FieldType::kUInt16: return "uint16";
    case FieldType::kInt32: return "int32";
    case FieldType::kUInt32: return "uint32";
    case FieldType::kInt64: return "int64";
    case FieldType::kUInt64: return "uint64";
    case FieldType::kFloat: return "float";
    case FieldType::kDouble: return "double";
    case FieldType::kBool: return "bool";
    case FieldType::kChar: return "char";
  }
  return "?";
}

const char* toString(LogStatus s) {
  switch (s) {
    case LogStatus::kOk: return "ok";
    case LogStatus::kWrongMagic: return "wrong magic";
    case LogStatus::kUnsupportedVersion: return "unsupported version";
    case LogStatus::kTruncated: return "truncated";
    case LogStatus::kCorrupt: return "corrupt";
    case LogStatus::kTooLarge: return "too large";
    case LogStatus::kMissingSignal: return "missing signal";
  }
  return "?";
}

int LogTopic::fieldIndex(const std::string& field) const {
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == field) return static_cast<int>(i);
  return -1;
}

const LogTopic* DecodedLog::find(const std::string& name, int instance) const {
  for (const LogTopic& t : topics)
    if (t.name == name && t.instance == instance) return &t;
  return nullptr;
}

std::string shortNumber(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

}  // namespace quadfdi
