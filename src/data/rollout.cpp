#include "data/rollout.h"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstring>
#include <thread>

#include "control/geometric.h"
#include "control/pid.h"
#include "data/residual.h"
#include "simulation/sensor_model.h"
#include "simulation/wind.h"

namespace quadfdi {
namespace {

bool sameDynamics(const VehicleParams& a, const VehicleParams& b) {
  return a.mass == b.mass && a.inertia_xx == b.inertia_xx && a.inertia_yy == b.inertia_yy &&
         a.inertia_zz == b.inertia_zz && a.thrust_coeff == b.thrust_coeff && a.drag_coeff == b.drag_coeff &&
         a.arm_length == b.arm_length && a.rotor_x == b.rotor_x && a.rotor_y == b.rotor_y &&
         a.yaw_moment_coeff == b.yaw_moment_coeff && a.gravity == b.gravity && a.linear_drag == b.linear_drag &&
         a.rotational_drag == b.rotational_drag && a.motor_time_constant == 0.0 && b.motor_time_constant == 0.0;
}

template <int N>
void store(const Eigen::Matrix<double, N, 1>& v, float* out) {
  for (int i = 0; i < N; ++i) out[i] = static_cast<float>(v(i));
}

// Salts of the per-trajectory streams (scenario_index is the stream index): the scenario stream
// (initial state, goal) stays the paper's; the draw and the sensor noise get their own.
constexpr std::uint64_t kDrawSalt = 0xD4A3'5EEDull;
constexpr std::uint64_t kSensorSalt = 0x5E45'0125ull;
constexpr std::uint64_t kRedrawSalt = 0x9E37'79B9'7F4A'7C15ull;  // the golden-ratio constant: attempt n's draw stream
constexpr std::uint64_t kProbeSalt = 0x0B5E'4F1Aull;             // the probe's own sensor noise
constexpr std::uint64_t kWindSalt = 0x0A1E'2B10ull;              // the wind's turbulence and gusts

// Flyability (docs/data.md#flyability): a randomised draw is flown healthy along its manoeuvre,
// for its whole length (pre-roll and recorded samples) but at least kMinFlyabilityProbe, before it
// is used; if the vehicle leaves the state bounds, or the controller holds a motor at a thrust
// limit for more than kMaxSaturatedFraction of the probe after kFlyabilityJudgedFrom (a saturating
// limit cycle: a high-gain design meeting a slow motor it was not designed for, or a manoeuvre
// beyond the drawn thrust), the draw is redrawn. Nobody flies such a pairing, so it is neither
// healthy training data nor a healthy flight whose alarms count. The first second is left out:
// recovering from the scenario's initial state may saturate on purpose. The whole flight, not a
// fixed second: on one-minute calibration flights a Crazyflie LQR on 31 ms motors grew its cycle
// for ~15 s before reaching the limits, and another cycled from ~2 s on (measured; both had
// passed a 1 s probe and held the largest healthy Θ̂ excursions).
constexpr double kMinFlyabilityProbe = 4.0;     // [s]
constexpr double kFlyabilityJudgedFrom = 1.0;   // [s]
constexpr double kMaxSaturatedFraction = 0.05;  // [-] of the judged steps
constexpr double kAtLimit = 1e-3;               // [-] of max thrust: a command this close to a limit is at it
constexpr int kFlyableAttempts = 8;             // draws tried before the last one is flown anyway

// Bryson's per-motor thrust deviation (control/lqr.cpp) as a fraction of hover thrust, so that one
// rule designs a comparable LQR for a 30 g and a 1.5 kg vehicle: 0.02 N of the Crazyflie's 0.0733 N.
constexpr double kLqrThrustDeviationOfHover = 0.02 / (0.0299 * 9.8 / 4.0);

// The LQR of a described vehicle at gain scale s: Bryson's weights with the thrust deviation scaled
// to the vehicle's hover thrust and Q multiplied by s² (state errors cost s² more: a faster loop).
LqrConfig lqrConfigFor(const VehicleParams& v, double s) {
  LqrConfig c = LqrConfig::bryson();
  const double deviation = kLqrThrustDeviationOfHover * v.hoverThrust();
  c.r_diag = Input::Constant(1.0 / (deviation * deviation));
  c.q_diag *= s * s;
  return c;
}

// The manoeuvre a draw describes, anchored at the scenario's goal (the circle and the
// point-to-point path start there; the figure-eight is centred there).
TrajectorySpec trajectoryFor(const ManoeuvreDraw& m, const Vec3& anchor) {
  TrajectorySpec t;
  t.start = anchor;
  switch (m.kind) {
    case ManoeuvreKind::kHover: t.kind = TrajectoryKind::kHover; break;
    case ManoeuvreKind::kPointToPoint:
      t.kind = TrajectoryKind::kPointToPoint;
      t.goal = anchor + m.size * Vec3(std::cos(m.direction), std::sin(m.direction), 0.0);
      t.speed = m.speed;
      break;
    case ManoeuvreKind::kCircle:
      t.kind = TrajectoryKind::kCircle;
      t.start = anchor - Vec3(m.size, 0.0, 0.0);  // the circle starts at centre + (radius, 0, 0)
      t.radius = m.size;
      t.speed = m.speed;
      break;
    case ManoeuvreKind::kFigureEight:
      t.kind = TrajectoryKind::kFigureEight;
      t.radius = m.size;
      t.speed = m.speed;
      break;
  }
  t.yaw_mode = m.facing_velocity ? YawMode::kFacingVelocity : YawMode::kFixed;
  t.facing_yaw_rate_max = m.facing_yaw_rate_max;
  t.yaw_sweep_amplitude = m.yaw_sweep_amplitude;
  t.yaw_sweep_period = m.yaw_sweep_period;
  return t;
}

// Gain levels the LQR designs are made at: `count` log-spaced points spanning the range.
std::vector<double> gainLevels(const Interval& range, int count) {
  if (!(range.hi > range.lo)) return {range.lo};
  std::vector<double> levels;
  for (int i = 0; i < count; ++i)
    levels.push_back(std::exp(std::log(range.lo) + (std::log(range.hi) - std::log(range.lo)) * i / (count - 1)));
  return levels;
}

// The per-trajectory fields of slot `slot`, written once its recorded part begins.
void recordStart(TrajectoryBatch& b, int slot, const State& x0, const Vec3& goal, const Input& theta, int fault_step,
                 std::uint64_t scenario_index) {
  const auto s = static_cast<std::size_t>(slot);
  for (int i = 0; i < kStateDim; ++i) b.initial_state[s * kStateDim + static_cast<std::size_t>(i)] = x0(i);
  for (int i = 0; i < 3; ++i) b.goal[s * 3 + static_cast<std::size_t>(i)] = goal(i);
  for (int i = 0; i < kInputDim; ++i) b.theta[s * kInputDim + static_cast<std::size_t>(i)] = static_cast<float>(theta(i));
  b.fault_step[s] = fault_step;
  b.scenario_index[s] = scenario_index;
}

// Samples after a crash hold zeros, so the batch's bytes depend only on the job.
void recordEnd(TrajectoryBatch& b, int slot, int length, StepStatus status) {
  const auto s = static_cast<std::size_t>(slot);
  if (length < b.samples) {
    const std::size_t from = b.sampleOffset(slot, length), to = b.sampleOffset(slot, b.samples);
    auto zero = [&](std::vector<float>& v, int channels) {
      std::fill(v.begin() + static_cast<std::ptrdiff_t>(from * channels), v.begin() + static_cast<std::ptrdiff_t>(to * channels), 0.0f);
    };
    zero(b.outputs, kOutputDim);
    zero(b.inputs, kInputDim);
    zero(b.states, kStateDim);
    zero(b.residuals, kOutputDim);
    zero(b.rates, kRateDim);
  }
  b.length[s] = length;
  b.end_status[s] = static_cast<std::uint8_t>(status);
}

}  // namespace

std::string validate(const RolloutConfig& c) {
  for (const auto* p : {&c.plant, &c.controller_model, &c.residual_model})
    if (const std::string problem = validate(*p); !problem.empty()) return problem;
  if (const std::string problem = validate(c.ranges); !problem.empty()) return problem;
  if (!(c.dt > 0.0) || !std::isfinite(c.dt)) return "dt must be finite and > 0";
  if (c.window < 1 || c.window > 100000) return "window T must be in 1 … 100000";
  if (c.preroll_max_steps < 0) return "pre-roll must be >= 0 steps";
  if (c.controller.kind == ControllerKind::kPid || c.randomisation.controllers.pid > 0.0)
    if (const std::string problem = validate(c.controller.pid); !problem.empty()) return problem;
  if (c.controller.kind == ControllerKind::kGeometric || c.randomisation.controllers.geometric > 0.0)
    if (const std::string problem = validate(c.controller.geometric); !problem.empty()) return problem;
  if (c.post_fault_steps < 0 || c.post_fault_steps > 1000000) return "post-fault steps must be in 0 … 1000000";
  if (c.randomisation.enabled())
    if (const std::string problem = validate(c.randomisation); !problem.empty()) return problem;
  return {};
}

std::vector<TrajectoryJob> algorithm1Jobs(std::uint64_t first_scenario, int initial_conditions,
                                          const std::vector<double>& thetas, const std::vector<int>& motors) {
  std::vector<TrajectoryJob> jobs;
  jobs.reserve(static_cast<std::size_t>(initial_conditions) * thetas.size() * motors.size());
  for (int i = 0; i < initial_conditions; ++i)
    for (int motor : motors)
      for (double theta : thetas) jobs.push_back({first_scenario + static_cast<std::uint64_t>(i), motor, theta});
  return jobs;
}

RolloutEngine::RolloutEngine(const RolloutConfig& config)
    : config_(config),
      plant_model_(RigidBodyModel::fromParams(config.plant)),
      residual_model_(RigidBodyModel::fromParams(config.residual_model)),
      residual_is_plant_(sameDynamics(config.plant, config.residual_model)) {
  error_ = validate(config);
  if (!error_.empty()) return;
  lqr_ = designLqr(config.controller_model, config.controller.lqr, config.dt);
  if (!lqr_.ok()) error_ = "LQR design failed: " + lqr_.error;
  const Randomisation& r = config.randomisation;
  if (!error_.empty() || !r.enabled()) return;
  // Five levels across the gain range: a draw flies the nearest (Riccati solves stay in setup).
  lqr_gain_levels_ = gainLevels(r.controllers.gain_scale, 5);
  described_ = describedVehicles(r);
  for (std::size_t v = 0; v < described_.size(); ++v) {
    vehicle_lqr_.emplace_back();
    for (double s : lqr_gain_levels_) {
      vehicle_lqr_.back().push_back(designLqr(described_[v], lqrConfigFor(described_[v], s), config.dt));
      if (!vehicle_lqr_.back().back().ok()) {
        error_ = "LQR design failed for vehicle '" + describedVehicleName(r, v) + "': " + vehicle_lqr_.back().back().error;
        return;
      }
    }
  }
}

std::unique_ptr<Controller> RolloutEngine::makeWorkerController() const {
  if (config_.controller.kind == ControllerKind::kLqr)
    return std::make_unique<LqrController>(config_.controller_model, lqr_.gain);
  if (config_.controller.kind == ControllerKind::kPid)
    return std::make_unique<PidController>(config_.controller_model, config_.controller.pid, config_.dt);
  if (config_.controller.kind == ControllerKind::kGeometric)
    return std::make_unique<GeometricController>(config_.controller_model, config_.controller.geometric, config_.dt);
  return std::make_unique<CbfQpController>(config_.controller_model, lqr_.gain, config_.controller.cbf);
}

void RolloutEngine::rolloutOne(const TrajectoryJob& job, Controller& controller, TrajectoryBatch& b, int slot) const {
  if (config_.randomisation.enabled()) return rolloutRandomised(job, b, slot);
  const int samples = b.samples, fault_step = config_.faultStep();
  const double dt = config_.dt, lag = config_.plant.motor_time_constant;

  Rng rng(config_.seed, job.scenario_index);
  const Scenario sc = sampleScenario(config_.ranges, rng);
  controller.reset();  // a worker's controller flies many scenarios: no state carries over
  controller.setGoal(sc.goal);
  Input theta = Input::Ones();
  theta(job.faulty_motor - 1) = job.theta;

  PlantState plant;
  plant.x = sc.initial_state;
  plant.rotor_thrust = Input::Constant(config_.plant.hoverThrust());
  ControlStep control;
  StepStatus status = checkState(plant.x, StateBounds{});

  // Optional healthy pre-roll (its length drawn from the same stream, after the scenario).
  const int preroll = config_.preroll_max_steps > 0
                          ? static_cast<int>(rng.next() % static_cast<std::uint64_t>(config_.preroll_max_steps + 1))
                          : 0;
  for (int k = 0; k < preroll && status == StepStatus::kOk; ++k) {
    controller.compute(plant.x, control);
    stepPlant(plant_model_, config_.integrator, dt, lag, control.u_cmd, plant);
    status = checkState(plant.x, StateBounds{});
  }

  recordStart(b, slot, plant.x, sc.goal, theta, fault_step, job.scenario_index);

  int length = 0;
  Output residual = Output::Zero();
  if (status == StepStatus::kOk) {
    for (int k = 0; k < samples; ++k) {
      const std::size_t o = b.sampleOffset(slot, k);
      store<kOutputDim>(outputOf(plant.x, config_.output), &b.outputs[o * kOutputDim]);
      store<kStateDim>(plant.x, &b.states[o * kStateDim]);
      store<kOutputDim>(residual, &b.residuals[o * kOutputDim]);
      store<kRateDim>(Vec3(plant.x.segment<kRateDim>(idx::kRate)), &b.rates[o * kRateDim]);
      controller.compute(plant.x, control);
      store<kInputDim>(control.u_cmd, &b.inputs[o * kInputDim]);
      length = k + 1;
      if (k + 1 == samples) break;

      const bool faulty = k >= fault_step;
      const Input applied = faulty ? Input(theta.cwiseProduct(control.u_cmd)) : control.u_cmd;
      // ȳ(k+1): the nominal model from the true x(k) under the commanded u(k). When the plant
      // is that model and receives the command unchanged, the prediction *is* the plant step,
      // so reuse it (bit-identical) instead of integrating twice.
      // (oneStepResidual of that step is exactly zero; tests check it.)
      const bool prediction_is_plant_step = residual_is_plant_ && (applied.array() == control.u_cmd.array()).all();
      const State x_prev = plant.x;
      stepPlant(plant_model_, config_.integrator, dt, lag, applied, plant);
      status = checkState(plant.x, StateBounds{});
      if (status != StepStatus::kOk) break;
      residual = prediction_is_plant_step ? Output::Zero()
                                          : oneStepResidual(residual_model_, config_.integrator, dt, x_prev,
                                                            control.u_cmd, plant.x, config_.output);
    }
  }
  recordEnd(b, slot, length, status);
}

std::unique_ptr<Controller> RolloutEngine::makeFlightController(const FlightDraw& d) const {
  // Designed on the described vehicle (what its user knows), not on the plant.
  const VehicleParams& described = described_[static_cast<std::size_t>(d.vehicle)];
  if (d.controller == DrawnController::kPid)
    return std::make_unique<PidController>(described, scaledPid(config_.controller.pid, d.gain_scale), config_.dt);
  if (d.controller == DrawnController::kGeometric)
    return std::make_unique<GeometricController>(described, scaledGeometric(config_.controller.geometric, d.gain_scale),
                                                 config_.dt);
  std::size_t level = 0;
  for (std::size_t i = 1; i < lqr_gain_levels_.size(); ++i)
    if (std::abs(std::log(lqr_gain_levels_[i] / d.gain_scale)) < std::abs(std::log(lqr_gain_levels_[level] / d.gain_scale)))
      level = i;
  const GainMatrix& gain = vehicle_lqr_[static_cast<std::size_t>(d.vehicle)][level].gain;
  if (d.controller == DrawnController::kLqr) return std::make_unique<LqrController>(described, gain);
  return std::make_unique<CbfQpController>(described, gain, config_.controller.cbf);
}

bool RolloutEngine::flyable(const FlightDraw& d, std::uint64_t scenario_index) const {
  const double dt = config_.dt;
  Rng rng(config_.seed, scenario_index);
  const Scenario sc = sampleScenario(config_.ranges, rng);
  const VehicleParams& described = described_[static_cast<std::size_t>(d.vehicle)];
  const RigidBodyModel plant_model = RigidBodyModel::fromParams(d.plant);
  const std::unique_ptr<Controller> controller = makeFlightController(d);
  const TrajectorySpec trajectory = trajectoryFor(d.manoeuvre, sc.goal);
  SensorModel sensors(d.sensors, dt);
  Rng sensor_rng(config_.seed ^ kSensorSalt ^ kProbeSalt, scenario_index);
  WindModel wind(d.wind, dt);
  Rng wind_rng(config_.seed ^ kWindSalt ^ kProbeSalt, scenario_index);
  wind.reset(wind_rng);
  PlantState plant;
  plant.x = sc.initial_state;
  plant.rotor_thrust = Input::Constant(d.plant.hoverThrust());
  sensors.reset(plant.x);
  ControlStep control;
  const int steps = std::max(static_cast<int>(std::lround(kMinFlyabilityProbe / dt)),
                             d.preroll_steps + config_.samplesPerTrajectory());
  const int judged_from = static_cast<int>(std::lround(kFlyabilityJudgedFrom / dt));
  const double low = described.min_thrust + kAtLimit * described.max_thrust, high = (1.0 - kAtLimit) * described.max_thrust;
  int saturated = 0;
  for (int k = 0; k < steps; ++k) {
    controller->setReference(referenceAt(trajectory, static_cast<double>(k) * dt));
    controller->compute(sensors.measure(plant.x, sensor_rng), control);
    stepPlant(plant_model, config_.integrator, dt, d.plant.motor_time_constant, d.thrust_gain * control.u_cmd, plant,
              wind.advance(wind_rng));
    if (checkState(plant.x, StateBounds{}) != StepStatus::kOk) return false;
    if (k >= judged_from && (control.u_cmd.minCoeff() <= low || control.u_cmd.maxCoeff() >= high)) ++saturated;
  }
  return saturated <= kMaxSaturatedFraction * (steps - judged_from);
}

FlightDraw RolloutEngine::flightDraw(std::uint64_t scenario_index, int* attempts) const {
  FlightDraw d;
  int attempt = 0;
  for (; attempt < kFlyableAttempts; ++attempt) {
    // Attempt 0 is the draw every flyable flight has always had; redraws take their own streams.
    Rng draw_rng(config_.seed ^ kDrawSalt ^ (static_cast<std::uint64_t>(attempt) * kRedrawSalt), scenario_index);
    d = drawFlight(config_.randomisation, described_, config_.dt, draw_rng);
    if (flyable(d, scenario_index)) break;
  }
  if (attempts) *attempts = std::min(attempt + 1, kFlyableAttempts);
  return d;
}

void RolloutEngine::rolloutRandomised(const TrajectoryJob& job, TrajectoryBatch& b, int slot) const {
  const int samples = b.samples, fault_step = config_.faultStep();
  const double dt = config_.dt;

  Rng rng(config_.seed, job.scenario_index);
  const Scenario sc = sampleScenario(config_.ranges, rng);
  const FlightDraw d = flightDraw(job.scenario_index);
  const VehicleParams& described = described_[static_cast<std::size_t>(d.vehicle)];
  const RigidBodyModel plant_model = RigidBodyModel::fromParams(d.plant);
  const RigidBodyModel described_model = RigidBodyModel::fromParams(described);
  const double lag = d.plant.motor_time_constant;
  const std::unique_ptr<Controller> controller = makeFlightController(d);
  const TrajectorySpec trajectory = trajectoryFor(d.manoeuvre, sc.goal);
  SensorModel sensors(d.sensors, dt);
  Rng sensor_rng(config_.seed ^ kSensorSalt, job.scenario_index);
  WindModel wind(d.wind, dt);
  Rng wind_rng(config_.seed ^ kWindSalt, job.scenario_index);
  wind.reset(wind_rng);

  Input theta = Input::Ones();
  theta(job.faulty_motor - 1) = job.theta;
  PlantState plant;
  plant.x = sc.initial_state;
  plant.rotor_thrust = Input::Constant(d.plant.hoverThrust());
  sensors.reset(plant.x);
  ControlStep control;
  StepStatus status = checkState(plant.x, StateBounds{});

  // Healthy pre-roll along the manoeuvre, then the recorded samples; step k flies t = k·dt.
  long step = 0;
  auto advance = [&](const State& estimate, const Input& applied_factor) {
    controller->setReference(referenceAt(trajectory, static_cast<double>(step) * dt));
    controller->compute(estimate, control);
    const Input applied = d.thrust_gain * applied_factor.cwiseProduct(control.u_cmd);
    stepPlant(plant_model, config_.integrator, dt, lag, applied, plant, wind.advance(wind_rng));
    ++step;
    status = checkState(plant.x, StateBounds{});
  };
  State estimate = sensors.measure(plant.x, sensor_rng);
  for (int k = 0; k < d.preroll_steps && status == StepStatus::kOk; ++k) {
    advance(estimate, Input::Ones());
    estimate = sensors.measure(plant.x, sensor_rng);
  }

  recordStart(b, slot, plant.x, sc.goal, theta, fault_step, job.scenario_index);

  int length = 0;
  Output residual = Output::Zero();
  if (status == StepStatus::kOk) {
    for (int k = 0; k < samples; ++k) {
      const std::size_t o = b.sampleOffset(slot, k);
      // The log holds what the flight controller had: the estimate and the command made from it.
      store<kOutputDim>(outputOf(estimate, config_.output), &b.outputs[o * kOutputDim]);
      store<kStateDim>(plant.x, &b.states[o * kStateDim]);
      store<kOutputDim>(residual, &b.residuals[o * kOutputDim]);
      store<kRateDim>(Vec3(estimate.segment<kRateDim>(idx::kRate)), &b.rates[o * kRateDim]);  // the gyro path's
      const State estimate_before = estimate;
      advance(estimate, k >= fault_step ? theta : Input::Ones());
      store<kInputDim>(control.u_cmd, &b.inputs[o * kInputDim]);
      length = k + 1;
      if (status != StepStatus::kOk || k + 1 == samples) break;
      estimate = sensors.measure(plant.x, sensor_rng);
      // ỹ: the described vehicle's one-step prediction from the previous estimate (what a user
      // with the description could compute), against the new estimate.
      residual = oneStepResidual(described_model, config_.integrator, dt, estimate_before, control.u_cmd, estimate,
                                 config_.output);
    }
  }
  recordEnd(b, slot, length, status);
}

bool RolloutEngine::run(const std::vector<TrajectoryJob>& jobs, int threads, TrajectoryBatch& batch,
                        const ProgressCallback& progress, const std::atomic<bool>* stop) const {
  if (!error_.empty()) return false;
  const int n = static_cast<int>(jobs.size());
  batch.resize(n, config_.samplesPerTrajectory());
  const int workers = std::max(1, std::min(n, threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency())));
  std::atomic<int> next{0}, done{0};
  // Dynamic scheduling in small chunks: each slot is written by exactly one worker, so the
  // result does not depend on which worker took it.
  constexpr int kChunk = 8;
  auto work = [&] {
    const std::unique_ptr<Controller> controller = makeWorkerController();
    for (;;) {
      if (stop && stop->load(std::memory_order_relaxed)) break;
      const int first = next.fetch_add(kChunk);
      if (first >= n) break;
      const int last = std::min(n, first + kChunk);
      for (int i = first; i < last; ++i) rolloutOne(jobs[static_cast<std::size_t>(i)], *controller, batch, i);
      const int finished = done.fetch_add(last - first) + (last - first);
      if (progress) progress(finished, n);
    }
  };
  if (workers == 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(workers));
    for (int w = 0; w < workers; ++w) pool.emplace_back(work);
    for (auto& t : pool) t.join();
  }
  return done.load() == n;
}

}  // namespace quadfdi
