// Where samples come from: a telemetry CSV, a converted autopilot log, a simulator. The one
// contract the detection session reads, so that every front end drives the same loop.
#pragma once

#include <string>

#include "core/types.h"

namespace quadfdi {

class SampleSource {
 public:
  enum class Next {
    kSample,   // `sample` holds the next one
    kSkipped,  // a row the source dropped (non-finite cell, …): `problem` says why; go on
    kEnd,
  };
  virtual ~SampleSource() = default;
  // Throws (the source's own error type, a one-line "WHERE: problem") for input it cannot go past.
  virtual Next next(TelemetrySample& sample, std::string& problem) = 0;
  virtual std::string where() const = 0;       // "FILE:LINE" or "FILE: topic T" of the last sample
  virtual bool moreReady() const { return true; }  // more input is waiting now (a live pipe may say no)
  // Every sample holds body rates (TelemetrySample::rates); false: they are all zero. Known once the
  // source is set up (a CSV's header read, a log's signals extracted), before the first sample.
  virtual bool carriesRates() const { return false; }
};

}  // namespace quadfdi
