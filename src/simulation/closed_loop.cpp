#include "simulation/closed_loop.h"

#include <cmath>
#include <string>

#include "simulation/rng.h"

namespace quadfdi {
namespace {

// Standard normal by Box–Muller on the portable Rng (no library-dependent distributions).
double gaussian(Rng& rng) {
  const double u1 = 1.0 - rng.uniform();  // (0, 1]
  const double u2 = rng.uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace

std::string validate(const SimulationSettings& s) {
  if (!(std::isfinite(s.dt) && s.dt > 0.0)) return "dt must be finite and > 0";
  if (s.steps < 1) return "steps must be >= 1";
  if (s.fault.fault_step < 0) return "fault step must be >= 0";
  for (int i = 0; i < kInputDim; ++i)
    if (!(s.fault.theta(i) >= 0.0 && s.fault.theta(i) <= 1.0))
      return "theta must lie in [0, 1], got " + std::to_string(s.fault.theta(i)) + " for motor " + std::to_string(i + 1);
  if (!(s.noise.position_std >= 0.0 && s.noise.attitude_std >= 0.0 && s.noise.rate_std >= 0.0 &&
        std::isfinite(s.noise.position_std) && std::isfinite(s.noise.attitude_std) && std::isfinite(s.noise.rate_std)))
    return "sensor noise standard deviations must be finite and >= 0";
  if (s.trajectory)
    if (std::string problem = validate(*s.trajectory); !problem.empty()) return problem;
  if (std::string problem = validate(s.wind); !problem.empty()) return problem;
  return {};
}

ClosedLoopSimulator::ClosedLoopSimulator(const VehicleParams& plant_params, const SimulationSettings& settings)
    : params_(plant_params), model_(RigidBodyModel::fromParams(plant_params)), settings_(settings) {}

FlightSummary ClosedLoopSimulator::run(Controller& controller, const State& x0, FlightLog* log) const {
  const int n = settings_.steps;
  if (log) {
    log->states.clear();
    log->outputs.clear();
    log->controls.clear();
    log->applied.clear();
    log->rates.clear();
    log->states.reserve(n);
    log->outputs.reserve(n);
    log->controls.reserve(n);
    log->applied.reserve(n);
    log->rates.reserve(n);
  }
  FlightSummary summary;
  PlantState plant;
  plant.x = x0;
  plant.rotor_thrust = Input::Constant(params_.hoverThrust());
  summary.end_status = checkState(x0, settings_.bounds);
  if (summary.cut()) return summary;

  const bool noisy = settings_.noise.position_std > 0.0 || settings_.noise.attitude_std > 0.0;
  Rng noise_rng(settings_.noise.seed, 0x5E45);
  // The gyro's noise has a stream of its own, so adding it leaves the position and attitude noise
  // of a seed as they were.
  Rng rate_noise_rng(settings_.noise.seed, 0x6A50);
  WindModel wind(settings_.wind, settings_.dt);
  Rng wind_rng(settings_.noise.seed, 0x0A1E);
  wind.reset(wind_rng);
  ControlStep control;
  controller.reset();
  for (int k = 0; k < n; ++k) {
    if (settings_.trajectory) controller.setReference(referenceAt(*settings_.trajectory, k * settings_.dt));
    controller.compute(plant.x, control);
    const Input applied =
        k >= settings_.fault.fault_step ? Input(settings_.fault.theta.cwiseProduct(control.u_cmd)) : control.u_cmd;
    if (log) {
      Output y = outputOf(plant.x, OutputKind::kPositionEuler);
      if (noisy) {
        for (int i = 0; i < 3; ++i) y(i) += settings_.noise.position_std * gaussian(noise_rng);
        for (int i = 3; i < 6; ++i) y(i) += settings_.noise.attitude_std * gaussian(noise_rng);
      }
      log->states.push_back(plant.x);
      log->outputs.push_back(y);
      log->controls.push_back(control);
      log->applied.push_back(applied);
      Vec3 rates = plant.x.segment<3>(idx::kRate);
      if (settings_.noise.rate_std > 0.0)
        for (int i = 0; i < 3; ++i) rates(i) += settings_.noise.rate_std * gaussian(rate_noise_rng);
      log->rates.push_back(rates);
    }
    switch (control.status) {
      case ControlStatus::kSaturated: ++summary.saturated_steps; break;
      case ControlStatus::kFiltered: ++summary.filtered_steps; break;
      case ControlStatus::kQpInfeasible:
      case ControlStatus::kQpFailed: ++summary.infeasible_steps; break;
      case ControlStatus::kOk: break;
    }
    if (control.active_constraints & kAltitudeFloorActive) ++summary.altitude_active_steps;
    if (control.active_constraints & kTiltLimitActive) ++summary.tilt_active_steps;
    ++summary.steps_completed;
    summary.final_state = plant.x;

    stepPlant(model_, settings_.integrator, settings_.dt, params_.motor_time_constant, applied, plant,
              wind.advance(wind_rng));
    summary.end_status = checkState(plant.x, settings_.bounds);
    if (summary.cut()) return summary;
    summary.final_state = plant.x;
  }
  return summary;
}

}  // namespace quadfdi
