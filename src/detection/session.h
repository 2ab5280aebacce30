// A detection run: samples from a source → the detector → outputs to a sink, with warnings
// passed back. The CLI, the fuzz target, the benchmark and the tests all drive this one loop.
#pragma once

#include <string>

#include "core/sample_source.h"
#include "detection/detector.h"
#include "detection/numbering_check.h"

namespace quadfdi {

class DetectionSink {
 public:
  virtual ~DetectionSink() = default;
  virtual void output(const DetectorOutput& d) = 0;
  virtual void warning(const std::string& text) = 0;  // one line, no newline
  virtual void idle() {}  // caught up with a live source: flush what was written
};

enum class SessionStatus {
  kDone,           // the source ended
  kNotIncreasing,  // a sample's time went back (where, t say which); a repeated time is skipped
  kTooCoarse,      // the source is sampled more coarsely than the detector accepts
  kNoRates,        // the model reads body rates and the source carries none: nothing was read
};

struct SessionResult {
  SessionStatus status = SessionStatus::kDone;
  std::string where;   // the source's position of the offending sample
  double t = 0.0;      // [s] its time
  long skipped = 0;    // samples the source dropped
  long repeated = 0;   // samples skipped for repeating the previous sample's time
  double first_t = 0.0;  // [s] time of the first sample read
  long samples = 0;      // samples read (not skipped), the offending one included
  long no_thrust = 0;    // of those, samples whose four commands are all ≤ 0 N
  NumberingCheckResult numbering;  // the motor columns checked against the flight's rotation
};

struct SessionConfig {
  bool live = false;        // read ahead only while the source says more input is ready
  int max_warnings = 10;    // [-] skipped-row warnings (of each kind) passed on individually; the rest are counted
  // false: the motor-numbering check takes the angular acceleration from the attitude even where
  // the source carries body rates (rates found not to agree with the attitude: logs/rate_agreement.h).
  bool numbering_from_rates = true;
};

// Runs to the end of the source (or the first refusal), then finishes the detector. Source
// errors (exceptions) propagate.
SessionResult runDetection(Detector& detector, SampleSource& source, DetectionSink& sink, const SessionConfig& config);

}  // namespace quadfdi
