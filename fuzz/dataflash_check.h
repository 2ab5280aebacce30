// The checks the DataFlash fuzz targets share (dataflash_fuzz: the binary log; dataflash_text_fuzz:
// the log as text): any bytes must give a DecodedLog or a LogIssue, never a crash, and what is
// accepted must be consistent through the ArduPilot extractor (logs/ardupilot_signals.h).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "conventions_check.h"
#include "fuzz_support.h"
#include "logs/ardupilot_signals.h"
#include "logs/dataflash.h"

namespace quadfdi::fuzz {

template <int N>
void checkSeries(const SignalSeries<N>& s) {
  QUADFDI_FUZZ_CHECK(s.t.size() == s.v.size());
  for (std::size_t k = 1; k < s.t.size(); ++k) QUADFDI_FUZZ_CHECK(s.t[k] > s.t[k - 1]);
}

// `issue` and `log`: what the reader under test made of data[0, size).
inline void checkDataflashRead(const std::uint8_t* data, std::size_t size, const LogIssue& issue, const DecodedLog& log) {
  static const bool verbose = std::getenv("QUADFDI_FUZZ_VERBOSE") != nullptr;
  if (verbose && !issue.ok())
    std::fprintf(stderr, "issue: byte %llu, line %llu: %s\n", static_cast<unsigned long long>(issue.offset),
                 static_cast<unsigned long long>(issue.line), issue.message.c_str());
  QUADFDI_FUZZ_CHECK(issue.ok() || !issue.message.empty());
  QUADFDI_FUZZ_CHECK(issue.offset <= size);
  QUADFDI_FUZZ_CHECK(issue.line <= size + 1);
  QUADFDI_FUZZ_CHECK(log.warnings.size() <= kDataflashMaxWarnings + 1);
  for (const LogTopic& t : log.topics) {
    QUADFDI_FUZZ_CHECK(!t.name.empty() && t.name.size() <= 4);
    QUADFDI_FUZZ_CHECK(t.instance >= 0 && t.instance <= 255);
    QUADFDI_FUZZ_CHECK(t.rows() > 0);
    QUADFDI_FUZZ_CHECK(t.fields.size() == t.columns.size());
    for (const auto& c : t.columns) QUADFDI_FUZZ_CHECK(c.size() == t.rows());
  }
  if (!issue.ok()) return;

  ArdupilotSignalOptions options;
  options.ekf_core = size > 0 ? data[size - 1] % 3 : 0;
  FlightSignals signals;
  const LogIssue extracted = extractArdupilotSignals(log, options, signals);
  if (verbose && !extracted.ok()) std::fprintf(stderr, "extract: %s: %s\n", extracted.topic.c_str(), extracted.message.c_str());
  if (!extracted.ok()) {
    QUADFDI_FUZZ_CHECK(!extracted.topic.empty() && !extracted.message.empty());
    return;
  }
  checkSeries(signals.position);
  checkSeries(signals.attitude);
  checkSeries(signals.command);
  QUADFDI_FUZZ_CHECK(!signals.attitude.empty() && !signals.position.empty());
  for (const auto& u : signals.command.v)
    for (double f : u) QUADFDI_FUZZ_CHECK(f >= 0.0 && f <= 1.0);
  for (const auto& a : signals.attitude.v)
    if (std::isfinite(a[2])) QUADFDI_FUZZ_CHECK(a[2] >= -3.2 && a[2] <= 3.2);
  for (std::size_t k = 1; k < signals.states.size(); ++k) QUADFDI_FUZZ_CHECK(signals.states[k].t >= signals.states[k - 1].t);
  checkConventionsLayer(signals, log.format, size % 2 == 0);
}

}  // namespace quadfdi::fuzz
