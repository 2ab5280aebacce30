// Estimator heading resets in a telemetry CSV (logs/heading_resets.h), its body rates against its
// attitude (logs/rate_agreement.h) and its attitude quaternion's reading against the flight
// (logs/quaternion_check.h), for `detect` on a file.
//
// The check needs the whole file: the attitude's own row-to-row noise sets its threshold, and a
// row is judged against its neighbours on both sides. A CSV is read row by row into the detector,
// so a file is read twice: once here, whole, to find the resets with its own p,q,r columns, then
// row by row through a HeadingCorrectedSource that takes them out of each sample's yaw. A live
// pipe is read once and not checked. Docs: docs/conventions.md#heading-resets-in-a-csv.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

#include "core/sample_source.h"
#include "io/telemetry_reader.h"
#include "logs/heading_resets.h"
#include "logs/quaternion_check.h"
#include "logs/rate_agreement.h"

namespace quadfdi {

// Every row of `in` read as `options` say, with p,q,r read too (whatever options.read_rates says),
// up to its end or the first row whose t does not increase (where the detector refuses the file),
// checked: a quaternion attitude's reading against the flight (logs/quaternion_check.h); then,
// unless another reading fits better (the attitude read is then not the flight's), whether p,q,r
// agree with the attitude's own turn (logs/rate_agreement.h), and where they do, the heading
// resets they do not show, in time order. Throws TelemetryError as TelemetryReader does (a bad
// header or row).
struct TelemetryFileChecks {
  bool has_rates = false;       // the header has p,q,r (else their checks were not made)
  bool has_quaternion = false;  // the attitude is qw,qx,qy,qz (else its check was not made)
  QuaternionCheck quaternion;
  RateAgreement rates;          // not checked where another quaternion reading fits (QuaternionVerdict::kOtherReading)
  HeadingResets heading;        // nor where the rates do not agree with the attitude (RateAgreementVerdict::kDiffers)
};
TelemetryFileChecks checkTelemetryFile(std::istream& in, const std::string& name, TelemetryReaderOptions options,
                                       const HeadingResetOptions& check = {});

// `inner`'s samples with each reset of `resets` taken out of the yaw of every sample at or after its t
// (as takeOutHeadingResets does to a log's attitude). `inner` outlives it.
class HeadingCorrectedSource : public SampleSource {
 public:
  HeadingCorrectedSource(SampleSource& inner, std::vector<HeadingShift> resets);
  Next next(TelemetrySample& sample, std::string& problem) override;
  std::string where() const override { return inner_.where(); }
  bool moreReady() const override { return inner_.moreReady(); }
  bool carriesRates() const override { return inner_.carriesRates(); }

 private:
  SampleSource& inner_;
  std::vector<HeadingShift> resets_;
  std::size_t applied_ = 0;  // resets_[0, applied_) are in `shift_`
  double shift_ = 0.0;       // [rad] their sum
};

}  // namespace quadfdi
