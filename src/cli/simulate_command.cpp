#include "cli/simulate_command.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "cli/cli_util.h"
#include "cli/options.h"
#include "control/controller_factory.h"
#include "io/atomic_file.h"
#include "io/controller_config.h"
#include "io/params_file.h"
#include "io/telemetry_csv.h"
#include "simulation/closed_loop.h"
#include "simulation/sampling.h"

namespace quadfdi::cli {

CLI::App* addSimulateCommand(CLI::App& app, SimulateOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Fly one closed-loop flight of the simulated Crazyflie, optionally with a motor fault,\n"
      "and write its telemetry CSV (t,x,y,z,roll,pitch,yaw,u1..u4; SI units, z up, ZYX Euler angles,\n"
      "u = commanded thrust per motor [N]). A summary goes to standard error.");
  auto t = std::make_shared<OptionTable>();
  t->addConfigFile(o.config);
  t->recordGivenIn(o.given);
  t->add("--controller", o.controller,
         "Controller: lqr, cbf (LQR filtered by the CBF-QP safety filter), pid (cascaded PID "
         "in the style of PX4 and the Crazyflie), or geometric (Lee's SE(3) tracking law, the Crazyflie's "
         "Mellinger controller; docs/control.md)")
      .choices({"lqr", "cbf", "pid", "geometric"});
  t->add("--params", o.params,
         "Plant parameters: nominal, perturbed, perturbed-strong, a parameter FILE "
         "(see configs/vehicle-example.toml), or a library vehicle's name (crazyflie2, racer250, quad450)").paramsFile();
  t->add("--controller-params", o.controller_params,
         "Model the controller is designed on (same forms as --params); default: the plant's").paramsFile();
  t->add("--lqr-weights", o.lqr_weights,
         "LQR weights: bryson (documented default) or authors (Q = I, R = I, Euler discretisation)")
      .choices({"bryson", "authors"});
  t->add("--controller-config", o.controller_config,
         "Controller FILE: LQR weights and CBF safe set (configs/controller-example.toml); "
         "--controller, --lqr-weights and --cbf-* flags given explicitly win").shippedFile();
  t->add("--motor", o.motor, "Faulty motor 1..4 (Crazyflie numbering: 1 front-right, 2 back-right, "
                             "3 back-left, 4 front-left); omit for a healthy flight")
      .range(1, 4)
      .defaultText("");
  t->add("--theta", o.theta, "Effectiveness of the faulty motor from the fault step on, in [0, 1] "
                             "(0 = complete failure)")
      .range(0.0, 1.0);
  t->add("--fault-step", o.fault_step, "Step at which the fault starts (t = step·dt)").atLeast(0);
  t->add("--steps", o.steps, "Number of control steps (dt = 0.002 s)").range(1, 100000000);
  t->add("--seed", o.seed, "Seed of the initial condition and goal draw (docs/control.md safe set)");
  t->add("--integrator", o.integrator, "Integrator: rk4 or euler (parity with the authors' code)")
      .choices({"rk4", "euler"});
  t->add("--output,-o", o.output, "Telemetry CSV to write; - for standard output");
  t->add("--full-state", o.full_state,
         "Append body velocity, body rates, applied thrusts and controller status columns");
  t->add("--rates", o.rates,
         "Append the logged body rates p,q,r [rad/s] alone, as an autopilot's log records them "
         "(what a model on scale-free-rates features reads; --full-state writes them too)");
  t->add("--goal", o.goal, "Override the sampled goal position: X Y Z [m]").values(3);
  t->add("--start", o.start,
         "Override the sampled initial state: 12 values x y z vx vy vz roll pitch yaw p q r "
         "(body velocity [m/s], angles [rad], body rates [rad/s])")
      .values(12);
  t->add("--trajectory", o.trajectory,
         "Reference to fly: hover (at the goal), point-to-point (minimum-jerk from the start to the "
         "goal), circle or figure-eight (centred on the goal)")
      .choices({"hover", "point-to-point", "circle", "figure-eight"});
  t->add("--speed", o.speed, "Trajectory speed [m/s]: point-to-point and figure-eight peak, circle constant")
      .above(0.0, 20.0);
  t->add("--radius", o.radius, "Circle radius, figure-eight half-length along x [m]").above(0.0, 100.0);
  t->add("--yaw-mode", o.yaw_mode, "Trajectory yaw: fixed (0) or velocity (nose along the path)")
      .choices({"fixed", "velocity"});
  t->add("--yaw-rate-max", o.facing_yaw_rate_max,
         "With --yaw-mode velocity on a circle: the nose turns at most this fast [rad/s] and falls behind a "
         "tighter path, as autopilots slew their mission yaw (PX4 MPC_YAWRAUTO_MAX 45 °/s = 0.79, ArduPilot "
         "ATC_SLEW_YAW 60 °/s = 1.05); 0: no limit")
      .atLeast(0);
  t->add("--yaw-sweep", o.yaw_sweep,
         "Heading sweep A·sin(2π·t/P) on top of the trajectory's yaw (any trajectory, hover too): A [rad] P [s]")
      .values(2);
  t->add("--position-noise", o.position_noise, "Std. dev. of additive noise on logged position [m]").atLeast(0);
  t->add("--attitude-noise", o.attitude_noise, "Std. dev. of additive noise on logged Euler angles [rad]")
      .atLeast(0);
  t->add("--rate-noise", o.rate_noise,
         "Std. dev. of additive noise on the logged body rates p,q,r [rad/s] (a gyro's white noise, "
         "docs/model.md#sensors); needs --rates or --full-state")
      .atLeast(0);
  t->add("--rotor-drag", o.rotor_drag,
         "Linear rotor drag per unit mass [1/s] (the plant's linear_drag = this × mass; 0: the parameter set's); "
         "wind acts through it (docs/model.md#wind: Crazyflie ≈ 0.26, Iris ≈ 0.17)")
      .atLeast(0);
  t->add("--wind-speed", o.wind_speed, "Steady horizontal wind [m/s] (needs rotor drag)").atLeast(0);
  t->add("--wind-direction", o.wind_direction, "World heading the wind blows toward [rad] (0 = +x)");
  t->add("--turbulence", o.turbulence, "Turbulence: std. dev. of each horizontal wind component [m/s] (vertical 0.51 of it)")
      .atLeast(0);
  t->add("--turbulence-tau", o.turbulence_tau, "Turbulence correlation time [s]").above(0.0, 1e6);
  t->add("--gust-rate", o.gust_rate, "Discrete 1 − cosine gusts per second, Poisson arrivals").atLeast(0);
  t->add("--gust-peak", o.gust_peak, "Largest gust peak [m/s] (each gust: ½–1 of it, random horizontal direction)").atLeast(0);
  t->add("--gust-duration", o.gust_duration, "Duration of one gust [s]").above(0.0, 1e6);
  t->add("--cbf-min-altitude", o.cbf_min_altitude, "CBF altitude floor [m] (cbf only)");
  t->add("--cbf-max-tilt", o.cbf_max_tilt, "CBF tilt limit, angle of the body z axis to vertical [rad] "
                                           "(cbf only)")
      .range(0.05, 1.4);
  t->add("--quiet,-q", o.quiet, "No summary on standard error");
  attachOptions(*cmd, t);
  return cmd;
}

namespace {

double maxTilt(const FlightLog& log) {
  double m = 0.0;
  for (const State& x : log.states) m = std::max(m, std::acos(std::cos(x(idx::kRoll)) * std::cos(x(idx::kPitch))));
  return m;
}

std::string vec3(const Vec3& v) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

}  // namespace

int runSimulate(const SimulateOptions& o) {
  auto given = [&](const char* key) { return o.given.count(key) > 0; };
  VehicleParams plant = loadVehicleParams(o.params);
  if (o.rotor_drag > 0.0) plant.linear_drag = o.rotor_drag * plant.mass;
  const VehicleParams design =
      o.controller_params.empty() ? plant : loadVehicleParams(o.controller_params);

  ControllerConfig cc;
  if (!o.controller_config.empty()) cc = loadControllerConfig(o.controller_config, cc);
  if (o.controller_config.empty() || given("controller")) parseControllerKind(o.controller, cc.kind);
  if (o.controller_config.empty() || given("lqr_weights"))
    cc.lqr = o.lqr_weights == "authors" ? LqrConfig::authors() : LqrConfig::brysonFor(design);
  if (o.controller_config.empty() || given("cbf_min_altitude")) cc.cbf.min_altitude = o.cbf_min_altitude;
  if (o.controller_config.empty() || given("cbf_max_tilt")) cc.cbf.max_tilt = o.cbf_max_tilt;
  // Options this flight would not read are refused, not ignored.
  if (cc.kind == ControllerKind::kPid || cc.kind == ControllerKind::kGeometric)
    refuseGiven(o.given, {"lqr_weights"}, std::string("is the LQR's (and the CBF-QP's, which filters it); --controller ") +
                                              toString(cc.kind) + " does not read it");
  if (cc.kind != ControllerKind::kCbfQp)
    refuseGiven(o.given, {"cbf_min_altitude", "cbf_max_tilt"}, "is the CBF-QP filter's; give --controller cbf");
  if (o.motor == 0) refuseGiven(o.given, {"theta", "fault_step"}, "needs --motor N (without it the flight is healthy)");
  require(o.motor == 0 || o.fault_step < o.steps,
          "--fault-step " + std::to_string(o.fault_step) + " is not before --steps " + std::to_string(o.steps) + ": the flight would stay healthy");
  if (!o.rates && !o.full_state)
    refuseGiven(o.given, {"rate_noise"}, "is noise on the body-rate columns, which only --rates or --full-state writes");
  if (o.yaw_mode != "velocity")
    refuseGiven(o.given, {"yaw_rate_max"}, "limits the nose's turn along the path: give --yaw-mode velocity");
  require(!(o.gust_rate > 0.0) || o.gust_peak > 0.0, "--gust-rate: needs --gust-peak > 0 (no gusts otherwise)");
  require(!(o.gust_peak > 0.0) || o.gust_rate > 0.0, "--gust-peak: needs --gust-rate > 0 (no gusts otherwise)");
  if (o.trajectory == "hover")
    refuseGiven(o.given, {"speed", "radius", "yaw_mode", "yaw_rate_max"}, "applies to --trajectory point-to-point, circle or figure-eight; hover holds the goal");
  else if (o.trajectory == "point-to-point")
    refuseGiven(o.given, {"radius"}, "is the circle's and the figure-eight's; point-to-point flies from the start to the goal");

  SimulationSettings settings;
  settings.steps = o.steps;
  settings.integrator = o.integrator == "euler" ? Integrator::kEuler : Integrator::kRk4;
  settings.noise.position_std = o.position_noise;
  settings.noise.attitude_std = o.attitude_noise;
  settings.noise.rate_std = o.rate_noise;
  settings.noise.seed = o.seed;
  settings.wind.mean_speed = o.wind_speed;
  settings.wind.mean_direction = o.wind_direction;
  settings.wind.turbulence_std = o.turbulence;
  settings.wind.turbulence_tau = o.turbulence_tau;
  settings.wind.gust_rate = o.gust_rate;
  settings.wind.gust_peak = o.gust_peak;
  settings.wind.gust_duration = o.gust_duration;
  if (settings.wind.active() && !(plant.linear_drag > 0.0))
    throw std::runtime_error("--wind-speed, --turbulence and --gust-peak act through rotor drag: give --rotor-drag (or linear_drag in --params)");
  if (o.motor != 0) {
    settings.fault.theta(o.motor - 1) = o.theta;
    settings.fault.fault_step = o.fault_step;
  }
  if (const std::string problem = validate(settings); !problem.empty())
    throw std::runtime_error("invalid simulation settings: " + problem);

  Rng rng(o.seed, 0);
  Scenario scenario = sampleScenario(SamplingRanges{}, rng);
  if (!o.goal.empty()) scenario.goal = Vec3(o.goal[0], o.goal[1], o.goal[2]);
  if (!o.start.empty())
    for (int i = 0; i < kStateDim; ++i) scenario.initial_state(i) = o.start[static_cast<std::size_t>(i)];
  if (!scenario.initial_state.allFinite() || !scenario.goal.allFinite())
    throw std::runtime_error("--start and --goal need finite numbers");
  if (const StepStatus s = checkState(scenario.initial_state, settings.bounds); s != StepStatus::kOk)
    throw std::runtime_error(std::string("--start is not a valid flight state: ") + toString(s));

  TrajectoryKind trajectory_kind = TrajectoryKind::kHover;
  parseTrajectoryKind(o.trajectory, trajectory_kind);
  if (!o.yaw_sweep.empty())
    require(std::isfinite(o.yaw_sweep[0]) && o.yaw_sweep[0] >= 0.0 && o.yaw_sweep[0] <= M_PI && std::isfinite(o.yaw_sweep[1]) &&
                o.yaw_sweep[1] > 0.0,
            "--yaw-sweep: needs an amplitude in [0, pi] rad and a period > 0 s");
  if (trajectory_kind != TrajectoryKind::kHover || !o.yaw_sweep.empty()) {
    TrajectorySpec spec;
    spec.kind = trajectory_kind;
    const bool line = trajectory_kind == TrajectoryKind::kPointToPoint;
    spec.start = line ? Vec3(scenario.initial_state.head<3>()) : scenario.goal;
    spec.goal = scenario.goal;
    spec.speed = o.speed;
    spec.radius = o.radius;
    spec.yaw_mode = o.yaw_mode == "velocity" ? YawMode::kFacingVelocity : YawMode::kFixed;
    spec.facing_yaw_rate_max = o.facing_yaw_rate_max;
    if (!o.yaw_sweep.empty()) {
      spec.yaw_sweep_amplitude = o.yaw_sweep[0];
      spec.yaw_sweep_period = o.yaw_sweep[1];
    }
    settings.trajectory = spec;
    if (const std::string problem = validate(settings); !problem.empty())
      throw std::runtime_error("invalid simulation settings: " + problem);
  }

  ControllerBuild build = makeController(design, cc, settings.dt);
  if (!build.controller) throw std::runtime_error(build.error);
  build.controller->setGoal(scenario.goal);

  const ClosedLoopSimulator sim(plant, settings);
  FlightLog log;
  const FlightSummary summary = sim.run(*build.controller, scenario.initial_state, &log);

  TelemetryCsvOptions csv;
  csv.dt = settings.dt;
  csv.full_state = o.full_state;
  csv.rates = o.rates;
  if (o.output == "-") {
    writeTelemetryCsv(std::cout, log, csv);
    std::cout.flush();
    if (!std::cout) throw std::runtime_error("standard output: write failed");
  } else {
    AtomicFileWriter writer(o.output);
    writeTelemetryCsv(writer.stream(), log, csv);
    writer.commit();
  }

  if (!o.quiet) {
    const double dt = settings.dt;
    const int n = summary.steps_completed;
    auto pct = [&](int k) { return n > 0 ? 100.0 * k / n : 0.0; };
    std::fprintf(stderr, "quadfdi simulate: %s controller, %s plant, %s, dt %.3f s, seed %llu\n",
                 toString(cc.kind), o.params.c_str(), toString(settings.integrator), dt, o.seed);
    std::fprintf(stderr, "  start %s m, goal %s m\n",
                 vec3(scenario.initial_state.head<3>()).c_str(), vec3(scenario.goal).c_str());
    if (settings.trajectory) {
      double sum = 0.0, worst = 0.0;
      for (int k = 0; k < log.size(); ++k) {
        const Vec3 p = log.states[static_cast<std::size_t>(k)].head<3>();
        const double e = (p - referenceAt(*settings.trajectory, k * dt).position).norm();
        sum += e * e;
        worst = std::max(worst, e);
      }
      char slew[48] = "", sweep[80] = "";
      if (o.facing_yaw_rate_max > 0.0) std::snprintf(slew, sizeof slew, " turning at most %.2f rad/s", o.facing_yaw_rate_max);
      if (!o.yaw_sweep.empty()) std::snprintf(sweep, sizeof sweep, ", sweep %.2f rad every %.2f s", o.yaw_sweep[0], o.yaw_sweep[1]);
      std::fprintf(stderr, "  trajectory: %s at %.2f m/s (radius %.2f m, yaw %s%s%s); tracking error RMS %.4f m, max %.4f m\n",
                   o.trajectory.c_str(), o.speed, o.radius, o.yaw_mode.c_str(), slew, sweep,
                   log.size() > 0 ? std::sqrt(sum / log.size()) : 0.0, worst);
    }
    if (o.motor != 0)
      std::fprintf(stderr, "  fault: motor %d at theta %.3f from step %d (t = %.3f s)\n", o.motor, o.theta,
                   o.fault_step, o.fault_step * dt);
    else
      std::fprintf(stderr, "  fault: none (healthy flight)\n");
    if (summary.cut())
      std::fprintf(stderr, "  result: CUT after %d of %d steps (t = %.3f s): %s\n", n, o.steps, n * dt,
                   toString(summary.end_status));
    else
      std::fprintf(stderr, "  result: completed %d steps (%.3f s)\n", n, n * dt);
    std::fprintf(stderr, "  final position error %.4f m, max tilt %.3f rad, min altitude %.3f m\n",
                 (summary.final_state.head<3>() - scenario.goal).norm(), maxTilt(log),
                 log.states.empty() ? 0.0 : [&] {
                   double z = log.states.front()(idx::kPz);
                   for (const State& x : log.states) z = std::min(z, x(idx::kPz));
                   return z;
                 }());
    std::fprintf(stderr, "  controller: saturated %.1f%% of steps", pct(summary.saturated_steps));
    if (cc.kind == ControllerKind::kCbfQp)
      std::fprintf(stderr, ", CBF filtered %.1f%% (altitude floor active %.1f%%, tilt limit active %.1f%%), "
                           "infeasible %d",
                   pct(summary.filtered_steps), pct(summary.altitude_active_steps), pct(summary.tilt_active_steps),
                   summary.infeasible_steps);
    std::fprintf(stderr, "\n  wrote %d rows to %s\n", n, o.output == "-" ? "standard output" : o.output.c_str());
  }
  return 0;
}

}  // namespace quadfdi::cli
