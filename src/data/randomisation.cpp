#include "data/randomisation.h"

#include <cmath>

namespace quadfdi {
namespace {

double draw(const Interval& i, Rng& rng) { return i.hi > i.lo ? rng.uniform(i.lo, i.hi) : i.lo; }

// Log-uniform over [lo, hi] (lo > 0): a factor of two is as likely up as down.
double drawLog(const Interval& i, Rng& rng) { return std::exp(draw({std::log(i.lo), std::log(i.hi)}, rng)); }

bool validInterval(const Interval& i) { return std::isfinite(i.lo) && std::isfinite(i.hi) && i.lo >= 0.0 && i.hi >= i.lo; }

// Index drawn with probability proportional to its weight (weights ≥ 0, sum > 0).
template <std::size_t N>
int pick(const double (&weights)[N], Rng& rng) {
  double total = 0.0;
  for (double w : weights) total += w;
  double u = rng.uniform() * total;
  for (std::size_t i = 0; i < N; ++i) {
    if (u < weights[i]) return static_cast<int>(i);
    u -= weights[i];
  }
  for (std::size_t i = N; i-- > 0;)
    if (weights[i] > 0.0) return static_cast<int>(i);
  return 0;
}

}  // namespace

const char* toString(ManoeuvreKind k) {
  switch (k) {
    case ManoeuvreKind::kHover: return "hover";
    case ManoeuvreKind::kPointToPoint: return "point-to-point";
    case ManoeuvreKind::kCircle: return "circle";
    case ManoeuvreKind::kFigureEight: return "figure-eight";
  }
  return "?";
}

bool parseManoeuvreKind(const std::string& text, ManoeuvreKind& kind) {
  for (ManoeuvreKind k : {ManoeuvreKind::kHover, ManoeuvreKind::kPointToPoint, ManoeuvreKind::kCircle, ManoeuvreKind::kFigureEight})
    if (text == toString(k)) {
      kind = k;
      return true;
    }
  return false;
}

const char* toString(DrawnController c) {
  switch (c) {
    case DrawnController::kLqr: return "lqr";
    case DrawnController::kPid: return "pid";
    case DrawnController::kCbfQp: return "cbf";
    case DrawnController::kGeometric: return "geometric";
  }
  return "?";
}

void delayPreroll(Randomisation& r, double seconds) {
  r.preroll_seconds.lo += seconds;
  r.preroll_seconds.hi += seconds;
}

std::string validate(const Randomisation& r) {
  if (r.vehicle_names.size() != r.vehicles.size()) return "randomisation: one name per vehicle";
  if (const std::string p = validate(r.airframes); !p.empty()) return "randomisation: airframes: " + p;
  for (std::size_t i = 0; i < r.vehicles.size(); ++i)
    if (const std::string p = validate(r.vehicles[i]); !p.empty()) return "vehicle '" + r.vehicle_names[i] + "': " + p;
  const ParameterSpread& p = r.parameters;
  for (const Interval* f : {&p.mass, &p.inertia, &p.thrust, &p.yaw_moment})
    if (!validInterval(*f) || !(f->lo >= 0.1 && f->hi <= 10.0)) return "randomisation: parameter factors must be 0.1 <= lo <= hi <= 10";
  if (!validInterval(p.motor_time_constant)) return "randomisation: motor time constant range must be 0 <= lo <= hi";
  const SensorRanges& s = r.sensors;
  for (const Interval* i : {&s.position_std, &s.velocity_std, &s.attitude_std, &s.rate_std, &s.attitude_filter_tau, &s.rate_filter_tau,
                            &s.estimate_error_tau})
    if (!validInterval(*i)) return "randomisation: sensor ranges must be 0 <= lo <= hi";
  if (s.delay_steps_max < 0 || s.delay_steps_max > 1000) return "randomisation: sensor delay must be in 0 … 1000 steps";
  const ManoeuvreMix& m = r.manoeuvres;
  for (double w : {m.hover, m.point_to_point, m.circle, m.figure_eight})
    if (!(w >= 0.0) || !std::isfinite(w)) return "randomisation: manoeuvre weights must be >= 0";
  if (!(m.hover + m.point_to_point + m.circle + m.figure_eight > 0.0)) return "randomisation: some manoeuvre weight must be > 0";
  if (!validInterval(m.speed) || !validInterval(m.size) || !(m.size.lo > 0.0 || m.hover > 0.0))
    return "randomisation: manoeuvre speed and size ranges must be 0 <= lo <= hi";
  if (!(m.max_lateral_accel > 0.0)) return "randomisation: max lateral acceleration must be > 0";
  if (!(m.facing_velocity >= 0.0 && m.facing_velocity <= 1.0 && m.yaw_sweep >= 0.0 && m.yaw_sweep <= 1.0))
    return "randomisation: manoeuvres.facing_velocity and manoeuvres.yaw_sweep are shares in [0, 1]";
  if (!validInterval(m.yaw_sweep_amplitude) || m.yaw_sweep_amplitude.lo < 0.0 || m.yaw_sweep_amplitude.hi > M_PI)
    return "randomisation: manoeuvres.yaw_sweep_amplitude must lie in [0, pi] rad";
  if (!validInterval(m.yaw_sweep_period) || !(m.yaw_sweep_period.lo > 0.0))
    return "randomisation: manoeuvres.yaw_sweep_period needs 0 < lo <= hi";
  if (!(std::isfinite(m.facing_velocity_yaw_rate_max) && m.facing_velocity_yaw_rate_max >= 0.0))
    return "randomisation: manoeuvres.facing_velocity_yaw_rate_max must be finite and >= 0 rad/s (0: no limit)";
  const ControllerMix& c = r.controllers;
  for (double w : {c.lqr, c.pid, c.cbf, c.geometric})
    if (!(w >= 0.0) || !std::isfinite(w)) return "randomisation: controller weights must be >= 0";
  if (!(c.lqr + c.pid + c.cbf + c.geometric > 0.0)) return "randomisation: some controller weight must be > 0";
  if (!validInterval(c.gain_scale) || !(c.gain_scale.lo > 0.0)) return "randomisation: gain scale range must be 0 < lo <= hi";
  if (!validInterval(r.preroll_seconds)) return "randomisation: pre-roll range must be 0 <= lo <= hi";
  const WindRanges& w = r.wind;
  for (const Interval* i : {&w.rotor_drag, &w.mean_speed, &w.turbulence_std, &w.turbulence_tau, &w.gust_rate, &w.gust_peak,
                            &w.gust_duration})
    if (!validInterval(*i)) return "randomisation: wind ranges must be 0 <= lo <= hi";
  if (!(w.turbulence_tau.lo > 0.0) || !(w.gust_duration.lo > 0.0))
    return "randomisation: wind turbulence_tau and gust_duration must be > 0";
  if (!w.enabled() && (w.mean_speed.hi > 0.0 || w.turbulence_std.hi > 0.0 || w.gust_peak.hi > 0.0))
    return "randomisation: wind without rotor drag has no effect: set wind.rotor_drag";
  return {};
}

std::string validate(const AirframeRanges& a) {
  if (a.count < 0 || a.count > 1000) return "count must be in 0 … 1000";
  if (!(a.share >= 0.0 && a.share <= 1.0)) return "share must be in [0, 1]";
  if (!a.enabled()) return {};
  for (const Interval* i : {&a.mass, &a.size_factor, &a.aspect, &a.inertia_factor, &a.yaw_inertia_ratio, &a.hover_fraction,
                            &a.yaw_moment_coeff})
    if (!validInterval(*i) || !(i->lo > 0.0)) return "mass, size_factor, aspect, inertia_factor, yaw_inertia_ratio, hover_fraction "
                                                     "and yaw_moment_coeff need 0 < lo <= hi";
  if (!(a.hover_fraction.hi < 1.0)) return "hover_fraction must stay below 1 (a vehicle hovering at full thrust cannot be controlled)";
  // Far beyond any quadrotor, and inside what the products below keep finite and non-zero.
  struct Bound { const Interval* range; double lo, hi; const char* text; };
  for (const Bound& b : {Bound{&a.mass, 1e-3, 1e3, "mass must lie in [0.001, 1000] kg"},
                         Bound{&a.size_factor, 1e-3, 10.0, "size_factor must lie in [0.001, 10] m/kg^(1/3)"},
                         Bound{&a.aspect, 0.1, 10.0, "aspect must lie in [0.1, 10]"},
                         Bound{&a.inertia_factor, 1e-3, 10.0, "inertia_factor must lie in [0.001, 10]"},
                         Bound{&a.yaw_inertia_ratio, 1e-3, 10.0, "yaw_inertia_ratio must lie in [0.001, 10]"},
                         Bound{&a.yaw_moment_coeff, 1e-4, 1.0, "yaw_moment_coeff must lie in [0.0001, 1] m"},
                         Bound{&a.motor_time_constant, 0.0, 1.0, "motor_time_constant must lie in [0, 1] s"}})
    if (!(b.range->lo >= b.lo && b.range->hi <= b.hi)) return b.text;
  if (!validInterval(a.idle_fraction) || !(a.idle_fraction.hi < a.hover_fraction.lo))
    return "idle_fraction must be 0 <= lo <= hi < hover_fraction's lo";
  if (!validInterval(a.motor_time_constant)) return "motor_time_constant needs 0 <= lo <= hi";
  return {};
}

std::vector<VehicleParams> drawAirframes(const AirframeRanges& a) {
  std::vector<VehicleParams> out;
  out.reserve(static_cast<std::size_t>(std::max(0, a.count)));
  Rng rng(a.seed, 0);
  for (int i = 0; i < a.count; ++i) {
    VehicleParams p;
    p.gravity = 9.81;  // [m/s²] as the vehicle files' default (io/vehicle_file.cpp)
    p.mass = drawLog(a.mass, rng);
    const double reach = draw(a.size_factor, rng) * std::cbrt(p.mass);  // [m] rotor distance from the centre
    const double aspect = drawLog(a.aspect, rng);
    p.rotor_x = reach * aspect / std::hypot(1.0, aspect);
    p.rotor_y = reach / std::hypot(1.0, aspect);
    p.arm_length = reach;
    p.inertia_xx = draw(a.inertia_factor, rng) * p.mass * p.rotor_y * p.rotor_y;
    p.inertia_yy = draw(a.inertia_factor, rng) * p.mass * p.rotor_x * p.rotor_x;
    p.inertia_zz = draw(a.yaw_inertia_ratio, rng) * (p.inertia_xx + p.inertia_yy);
    p.max_thrust = p.hoverThrust() / draw(a.hover_fraction, rng);
    p.min_thrust = draw(a.idle_fraction, rng) * p.max_thrust;
    p.yaw_moment_coeff = drawLog(a.yaw_moment_coeff, rng);
    p.motor_time_constant = draw(a.motor_time_constant, rng);
    // C_T, C_D only feed yawCoeff() when yaw_moment_coeff is 0: keep their ratio consistent anyway.
    p.drag_coeff = p.thrust_coeff * p.yaw_moment_coeff;
    out.push_back(p);
  }
  return out;
}

std::vector<VehicleParams> describedVehicles(const Randomisation& r) {
  std::vector<VehicleParams> all = r.vehicles;
  const std::vector<VehicleParams> synthetic = drawAirframes(r.airframes);
  all.insert(all.end(), synthetic.begin(), synthetic.end());
  return all;
}

std::string describedVehicleName(const Randomisation& r, std::size_t index) {
  if (index < r.vehicle_names.size()) return r.vehicle_names[index];
  return "airframe-" + std::to_string(index - r.vehicle_names.size() + 1);
}

FlightDraw drawFlight(const Randomisation& r, double dt, Rng& rng) { return drawFlight(r, describedVehicles(r), dt, rng); }

FlightDraw drawFlight(const Randomisation& r, const std::vector<VehicleParams>& described, double dt, Rng& rng) {
  FlightDraw d;
  // A fixed number of draws in a fixed order, whatever the ranges, so that widening one range
  // does not reshuffle the others. Synthetic airframes take two draws (which kind, which one)
  // only when there are any, so that every earlier model's flights are unchanged.
  const std::size_t library = r.vehicles.size();
  if (r.airframes.enabled()) {
    const bool synthetic = rng.uniform() < r.airframes.share;
    const std::uint64_t pick_one = rng.next();
    d.vehicle = static_cast<int>(synthetic ? library + pick_one % static_cast<std::uint64_t>(r.airframes.count)
                                           : pick_one % library);
  } else {
    d.vehicle = static_cast<int>(rng.next() % library);
  }
  VehicleParams& p = d.plant;
  p = described.at(static_cast<std::size_t>(d.vehicle));
  p.mass *= draw(r.parameters.mass, rng);
  p.inertia_xx *= draw(r.parameters.inertia, rng);
  p.inertia_yy *= draw(r.parameters.inertia, rng);
  p.inertia_zz *= draw(r.parameters.inertia, rng);
  d.thrust_gain = draw(r.parameters.thrust, rng);
  const double yaw = draw(r.parameters.yaw_moment, rng);
  p.yaw_moment_coeff = p.yawCoeff() * yaw;
  const double tau = draw(r.parameters.motor_time_constant, rng);
  if (r.parameters.motor_time_constant.hi > 0.0) p.motor_time_constant = tau;

  const SensorRanges& s = r.sensors;
  d.sensors.position_std = draw(s.position_std, rng);
  d.sensors.velocity_std = draw(s.velocity_std, rng);
  d.sensors.attitude_std = draw(s.attitude_std, rng);
  d.sensors.rate_std = draw(s.rate_std, rng);
  d.sensors.attitude_filter_tau = draw(s.attitude_filter_tau, rng);
  d.sensors.rate_filter_tau = draw(s.rate_filter_tau, rng);
  d.sensors.delay_steps = static_cast<int>(rng.next() % static_cast<std::uint64_t>(s.delay_steps_max + 1));
  d.sensors.estimate_error_tau = draw(s.estimate_error_tau, rng);

  const ControllerMix& c = r.controllers;
  // One uniform draw whatever the weights: a zero weight added at the end changes no flight.
  const double controller_weights[4] = {c.lqr, c.pid, c.cbf, c.geometric};
  d.controller = static_cast<DrawnController>(pick(controller_weights, rng));
  // Gains spread log-uniformly: ×2 and ×½ are equally likely departures.
  d.gain_scale = std::exp(draw({std::log(c.gain_scale.lo), std::log(c.gain_scale.hi)}, rng));

  const ManoeuvreMix& m = r.manoeuvres;
  const double manoeuvre_weights[4] = {m.hover, m.point_to_point, m.circle, m.figure_eight};
  ManoeuvreDraw& md = d.manoeuvre;
  md.kind = static_cast<ManoeuvreKind>(pick(manoeuvre_weights, rng));
  md.speed = draw(m.speed, rng);
  md.size = draw(m.size, rng);
  md.direction = rng.uniform(-M_PI, M_PI);
  if (md.kind == ManoeuvreKind::kHover) {
    md.speed = 0.0;
  } else if (md.kind != ManoeuvreKind::kPointToPoint) {
    // A circle's acceleration is v²/r; the 1:2 Lissajous figure-eight of half-length a and peak
    // speed v (control/reference.h) peaks at √5·a·ω² = (√5/2)·v²/a ≈ 1.12·v²/a.
    const double accel_per_v2_over_size = md.kind == ManoeuvreKind::kCircle ? 1.0 : 0.5 * std::sqrt(5.0);
    md.size = std::max(md.size, accel_per_v2_over_size * md.speed * md.speed / m.max_lateral_accel);
  }
  d.preroll_steps = static_cast<int>(std::lround(draw(r.preroll_seconds, rng) / dt));

  // The wind's draws come last and only with drag, so that every draw above (and every model
  // trained before wind existed) is unchanged.
  const WindRanges& w = r.wind;
  if (w.enabled()) {
    p.linear_drag = draw(w.rotor_drag, rng) * p.mass;
    d.wind.mean_speed = draw(w.mean_speed, rng);
    d.wind.mean_direction = rng.uniform(-M_PI, M_PI);
    d.wind.turbulence_std = draw(w.turbulence_std, rng);
    d.wind.turbulence_tau = draw(w.turbulence_tau, rng);
    d.wind.gust_rate = draw(w.gust_rate, rng);
    d.wind.gust_peak = draw(w.gust_peak, rng);
    d.wind.gust_duration = draw(w.gust_duration, rng);
  }
  // The heading's draws come after the wind's and only when asked for, for the same reason.
  if (m.headingEnabled()) {
    md.facing_velocity = md.kind != ManoeuvreKind::kHover && rng.uniform(0.0, 1.0) < m.facing_velocity;
    // Not a draw: the limit changes no flight's draws, only how a nose-first circle's heading turns.
    if (md.facing_velocity && md.kind == ManoeuvreKind::kCircle) md.facing_yaw_rate_max = m.facing_velocity_yaw_rate_max;
    const bool sweep = rng.uniform(0.0, 1.0) < m.yaw_sweep;
    const double amplitude = draw(m.yaw_sweep_amplitude, rng), period = draw(m.yaw_sweep_period, rng);
    if (sweep) {
      md.yaw_sweep_amplitude = amplitude;
      md.yaw_sweep_period = period;
    }
  }
  return d;
}

}  // namespace quadfdi
