// Shared by the log fuzzers: extracted signals through the conventions layer
// (logs/telemetry_from_log.h). Whatever the log, it gives a refusal with a sentence or a source
// whose samples are on the clock (times increasing, spaced dt within a stretch), finite or
// dropped, and whose report names every phase. At most `max_samples` are drawn per input.
#pragma once

#include <cmath>
#include <string>

#include "fuzz_support.h"
#include "logs/telemetry_from_log.h"

namespace quadfdi {

inline void checkConventionsLayer(const FlightSignals& signals, LogFormat format, bool with_mass, long max_samples = 20000) {
  ImportOptions o;
  o.min_rate_attitude = o.min_rate_command = o.min_rate_position = 1e-3;  // let coarse fuzz logs through
  if (with_mass) o.mass = 0.03;
  else o.max_thrust = 0.15;
  LogSampleSource source;
  const ImportRefusal refusal = buildLogSampleSource(signals, format, o, source);
  if (refusal.refused()) return;
  QUADFDI_FUZZ_CHECK(!source.report().phases.empty());
  QUADFDI_FUZZ_CHECK(!source.report().text().empty());
  QUADFDI_FUZZ_CHECK(std::isfinite(source.report().thrust_factor) && source.report().thrust_factor > 0.0);
  TelemetrySample s;
  std::string problem;
  double last = -1e300;
  long drawn = 0;
  for (SampleSource::Next n; drawn < max_samples && (n = source.next(s, problem)) != SampleSource::Next::kEnd; ++drawn) {
    if (n == SampleSource::Next::kSkipped) {
      QUADFDI_FUZZ_CHECK(!problem.empty());
      continue;
    }
    QUADFDI_FUZZ_CHECK(s.t > last);
    last = s.t;
    for (double v : s.y) QUADFDI_FUZZ_CHECK(std::isfinite(v));
    for (double v : s.u) QUADFDI_FUZZ_CHECK(std::isfinite(v));
    for (double v : s.rates) QUADFDI_FUZZ_CHECK(std::isfinite(v));
  }
}

}  // namespace quadfdi
