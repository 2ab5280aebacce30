#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "model/integrator.h"
#include "simulation/wind.h"

namespace quadfdi {
namespace {

TEST(Wind, StillAirIsZeroAndMovesNothing) {
  WindModel wind(WindConfig{}, 0.002);
  Rng rng(1, 2);
  wind.reset(rng);
  for (int k = 0; k < 1000; ++k) ASSERT_EQ(wind.step(rng), Vec3::Zero());

  // With drag, a zero wind vector and no wind at all step the plant bit for bit alike.
  VehicleParams p = nominalParams();
  p.linear_drag = 0.3 * p.mass;
  const RigidBodyModel model = RigidBodyModel::fromParams(p);
  PlantState a, b;
  a.x << 0.1, -0.2, 1.0, 0.5, -0.3, 0.1, 0.05, -0.04, 0.3, 0.2, -0.1, 0.05;
  b.x = a.x;
  a.rotor_thrust = b.rotor_thrust = Input::Constant(p.hoverThrust());
  const Vec3 zero = Vec3::Zero();
  for (int k = 0; k < 200; ++k) {
    const Input u = Input::Constant(p.hoverThrust() * (1.0 + 0.01 * std::sin(0.1 * k)));
    stepPlant(model, Integrator::kRk4, 0.002, 0.02, u, a);
    stepPlant(model, Integrator::kRk4, 0.002, 0.02, u, b, &zero);
  }
  for (int i = 0; i < kStateDim; ++i) EXPECT_EQ(a.x(i), b.x(i)) << i;
}

TEST(Wind, ALevelHoveringBodyDriftsWithASteadyWind) {
  // Thrust balances gravity and attitude stays level, so the only horizontal force is the drag
  // −c(v − w): the body's velocity relaxes to the wind's with time constant m/c.
  VehicleParams p = nominalParams();
  p.linear_drag = 0.25 * p.mass;  // m/c = 4 s
  const RigidBodyModel model = RigidBodyModel::fromParams(p);
  const Vec3 wind(3.0, -1.5, 0.0);
  PlantState plant;
  plant.x(idx::kPz) = 1.0;
  plant.x(idx::kYaw) = 0.7;  // the drag acts in the body frame: heading must not matter
  plant.rotor_thrust = Input::Constant(p.hoverThrust());
  const double dt = 0.002;
  std::vector<double> speeds;
  for (int k = 0; k < static_cast<int>(40.0 / dt); ++k) {
    stepPlant(model, Integrator::kRk4, dt, 0.0, Input::Constant(p.hoverThrust()), plant, &wind);
    if (k + 1 == static_cast<int>(4.0 / dt)) {
      const Vec3 v_world = rotationBodyToWorld(0.0, 0.0, 0.7) * plant.x.segment<3>(idx::kVel);
      EXPECT_NEAR(v_world.x(), 3.0 * (1.0 - std::exp(-1.0)), 1e-6);  // one time constant
      EXPECT_NEAR(v_world.y(), -1.5 * (1.0 - std::exp(-1.0)), 1e-6);
    }
  }
  const Vec3 v_world = rotationBodyToWorld(0.0, 0.0, 0.7) * plant.x.segment<3>(idx::kVel);
  EXPECT_NEAR(v_world.x(), 3.0, 3.0 * std::exp(-10.0) + 1e-9);
  EXPECT_NEAR(v_world.y(), -1.5, 1.5 * std::exp(-10.0) + 1e-9);
  EXPECT_NEAR(v_world.z(), 0.0, 1e-9);
  EXPECT_NEAR(plant.x(idx::kRoll), 0.0, 1e-12);
  EXPECT_NEAR(plant.x(idx::kPitch), 0.0, 1e-12);
}

TEST(Wind, TurbulenceHasItsStatedStdAndCorrelationTime) {
  WindConfig c;
  c.turbulence_std = 1.2;
  c.turbulence_tau = 0.2;
  const double dt = 0.002;
  WindModel wind(c, dt);
  Rng rng(7, 3);
  wind.reset(rng);
  const int n = 500000;  // 1000 s, 5000 correlation times
  const int lag = static_cast<int>(c.turbulence_tau / dt);
  std::vector<Vec3> w(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) w[static_cast<std::size_t>(k)] = wind.step(rng);
  for (int axis = 0; axis < 3; ++axis) {
    double sum = 0.0, sq = 0.0, cross = 0.0;
    for (int k = 0; k < n; ++k) {
      const double x = w[static_cast<std::size_t>(k)](axis);
      sum += x;
      sq += x * x;
      if (k >= lag) cross += x * w[static_cast<std::size_t>(k - lag)](axis);
    }
    const double var = sq / n - (sum / n) * (sum / n);
    const double expected_std = axis < 2 ? c.turbulence_std : kVerticalTurbulenceRatio * c.turbulence_std;
    EXPECT_NEAR(std::sqrt(var), expected_std, 0.05 * expected_std) << axis;
    EXPECT_NEAR(cross / (n - lag) / var, std::exp(-1.0), 0.05) << axis;  // ρ(τ) = e^{−1}
    EXPECT_NEAR(sum / n, 0.0, 0.1 * expected_std) << axis;
  }
}

TEST(Wind, AGustIsOneHorizontalOneMinusCosineOnTopOfTheMeanWind) {
  WindConfig c;
  c.mean_speed = 2.0;
  c.mean_direction = 0.5 * M_PI;  // toward +y
  c.gust_rate = 1e6;              // one starts at the first step
  c.gust_peak = 4.0;
  c.gust_duration = 0.5;
  const double dt = 0.002;
  WindModel wind(c, dt);
  Rng rng(3, 9);
  wind.reset(rng);
  EXPECT_NEAR(wind.velocity().y(), 2.0, 1e-12);
  const int steps = static_cast<int>(std::lround(c.gust_duration / dt));
  std::vector<Vec3> gusts;
  for (int k = 0; k < steps; ++k) gusts.push_back(wind.step(rng) - Vec3(0.0, 2.0, 0.0));  // started at step 0
  int at_peak = 0;
  for (int k = 0; k < steps; ++k)
    if (gusts[static_cast<std::size_t>(k)].norm() > gusts[static_cast<std::size_t>(at_peak)].norm()) at_peak = k;
  EXPECT_EQ(at_peak, steps / 2) << "the peak is at half the duration";
  const double peak = gusts[static_cast<std::size_t>(at_peak)].norm();
  const Vec3 direction = gusts[static_cast<std::size_t>(at_peak)] / peak;
  EXPECT_NEAR(direction.z(), 0.0, 1e-12);
  for (int k = 1; k < steps; ++k) {
    const Vec3& g = gusts[static_cast<std::size_t>(k)];
    ASSERT_NEAR(g.dot(direction), g.norm(), 1e-9) << k;  // one direction throughout
    const double expected = 0.5 * peak * (1.0 - std::cos(2.0 * M_PI * k * dt / c.gust_duration));
    ASSERT_NEAR(g.norm(), expected, 1e-9) << k;          // the 1 − cosine shape
  }
  EXPECT_GE(peak, 0.5 * c.gust_peak - 1e-9);
  EXPECT_LE(peak, c.gust_peak + 1e-9);
}

TEST(Wind, TheSameStreamGivesTheSameWindAndTheConfigIsChecked) {
  WindConfig c;
  c.mean_speed = 1.0;
  c.turbulence_std = 0.5;
  c.gust_rate = 0.5;
  c.gust_peak = 2.0;
  EXPECT_EQ(validate(c), "");
  WindModel a(c, 0.002), b(c, 0.002);
  Rng ra(4, 4), rb(4, 4);
  a.reset(ra);
  b.reset(rb);
  for (int k = 0; k < 5000; ++k) ASSERT_EQ(a.step(ra), b.step(rb));
  c.turbulence_tau = 0.0;
  EXPECT_NE(validate(c), "");
  c.turbulence_tau = 1.0;
  c.gust_peak = -1.0;
  EXPECT_NE(validate(c), "");
}

}  // namespace
}  // namespace quadfdi
