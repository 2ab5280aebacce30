// A small, line-oriented configuration format (a TOML subset):
//   # comment
//   [section]            → following keys are "section.key"
//   key = 1.5e-3         → numbers, true/false, "strings", [1, 2, 3] lists
// Every entry remembers its line, so every error names file and line.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "io/file_bytes.h"

namespace quadfdi {

// "FILE:LINE: problem" — thrown only at the edges (file and config parsing).
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct KeyValueEntry {
  std::string key;    // with "section." prefix when inside a [section]
  std::string value;  // raw text after '=', trimmed, comment removed
  int line = 0;       // 1-based
};

struct KeyValueDocument {
  std::string source;  // file name used in messages
  std::vector<KeyValueEntry> entries;

  const KeyValueEntry* find(const std::string& key) const;
  [[noreturn]] void fail(const KeyValueEntry& entry, const std::string& problem) const;
  double number(const KeyValueEntry& entry) const;
  long long integer(const KeyValueEntry& entry) const;
  bool boolean(const KeyValueEntry& entry) const;
  std::string string(const KeyValueEntry& entry) const;   // "quoted" or bare word
  std::vector<double> numberList(const KeyValueEntry& entry) const;
};

// Parses text; throws ConfigError("SOURCE:LINE: problem") on malformed lines or duplicate keys.
KeyValueDocument parseKeyValue(const std::string& text, const std::string& source);
// Whole file as text, at most io/file_bytes.h's kMaxConfigFileBytes; throws ConfigError("PATH:
// problem") when it cannot be read, is a folder, a device or (unless `pipes` reads them) a pipe, or is
// larger. `kind` names what the file should be in that message ("a vehicle file"). A pipe gives its
// bytes once: only a caller that reads the file once in a run may read one.
std::string readTextFile(const std::string& path, const std::string& kind = "a configuration file",
                         PipeReading pipes = PipeReading::kRefuse);
// Reads and parses a file; throws ConfigError naming the file when it cannot be read.
KeyValueDocument readKeyValueFile(const std::string& path);

// Strict number parsing shared by configs and CSV readers: the whole text must be a
// finite decimal number. Returns false otherwise.
bool parseFiniteNumber(const std::string& text, double& value);

}  // namespace quadfdi
