// `quadfdi calibrate`: simulated flights → Θ̂ streams → the sequential rule's calibration
// (detection/calibration.h, docs/decisions.md "Calibration"). The flights come from one function,
// simulateFlight, so that another vehicle, controller or trajectory generator can replace it.
#include "cli/calibrate_command.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <memory>
#include <optional>

#include "cli/cli_util.h"
#include "cli/detect_command.h"
#include "cli/options.h"
#include "cli/sequential_report.h"
#include "control/controller_factory.h"
#include "data/rollout.h"
#include "detection/calibration.h"
#include "detection/session.h"
#include "evaluation/flight_streams.h"
#include "evaluation/level_choice.h"
#include "io/calibration_file.h"
#include "io/model_file.h"
#include "io/params_file.h"
#include "io/randomisation_file.h"
#include "simulation/closed_loop.h"
#include "simulation/rng.h"
#include "simulation/sampling.h"

namespace quadfdi::cli {

CLI::App* addCalibrateCommand(CLI::App& app, CalibrateOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Calibrate the sequential alarm rule for a model: simulate healthy flights (LQR, nominal Crazyflie, a new goal\n"
      "every --goal-period), fit the noise model of Θ̂ and solve the CUSUM thresholds for --false-alarms-per-hour;\n"
      "simulate faulty flights for the model error of the Θ̂ estimate. Writes JSON for `detect --calibration`.");
  auto t = std::make_shared<OptionTable>();
  t->addConfigFile(o.config);
  t->recordGivenIn(o.given);
  t->add("--model,-m", o.model, "Model file (default: the shipped model, or $QUADFDI_MODEL)").defaultText("").shippedFile();
  t->add("--output,-o", o.output, "Calibration JSON to write (default: MODEL.calibration.json beside the model, which detect reads)")
      .defaultText("");
  t->add("--flights", o.flights, "Healthy flights").range(1, 100000);
  t->add("--flight-seconds", o.flight_seconds, "Length of each healthy flight [s]").range(1.0, 36000.0);
  t->add("--settle", o.settle,
         "Seconds at the start of each healthy flight that are not calibrated on: the recovery from the random initial state "
         "every simulated flight starts in, which a pilot's flight does not")
      .atLeast(0.0);
  t->add("--goal-period", o.goal_period, "A new goal this often [s]").range(0.1, 36000.0);
  t->add("--faulty-flights", o.faulty_flights, "Faulty flights (random motor, Θ uniform in [0, 0.9]) for the estimate's model error")
      .range(0, 100000);
  t->add("--seed", o.seed, "Scenario seed");
  t->add("--false-alarms-per-hour", o.false_alarms_per_hour, "Target false alarms per flight hour").above(0.0, 3600.0);
  t->add("--degraded-below", o.degraded_below,
         "Degraded level; given several (e.g. 0.8 0.85 0.9), each is calibrated and the one that names the motor of the most "
         "faulty flights (Θ below the highest) within --delay-budget wins, a tie going to the higher")
      .above(0.0, 1.0);
  t->add("--delay-budget", o.delay_budget, "Choosing among several --degraded-below: the delay a fault must be reported within [s]")
      .above(0.0, 60.0);
  t->add("--failed-below", o.failed_below, "Failed level").above(0.0, 1.0);
  t->add("--interval", o.interval,
         "The Θ estimate's interval: spread (a spread fitted per range of the estimate) or belt (a confidence belt fitted per "
         "true Θ and inverted: it holds Θ at its level for each Θ; docs/decisions.md)")
      .choices({"spread", "belt"});
  t->add("--refit-interval", o.refit_interval,
         "Refit only the Θ interval of this calibration FILE (by --interval) on the faulty flights — give the --randomise, "
         "--vehicle, --seed and --faulty-flights that made it — keeping its noise model, levels and thresholds; no healthy flight "
         "is flown. Writes -o, else FILE itself");
  t->add("--degraded-cap", o.degraded_cap,
         "Most one sample adds to the degraded CUSUM [effectiveness] (a robust CUSUM: a short deep dip of healthy Θ̂ weighs "
         "no more than a mild fault's sustained one; 0: no cap)")
      .atLeast(0.0);
  t->add("--failed-cap", o.failed_cap,
         "Most one sample adds to the failed CUSUM [effectiveness] (as --degraded-cap, for the failed level; 0: no cap); given "
         "several (e.g. 0.15 0.2 0 ), each is calibrated, the degraded level chosen again under it, and the one that names the "
         "motor of the most faulty flights below --failed-below within --failed-delay-budget wins, a tie going to the smaller")
      .atLeast(0.0);
  t->add("--failed-min-share", o.failed_min_share,
         "The failed statistic gains evidence against a motor only while its command is at least this share of the mean "
         "command (a motor that has lost its thrust is commanded up by any stabilising controller; 0: always)")
      .range(0.0, 4.0);
  t->add("--degraded-min-share", o.degraded_min_share,
         "Both statistics gain evidence against a motor only while its command is at least this share of the mean command "
         "(a motor at effectiveness Θ is commanded about 4 / (3Θ + 1) of the mean in steady flight; 0: always)")
      .range(0.0, 4.0);
  t->add("--failed-delay-budget", o.failed_delay_budget,
         "Choosing among several --failed-cap: the delay a fault below --failed-below must be named within [s]")
      .above(0.0, 60.0);
  t->add("--reference", o.reference,
         "What the rule reads as a motor's effectiveness: others (its Θ̂ over the median of the other three motors': a dip "
         "every motor shares cancels) or absolute (Θ̂ as the network gives it, the rule before 2026-11-26)")
      .choices({"others", "absolute"});
  t->add("--estimate-reference", o.estimate_reference,
         "What the Θ estimate and its interval read: absolute (the network's Θ̂ of the flagged motor) or others (as --reference)")
      .choices({"others", "absolute"});
  t->add("--position-noise", o.position_noise, "Sensor noise on position [m]").atLeast(0.0);
  t->add("--attitude-noise", o.attitude_noise, "Sensor noise on Euler angles [rad]").atLeast(0.0);
  t->add("--randomise", o.randomise,
         "Randomisation FILE (configs/randomisation-default.toml): fly its vehicles, controllers, manoeuvres and estimator "
         "noise instead of the nominal Crazyflie under LQR").shippedFile();
  t->add("--vehicle", o.vehicles, "With --randomise: vehicle description FILEs instead of the file's (repeatable)").vehicleFile();
  t->add("--quiet,-q", o.quiet, "No report on stderr");
  attachOptions(*cmd, t);
  return cmd;
}

namespace {

// "; vehicles crazyflie2, racer250" for --vehicle FILEs, else nothing (the randomisation file's).
std::string vehicleNames(const std::vector<std::string>& files) {
  std::string s;
  for (const std::string& f : files) s += (s.empty() ? "; vehicles " : ", ") + std::filesystem::path(f).stem().string();
  return s;
}

// One flight's telemetry: segments of goal_period toward goals drawn from the sampling ranges,
// each continuing from the previous segment's final state; a fault (motor 1..4, Θ) from
// `fault_step` on. Returns the telemetry at the simulation's dt.
std::vector<TelemetrySample> simulateFlight(std::uint64_t seed, std::uint64_t stream, int steps, int goal_steps, int motor,
                                            double theta, int fault_step, const CalibrateOptions& o) {
  Rng rng(seed, stream);
  Scenario scenario = sampleScenario(SamplingRanges{}, rng);
  ControllerBuild build = makeController(nominalParams(), ControllerConfig{}, 0.002);
  if (!build.controller) throw std::runtime_error(build.error);
  std::vector<TelemetrySample> out;
  out.reserve(static_cast<std::size_t>(steps));
  State x = scenario.initial_state;
  FlightLog log;
  for (int done = 0; done < steps;) {
    SimulationSettings settings;
    settings.steps = std::min(goal_steps, steps - done);
    settings.noise.position_std = o.position_noise;
    settings.noise.attitude_std = o.attitude_noise;
    settings.noise.seed = seed ^ (stream << 20) ^ static_cast<std::uint64_t>(done);
    if (motor > 0 && fault_step < done + settings.steps) {
      settings.fault.theta(motor - 1) = theta;
      settings.fault.fault_step = std::max(0, fault_step - done);
    }
    build.controller->setGoal(scenario.goal);
    const FlightSummary summary = ClosedLoopSimulator(nominalParams(), settings).run(*build.controller, x, &log);
    for (int k = 0; k < log.size(); ++k) {
      TelemetrySample s;
      s.t = settings.dt * (done + k);
      for (int i = 0; i < 6; ++i) s.y[static_cast<std::size_t>(i)] = log.outputs[static_cast<std::size_t>(k)](i);
      for (int i = 0; i < 4; ++i) s.u[static_cast<std::size_t>(i)] = log.controls[static_cast<std::size_t>(k)].u_cmd(i);
      out.push_back(s);
    }
    if (summary.cut()) break;  // the flight ends where the plant left its bounds
    done += settings.steps;
    x = summary.final_state;
    scenario.goal = sampleScenario(SamplingRanges{}, rng).goal;
  }
  return out;
}

class VectorSource : public SampleSource {
 public:
  explicit VectorSource(const std::vector<TelemetrySample>& s) : s_(s) {}
  Next next(TelemetrySample& sample, std::string&) override {
    if (at_ == s_.size()) return Next::kEnd;
    sample = s_[at_++];
    return Next::kSample;
  }
  std::string where() const override { return "sample " + std::to_string(at_); }
  bool moreReady() const override { return true; }

 private:
  const std::vector<TelemetrySample>& s_;
  std::size_t at_ = 0;
};

class ThetaSink : public DetectionSink {
 public:
  void output(const DetectorOutput& d) override { theta.push_back(d.theta); }
  void warning(const std::string&) override {}
  std::vector<MotorTheta> theta;
};

// Θ̂ at every model sample from the first full window on (stride 1: dense).
std::vector<MotorTheta> thetaStream(const TrainedModel& model, const std::vector<TelemetrySample>& flight) {
  DetectorConfig config;
  config.symmetry = model.metadata.symmetry;
  config.stride = 1;
  config.rule = AlarmRule::kPersistence;
  config.resampler.dt = model.metadata.dt;
  // Simulated flights have no estimator resets, and the index mapping below needs one stretch.
  config.resampler.max_speed = config.resampler.max_angular_rate = std::numeric_limits<double>::infinity();
  Detector detector(config, model);
  VectorSource source(flight);
  ThetaSink sink;
  runDetection(detector, source, sink, SessionConfig{});
  return std::move(sink.theta);
}

// The command gate's mask for each Θ̂ of thetaStream (stream index i is flight sample i + T − 1;
// the simulated flights are at the model rate, so the detector's resampler passes them through).
std::vector<std::uint8_t> observableMasks(const std::vector<TelemetrySample>& flight, int window, double failed_min_share,
                                          double degraded_min_share) {
  CommandGateConfig config;
  config.hold = window;
  config.failed_min_share = failed_min_share;
  config.degraded_min_share = degraded_min_share;
  CommandGate gate(config);
  std::vector<std::uint8_t> masks;
  for (std::size_t k = 0; k < flight.size(); ++k) {
    const std::uint8_t mask = gate.step(flight[k].u);
    if (static_cast<long>(k) >= window - 1) masks.push_back(mask);
  }
  return masks;
}

// Complete failures flown for the belt's node at Θ = 0 (--interval belt): a tenth of the faulty
// flights, at least 60. The faulty flights' uniform Θ puts almost none there, and at the boundary
// the estimate cannot be moved from a neighbouring Θ (fitThetaBelt).
int beltBoundaryFlights(int faulty_flights) { return faulty_flights > 0 ? std::max(60, faulty_flights / 10) : 0; }

// A --degraded-cap / --failed-cap value as the CUSUM's cap: 0 means none.
double incrementCap(double option) { return option > 0.0 ? option : kNoIncrementCap; }

// A cap as the calibrate report prints it: "0.15", or "none".
std::string capText(double cap) {
  if (cap == kNoIncrementCap) return "none";
  char text[32];
  std::snprintf(text, sizeof text, "%g", cap);
  return text;
}

// ", failed cap 0.15" for a capped failed statistic (the calibration's provenance), else nothing.
std::string failedCapNote(double cap) { return cap == kNoIncrementCap ? "" : ", failed cap " + capText(cap); }

// What the flights were (the calibration's provenance): the nominal Crazyflie's goals and noise, or
// the randomisation and the vehicles flown instead of its own.
std::string flownNote(const CalibrateOptions& o) {
  return o.randomise.empty() ? "LQR, nominal Crazyflie, goal every " + std::to_string(o.goal_period) + " s, sensor noise " +
                                   std::to_string(o.position_noise) + " m, " + std::to_string(o.attitude_noise) + " rad"
                             : "randomisation " + o.randomise + vehicleNames(o.vehicles);
}

}  // namespace

int runCalibrate(const CalibrateOptions& o) {
  for (double level : o.degraded_below) require(o.failed_below < level, "--failed-below must be below --degraded-below");
  // Options this run would not read are refused, not ignored: without a randomisation the flights
  // are the nominal Crazyflie's under LQR (a --vehicle would silently not be the airframe's); with
  // one, its estimator noise and manoeuvres are flown; a refit flies no healthy flight.
  if (o.randomise.empty())
    refuseGiven(o.given, {"vehicle"}, "needs --randomise FILE (e.g. configs/randomisation-default.toml): without it calibrate flies the nominal Crazyflie");
  else
    refuseGiven(o.given, {"position_noise", "attitude_noise", "goal_period"},
                "applies only without --randomise (the randomisation's estimator noise and manoeuvres are flown)");
  if (!o.refit_interval.empty())
    refuseGiven(o.given,
                {"flights", "flight_seconds", "settle", "false_alarms_per_hour", "degraded_below", "failed_below", "delay_budget",
                 "degraded_cap", "failed_cap", "failed_delay_budget", "failed_min_share", "degraded_min_share", "reference", "estimate_reference"},
                "--refit-interval keeps the file's levels, thresholds, caps and references and flies no healthy flight: drop it");
  if (o.degraded_below.size() < 2) refuseGiven(o.given, {"delay_budget"}, "only chooses among several --degraded-below levels");
  if (o.failed_cap.size() < 2) refuseGiven(o.given, {"failed_delay_budget"}, "only chooses among several --failed-cap values");
  if (o.faulty_flights == 0 && o.interval == "belt") refuseGiven(o.given, {"interval"}, "belt needs --faulty-flights > 0 to fit it on");
  const std::string model_path = o.model.empty() ? defaultModelPath() : o.model;
  const TrainedModel model = readModelFile(model_path);
  const double dt = model.metadata.dt;
  require(std::abs(dt - 0.002) < 1e-12, model_path + ": calibrate simulates at 500 Hz; the model runs at dt = " + std::to_string(dt));
  const int T = model.metadata.window;
  const int steps = static_cast<int>(std::lround(o.flight_seconds / dt));
  const int goal_steps = std::max(1, static_cast<int>(std::lround(o.goal_period / dt)));
  const long settle_samples = std::lround(o.settle / dt);  // of each healthy Θ̂ stream
  const bool refit = !o.refit_interval.empty();
  const int healthy_flights = refit ? 0 : o.flights;  // a refit flies only faulty flights
  DecisionCalibration c;
  if (refit) {
    c = readCalibrationFile(o.refit_interval);
    require(std::abs(c.dt - dt) <= 1e-12 * dt, o.refit_interval + ": calibrated at dt = " + std::to_string(c.dt) + " s, the model runs at " +
                                                   std::to_string(dt) + " s");
    require(o.faulty_flights > 0, "--refit-interval needs --faulty-flights > 0");
    const std::string other = calibrationModelProblem(c, model.file_crc32);
    require(other.empty(), o.refit_interval + ": " + other);
  }
  require(settle_samples < steps - T, "--settle must leave some of each --flight-seconds flight");
  // The command gate's failed share: a refit's faulty flights are gated as the file's detector gates them.
  const double failed_min_share = refit ? c.failed.min_command_share : o.failed_min_share;
  const double degraded_min_share = refit ? c.degraded.min_command_share : o.degraded_min_share;
  constexpr std::uint64_t kFirstStream = std::uint64_t{1} << 42;  // disjoint from training (0 …), held-out (2⁴⁰), test (2⁴¹)

  std::vector<std::vector<MotorTheta>> healthy;
  std::vector<std::vector<std::uint8_t>> healthy_observable;  // the command gate's masks (detection/command_gate.h)
  long samples = 0;
  // Randomised flights (--randomise): every library vehicle, controller, manoeuvre and estimator.
  std::vector<FlightThetaStream> faulty, boundary;  // boundary: complete failures for the belt (--interval belt)
  std::optional<RolloutConfig> healthy_rollout;      // randomised: how the healthy flights were drawn, to name them
  if (!o.randomise.empty()) {
    RolloutConfig rc;
    rc.window = T;
    rc.dt = dt;
    rc.output = model.metadata.output;
    rc.randomisation = loadRandomisation(o.randomise);
    if (!o.vehicles.empty()) flyOnlyVehicles(rc.randomisation, o.vehicles);
    rc.seed = o.seed + kFirstStream;
    rc.post_fault_steps = std::max(1, steps - T);
    std::vector<TrajectoryJob> jobs;
    for (int f = 0; f < healthy_flights; ++f) jobs.push_back({static_cast<std::uint64_t>(f), 2, 1.0});
    ThetaStreamOptions streaming;  // all cores
    streaming.gate.failed_min_share = failed_min_share;
    streaming.gate.degraded_min_share = degraded_min_share;
    streaming.chunk = 16;          // minute-long flights: 16 at a time bound the raw samples held at once
    healthy_rollout = rc;
    for (FlightThetaStream& s : simulateThetaStreams(model, rc, jobs, streaming)) {
      dropLeadingSamples(s, settle_samples);
      samples += static_cast<long>(s.theta.size());
      healthy.push_back(std::move(s.theta));
      healthy_observable.push_back(std::move(s.observable));
    }
    const int w = SequentialConfig{}.estimate_window;
    rc.seed = o.seed + kFirstStream + 1;
    rc.post_fault_steps = 2 * T + 4 * w;
    delayPreroll(rc.randomisation, o.settle);  // faults come after the initial upset too
    jobs.clear();
    Rng draw(o.seed, kFirstStream - 2);
    for (int f = 0; f < o.faulty_flights; ++f)
      jobs.push_back({static_cast<std::uint64_t>(f), 1 + static_cast<int>(draw.next() % 4), draw.uniform(0.0, 0.9)});
    faulty = simulateThetaStreams(model, rc, jobs, streaming);
    if (o.interval == "belt") {  // complete failures for the belt's node at Θ = 0, after the faulty flights
      jobs.clear();
      Rng motors(o.seed, kFirstStream - 3);
      for (int f = 0; f < beltBoundaryFlights(o.faulty_flights); ++f)
        jobs.push_back({static_cast<std::uint64_t>(o.faulty_flights + f), 1 + static_cast<int>(motors.next() % 4), 0.0});
      boundary = simulateThetaStreams(model, rc, jobs, streaming);
    }
  } else {
    for (int f = 0; f < healthy_flights; ++f) {
      const std::vector<TelemetrySample> flight = simulateFlight(o.seed, kFirstStream + static_cast<std::uint64_t>(f), steps, goal_steps, 0, 1.0, 0, o);
      FlightThetaStream s;
      s.theta = thetaStream(model, flight);
      s.observable = observableMasks(flight, T, failed_min_share, degraded_min_share);
      dropLeadingSamples(s, settle_samples);
      samples += static_cast<long>(s.theta.size());
      healthy.push_back(std::move(s.theta));
      healthy_observable.push_back(std::move(s.observable));
    }
  }
  if (!refit) {
    parseThetaReference(o.reference, &c.reference);  // CLI11 checked the choices
    parseThetaReference(o.estimate_reference, &c.estimate_reference);
    // The noise model and the excursions are of what the rule reads, the estimate's noise model of
    // what the estimate reads; faulty streams stay the network's output, which the rule converts
    // itself (chooseDegradedLevel) or below (the spread).
    if (ownEstimateNoise(c)) c.estimate_noise = fitNoiseModel(healthy, 0, c.estimate_reference);
    // One pass: each estimate becomes the rule's input, and its mask what the rule then lets gain
    // evidence, as in its update (an empty mask vector: every motor observable, left so).
    for (std::size_t f = 0; f < healthy.size(); ++f) {
      std::vector<std::uint8_t>& masks = healthy_observable[f];
      for (std::size_t i = 0; i < healthy[f].size(); ++i) {
        healthy[f][i] = ruleInput(healthy[f][i], c.reference);
        if (i < masks.size()) masks[i] = evidenceMask(masks[i], healthy[f][i], c.reference);
      }
    }
    c.noise = fitNoiseModel(healthy);
    c.dt = dt;
    c.flights = o.flights;
    c.flight_hours = static_cast<double>(samples) * dt / 3600.0;
    c.target_rate = o.false_alarms_per_hour;
  }
  ThetaNoiseModel& interval_noise = estimateNoise(c);

  // Faulty flights of the default path (nominal Crazyflie under LQR): fault at step 500; flight
  // `index` of the faulty scenario streams.
  auto flyFaulty = [&](int index, int motor, double theta) {
    FlightThetaStream s;
    s.truth.motor = motor;
    s.truth.theta = theta;
    const int fault_step = 500, flight_steps = fault_step + 2 * T + 4 * SequentialConfig{}.estimate_window;
    const std::vector<TelemetrySample> flight = simulateFlight(o.seed, kFirstStream + (std::uint64_t{1} << 30) + static_cast<std::uint64_t>(index),
                                                               flight_steps, flight_steps, motor, theta, fault_step, o);
    s.theta = thetaStream(model, flight);
    s.observable = observableMasks(flight, T, failed_min_share, degraded_min_share);
    s.truth.fault_sample = fault_step - (T - 1);  // stream index of the fault's sample
    return s;
  };
  Rng draw(o.seed, kFirstStream - 1);
  for (int f = 0; o.randomise.empty() && f < o.faulty_flights; ++f) {
    const int motor = 1 + static_cast<int>(draw.uniform(0.0, 4.0)) % 4;
    faulty.push_back(flyFaulty(f, motor, draw.uniform(0.0, 0.9)));
  }
  Rng motors(o.seed, kFirstStream - 3);
  for (int f = 0; o.randomise.empty() && o.interval == "belt" && f < beltBoundaryFlights(o.faulty_flights); ++f)
    boundary.push_back(flyFaulty(o.faulty_flights + f, 1 + static_cast<int>(motors.next() % 4), 0.0));

  // Model error of the estimate: from the sample the fault has been flown through (the network's
  // window T holds only faulty samples; evaluation/sequential_metrics.h flown_through) on, every
  // half window, the mean of the last estimate_window samples of the true motor against Θ — the
  // estimate the rule states there. Its first windows still hold Θ̂ of partly healthy inputs.
  const int w = SequentialConfig{}.estimate_window;
  std::vector<double> est, truth, noise_var;
  auto addPairs = [&](const std::vector<FlightThetaStream>& flights) {
    for (const FlightThetaStream& s : flights) {
      const int motor = s.truth.motor;
      for (long end = s.truth.fault_sample + T + 1; end <= static_cast<long>(s.theta.size()); end += std::max(1, w / 2)) {
        double sum = 0.0;
        for (long k = end - w; k < end; ++k)
          sum += static_cast<double>(ruleInput(s.theta[static_cast<std::size_t>(k)], c.estimate_reference)[static_cast<std::size_t>(motor - 1)]);
        est.push_back(sum / w);
        truth.push_back(s.truth.theta);
        noise_var.push_back(ar1MeanVariance(interval_noise.sigma, interval_noise.phi, w));
      }
    }
  };
  addPairs(faulty);
  c.faulty_flights = o.faulty_flights;
  if (!est.empty()) {
    const EstimateSpread spread = fitEstimateSpread(est, truth, noise_var, SequentialConfig{}.interval_level);
    interval_noise.noise_scale = spread.noise_scale;
    interval_noise.model_sigma = spread.model_sigma;
    interval_noise.spread_bins = fitBinnedEstimateSpread(est, truth, noise_var, SequentialConfig{}.interval_level);
    interval_noise.belt.clear();
    if (o.interval == "belt") {
      addPairs(boundary);  // the belt's only: the spread keeps the faulty flights' draw of Θ
      interval_noise.belt = fitThetaBelt(est, truth, SequentialConfig{}.interval_level);
    }
  }
  if (refit) {
    char what[160];
    std::snprintf(what, sizeof what, "; interval refitted (%s) on %d faulty flights%s", o.interval.c_str(), o.faulty_flights,
                  boundary.empty() ? "" : (" and " + std::to_string(boundary.size()) + " complete failures").c_str());
    // The refit's own flights, which need not be the file's (an interval fitted on other airframes).
    c.source += what + std::string(", ") + flownNote(o) + ", seed " + std::to_string(o.seed);
    const std::string output = o.output.empty() ? o.refit_interval : o.output;
    writeCalibrationFile(output, c);
    if (!o.quiet)
      std::fprintf(stderr, "calibrate: interval of %s refitted (%s, %zu estimates); wrote %s\n", o.refit_interval.c_str(), o.interval.c_str(),
                   est.size(), output.c_str());
    return 0;
  }

  const double per_level = o.false_alarms_per_hour / 2.0;
  const double cap = incrementCap(o.degraded_cap);
  LevelChoiceConfig choose;
  choose.candidates = o.degraded_below;
  choose.cap = cap;
  choose.noise = c.noise;
  choose.reference = c.reference;
  choose.flight_hours = c.flight_hours;
  choose.rate_per_hour = per_level;
  choose.dt = dt;
  choose.delay_budget = std::lround(o.delay_budget / dt);
  // One candidate needs no faulty flight to win; several need some to be told apart.
  require(o.degraded_below.size() == 1 || !faulty.empty(), "choosing among several --degraded-below needs --faulty-flights > 0");
  require(o.failed_cap.size() == 1 || !faulty.empty(), "choosing among several --failed-cap needs --faulty-flights > 0");
  FailedCapChoiceConfig choose_cap;
  for (double option : o.failed_cap) choose_cap.caps.push_back(incrementCap(option));
  choose_cap.level = o.failed_below;
  choose_cap.degraded = choose;
  choose_cap.delay_budget = std::lround(o.failed_delay_budget / dt);
  // The complete failures flown for the belt count too when caps are chosen: they are the faults a 50 ms decision is
  // owed for (the degraded level is then chosen on them as well; each names them within 300 ms, so the order holds).
  // Moved, not copied: neither list is read after the choice.
  if (o.failed_cap.size() > 1) faulty.insert(faulty.end(), std::make_move_iterator(boundary.begin()), std::make_move_iterator(boundary.end()));
  const std::vector<FlightThetaStream> no_flights;  // one level and one cap: nothing to choose, nothing to score
  const std::vector<FlightThetaStream>& scored = o.degraded_below.size() == 1 && o.failed_cap.size() == 1 ? no_flights : faulty;
  const FailedCapChoice cap_choice = chooseFailedCap(healthy, scored, choose_cap, &healthy_observable);
  const FailedCapCandidate& chosen_cap = cap_choice.candidates[static_cast<std::size_t>(cap_choice.chosen)];
  c.failed = chosen_cap.failed;
  c.failed.min_command_share = failed_min_share;
  const LevelChoice& choice = chosen_cap.degraded;
  c.degraded = choice.candidates[static_cast<std::size_t>(choice.chosen)].degraded;
  c.degraded.min_command_share = degraded_min_share;
  std::string chosen_from;
  if (choice.candidates.size() > 1) {
    char part[160];
    for (const LevelCandidate& l : choice.candidates) {
      std::snprintf(part, sizeof part, "%s%.3g (h %.3g: %d of %d within %g s)", chosen_from.empty() ? "" : ", ", l.degraded.level,
                    l.degraded.threshold, l.isolated, l.faults, o.delay_budget);
      chosen_from += part;
    }
    chosen_from = "; degraded level chosen from " + chosen_from;
  }
  if (cap_choice.candidates.size() > 1) {
    std::string caps;
    char part[160];
    for (const FailedCapCandidate& f : cap_choice.candidates) {
      std::snprintf(part, sizeof part, "%s%s (h %.3g: %d of %d within %g s)", caps.empty() ? "" : ", ", capText(f.failed.increment_cap).c_str(),
                    f.failed.threshold, f.named, f.faults, o.failed_delay_budget);
      caps += part;
    }
    chosen_from += "; failed cap chosen from " + caps;
  }
  // Numbers formatted in a bounded buffer; the paths and the level choice appended, never cut.
  char flights[160];
  std::snprintf(flights, sizeof flights, "%d healthy flights of %g s, counted from %g s on, %d faulty flights", o.flights,
                o.flight_seconds, o.settle, o.faulty_flights);
  c.source = "quadfdi calibrate: model " + model_path + "; " + flights + "; reference " + o.reference + ", estimate " + o.estimate_reference + (o.interval == "belt" ? ", interval belt" : "") +
             failedCapNote(c.failed.increment_cap) +
             (failed_min_share > 0.0 ? ", failed evidence at command shares from " + capText(failed_min_share) : std::string()) +
             (degraded_min_share > 0.0 ? ", all evidence at command shares from " + capText(degraded_min_share) : std::string()) + "; " +
             flownNote(o) + "; seed " + std::to_string(o.seed) + chosen_from;
  c.model_crc32 = model.file_crc32;
  const std::string output = o.output.empty() ? calibrationSidecarPath(model_path) : o.output;
  writeCalibrationFile(output, c);
  if (!o.quiet) {
    std::fprintf(stderr, "calibrate: %.3f flight hours healthy: Θ̂ (%s) mean %.4f, σ %.4f, φ %.4f at %g Hz\n", c.flight_hours,
                 toString(c.reference), c.noise.healthy_mean, c.noise.sigma, c.noise.phi, 1.0 / dt);
    std::fprintf(stderr, "calibrate: estimate (%s): σ %.4f, φ %.4f; noise × %.3f, model error σ %.4f (%zu estimates)\n",
                 toString(c.estimate_reference), interval_noise.sigma, interval_noise.phi, interval_noise.noise_scale, interval_noise.model_sigma,
                 est.size());
    double from = 0.0;
    for (const SpreadBin& b : interval_noise.spread_bins) {
      char range[48];
      if (&b == &interval_noise.spread_bins.back()) std::snprintf(range, sizeof range, "from %.2f up", from);
      else std::snprintf(range, sizeof range, "from %.2f below %.2f", from, b.estimate_below);
      std::fprintf(stderr, "calibrate: estimates %s: noise × %.3f, model error σ %.4f (%ld estimates)\n", range, b.noise_scale, b.model_sigma, b.pairs);
      from = b.estimate_below;
    }
    for (const LevelCalibration* l : {&c.degraded, &c.failed})
      std::fprintf(stderr,
                   "calibrate: level %.2f, cap %g: h = %.3f (%s; %ld excursions), %ld alarms in the data = %.3g/h (95 %% bound %.3g/h); "
                   "no alarm sooner than %ld samples (%.0f ms), however clear the fault\n",
                   l->level, l->increment_cap, l->threshold, l->method.c_str(), l->excursions, l->alarms_at_threshold, l->rate_at_threshold,
                   l->rate_upper_bound, fewestSamplesToAlarm(*l), 1e3 * c.dt * static_cast<double>(fewestSamplesToAlarm(*l)));
    for (std::size_t i = 0; choice.candidates.size() > 1 && i < choice.candidates.size(); ++i) {
      const LevelCandidate& l = choice.candidates[i];
      std::fprintf(stderr, "calibrate: degraded level %.3g: h = %.3f, %d of %d faults (Θ < %.3g) named within %g s%s\n", l.degraded.level,
                   l.degraded.threshold, l.isolated, l.faults, *std::max_element(o.degraded_below.begin(), o.degraded_below.end()),
                   o.delay_budget, static_cast<int>(i) == choice.chosen ? " (chosen)" : "");
    }
    for (std::size_t i = 0; cap_choice.candidates.size() > 1 && i < cap_choice.candidates.size(); ++i) {
      const FailedCapCandidate& f = cap_choice.candidates[i];
      std::fprintf(stderr, "calibrate: failed cap %s: h = %.3f, %d of %d faults (Θ < %.3g) named within %g s%s\n",
                   capText(f.failed.increment_cap).c_str(), f.failed.threshold, f.named, f.faults, o.failed_below, o.failed_delay_budget,
                   static_cast<int>(i) == cap_choice.chosen ? " (chosen)" : "");
    }
    // Which flights the thresholds stand on: the largest excursions at each level (healthy flights
    // are jobs 0, 1, … in order, so a stream's index is its flight's scenario index).
    constexpr std::size_t kNamed = 3;
    const std::unique_ptr<RolloutEngine> engine = healthy_rollout ? std::make_unique<RolloutEngine>(*healthy_rollout) : nullptr;
    for (const auto& [l, of] : {std::pair{&c.degraded, EvidenceLevel::kDegraded}, std::pair{&c.failed, EvidenceLevel::kFailed}}) {
      const std::vector<Excursion> largest = largestExcursions(healthy, l->level, kNamed, 0, l->increment_cap, &healthy_observable, of);
      std::string named;
      for (const Excursion& e : largest) {
        char part[160];
        std::snprintf(part, sizeof part, "%s%.3g in healthy flight %zu, motor %d, from %.1f s for %.2f s", named.empty() ? "" : "; ", e.peak,
                      e.stream, e.motor + 1, streamIndexSeconds(e.start, settle_samples, T, dt), static_cast<double>(e.length) * dt);
        named += part;
        if (engine) named += " (" + drawnFlightText(engine->flightDraw(static_cast<std::uint64_t>(e.stream)), healthy_rollout->randomisation) + ")";
      }
      if (!named.empty()) std::fprintf(stderr, "calibrate: largest excursions at level %.2f: %s\n", l->level, named.c_str());
    }
    std::fprintf(stderr, "calibrate: wrote %s\n", output.c_str());
  }
  return 0;
}

}  // namespace quadfdi::cli
