#include <gtest/gtest.h>

#include <cmath>

#include "data/randomisation.h"

namespace quadfdi {
namespace {

Randomisation twoVehicles() {
  Randomisation r;
  r.vehicles = {nominalParams(), perturbedParams()};
  r.vehicle_names = {"nominal", "perturbed"};
  r.parameters.mass = {0.85, 1.15};
  r.parameters.inertia = {0.8, 1.2};
  r.parameters.thrust = {0.9, 1.1};
  r.parameters.motor_time_constant = {0.01, 0.05};
  r.sensors.position_std = {0.0, 0.005};
  r.sensors.rate_filter_tau = {0.002, 0.008};
  r.sensors.delay_steps_max = 5;
  r.manoeuvres = {0.4, 0.3, 0.3, 0.0, {0.3, 2.0}, {0.5, 2.0}, 4.9};
  r.controllers = {0.35, 0.45, 0.2, {0.7, 1.4}};
  r.preroll_seconds = {0.2, 2.0};
  return r;
}

AirframeRanges someAirframes() {
  AirframeRanges a;
  a.count = 12;
  a.seed = 9;
  return a;
}

TEST(Airframes, ArePureFunctionsOfTheirSeedAndRanges) {
  const AirframeRanges a = someAirframes();
  AirframeRanges b = a;
  const std::vector<VehicleParams> x = drawAirframes(a), y = drawAirframes(a);
  ASSERT_EQ(x.size(), 12u);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_EQ(x[i].mass, y[i].mass);
  b.seed = 10;
  EXPECT_NE(drawAirframes(b)[0].mass, x[0].mass);
  b = a;
  b.count = 0;
  EXPECT_TRUE(drawAirframes(b).empty());
}

// Each airframe is a valid symmetric X whose derived quantities lie in the stated ranges.
TEST(Airframes, StayInsideTheirScalingRanges) {
  AirframeRanges a = someAirframes();
  a.count = 200;
  for (const VehicleParams& p : drawAirframes(a)) {
    ASSERT_EQ(validate(p), "");
    EXPECT_GE(p.mass, a.mass.lo);
    EXPECT_LE(p.mass, a.mass.hi);
    const double reach = std::hypot(p.rotor_x, p.rotor_y) / std::cbrt(p.mass);
    EXPECT_GE(reach, a.size_factor.lo - 1e-12);
    EXPECT_LE(reach, a.size_factor.hi + 1e-12);
    EXPECT_GE(p.rotor_x / p.rotor_y, a.aspect.lo - 1e-12);
    EXPECT_LE(p.rotor_x / p.rotor_y, a.aspect.hi + 1e-12);
    for (double f : {p.inertia_xx / (p.mass * p.rotor_y * p.rotor_y), p.inertia_yy / (p.mass * p.rotor_x * p.rotor_x)}) {
      EXPECT_GE(f, a.inertia_factor.lo - 1e-12);
      EXPECT_LE(f, a.inertia_factor.hi + 1e-12);
    }
    const double zz = p.inertia_zz / (p.inertia_xx + p.inertia_yy);
    EXPECT_GE(zz, a.yaw_inertia_ratio.lo - 1e-12);
    EXPECT_LE(zz, a.yaw_inertia_ratio.hi + 1e-12);
    const double hover = p.hoverThrust() / p.max_thrust;
    EXPECT_GE(hover, a.hover_fraction.lo - 1e-12);
    EXPECT_LE(hover, a.hover_fraction.hi + 1e-12);
    EXPECT_LE(p.min_thrust, a.idle_fraction.hi * p.max_thrust + 1e-12);
    EXPECT_GE(p.yawCoeff(), a.yaw_moment_coeff.lo - 1e-12);
    EXPECT_LE(p.yawCoeff(), a.yaw_moment_coeff.hi + 1e-12);
  }
}

TEST(Airframes, FlightsFlyThemAtTheirShareAndLeaveOtherDrawsAlone) {
  Randomisation r = twoVehicles();
  const Randomisation without = r;
  r.airframes = someAirframes();
  r.airframes.share = 0.25;
  ASSERT_EQ(validate(r), "");
  const std::vector<VehicleParams> described = describedVehicles(r);
  ASSERT_EQ(described.size(), 14u);
  std::vector<int> flown(described.size(), 0);
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    Rng rng(3, static_cast<std::uint64_t>(i));
    const FlightDraw d = drawFlight(r, described, 0.002, rng);
    ++flown[static_cast<std::size_t>(d.vehicle)];
    // The plant is drawn around the airframe it flies.
    const VehicleParams& base = described[static_cast<std::size_t>(d.vehicle)];
    EXPECT_GE(d.plant.mass, 0.85 * base.mass - 1e-12);
    EXPECT_LE(d.plant.mass, 1.15 * base.mass + 1e-12);
  }
  int synthetic = 0;
  for (std::size_t v = 2; v < flown.size(); ++v) {
    EXPECT_GT(flown[v], 0) << describedVehicleName(r, v);
    synthetic += flown[v];
  }
  EXPECT_NEAR(synthetic / double(n), 0.25, 0.015);
  // Without airframes a draw takes the stream it always took.
  Rng a(5, 11), b(5, 11);
  const FlightDraw plain = drawFlight(without, 0.002, a);
  EXPECT_EQ(plain.vehicle, static_cast<int>(Rng(5, 11).next() % 2));
  EXPECT_EQ(plain.plant.mass, drawFlight(without, describedVehicles(without), 0.002, b).plant.mass);
}

TEST(Randomisation, DrawsArePureFunctionsOfTheStream) {
  const Randomisation r = twoVehicles();
  ASSERT_EQ(validate(r), "");
  Rng a(5, 11), b(5, 11), c(5, 12);
  const FlightDraw da = drawFlight(r, 0.002, a), db = drawFlight(r, 0.002, b), dc = drawFlight(r, 0.002, c);
  EXPECT_EQ(da.plant.mass, db.plant.mass);
  EXPECT_EQ(da.sensors.position_std, db.sensors.position_std);
  EXPECT_EQ(da.manoeuvre.speed, db.manoeuvre.speed);
  EXPECT_EQ(da.preroll_steps, db.preroll_steps);
  EXPECT_NE(da.plant.mass, dc.plant.mass);
}

TEST(Randomisation, DrawsStayInsideTheirRangesAndFollowTheWeights) {
  const Randomisation r = twoVehicles();
  int counts[4] = {0, 0, 0, 0}, manoeuvres[4] = {0, 0, 0, 0}, vehicles[2] = {0, 0};
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    Rng rng(1, static_cast<std::uint64_t>(i));
    const FlightDraw d = drawFlight(r, 0.002, rng);
    const VehicleParams& described = r.vehicles[static_cast<std::size_t>(d.vehicle)];
    ASSERT_GE(d.plant.mass, described.mass * 0.85 - 1e-15);
    ASSERT_LE(d.plant.mass, described.mass * 1.15 + 1e-15);
    ASSERT_GE(d.plant.inertia_zz, described.inertia_zz * 0.8 - 1e-15);
    ASSERT_LE(d.plant.inertia_zz, described.inertia_zz * 1.2 + 1e-15);
    ASSERT_GE(d.thrust_gain, 0.9);
    ASSERT_LE(d.thrust_gain, 1.1);
    ASSERT_GE(d.plant.motor_time_constant, 0.01);
    ASSERT_LE(d.plant.motor_time_constant, 0.05);
    ASSERT_GE(d.sensors.rate_filter_tau, 0.002);
    ASSERT_LE(d.sensors.delay_steps, 5);
    ASSERT_GE(d.gain_scale, 0.7 - 1e-12);
    ASSERT_LE(d.gain_scale, 1.4 + 1e-12);
    ASSERT_GE(d.preroll_steps, 100);
    ASSERT_LE(d.preroll_steps, 1000);
    if (d.manoeuvre.kind == ManoeuvreKind::kCircle) {  // widened until v²/r ≤ the lateral acceleration bound
      ASSERT_LE(d.manoeuvre.speed * d.manoeuvre.speed / d.manoeuvre.size, 4.9 + 1e-9);
    }
    ++counts[static_cast<int>(d.controller)];
    ++manoeuvres[static_cast<int>(d.manoeuvre.kind)];
    ++vehicles[d.vehicle];
  }
  EXPECT_NEAR(counts[0] / double(n), 0.35, 0.015);
  EXPECT_NEAR(counts[1] / double(n), 0.45, 0.015);
  EXPECT_NEAR(counts[2] / double(n), 0.20, 0.015);
  EXPECT_EQ(counts[3], 0);      // the geometric controller's weight is 0: never drawn
  EXPECT_EQ(manoeuvres[3], 0);  // weight 0: never drawn
  EXPECT_NEAR(manoeuvres[0] / double(n), 0.4, 0.015);
  EXPECT_NEAR(vehicles[0] / double(n), 0.5, 0.015);
}

TEST(Randomisation, ZeroSpreadsGiveTheDescribedVehicleExactly) {
  Randomisation r;
  r.vehicles = {nominalParams()};
  r.vehicle_names = {"nominal"};
  Rng rng(3, 4);
  const FlightDraw d = drawFlight(r, 0.002, rng);
  EXPECT_EQ(d.plant.mass, nominalParams().mass);
  EXPECT_EQ(d.plant.inertia_xx, nominalParams().inertia_xx);
  EXPECT_EQ(d.plant.motor_time_constant, nominalParams().motor_time_constant);
  EXPECT_EQ(d.thrust_gain, 1.0);
  EXPECT_FALSE(d.sensors.active());
  EXPECT_EQ(d.controller, DrawnController::kLqr);
  EXPECT_EQ(d.manoeuvre.kind, ManoeuvreKind::kHover);
  EXPECT_EQ(d.preroll_steps, 0);
}

TEST(Randomisation, ValidateNamesTheProblem) {
  Randomisation r = twoVehicles();
  r.controllers = {0.0, 0.0, 0.0, {1.0, 1.0}};
  EXPECT_NE(validate(r).find("controller weight"), std::string::npos);
  r = twoVehicles();
  r.sensors.attitude_std = {0.01, 0.0};
  EXPECT_NE(validate(r).find("sensor ranges"), std::string::npos);
  r = twoVehicles();
  r.parameters.mass = {1.2, 1.1};
  EXPECT_NE(validate(r).find("parameter factors"), std::string::npos);
}

TEST(Randomisation, WindIsDrawnLastSoEveryOtherDrawIsUnchanged) {
  const Randomisation still = twoVehicles();
  Randomisation windy = still;
  windy.wind.rotor_drag = {0.15, 0.35};
  windy.wind.mean_speed = {0.0, 5.0};
  windy.wind.turbulence_std = {0.0, 1.5};
  windy.wind.turbulence_tau = {0.5, 5.0};
  windy.wind.gust_rate = {0.0, 0.1};
  windy.wind.gust_peak = {0.0, 3.0};
  windy.wind.gust_duration = {0.5, 2.0};
  ASSERT_EQ(validate(windy), "");
  for (int i = 0; i < 200; ++i) {
    Rng a(9, static_cast<std::uint64_t>(i)), b(9, static_cast<std::uint64_t>(i));
    const FlightDraw ds = drawFlight(still, 0.002, a), dw = drawFlight(windy, 0.002, b);
    ASSERT_EQ(ds.vehicle, dw.vehicle);
    ASSERT_EQ(ds.plant.mass, dw.plant.mass);
    ASSERT_EQ(ds.plant.inertia_yy, dw.plant.inertia_yy);
    ASSERT_EQ(ds.sensors.attitude_std, dw.sensors.attitude_std);
    ASSERT_EQ(ds.controller, dw.controller);
    ASSERT_EQ(ds.manoeuvre.size, dw.manoeuvre.size);
    ASSERT_EQ(ds.preroll_steps, dw.preroll_steps);
    EXPECT_FALSE(ds.wind.active());
    EXPECT_EQ(ds.plant.linear_drag, 0.0);
    // The drag is per unit of the drawn mass.
    ASSERT_GE(dw.plant.linear_drag, 0.15 * dw.plant.mass * (1 - 1e-12));
    ASSERT_LE(dw.plant.linear_drag, 0.35 * dw.plant.mass * (1 + 1e-12));
    ASSERT_LE(dw.wind.mean_speed, 5.0);
    ASSERT_GE(dw.wind.turbulence_tau, 0.5);
    ASSERT_LE(dw.wind.gust_duration, 2.0);
    ASSERT_EQ(validate(dw.wind), "");
  }
}

// The heading's draws come after the wind's: asking for them changes no other draw; hover never
// faces its (zero) velocity; the shares and ranges are kept.
TEST(Randomisation, HeadingIsDrawnLastSoEveryOtherDrawIsUnchanged) {
  Randomisation fixed = twoVehicles();
  fixed.manoeuvres.hover = fixed.manoeuvres.point_to_point = fixed.manoeuvres.circle = 1.0;
  fixed.wind.rotor_drag = {0.15, 0.35};
  fixed.wind.mean_speed = {0.0, 5.0};
  Randomisation turning = fixed;
  turning.manoeuvres.facing_velocity = 0.5;
  turning.manoeuvres.yaw_sweep = 0.3;
  turning.manoeuvres.yaw_sweep_amplitude = {0.2, 1.2};
  turning.manoeuvres.yaw_sweep_period = {3.0, 10.0};
  turning.manoeuvres.facing_velocity_yaw_rate_max = 1.0;
  ASSERT_EQ(validate(turning), "");
  int moving = 0, facing = 0, swept = 0, slewed = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    Rng a(9, static_cast<std::uint64_t>(i)), b(9, static_cast<std::uint64_t>(i));
    const FlightDraw df = drawFlight(fixed, 0.002, a), dt = drawFlight(turning, 0.002, b);
    ASSERT_EQ(df.plant.mass, dt.plant.mass);
    ASSERT_EQ(df.controller, dt.controller);
    ASSERT_EQ(df.manoeuvre.kind, dt.manoeuvre.kind);
    ASSERT_EQ(df.manoeuvre.size, dt.manoeuvre.size);
    ASSERT_EQ(df.manoeuvre.direction, dt.manoeuvre.direction);
    ASSERT_EQ(df.wind.mean_speed, dt.wind.mean_speed);
    ASSERT_EQ(df.preroll_steps, dt.preroll_steps);
    EXPECT_FALSE(df.manoeuvre.facing_velocity);
    EXPECT_EQ(df.manoeuvre.yaw_sweep_amplitude, 0.0);
    if (dt.manoeuvre.kind == ManoeuvreKind::kHover) EXPECT_FALSE(dt.manoeuvre.facing_velocity);
    else ++moving;
    facing += dt.manoeuvre.facing_velocity;
    // The slew limit is no draw: it rides on nose-first circles alone.
    const bool nose_first_circle = dt.manoeuvre.facing_velocity && dt.manoeuvre.kind == ManoeuvreKind::kCircle;
    EXPECT_EQ(dt.manoeuvre.facing_yaw_rate_max, nose_first_circle ? 1.0 : 0.0);
    EXPECT_EQ(df.manoeuvre.facing_yaw_rate_max, 0.0);
    slewed += nose_first_circle && dt.manoeuvre.speed > dt.manoeuvre.size;
    if (dt.manoeuvre.yaw_sweep_amplitude > 0.0) {
      ++swept;
      EXPECT_GE(dt.manoeuvre.yaw_sweep_amplitude, 0.2);
      EXPECT_LE(dt.manoeuvre.yaw_sweep_amplitude, 1.2);
      EXPECT_GE(dt.manoeuvre.yaw_sweep_period, 3.0);
      EXPECT_LE(dt.manoeuvre.yaw_sweep_period, 10.0);
    }
  }
  // Binomial: 4σ bands around the shares.
  EXPECT_NEAR(facing, 0.5 * moving, 4.0 * std::sqrt(0.25 * moving));
  EXPECT_NEAR(swept, 0.3 * n, 4.0 * std::sqrt(0.21 * n));
  EXPECT_GT(slewed, 0);  // some circles turn faster than the limit
  turning.manoeuvres.facing_velocity_yaw_rate_max = -1.0;
  EXPECT_NE(validate(turning).find("facing_velocity_yaw_rate_max"), std::string::npos);
  turning.manoeuvres.facing_velocity_yaw_rate_max = 1.0;
  turning.manoeuvres.yaw_sweep = 1.5;
  EXPECT_NE(validate(turning).find("shares in [0, 1]"), std::string::npos);
  turning.manoeuvres.yaw_sweep = 0.3;
  turning.manoeuvres.yaw_sweep_period = {0.0, 2.0};
  EXPECT_NE(validate(turning).find("yaw_sweep_period"), std::string::npos);
}

TEST(Randomisation, WindWithoutDragIsRefused) {
  Randomisation r = twoVehicles();
  r.wind.mean_speed = {1.0, 3.0};
  EXPECT_NE(validate(r).find("rotor drag"), std::string::npos);
  r.wind.rotor_drag = {0.2, 0.3};
  EXPECT_EQ(validate(r), "");
  r.wind.turbulence_tau = {0.0, 1.0};
  EXPECT_NE(validate(r).find("turbulence_tau"), std::string::npos);
}

}  // namespace
}  // namespace quadfdi
