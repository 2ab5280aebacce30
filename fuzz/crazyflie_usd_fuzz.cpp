// Crazyflie micro-SD deck logs (logs/crazyflie_usd.h) and then the Crazyflie extractor
// (logs/crazyflie_signals.h), as an import reads a log: any bytes must give a DecodedLog whose
// tables are consistent, or one LogIssue with an offset inside the input — never a crash, a hang
// or a sanitizer report; the extractor must give consistent, finite, time-ordered signals or
// one LogIssue with a message.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "conventions_check.h"
#include "fuzz_support.h"
#include "logs/crazyflie_signals.h"
#include "logs/crazyflie_usd.h"

using namespace quadfdi;

namespace {

template <int N>
void checkSeries(const SignalSeries<N>& s) {
  QUADFDI_FUZZ_CHECK(s.t.size() == s.v.size() && !s.t.empty());
  for (std::size_t i = 0; i < s.t.size(); ++i) {
    QUADFDI_FUZZ_CHECK(std::isfinite(s.t[i]) && s.t[i] >= 0.0);
    if (i > 0) QUADFDI_FUZZ_CHECK(s.t[i] > s.t[i - 1]);
    for (double x : s.v[i]) QUADFDI_FUZZ_CHECK(std::isfinite(x));
  }
}

void extract(const DecodedLog& log, CrazyflieThrustMap map) {
  CrazyflieSignalOptions o;
  o.thrust_map = map;
  FlightSignals s;
  const LogIssue i = extractCrazyflieSignals(log, o, s);
  if (!i.ok()) {
    QUADFDI_FUZZ_CHECK(!i.message.empty());
    if (std::getenv("QUADFDI_FUZZ_VERBOSE")) std::fprintf(stderr, "extract: %s\n", i.message.c_str());
    return;
  }
  checkSeries(s.position);
  checkSeries(s.attitude);
  checkSeries(s.command);
  QUADFDI_FUZZ_CHECK(s.command_kind == CommandKind::kThrustNewton && !s.conventions.empty());
  for (const auto& f : s.command.v)
    for (double x : f) QUADFDI_FUZZ_CHECK(x >= -1.0 && x <= 10.0);  // [N] bounded by the maps' ranges
  checkConventionsLayer(s, log.format, false);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ByteSpan bytes{data, size};
  DecodedLog log;
  const LogIssue issue = readCrazyflieUsd(bytes, log);
  if (!issue.ok()) {
    QUADFDI_FUZZ_CHECK(!issue.message.empty() && issue.offset <= size);
    if (std::getenv("QUADFDI_FUZZ_VERBOSE"))
      std::fprintf(stderr, "read: byte %llu: %s\n", static_cast<unsigned long long>(issue.offset),
                   issue.message.c_str());
    return 0;
  }
  QUADFDI_FUZZ_CHECK(looksLikeCrazyflieUsd(bytes));
  QUADFDI_FUZZ_CHECK(log.format == LogFormat::kCrazyflieUsd);
  for (const LogTopic& t : log.topics) {
    QUADFDI_FUZZ_CHECK(t.columns.size() == t.fields.size());
    for (const auto& c : t.columns) QUADFDI_FUZZ_CHECK(c.size() == t.rows());
    for (std::int64_t ts : t.timestamp_us) QUADFDI_FUZZ_CHECK(ts >= 0);
  }
  extract(log, CrazyflieThrustMap::kAuto);
  extract(log, CrazyflieThrustMap::kQuadraticDuty);
  return 0;
}
