// Heading resets in a telemetry CSV: see telemetry_heading.h.
#include "io/telemetry_heading.h"

#include <utility>

#include "core/frames.h"
#include "logs/flight_signals.h"

namespace quadfdi {

TelemetryFileChecks checkTelemetryFile(std::istream& in, const std::string& name, TelemetryReaderOptions options,
                                       const HeadingResetOptions& check) {
  options.read_rates = true;
  TelemetryReader reader(in, name, options);
  TelemetryFileChecks out;
  out.has_rates = reader.carriesRates();
  out.has_quaternion = reader.quaternionAttitude();
  if (!out.has_rates && !out.has_quaternion) return out;
  SignalSeries<3> position, attitude, rates;
  TelemetrySample s;
  std::string problem;
  for (SampleSource::Next row; (row = reader.next(s, problem)) != SampleSource::Next::kEnd;) {
    if (row != SampleSource::Next::kSample) continue;
    if (!attitude.t.empty() && !(s.t > attitude.t.back())) break;  // the detector refuses the file here (time going back)
    position.t.push_back(s.t);
    position.v.push_back({s.y[0], s.y[1], s.y[2]});
    attitude.t.push_back(s.t);
    attitude.v.push_back({s.y[3], s.y[4], s.y[5]});
    if (out.has_rates) {
      rates.t.push_back(s.t);
      rates.v.push_back(s.rates);
    }
  }
  // The quaternion's reading first: the rates and the heading are judged against the attitude.
  if (out.has_quaternion) {
    out.quaternion = checkQuaternionReading(position, attitude, rates, options.quaternion, options.frame == TelemetryFrame::kNed,
                                            options.body_turn);
    if (out.quaternion.verdict == QuaternionVerdict::kOtherReading) return out;
  }
  if (!out.has_rates) return out;
  out.rates = checkRateAgreement(attitude, rates);  // a reset moves one window only
  if (out.rates.verdict != RateAgreementVerdict::kDiffers) out.heading = takeOutHeadingResets(attitude, rates, check);
  return out;
}

HeadingCorrectedSource::HeadingCorrectedSource(SampleSource& inner, std::vector<HeadingShift> resets)
    : inner_(inner), resets_(std::move(resets)) {}

SampleSource::Next HeadingCorrectedSource::next(TelemetrySample& sample, std::string& problem) {
  const Next row = inner_.next(sample, problem);
  if (row != Next::kSample) return row;
  for (; applied_ < resets_.size() && resets_[applied_].t <= sample.t; ++applied_) shift_ += resets_[applied_].shift;
  if (shift_ != 0.0) sample.y[5] = wrapAngle(sample.y[5] - shift_);
  return row;
}

}  // namespace quadfdi
