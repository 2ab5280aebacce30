#include "detection/session.h"

#include <cmath>
#include <cstdio>

namespace quadfdi {

SessionResult runDetection(Detector& detector, SampleSource& source, DetectionSink& sink, const SessionConfig& config) {
  SessionResult result;
  TelemetrySample sample;
  std::string problem;
  DetectorOutput d;
  NumberingCheck numbering;
  numbering.setup(source.carriesRates() && config.numbering_from_rates);
  double last_t = 0.0;  // [s] of the last sample read
  if (detector.readsRates() && !source.carriesRates()) {  // zeros read as rates would be a vehicle at rest
    result.status = SessionStatus::kNoRates;
    result.where = source.where();
    return result;
  }
  for (;;) {
    const SampleSource::Next next = source.next(sample, problem);
    if (next == SampleSource::Next::kEnd) break;
    if (next == SampleSource::Next::kSkipped) {
      if (result.skipped++ < config.max_warnings) sink.warning(problem);
      continue;
    }
    // A time written twice (a variable-step solver's event, a logger repeating a row) is no step
    // back in time: the first row stands and the repeat is skipped.
    if (result.samples > 0 && sample.t == last_t) {
      if (result.repeated++ < config.max_warnings)
        sink.warning(source.where() + ": t repeats the previous row's time; row skipped (the first one is kept)");
      continue;
    }
    last_t = sample.t;
    if (result.samples++ == 0) result.first_t = sample.t;
    if (sample.u[0] <= 0.0 && sample.u[1] <= 0.0 && sample.u[2] <= 0.0 && sample.u[3] <= 0.0) ++result.no_thrust;
    numbering.step(sample);
    const bool look_ahead = !config.live || source.moreReady();
    const ResampleStatus status = detector.push(sample, look_ahead);
    if (status == ResampleStatus::kNotIncreasing || status == ResampleStatus::kTooCoarse) {
      result.status = status == ResampleStatus::kNotIncreasing ? SessionStatus::kNotIncreasing : SessionStatus::kTooCoarse;
      result.where = source.where();
      result.t = sample.t;
      return result;
    }
    if (status == ResampleStatus::kRestarted) sink.warning(source.where() + ": gap in the log; the detector starts again");
    if (status == ResampleStatus::kJumped) {
      const EstimateJump& j = detector.lastJump();
      char text[160];
      std::snprintf(text, sizeof text, ": the state estimate jumped (%.2f m, %.1f° in %.1f ms: an estimator reset?); the detector starts again",
                    j.position, j.angle * 180.0 / M_PI, j.interval * 1e3);
      sink.warning(source.where() + text);
    }
    while (detector.pop(d)) {
      numbering.alarm(d.alarm);
      sink.output(d);
    }
    if (config.live && !look_ahead) sink.idle();
  }
  detector.finish();
  while (detector.pop(d)) sink.output(d);
  result.numbering = numbering.result();
  if (result.skipped > config.max_warnings)
    sink.warning(std::to_string(result.skipped) + " rows skipped in all (non-finite or empty cells)");
  if (result.repeated > config.max_warnings)
    sink.warning(std::to_string(result.repeated) + " rows skipped in all for repeating the previous row's time");
  // A vehicle in the air commands thrust; one that commands none most of the time is on the ground,
  // or its commands were read in another unit or range, and no fault can show in them.
  if (2 * result.no_thrust > result.samples)
    sink.warning(std::to_string(result.no_thrust) + " of " + std::to_string(result.samples) +
                 " samples command no thrust from any motor (u1..u4 all <= 0): no fault can show there; are the "
                 "commands in the unit and range they were read as?");
  return result;
}

}  // namespace quadfdi
