#include "data/rollout.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <thread>

#include "data/residual.h"

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

}  // namespace

std::string validate(const RolloutConfig& c) {
  for (const auto* p : {&c.plant, &c.controller_model, &c.residual_model})
    if (const std::string problem = validate(*p); !problem.empty()) return problem;
  if (const std::string problem = validate(c.ranges); !problem.empty()) return problem;
  if (!(c.dt > 0.0) || !std::isfinite(c.dt)) return "dt must be finite and > 0";
  if (c.window < 1 || c.window > 100000) return "window T must be in 1 … 100000";
  if (c.preroll_max_steps < 0) return "pre-roll must be >= 0 steps";
  if (c.controller.kind == ControllerKind::kPid)
    if (const std::string problem = validate(c.controller.pid); !problem.empty()) return problem;
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
}

std::unique_ptr<Controller> RolloutEngine::makeWorkerController() const {
  if (config_.controller.kind == ControllerKind::kLqr)
    return std::make_unique<LqrController>(config_.controller_model, lqr_.gain);
  if (config_.controller.kind == ControllerKind::kPid)
    return std::make_unique<PidController>(config_.controller_model, config_.controller.pid, config_.dt);
  return std::make_unique<CbfQpController>(config_.controller_model, lqr_.gain, config_.controller.cbf);
}

void RolloutEngine::rolloutOne(const TrajectoryJob& job, Controller& controller, TrajectoryBatch& b, int slot) const {
  const auto s = static_cast<std::size_t>(slot);
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

  for (int i = 0; i < kStateDim; ++i) b.initial_state[s * kStateDim + static_cast<std::size_t>(i)] = plant.x(i);
  for (int i = 0; i < 3; ++i) b.goal[s * 3 + static_cast<std::size_t>(i)] = sc.goal(i);
  for (int i = 0; i < kInputDim; ++i) b.theta[s * kInputDim + static_cast<std::size_t>(i)] = static_cast<float>(theta(i));
  b.fault_step[s] = fault_step;
  b.scenario_index[s] = job.scenario_index;

  int length = 0;
  Output residual = Output::Zero();
  if (status == StepStatus::kOk) {
    for (int k = 0; k < samples; ++k) {
      const std::size_t o = b.sampleOffset(slot, k);
      store<kOutputDim>(outputOf(plant.x, config_.output), &b.outputs[o * kOutputDim]);
      store<kStateDim>(plant.x, &b.states[o * kStateDim]);
      store<kOutputDim>(residual, &b.residuals[o * kOutputDim]);
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
  // Samples after a crash hold zeros, so the batch's bytes depend only on the job.
  if (length < samples) {
    const std::size_t from = b.sampleOffset(slot, length), to = b.sampleOffset(slot, samples);
    std::fill(b.outputs.begin() + static_cast<std::ptrdiff_t>(from * kOutputDim), b.outputs.begin() + static_cast<std::ptrdiff_t>(to * kOutputDim), 0.0f);
    std::fill(b.inputs.begin() + static_cast<std::ptrdiff_t>(from * kInputDim), b.inputs.begin() + static_cast<std::ptrdiff_t>(to * kInputDim), 0.0f);
    std::fill(b.states.begin() + static_cast<std::ptrdiff_t>(from * kStateDim), b.states.begin() + static_cast<std::ptrdiff_t>(to * kStateDim), 0.0f);
    std::fill(b.residuals.begin() + static_cast<std::ptrdiff_t>(from * kOutputDim), b.residuals.begin() + static_cast<std::ptrdiff_t>(to * kOutputDim), 0.0f);
  }
  b.length[s] = length;
  b.end_status[s] = static_cast<std::uint8_t>(status);
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
