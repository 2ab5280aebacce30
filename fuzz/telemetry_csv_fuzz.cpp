// Telemetry CSV (io/telemetry_reader.h) into the resampler and the online detector, as
// `quadfdi detect` reads a log: any bytes must end in samples, skipped rows or one
// TelemetryError — never a crash, a hang or a sanitizer report. The same bytes read as a merged
// export (io/merged_telemetry.h, `--format csv-merged`) go through the conventions layer.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include <vector>

#include "conventions_check.h"
#include "detection/resampler.h"
#include "detection/session.h"
#include "fuzz_support.h"
#include "io/merged_telemetry.h"
#include "io/telemetry_heading.h"
#include "io/telemetry_reader.h"
#include "networks/model.h"

using namespace quadfdi;

namespace {

// Tiny seeded networks (T = 10), cheap enough to run per input; their untrained Θ̂ near 0.5
// drives the alarm logic both ways: the paper's windowed LSTM, and a streaming TCN — on body
// rates when the CSV has p, q, r.
const TrainedModel& model(bool streaming, bool rates = false) {
  static const std::unique_ptr<TrainedModel> models[3] = {
      [] {
        ModelMetadata m;
        m.window = 10;
        m.hidden = 8;
        configureCpu(1);
        const FaultIdentifier net = FaultIdentifier::create(m, 1);
        return std::make_unique<TrainedModel>(TrainedModel{net.metadata(), exportWeights(net)});
      }(),
      [] {
        ModelMetadata m;
        m.architecture = Architecture::kTcn;
        m.features = FeatureSet::kModelFreeHeading;
        m.window = 10;
        m.tcn.channels = 8;
        m.tcn.dilations = {1, 2, 1};  // receptive field 9 = T − 1
        const FaultIdentifier net = FaultIdentifier::create(m, 1);
        return std::make_unique<TrainedModel>(TrainedModel{net.metadata(), exportWeights(net)});
      }(),
      [] {
        ModelMetadata m;
        m.architecture = Architecture::kTcn;
        m.features = FeatureSet::kScaleFreeRates;
        m.window = 10;
        m.tcn.channels = 8;
        m.tcn.dilations = {1, 2, 1};
        const FaultIdentifier net = FaultIdentifier::create(m, 1);
        return std::make_unique<TrainedModel>(TrainedModel{net.metadata(), exportWeights(net)});
      }()};
  return *models[streaming ? (rates ? 2 : 1) : 0];
}

// The detector's settings, from the first byte (also the header's first character; a header
// starting with 't' gives the defaults of `quadfdi detect`): file mode (look-ahead) or
// streaming, `--stride` (1 … 1000), `--max-gap` (the longest hole bridged), the model's dt and
// the network (windowed LSTM or streaming TCN).
DetectorConfig configFor(std::uint8_t first, bool& live, bool& tcn) {
  static constexpr int kStrides[4] = {4, 1, 37, 1000};
  // Holes up to 10 s bridged at dt down to 0.5 ms: up to 2e4 model samples from one input sample
  // (the history holds T + 4096); 1e5 s is past what the detector accepts.
  static constexpr double kMaxGaps[4] = {0.02, 0.5, 10.0, 1e5};     // [s]
  static constexpr double kDts[4] = {0.002, 0.001, 0.0005, 0.002};  // [s]
  const unsigned bits = first ^ static_cast<unsigned>('t');
  DetectorConfig c;
  c.stride = kStrides[bits & 3];
  live = (bits & 4) != 0;
  c.resampler.max_gap = kMaxGaps[(bits >> 3) & 3];
  c.resampler.dt = kDts[(bits >> 5) & 3];
  tcn = (bits & 0x80) != 0;
  return c;
}

// Every output in range.
class CheckingSink : public DetectionSink {
 public:
  void output(const DetectorOutput& out) override {
    QUADFDI_FUZZ_CHECK(out.motor >= 0 && out.motor <= 4);
    for (float th : out.theta) QUADFDI_FUZZ_CHECK(th >= 0.0f && th <= 1.0f);
  }
  void warning(const std::string& text) override { QUADFDI_FUZZ_CHECK(!text.empty()); }
};

// The samples read before the end or the first error, replayed as a source.
class ReplaySource : public SampleSource {
 public:
  ReplaySource(const std::vector<TelemetrySample>& samples, bool rates) : samples_(samples), rates_(rates) {}
  Next next(TelemetrySample& sample, std::string&) override {
    if (at_ == samples_.size()) return Next::kEnd;
    sample = samples_[at_++];
    return Next::kSample;
  }
  std::string where() const override { return "fuzz.csv:" + std::to_string(at_); }
  bool moreReady() const override { return at_ % 3 != 0; }  // a live pipe that sometimes runs dry
  bool carriesRates() const override { return rates_; }

 private:
  const std::vector<TelemetrySample>& samples_;
  bool rates_;
  std::size_t at_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  model(false);
  model(true);
  model(true, true);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  bool live = false, tcn = false;
  const DetectorConfig config = configFor(size > 0 ? data[0] : 0, live, tcn);
  std::istringstream in(fuzz::text(data, size));
  std::vector<TelemetrySample> samples;
  bool rates = false;  // the header has p, q, r
  // quadfdi's frames or NED (detect --csv-frame), thrusts, rotor speeds, throttles or PWM pulses
  // (--csv-commands; the last two through the 1.5 kg quad's thrust curve), by the input's length.
  TelemetryReaderOptions reading;
  reading.frame = size % 2 != 0 ? TelemetryFrame::kNed : TelemetryFrame::kZUp;
  constexpr CommandQuantity kQuantities[] = {CommandQuantity::kThrust, CommandQuantity::kRotorSpeed,
                                             CommandQuantity::kThrottle, CommandQuantity::kPwm};
  reading.commands = kQuantities[(size / 2) % 4];
  reading.curve.max_thrust = 7.0664;  // [N] configs/vehicles/quad450.toml
  reading.curve.model_factor = 0.806;
  // t in seconds or a ROS stamp in nanoseconds (--csv-time-unit), u1 as a topic path (--csv-columns),
  // angles in radians or degrees.
  if ((size / 8) % 2 != 0) reading.time_unit = 1e-9;
  if ((size / 16) % 2 != 0) reading.header_names = {{"u1", "/motors/0"}};
  reading.angles_in_degrees = (size / 32) % 2 != 0;  // --csv-angle-unit deg
  reading.quaternion = kQuaternionReadings[(size / 64) % 4];  // --csv-quaternion
  try {
    TelemetryReader reader(in, "fuzz.csv", reading);
    rates = reader.carriesRates();
    TelemetrySample sample;
    std::string problem;
    for (;;) {
      const SampleSource::Next row = reader.next(sample, problem);
      if (row == SampleSource::Next::kEnd) break;
      if (row == SampleSource::Next::kSkipped) {
        QUADFDI_FUZZ_CHECK(!problem.empty());
        continue;
      }
      QUADFDI_FUZZ_CHECK(std::isfinite(sample.t) && std::abs(sample.t) <= 1e13);
      for (double w : sample.rates) QUADFDI_FUZZ_CHECK(std::abs(w) <= 100.0);  // [rad/s] the reader's bound
      samples.push_back(sample);
    }
  } catch (const TelemetryError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz.csv", 0) == 0);
  }
  // As `quadfdi detect` checks a file (io/telemetry_heading.h): the whole file read with its p,q,r;
  // the rates against the attitude, then resets, each finite and at a row's time in order, or one TelemetryError.
  HeadingResets heading;
  try {
    std::istringstream whole(fuzz::text(data, size));
    const TelemetryFileChecks checks = checkTelemetryFile(whole, "fuzz.csv", reading);
    heading = checks.heading;
    // The body-rate check: correlations and scale finite, and a verdict only on rows with rates.
    for (std::size_t i = 0; i < 3; ++i)
      QUADFDI_FUZZ_CHECK(std::isfinite(checks.rates.axis_correlation[i]) && std::abs(checks.rates.axis_correlation[i]) <= 1.0 + 1e-9);
    QUADFDI_FUZZ_CHECK(std::isfinite(checks.rates.scale) && checks.rates.scale > 0.0);
    QUADFDI_FUZZ_CHECK(checks.has_rates || checks.rates.verdict == RateAgreementVerdict::kNotChecked);
    QUADFDI_FUZZ_CHECK(!checks.rates.text().empty());
    // The quaternion check: fits and slopes finite, a verdict only on a quaternion, another reading named only as another.
    const QuaternionCheck& q = checks.quaternion;
    for (std::size_t k = 0; k < 4; ++k) {
      QUADFDI_FUZZ_CHECK(std::isfinite(q.tilt_fit[k]) && std::abs(q.tilt_fit[k]) <= 1.0 + 1e-9);
      QUADFDI_FUZZ_CHECK(std::isfinite(q.rate_score[k]) && std::isfinite(q.axis_slope[k][0]) && std::isfinite(q.axis_slope[k][1]));
    }
    QUADFDI_FUZZ_CHECK(checks.has_quaternion || q.verdict == QuaternionVerdict::kNotChecked);
    QUADFDI_FUZZ_CHECK((q.verdict == QuaternionVerdict::kOtherReading) == (q.best != q.read));
    QUADFDI_FUZZ_CHECK(!q.text().empty());
    QUADFDI_FUZZ_CHECK(heading.resets.size() == heading.count && (heading.checked || heading.count == 0));
    for (std::size_t i = 0; i < heading.resets.size(); ++i) {
      QUADFDI_FUZZ_CHECK(std::isfinite(heading.resets[i].t) && std::isfinite(heading.resets[i].shift));
      QUADFDI_FUZZ_CHECK(std::abs(heading.resets[i].shift) >= heading.threshold && heading.threshold > 0.0);
      QUADFDI_FUZZ_CHECK(i == 0 || heading.resets[i].t > heading.resets[i - 1].t);
    }
  } catch (const TelemetryError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz.csv", 0) == 0);
  }
  // As a merged export: signals from the rows that hold them, or one TelemetryError naming a line.
  try {
    std::istringstream merged_in(fuzz::text(data, size));
    TelemetryReader reader(merged_in, "fuzz.csv", reading);
    FlightSignals signals;
    const MergedTelemetryCounts counts = readMergedTelemetry(reader, signals);
    QUADFDI_FUZZ_CHECK(counts.without_time + counts.without_signal <= counts.rows);
    for (const SignalSeries<3>* s : {&signals.position, &signals.attitude, &signals.rates})
      for (std::size_t i = 1; i < s->t.size(); ++i) QUADFDI_FUZZ_CHECK(s->t[i] > s->t[i - 1]);
    checkConventionsLayer(signals, LogFormat::kMergedCsv, false, 5000);
  } catch (const TelemetryError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz.csv", 0) == 0);
  }
  // Grid samples: finite, in time order (a restart only moves the grid forward). The resampler
  // alone also takes samples after one it refused. A few bridged holes make tens of thousands of
  // grid samples, each a network evaluation below: the input is cut after the row that passes
  // kMaxGridSamples (one 10 s hole at 0.5 ms fits), so no input runs into libFuzzer's timeout and
  // the fuzzer spends its time on many inputs rather than a few long ones.
  constexpr long kMaxGridSamples = 30000;
  Resampler resampler(config.resampler);
  double last_grid_t = -std::numeric_limits<double>::infinity();
  long grid_samples = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    resampler.push(samples[i], [&](const TelemetrySample& s) {
      QUADFDI_FUZZ_CHECK(std::isfinite(s.t) && s.t > last_grid_t);
      for (double v : s.y) QUADFDI_FUZZ_CHECK(std::isfinite(v));
      for (double v : s.u) QUADFDI_FUZZ_CHECK(std::isfinite(v));
      for (double v : s.rates) QUADFDI_FUZZ_CHECK(std::isfinite(v));
      last_grid_t = s.t;
      ++grid_samples;
    });
    if (grid_samples > kMaxGridSamples) {
      samples.resize(i + 1);
      break;
    }
  }
  // As `quadfdi detect`: one detection session, which stops at a refused sample.
  std::unique_ptr<Detector> detector;
  try {
    detector = std::make_unique<Detector>(config, model(tcn, rates));
  } catch (const std::invalid_argument& e) {  // settings the detector refuses (max_gap / dt too large)
    fuzz::report(e);
    return 0;
  }
  ReplaySource replay(samples, rates);
  HeadingCorrectedSource corrected(replay, heading.resets);  // the resets taken out, as detect streams a file
  SampleSource& source = heading.resets.empty() ? static_cast<SampleSource&>(replay) : corrected;
  CheckingSink sink;
  SessionConfig session;
  session.live = live;
  const SessionResult r = runDetection(*detector, source, sink, session);
  QUADFDI_FUZZ_CHECK(r.status == SessionStatus::kDone || !r.where.empty());
  // The motor-numbering check the session runs beside the detector: finite, and a verdict only
  // on flight it has.
  const NumberingCheckResult& n = r.numbering;
  QUADFDI_FUZZ_CHECK(std::isfinite(n.seconds) && n.seconds >= 0.0);
  QUADFDI_FUZZ_CHECK(n.verdict == NumberingVerdict::kTooShort || n.seconds >= NumberingCheckConfig{}.min_seconds);
  for (const auto& row : n.fit)
    for (const double v : row) QUADFDI_FUZZ_CHECK(std::isfinite(v));
  QUADFDI_FUZZ_CHECK(std::isfinite(n.tilt_fit) && std::abs(n.tilt_fit) <= 1.0 + 1e-9);
  QUADFDI_FUZZ_CHECK(!n.text().empty());
  return 0;
}
