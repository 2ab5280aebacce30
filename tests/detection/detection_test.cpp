#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "control/controller_factory.h"
#include "detection/detector.h"
#include "detection/session.h"
#include "io/model_file.h"
#include "networks/model.h"
#include "simulation/closed_loop.h"
#include "simulation/rng.h"
#include "simulation/sampling.h"

namespace quadfdi {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ---------- resampling ----------

TelemetrySample linearSample(double t) {
  TelemetrySample s;
  s.t = t;
  for (int i = 0; i < 6; ++i) s.y[static_cast<std::size_t>(i)] = 0.1 * (i + 1) * t - 0.2 * i;
  for (int i = 0; i < 4; ++i) s.u[static_cast<std::size_t>(i)] = 0.07 + 0.001 * i + t;
  for (int i = 0; i < 3; ++i) s.rates[static_cast<std::size_t>(i)] = 2.0 * (i - 1) * t + 0.3;
  return s;
}

std::vector<TelemetrySample> resampleAll(Resampler& r, const std::vector<TelemetrySample>& in,
                                         std::vector<ResampleStatus>* statuses = nullptr) {
  std::vector<TelemetrySample> out;
  for (const TelemetrySample& s : in) {
    const ResampleStatus st = r.push(s, [&](const TelemetrySample& g) { out.push_back(g); });
    if (statuses) statuses->push_back(st);
  }
  return out;
}

TEST(Resampler, PassesAModelRateLogThroughUnchanged) {
  Resampler r(ResamplerConfig{});
  std::vector<TelemetrySample> in;
  for (int k = 0; k < 50; ++k) in.push_back(linearSample(0.002 * k));
  const std::vector<TelemetrySample> out = resampleAll(r, in);
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t k = 0; k < in.size(); ++k) {
    EXPECT_EQ(out[k].t, in[k].t);
    EXPECT_EQ(out[k].y, in[k].y);
    EXPECT_EQ(out[k].u, in[k].u);
  }
}

TEST(Resampler, InterpolatesJitteredAndFasterLogsOntoTheGrid) {
  for (const double period : {0.001, 0.0017, 0.004}) {
    Resampler r(ResamplerConfig{});
    std::vector<TelemetrySample> in;
    Rng rng(5, 1);
    for (int k = 0; k < 400; ++k) in.push_back(linearSample(period * k + (k ? 0.3 * period * rng.uniform(-1.0, 1.0) : 0.0)));
    const std::vector<TelemetrySample> out = resampleAll(r, in);
    const double span = in.back().t - in.front().t;
    EXPECT_NEAR(static_cast<double>(out.size()), span / 0.002 + 1, 1.0) << period;
    std::size_t a = 0;
    for (std::size_t j = 0; j < out.size(); ++j) {
      EXPECT_NEAR(out[j].t, in.front().t + 0.002 * static_cast<double>(j), 1e-12);
      const TelemetrySample exact = linearSample(out[j].t);
      for (int i = 0; i < 6; ++i) EXPECT_NEAR(out[j].y[static_cast<std::size_t>(i)], exact.y[static_cast<std::size_t>(i)], 1e-12);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(out[j].rates[static_cast<std::size_t>(i)], exact.rates[static_cast<std::size_t>(i)], 1e-12);
      // The command is held: it is the one logged at or before the grid time.
      while (a + 1 < in.size() && in[a + 1].t <= out[j].t + 1e-12) ++a;
      EXPECT_EQ(out[j].u, in[a].u) << period << " at " << j;
    }
  }
}

TEST(Resampler, InterpolatesYawTheShortWayRound) {
  Resampler r(ResamplerConfig{});
  TelemetrySample a = linearSample(0.0), b = linearSample(0.004);
  a.y[5] = kPi - 0.01;
  b.y[5] = -kPi + 0.01;  // 0.02 rad further on, across the ±π seam
  const std::vector<TelemetrySample> out = resampleAll(r, {a, b});
  ASSERT_EQ(out.size(), 3u);
  EXPECT_NEAR(std::abs(out[1].y[5]), kPi, 1e-12);
}

TEST(Resampler, RefusesTimeThatDoesNotIncreaseAndLogsThatAreTooCoarse) {
  Resampler r(ResamplerConfig{});
  std::vector<ResampleStatus> st;
  resampleAll(r, {linearSample(0.0), linearSample(0.002), linearSample(0.002), linearSample(0.001)}, &st);
  EXPECT_EQ(st[2], ResampleStatus::kNotIncreasing);
  EXPECT_EQ(st[3], ResampleStatus::kNotIncreasing);

  Resampler coarse(ResamplerConfig{});
  std::vector<TelemetrySample> in;
  for (int k = 0; k < 20; ++k) in.push_back(linearSample(0.01 * k));  // 100 Hz
  st.clear();
  resampleAll(coarse, in, &st);
  int refused = 0;
  for (ResampleStatus s : st) refused += s == ResampleStatus::kTooCoarse;
  EXPECT_GT(refused, 0);
}

TEST(Resampler, RestartsTheGridAfterAGap) {
  Resampler r(ResamplerConfig{});
  std::vector<TelemetrySample> in;
  for (int k = 0; k < 10; ++k) in.push_back(linearSample(0.002 * k));
  for (int k = 0; k < 10; ++k) in.push_back(linearSample(0.1001 + 0.002 * k));
  std::vector<ResampleStatus> st;
  const std::vector<TelemetrySample> out = resampleAll(r, in, &st);
  EXPECT_EQ(st[10], ResampleStatus::kRestarted);
  ASSERT_EQ(out.size(), 20u);
  EXPECT_EQ(out[10].t, 0.1001);
}

// An estimator reset (a GNSS glitch, a height-source switch, a heading realignment) steps the
// estimate faster than any flight: the grid starts again after it, as after a gap. Fast flight, a
// fast yaw spin across ±π and a pass through pitch 90° (where Euler roll and yaw swing by π while
// the vehicle turns 1°) are flight.
TEST(Resampler, RestartsAfterAnEstimatorResetButNotInFastFlight) {
  for (const int coordinate : {2, 5}) {  // a 0.3 m height step, a 30° heading step, in 2 ms
    Resampler r(ResamplerConfig{});
    std::vector<TelemetrySample> in;
    for (int k = 0; k < 20; ++k) {
      in.push_back(linearSample(0.002 * k));
      if (k >= 10) in.back().y[static_cast<std::size_t>(coordinate)] += coordinate == 2 ? 0.3 : kPi / 6;
    }
    std::vector<ResampleStatus> st;
    const std::vector<TelemetrySample> out = resampleAll(r, in, &st);
    for (int k = 0; k < 20; ++k) EXPECT_EQ(st[static_cast<std::size_t>(k)], k == 10 ? ResampleStatus::kJumped : ResampleStatus::kOk) << k;
    ASSERT_EQ(out.size(), 20u);
    EXPECT_EQ(out[10].y, in[10].y);  // the new stretch starts at the sample after the step
    // The step plus 2 ms of linearSample's own motion.
    EXPECT_NEAR(r.lastJump().position, coordinate == 2 ? 0.3 : 0.0, 0.003);
    EXPECT_NEAR(r.lastJump().angle, coordinate == 2 ? 0.0 : kPi / 6, 0.003);
    EXPECT_NEAR(r.lastJump().interval, 0.002, 1e-15);
  }
  // 40 m/s forward and 30 rad/s of yaw, with up to 1 cm and 5 mrad of noise: no step.
  Resampler fast(ResamplerConfig{});
  Rng rng(3, 1);
  std::vector<TelemetrySample> in;
  for (int k = 0; k < 1000; ++k) {
    TelemetrySample s = linearSample(0.002 * k);
    s.y[0] = 40.0 * s.t + rng.uniform(-0.01, 0.01);
    s.y[3] = rng.uniform(-0.005, 0.005);
    s.y[5] = std::remainder(30.0 * s.t + rng.uniform(-0.005, 0.005), 2 * kPi);
    in.push_back(s);
  }
  std::vector<ResampleStatus> st;
  resampleAll(fast, in, &st);
  for (ResampleStatus s : st) EXPECT_EQ(s, ResampleStatus::kOk);
  // Through pitch 90°: (0, 89.5°, 0) then (π, 89.5°, π), which is pitch 90.5°.
  const EulerZyx before{0.0, 89.5 * kPi / 180, 0.0}, after{kPi, 89.5 * kPi / 180, kPi};
  EXPECT_NEAR(rotationAngleBetween(before, after), kPi / 180, 1e-9);
  Resampler flip(ResamplerConfig{});
  TelemetrySample a = linearSample(0.0), b = linearSample(0.002);
  a.y[3] = before.roll, a.y[4] = before.pitch, a.y[5] = before.yaw;
  b.y[3] = after.roll, b.y[4] = after.pitch, b.y[5] = after.yaw;
  st.clear();
  resampleAll(flip, {a, b}, &st);
  EXPECT_EQ(st[1], ResampleStatus::kOk);
}

// ---------- alarm persistence ----------

TEST(AlarmFilter, NeedsPersistentEvidenceForOneMotorToRaise) {
  AlarmConfig c;  // raise_below 0.5, raise_after 5
  AlarmFilter f(c);
  const std::array<float, 4> healthy{0.97f, 0.96f, 0.98f, 0.95f}, motor3{0.9f, 0.9f, 0.1f, 0.9f}, motor1{0.1f, 0.9f, 0.9f, 0.9f};
  EXPECT_FALSE(f.update(motor3, 0).active);  // one noisy window
  EXPECT_FALSE(f.update(healthy, 1).active);
  for (long k = 2; k < 6; ++k) EXPECT_FALSE(f.update(k % 2 ? motor1 : motor3, k).active);  // motors disagree
  for (long k = 6; k < 10; ++k) EXPECT_FALSE(f.update(motor3, k).active);
  const AlarmState s = f.update(motor3, 10);  // fifth in a row
  EXPECT_TRUE(s.active && s.raised);
  EXPECT_EQ(s.motor, 3);
  EXPECT_FALSE(f.update(motor3, 11).raised);  // raised once
}

TEST(AlarmFilter, TiesGoToTheLowerMotorAndClearingNeedsLastingHealth) {
  AlarmConfig c;
  c.raise_after = 1;
  c.clear_after = 100;  // samples
  AlarmFilter f(c);
  EXPECT_EQ(f.update({0.9f, 0.2f, 0.9f, 0.2f}, 0).motor, 2);
  const std::array<float, 4> healthy{0.97f, 0.96f, 0.98f, 0.95f};
  EXPECT_TRUE(f.update(healthy, 8).active);
  EXPECT_TRUE(f.update({0.9f, 0.7f, 0.9f, 0.9f}, 56).active);  // between the thresholds: resets the healthy run
  EXPECT_TRUE(f.update(healthy, 64).active);
  EXPECT_TRUE(f.update(healthy, 162).active);  // 99 samples of health
  const AlarmState s = f.update(healthy, 163);    // 100
  EXPECT_TRUE(s.cleared);
  EXPECT_FALSE(s.active);
  EXPECT_EQ(s.motor, 0);
}

// ---------- the detector with the shipped network ----------

struct Flight {
  std::vector<TelemetrySample> samples;
};

Flight fly(int motor, double theta, int fault_step, int steps, std::uint64_t seed) {
  SimulationSettings settings;
  settings.steps = steps;
  if (motor) {
    settings.fault.theta(motor - 1) = theta;
    settings.fault.fault_step = fault_step;
  }
  Rng rng(seed, 0);
  const Scenario scenario = sampleScenario(SamplingRanges{}, rng);
  ControllerBuild build = makeController(nominalParams(), ControllerConfig{}, settings.dt);
  build.controller->setGoal(scenario.goal);
  const ClosedLoopSimulator sim(nominalParams(), settings);
  FlightLog log;
  sim.run(*build.controller, scenario.initial_state, &log);
  Flight f;
  for (int k = 0; k < log.size(); ++k) {
    TelemetrySample s;
    s.t = settings.dt * k;
    for (int i = 0; i < 6; ++i) s.y[static_cast<std::size_t>(i)] = log.outputs[static_cast<std::size_t>(k)](i);
    for (int i = 0; i < 4; ++i) s.u[static_cast<std::size_t>(i)] = log.controls[static_cast<std::size_t>(k)].u_cmd(i);
    f.samples.push_back(s);
  }
  return f;
}

class ShippedDetector : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    model_ = std::make_unique<TrainedModel>(readModelFile(QUADFDI_SOURCE_DIR "/models/lstm-model-free.qfdw"));
  }
  static void TearDownTestSuite() { model_.reset(); }
  static DetectorConfig config() {
    DetectorConfig c;
    c.symmetry = model_->metadata.symmetry;
    return c;
  }
  static std::vector<DetectorOutput> run(const std::vector<TelemetrySample>& samples, bool look_ahead,
                                         DetectorSummary* summary = nullptr, DetectorConfig c = config()) {
    Detector d(c, *model_);
    std::vector<DetectorOutput> out;
    DetectorOutput o;
    for (const TelemetrySample& s : samples) {
      EXPECT_NE(d.push(s, look_ahead), ResampleStatus::kNotIncreasing);
      while (d.pop(o)) out.push_back(o);
    }
    d.finish();
    while (d.pop(o)) out.push_back(o);
    if (summary) *summary = d.summary();
    return out;
  }
  static std::unique_ptr<TrainedModel> model_;
};
std::unique_ptr<TrainedModel> ShippedDetector::model_;

TEST_F(ShippedDetector, FindsACompleteFaultInEveryMotorAndNamesIt) {
  for (int motor = 1; motor <= 4; ++motor) {
    const Flight f = fly(motor, 0.0, 300, 500, 10 + static_cast<std::uint64_t>(motor));
    DetectorSummary s;
    const std::vector<DetectorOutput> out = run(f.samples, true, &s);
    ASSERT_GE(s.alarms_raised, 1) << "motor " << motor;
    EXPECT_EQ(s.first_alarm_motor, motor);
    EXPECT_GT(s.first_alarm_t, 0.6);           // not before the fault (t = 0.6 s)
    EXPECT_LT(s.first_alarm_t, 0.6 + 0.050);   // within 50 ms
    EXPECT_LT(s.first_alarm_theta, 0.5f);
    // One line per input sample from the first full window on.
    EXPECT_EQ(out.size(), f.samples.size() - 99);
    EXPECT_TRUE(out.back().alarm);
    EXPECT_EQ(out.back().motor, motor);
  }
}

TEST_F(ShippedDetector, StaysQuietOnHealthyFlights) {
  for (std::uint64_t seed = 20; seed < 24; ++seed) {
    DetectorSummary s;
    run(fly(0, 1.0, 0, 1500, seed).samples, true, &s);
    EXPECT_EQ(s.alarms_raised, 0) << "seed " << seed;
    EXPECT_LT(s.evaluations, 1500 / 3);  // the stride is doing its job while healthy
  }
}

TEST_F(ShippedDetector, StreamingGivesExactlyTheFileModeOutput) {
  const Flight f = fly(2, 0.0, 400, 700, 31);
  const std::vector<DetectorOutput> file = run(f.samples, true), stream = run(f.samples, false);
  ASSERT_EQ(file.size(), stream.size());
  for (std::size_t i = 0; i < file.size(); ++i) {
    EXPECT_EQ(file[i].t, stream[i].t);
    EXPECT_EQ(file[i].theta, stream[i].theta);
    EXPECT_EQ(file[i].alarm, stream[i].alarm);
    EXPECT_EQ(file[i].motor, stream[i].motor);
  }
}

TEST_F(ShippedDetector, StrideOneAgreesOnTheAlarm) {
  const Flight f = fly(4, 0.0, 300, 500, 41);
  DetectorConfig every = config();
  every.stride = 1;
  DetectorSummary strided, full;
  run(f.samples, true, &strided);
  run(f.samples, true, &full, every);
  EXPECT_EQ(strided.first_alarm_motor, full.first_alarm_motor);
  EXPECT_LE(strided.first_alarm_t - full.first_alarm_t, 0.002 * (config().stride - 1) + 1e-9);
  EXPECT_GT(full.evaluations, 2 * strided.evaluations);
}

TEST_F(ShippedDetector, HandlesFasterJitteredAndGappyLogs) {
  const Flight f = fly(3, 0.0, 400, 600, 51);
  // 1 kHz with jitter: midpoints inserted, every time moved by up to ±0.2 ms.
  std::vector<TelemetrySample> fast;
  Rng rng(9, 2);
  for (std::size_t k = 0; k + 1 < f.samples.size(); ++k) {
    TelemetrySample a = f.samples[k], mid = a;
    mid.t = a.t + 0.001;
    for (int i = 0; i < 6; ++i) mid.y[static_cast<std::size_t>(i)] = 0.5 * (a.y[static_cast<std::size_t>(i)] + f.samples[k + 1].y[static_cast<std::size_t>(i)]);
    a.t += 0.0002 * rng.uniform(-1.0, 1.0);
    mid.t += 0.0002 * rng.uniform(-1.0, 1.0);
    fast.push_back(a);
    fast.push_back(mid);
  }
  DetectorSummary s;
  const std::vector<DetectorOutput> out = run(fast, true, &s);
  EXPECT_EQ(s.first_alarm_motor, 3);
  EXPECT_LT(std::abs(s.first_alarm_t - 0.8), 0.06);
  EXPECT_GT(out.size(), fast.size() - 220);  // one line per input sample after the first window

  // A 40 ms hole before the fault: the detector restarts and still finds it.
  std::vector<TelemetrySample> gappy;
  for (std::size_t k = 0; k < f.samples.size(); ++k)
    if (k < 150 || k >= 170) gappy.push_back(f.samples[k]);
  run(gappy, true, &s);
  EXPECT_EQ(s.restarts, 1);
  EXPECT_EQ(s.first_alarm_motor, 3);
}

// Found by fuzzing: a hole shorter than --max-gap but longer than the history (here 9 s with a
// 10-s max gap) is interpolated across; the history must make room instead of overflowing.
TEST_F(ShippedDetector, InterpolatesAcrossALongAllowedHole) {
  const Flight f = fly(0, 1.0, 0, 400, 61);
  std::vector<TelemetrySample> samples = f.samples;
  for (std::size_t k = 200; k < samples.size(); ++k) samples[k].t += 9.0;
  DetectorConfig c = config();
  c.resampler.max_gap = 10.0;
  c.resampler.max_input_period = 10.0;
  DetectorSummary s;
  const std::vector<DetectorOutput> out = run(samples, true, &s, c);
  EXPECT_EQ(s.restarts, 0);
  EXPECT_EQ(out.size(), samples.size() - 99);
  for (const DetectorOutput& o : out)
    for (float t : o.theta) EXPECT_TRUE(t >= 0.0f && t <= 1.0f);
}

TEST(Detector, RefusesNetworksItCannotRun) {
  ModelMetadata m;
  m.window = 20;
  m.hidden = 8;
  const FaultIdentifier net = FaultIdentifier::create(m, 1);
  TrainedModel model{net.metadata(), exportWeights(net)};
  DetectorConfig c;
  c.stride = 0;
  EXPECT_THROW(Detector(c, model), std::invalid_argument);
  c.stride = 4;
  model.metadata.features = FeatureSet::kModelBased;  // needs residuals the detector does not have
  EXPECT_THROW(Detector(c, model), std::invalid_argument);
  model.metadata.features = FeatureSet::kModelFree;
  model.metadata.trained_motor = 3;  // the maps send every motor to motor 2
  EXPECT_THROW(Detector(c, model), std::invalid_argument);
}

// ---------- body rates ----------

TrainedModel ratesModel(Architecture architecture) {
  ModelMetadata m;
  m.architecture = architecture;
  m.window = 100;
  m.hidden = 16;
  m.features = FeatureSet::kScaleFreeRates;
  m.feature_mean.assign(static_cast<std::size_t>(m.channels()), 0.1f);
  m.feature_std.assign(static_cast<std::size_t>(m.channels()), 2.0f);
  const FaultIdentifier net = FaultIdentifier::create(m, 3);
  return {net.metadata(), exportWeights(net)};
}

// A flight on the model's clock with body rates, every value a float (the history's type).
std::vector<TelemetrySample> flightWithRates(int n, double dt) {
  std::vector<TelemetrySample> flight(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    TelemetrySample& s = flight[static_cast<std::size_t>(k)];
    s.t = k * dt;
    for (int i = 0; i < 6; ++i) s.y[static_cast<std::size_t>(i)] = static_cast<float>(0.2 * std::sin(0.03 * k + i));
    for (int i = 0; i < 4; ++i) s.u[static_cast<std::size_t>(i)] = static_cast<float>(0.07 + 0.01 * std::sin(0.05 * k + 2 * i));
    for (int i = 0; i < 3; ++i) s.rates[static_cast<std::size_t>(i)] = static_cast<float>(1.5 * std::sin(0.04 * k + 3 * i));
  }
  return flight;
}

// A network on body rates, windowed (an LSTM evaluated at every sample) or streaming (a TCN): the
// detector carries each sample's rates into its history and gives exactly the windowed
// estimator's Θ̂ on the last T samples with their rates — and not the one without them.
class RatesDetector : public ::testing::TestWithParam<Architecture> {};

TEST_P(RatesDetector, EstimatesFromEachSamplesBodyRates) {
  const TrainedModel model = ratesModel(GetParam());
  DetectorConfig c;
  c.stride = 1;
  c.rule = AlarmRule::kPersistence;
  c.resampler.dt = model.metadata.dt;
  Detector detector(c, model);
  EXPECT_TRUE(detector.readsRates());
  EXPECT_EQ(detector.streaming(), GetParam() == Architecture::kTcn);
  const int n = 180, t_len = model.metadata.window;
  const std::vector<TelemetrySample> flight = flightWithRates(n, model.metadata.dt);
  std::vector<DetectorOutput> out;
  for (const TelemetrySample& s : flight) {
    ASSERT_EQ(detector.push(s, false), ResampleStatus::kOk);
    for (DetectorOutput o; detector.pop(o);) out.push_back(o);
  }
  detector.finish();
  for (DetectorOutput o; detector.pop(o);) out.push_back(o);
  ASSERT_EQ(out.size(), static_cast<std::size_t>(n - t_len + 1));

  MotorEstimator windows(model, SymmetryMode::kExactGroup);
  std::vector<float> y, u, w;
  for (const TelemetrySample& s : flight) {
    y.insert(y.end(), s.y.begin(), s.y.end());
    u.insert(u.end(), s.u.begin(), s.u.end());
    w.insert(w.end(), s.rates.begin(), s.rates.end());
  }
  const std::vector<float> still(w.size(), 0.0f);
  std::vector<float> features(static_cast<std::size_t>(kMotors) * windows.featuresPerWindow());
  int moved_by_rates = 0;
  for (std::size_t j = 0; j < out.size(); ++j) {
    const std::size_t first = j;  // output j is sample T − 1 + j
    EXPECT_EQ(out[j].t, flight[first + static_cast<std::size_t>(t_len) - 1].t);
    MotorTheta with{}, without{};
    windows.gather(&y[first * kOutputDim], &u[first * kInputDim], nullptr, &w[first * kRateDim], features.data());
    windows.estimate(features.data(), 1, &with);
    windows.gather(&y[first * kOutputDim], &u[first * kInputDim], nullptr, &still[first * kRateDim], features.data());
    windows.estimate(features.data(), 1, &without);
    EXPECT_EQ(out[j].theta, with) << "output " << j;
    moved_by_rates += with != without;
  }
  EXPECT_GT(moved_by_rates, static_cast<int>(out.size()) / 2);
}

INSTANTIATE_TEST_SUITE_P(WindowedAndStreaming, RatesDetector, ::testing::Values(Architecture::kLstm, Architecture::kTcn),
                         [](const ::testing::TestParamInfo<Architecture>& param) {
                           return param.param == Architecture::kTcn ? std::string("Tcn") : std::string("Lstm");
                         });

class VectorSource : public SampleSource {
 public:
  VectorSource(std::vector<TelemetrySample> samples, bool rates) : samples_(std::move(samples)), rates_(rates) {}
  Next next(TelemetrySample& sample, std::string&) override {
    if (next_ == samples_.size()) return Next::kEnd;
    sample = samples_[next_++];
    return Next::kSample;
  }
  std::string where() const override { return "flight.csv:" + std::to_string(next_ + 1); }
  bool carriesRates() const override { return rates_; }

 private:
  std::vector<TelemetrySample> samples_;
  std::size_t next_ = 0;
  bool rates_;
};

class CountingSink : public DetectionSink {
 public:
  void output(const DetectorOutput&) override { ++outputs; }
  void warning(const std::string&) override { ++warnings; }
  int outputs = 0, warnings = 0;
};

// A network on body rates given telemetry without them reads nothing (zeros would be a vehicle
// at rest, whatever it did) and says where; given them, it runs. A network without rates reads
// telemetry with them as it reads any.
TEST(RatesDetector, RefusesASourceWithoutBodyRates) {
  const TrainedModel model = ratesModel(Architecture::kTcn);
  DetectorConfig c;
  c.resampler.dt = model.metadata.dt;
  const std::vector<TelemetrySample> flight = flightWithRates(150, model.metadata.dt);
  for (const bool rates : {false, true}) {
    Detector detector(c, model);
    VectorSource source(flight, rates);
    CountingSink sink;
    const SessionResult r = runDetection(detector, source, sink, SessionConfig{});
    EXPECT_EQ(r.status, rates ? SessionStatus::kDone : SessionStatus::kNoRates);
    EXPECT_EQ(r.samples, rates ? 150 : 0);
    EXPECT_EQ(sink.outputs, rates ? 51 : 0);
    if (!rates) {
      EXPECT_EQ(r.where, "flight.csv:1");
    }
  }
  ModelMetadata m;
  m.window = 20;
  m.hidden = 8;
  const FaultIdentifier plain = FaultIdentifier::create(m, 1);
  Detector detector(c, TrainedModel{plain.metadata(), exportWeights(plain)});
  EXPECT_FALSE(detector.readsRates());
  VectorSource source(flight, true);
  CountingSink sink;
  EXPECT_EQ(runDetection(detector, source, sink, SessionConfig{}).status, SessionStatus::kDone);
  EXPECT_EQ(sink.outputs, 131);
}

}  // namespace
}  // namespace quadfdi
