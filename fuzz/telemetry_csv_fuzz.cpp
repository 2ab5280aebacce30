// Telemetry CSV (io/telemetry_reader.h) into the resampler and the online detector, as
// `quadfdi detect` reads a log: any bytes must end in samples, skipped rows or one
// TelemetryError — never a crash, a hang or a sanitizer report.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
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

// The detector's settings, from the first byte (also the header's first character; a header
// starting with 't' gives the defaults of `quadfdi detect`): file mode (look-ahead) or
// streaming, `--stride` (1 … 1000), `--max-gap` (the longest hole bridged) and the model's dt.
DetectorConfig configFor(std::uint8_t first, bool& look_ahead) {
  static constexpr int kStrides[4] = {4, 1, 37, 1000};
  // Holes up to 10 s bridged at dt down to 0.5 ms: up to 2e4 model samples from one input sample
  // (the history holds T + 4096); 1e5 s is past what the detector accepts.
  static constexpr double kMaxGaps[4] = {0.02, 0.5, 10.0, 1e5};     // [s]
  static constexpr double kDts[4] = {0.002, 0.001, 0.0005, 0.002};  // [s]
  const unsigned bits = first ^ static_cast<unsigned>('t');
  DetectorConfig c;
  c.window = engine().window();
  c.stride = kStrides[bits & 3];
  look_ahead = (bits & 4) == 0;
  c.resampler.max_gap = kMaxGaps[(bits >> 3) & 3];
  c.resampler.dt = kDts[(bits >> 5) & 3];
  return c;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  engine();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  bool look_ahead = true;
  const DetectorConfig config = configFor(size > 0 ? data[0] : 0, look_ahead);
  std::istringstream in(fuzz::text(data, size));
  try {
    TelemetryReader reader(in, "fuzz.csv");
    std::unique_ptr<Detector> detector;
    std::unique_ptr<Resampler> resampler;
    try {
      detector = std::make_unique<Detector>(config, engine());
      resampler = std::make_unique<Resampler>(config.resampler);
    } catch (const std::invalid_argument& e) {  // settings the detector refuses (max_gap / dt too large)
      fuzz::report(e);
    }
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
      if (resampler) {
        // Grid samples: finite, in time order (a restart only moves the grid forward). The
        // resampler alone also takes samples after one it refused.
        resampler->push(sample, [&](const TelemetrySample& s) {
          QUADFDI_FUZZ_CHECK(std::isfinite(s.t) && s.t > last_grid_t);
          for (double v : s.y) QUADFDI_FUZZ_CHECK(std::isfinite(v));
          for (double v : s.u) QUADFDI_FUZZ_CHECK(std::isfinite(v));
          last_grid_t = s.t;
        });
      }
      if (!detector) continue;
      // As `quadfdi detect`: a refused sample (time not increasing, log too coarse) ends the run.
      const ResampleStatus status = detector->push(sample, look_ahead);
      if (status == ResampleStatus::kNotIncreasing || status == ResampleStatus::kTooCoarse) {
        detector.reset();
        continue;
      }
      DetectorOutput out;
      while (detector->pop(out)) {
        QUADFDI_FUZZ_CHECK(out.motor >= 0 && out.motor <= 4);
        for (float th : out.theta) QUADFDI_FUZZ_CHECK(th >= 0.0f && th <= 1.0f);
      }
    }
    if (detector) {
      detector->finish();
      DetectorOutput out;
      while (detector->pop(out)) QUADFDI_FUZZ_CHECK(out.motor >= 0 && out.motor <= 4);
    }
  } catch (const TelemetryError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz.csv", 0) == 0);
  }
  return 0;
}
