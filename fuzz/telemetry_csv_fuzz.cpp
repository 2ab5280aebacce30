// Telemetry CSV (io/telemetry_reader.h) into the resampler and the online detector, as
// `quadfdi detect` reads a log: any bytes must end in samples, skipped rows or one
// TelemetryError — never a crash, a hang or a sanitizer report.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <string>

#include "detection/detector.h"
#include "detection/resampler.h"
#include "fuzz_support.h"
#include "io/telemetry_reader.h"
#include "networks/inference.h"
#include "networks/model.h"

using namespace quadfdi;

namespace {

// A tiny model-free LSTM (T = 10, H = 8) with seeded weights: cheap enough to run per input,
// and its untrained Θ̂ near 0.5 drives the alarm logic both ways.
InferenceEngine& engine() {
  static const std::unique_ptr<InferenceEngine> e = [] {
    ModelMetadata m;
    m.architecture = Architecture::kLstm;
    m.features = FeatureSet::kModelFree;
    m.output = OutputKind::kPositionEuler;
    m.window = 10;
    m.hidden = 8;
    configureCpuThreads(1);
    return std::make_unique<InferenceEngine>(exportWeights(FaultIdentifier::create(m, 1)));
  }();
  return *e;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  engine();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The detector's configuration varies with the first byte, so both file mode (look-ahead)
  // and streaming, and strides 1 … 4, are exercised on the same rows.
  const std::uint8_t mode = size > 0 ? data[0] : 0;
  std::istringstream in(fuzz::text(data, size));
  try {
    TelemetryReader reader(in, "fuzz.csv");
    ResamplerConfig rc;
    Resampler resampler(rc);
    DetectorConfig dc;
    dc.window = engine().window();
    dc.stride = 1 + (mode & 3);
    const bool look_ahead = (mode & 4) != 0;
    Detector detector(dc, engine());
    bool detector_stopped = false;
    double last_grid_t = -std::numeric_limits<double>::infinity();
    TelemetrySample sample;
    std::string problem;
    for (;;) {
      const TelemetryReader::Row row = reader.next(sample, problem);
      if (row == TelemetryReader::Row::kEnd) break;
      if (row == TelemetryReader::Row::kSkipped) {
        QUADFDI_FUZZ_CHECK(!problem.empty());
        continue;
      }
      QUADFDI_FUZZ_CHECK(std::isfinite(sample.t) && std::abs(sample.t) <= 1e9);
      const ResampleStatus status = resampler.push(sample, [&](const TelemetrySample& s) {
        // Grid samples: finite, in time order (a restart may only move the grid forward).
        QUADFDI_FUZZ_CHECK(std::isfinite(s.t) && s.t > last_grid_t);
        for (double v : s.y) QUADFDI_FUZZ_CHECK(std::isfinite(v));
        for (double v : s.u) QUADFDI_FUZZ_CHECK(std::isfinite(v));
        last_grid_t = s.t;
      });
      (void)status;
      if (detector_stopped) continue;
      // As `quadfdi detect`: a refused sample (time not increasing, log too coarse) ends the run.
      const ResampleStatus ds = detector.push(sample, look_ahead);
      if (ds == ResampleStatus::kNotIncreasing || ds == ResampleStatus::kTooCoarse) {
        detector_stopped = true;
        continue;
      }
      DetectorOutput out;
      while (detector.pop(out)) {
        QUADFDI_FUZZ_CHECK(out.motor >= 0 && out.motor <= 4);
        for (float th : out.theta) QUADFDI_FUZZ_CHECK(th >= 0.0f && th <= 1.0f);
      }
    }
    detector.finish();
    DetectorOutput out;
    while (detector.pop(out)) QUADFDI_FUZZ_CHECK(out.motor >= 0 && out.motor <= 4);
  } catch (const TelemetryError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz.csv", 0) == 0);
  }
  return 0;
}
