// Reading flight telemetry (docs/conventions.md) for the detector: header names the columns (any order,
// extra columns ignored), one sample per row. Rows are read one at a time so a live pipe works.
#pragma once

#include <array>
#include <istream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/motor_numbering.h"
#include "core/sample_source.h"

namespace quadfdi {

// "NAME:LINE: problem" — bad input the reader cannot go past.
class TelemetryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class TelemetryReader : public SampleSource {
 public:
  // Reads the header (blank lines and lines starting with '#' are skipped). Throws TelemetryError
  // for an empty input or a header without the required columns.
  TelemetryReader(std::istream& in, std::string name);

  using Row = SampleSource::Next;
  // kSample: `sample` holds the row; kSkipped: a NaN, infinite, empty or absurd (|v| > 1e9) cell,
  // `problem` says which, the row is dropped; kEnd.

  // Throws TelemetryError for a row that is not telemetry (wrong cell count, text in a number).
  Next next(TelemetrySample& sample, std::string& problem) override;
  std::string where() const override { return name_ + ":" + std::to_string(line_); }
  bool moreReady() const override;  // standard input: buffered or pollable data; files: always

  long line() const { return line_; }  // 1-based number of the last line read
  // The "# motor_numbering: NAME = A B C D" comment before the header (writeTelemetryCsvHeader),
  // if the file has one: the autopilot's numbers of quadfdi's motors 1..4.
  const std::optional<MotorNumbering>& numbering() const { return numbering_; }
  const std::string& name() const { return name_; }

  static const char* const kRequiredColumns[11];  // t, x, y, z, roll, pitch, yaw, u1 … u4

 private:
  bool readLine(std::string& text);
  void readNumberingComment(const std::string& comment);
  std::istream& in_;
  std::string name_;
  long line_ = 0;
  int cells_ = 0;                 // columns in the header
  std::array<int, 11> column_{};  // cell index of each required column
  std::vector<std::string> cells_buffer_;
  std::optional<MotorNumbering> numbering_;
};

}  // namespace quadfdi
