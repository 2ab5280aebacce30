#include <gtest/gtest.h>

#include "config_refusal.h"
#include "io/controller_config.h"
#include "io/key_value.h"

namespace quadfdi {
namespace {

std::string errorOf(const std::string& text) {
  return test::configRefusal([&] { controllerConfigFromText(text, "c.toml", ControllerConfig{}); });
}

TEST(ControllerConfig, PresetThenOverridesAndCbfValues) {
  const ControllerConfig c = controllerConfigFromText(
      "controller = \"cbf\"\n[lqr]\nr_diag = [1, 1, 1, 1]\nweights = \"authors\"\n[cbf]\nmax_tilt = 0.4\ntilt_limit = false\n",
      "c.toml", ControllerConfig{});
  EXPECT_EQ(c.kind, ControllerKind::kCbfQp);
  EXPECT_EQ(c.lqr.discretization, Discretization::kForwardEuler);  // from the preset
  EXPECT_EQ(c.lqr.q_diag, StateWeights::Ones());
  EXPECT_EQ(c.cbf.max_tilt, 0.4);
  EXPECT_FALSE(c.cbf.tilt_limit_enabled);
  EXPECT_TRUE(c.cbf.altitude_floor_enabled);
}

TEST(ControllerConfig, ShippedExampleEqualsTheDefaults) {
  const ControllerConfig c = loadControllerConfig(std::string(QUADFDI_SOURCE_DIR) + "/configs/controller-example.toml",
                                                  ControllerConfig{});
  const ControllerConfig d;
  EXPECT_LT((c.lqr.q_diag - d.lqr.q_diag).cwiseQuotient(d.lqr.q_diag).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_EQ(c.lqr.r_diag, d.lqr.r_diag);
  EXPECT_EQ(c.cbf.tilt_alpha1, d.cbf.tilt_alpha1);
  EXPECT_EQ(c.cbf.min_altitude, d.cbf.min_altitude);
  EXPECT_EQ(c.pid.position_divisor, d.pid.position_divisor);
  EXPECT_EQ(c.pid.velocity_gain_xy, d.pid.velocity_gain_xy);
  EXPECT_EQ(c.pid.rate_gain_rp, d.pid.rate_gain_rp);
  EXPECT_EQ(c.pid.max_tilt, d.pid.max_tilt);
  EXPECT_EQ(c.pid.rate_integral_limit, d.pid.rate_integral_limit);
  EXPECT_EQ(c.pid.velocity_derivative_cutoff, d.pid.velocity_derivative_cutoff);
  EXPECT_EQ(c.geometric.position_divisor, d.geometric.position_divisor);
  EXPECT_EQ(c.geometric.position_frequency_xy, d.geometric.position_frequency_xy);
  EXPECT_EQ(c.geometric.position_integral, d.geometric.position_integral);
  EXPECT_EQ(c.geometric.attitude_frequency_rp, d.geometric.attitude_frequency_rp);
  EXPECT_EQ(c.geometric.attitude_integral_rp, d.geometric.attitude_integral_rp);
  EXPECT_EQ(c.geometric.attitude_integral_yaw, d.geometric.attitude_integral_yaw);
  EXPECT_EQ(c.geometric.attitude_integral_limit, d.geometric.attitude_integral_limit);
}

TEST(ControllerConfig, PidKeys) {
  const ControllerConfig c = controllerConfigFromText(
      "controller = \"pid\"\n[pid]\nrate_divisor = 2\nattitude_divisor = 4\nrate_gain_rp = 40\nyaw_weight = 0.5\n"
      "velocity_derivative_cutoff = 0\n",
      "c.toml", ControllerConfig{});
  EXPECT_EQ(c.kind, ControllerKind::kPid);
  EXPECT_EQ(c.pid.rate_divisor, 2);
  EXPECT_EQ(c.pid.attitude_divisor, 4);
  EXPECT_EQ(c.pid.rate_gain_rp, 40.0);
  EXPECT_EQ(c.pid.yaw_weight, 0.5);
  EXPECT_EQ(c.pid.velocity_derivative_cutoff, 0.0);  // 0: the filter off
  EXPECT_EQ(c.pid.position_gain_xy, PidConfig{}.position_gain_xy);
}

TEST(ControllerConfig, GeometricKeys) {
  const ControllerConfig c = controllerConfigFromText(
      "controller = \"geometric\"\n[geometric]\nposition_divisor = 5\nattitude_frequency_rp = 12\n"
      "attitude_integral_yaw = 0\nmax_tilt = 0.5\n",
      "c.toml", ControllerConfig{});
  EXPECT_EQ(c.kind, ControllerKind::kGeometric);
  EXPECT_EQ(c.geometric.position_divisor, 5);
  EXPECT_EQ(c.geometric.attitude_frequency_rp, 12.0);
  EXPECT_EQ(c.geometric.attitude_integral_yaw, 0.0);
  EXPECT_EQ(c.geometric.max_tilt, 0.5);
  EXPECT_EQ(c.geometric.position_frequency_xy, GeometricConfig{}.position_frequency_xy);
  EXPECT_EQ(c.pid.rate_gain_rp, PidConfig{}.rate_gain_rp);  // the PID's section untouched
}

TEST(ControllerConfig, BadValuesNameFileAndLine) {
  EXPECT_EQ(errorOf("[lqr]\nq_diag = [1, 2]\n"), "c.toml:2: lqr.q_diag needs 12 values (state.h order), got 2");
  EXPECT_EQ(errorOf("[lqr]\nr_diag = [1, 0, 1, 1]\n"), "c.toml:2: lqr.r_diag values must be > 0");
  EXPECT_EQ(errorOf("[cbf]\nmax_tilt = 2\n"), "c.toml:2: cbf.max_tilt must be in (0, 1.5) rad");
  EXPECT_EQ(errorOf("[cbf]\ntilt_alpha1 = -1\n"), "c.toml:2: 'cbf.tilt_alpha1' must be > 0");
  EXPECT_EQ(errorOf("\n[lqr]\nweights = \"fast\"\n"), "c.toml:3: lqr.weights must be \"bryson\" or \"authors\", got 'fast'");
  EXPECT_EQ(errorOf("gains = 3\n"), "c.toml:1: unknown key 'gains'");
  EXPECT_EQ(errorOf("[pid]\n\nrate_divisor = 0\n"), "c.toml:3: 'pid.rate_divisor' must be an integer in 1 … 1000 (steps)");
  EXPECT_EQ(errorOf("[pid]\nyaw_weight = 2\n"), "c.toml:2: PID yaw_weight must lie in (0, 1]");
  EXPECT_EQ(errorOf("[pid]\nrate_gain_rp = -3\n"), "c.toml:2: PID gains and limits must be finite and >= 0");
  EXPECT_EQ(errorOf("[pid]\nvelocity_derivative_cutoff = -5\n"), "c.toml:2: PID gains and limits must be finite and >= 0");
  EXPECT_EQ(errorOf("[pid]\nrate_gain = 3\n"), "c.toml:2: unknown key 'pid.rate_gain'");
  EXPECT_EQ(errorOf("controller = \"mpc\"\n"),
            "c.toml:1: controller must be \"lqr\", \"cbf\", \"pid\" or \"geometric\", got 'mpc'");
  EXPECT_EQ(errorOf("[geometric]\nattitude_damping_rp = 0\n"),
            "c.toml:2: geometric frequencies and damping ratios must be finite and > 0");
  EXPECT_EQ(errorOf("[geometric]\n\nposition_divisor = 0\n"),
            "c.toml:3: 'geometric.position_divisor' must be an integer in 1 … 1000 (steps)");
  EXPECT_EQ(errorOf("[geometric]\nattitude_integral_limit = 2\n"),
            "c.toml:2: geometric attitude_integral_limit must lie in [0, 1]");
  EXPECT_EQ(errorOf("[geometric]\nrate_gain_rp = 30\n"), "c.toml:2: unknown key 'geometric.rate_gain_rp'");
}

}  // namespace
}  // namespace quadfdi
