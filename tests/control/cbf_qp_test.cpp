#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "control/cbf_qp.h"
#include "test_support.h"

namespace quadfdi {
namespace {

// ḣ and ḧ = a·u + drift from computeCbfRows must match the dynamics: check them with
// finite differences of h along the true flow under a held input.
TEST(CbfQp, BarrierDerivativesMatchTheDynamics) {
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (const char* name : {"nominal", "perturbed"}) {
    VehicleParams p = namedParams(name);
    p.linear_drag = 2e-3;
    p.rotational_drag = 1e-7;
    const RigidBodyModel m = RigidBodyModel::fromParams(p);
    CbfConfig cfg;
    for (int trial = 0; trial < 100; ++trial) {
      State x = test::hoverState(Vec3(0, 0, 1));
      for (int i = idx::kVel; i < kStateDim; ++i) x(i) = (i == idx::kYaw ? 3.0 : 0.6) * d(gen);
      Input u;
      for (int j = 0; j < 4; ++j) u(j) = 0.04 + 0.03 * d(gen);
      CbfRows rows;
      computeCbfRows(m, cfg, x, rows);
      ASSERT_EQ(rows.count, 2);
      auto barriers = [&](const State& s) {
        const BarrierValues b = barrierValues(s, cfg);
        return Eigen::Vector2d(b.altitude, b.tilt);
      };
      auto flow = [&](double t) {
        PlantState ps;
        ps.x = x;
        const int n = 8;
        for (int k = 0; k < n; ++k) stepPlant(m, Integrator::kRk4, t / n, 0.0, u, ps);
        return ps.x;
      };
      // Central differences in time (RK4 with negative dt integrates backwards).
      // Step sizes balance truncation (the third derivative is large: torque/J ~ 1e2 rad/s²)
      // against round-off.
      const double dt1 = 1e-5, dt2 = 1e-4;
      const Eigen::Vector2d h0 = barriers(x);
      const Eigen::Vector2d hdot = (barriers(flow(dt1)) - barriers(flow(-dt1))) / (2 * dt1);
      const Eigen::Vector2d hddot = (barriers(flow(dt2)) - 2 * h0 + barriers(flow(-dt2))) / (dt2 * dt2);
      EXPECT_LT((rows.h - h0).cwiseAbs().maxCoeff(), 1e-15);
      EXPECT_NEAR(rows.hdot(0), hdot(0), 1e-7);
      EXPECT_NEAR(rows.hdot(1), hdot(1), 1e-7);
      const Eigen::Vector2d predicted = rows.a * u + rows.drift;
      EXPECT_NEAR(predicted(0), hddot(0), 1e-4 * (1 + std::abs(hddot(0))));
      EXPECT_NEAR(predicted(1), hddot(1), 1e-4 * (1 + std::abs(hddot(1))));
    }
  }
}

struct SafetyRecord {
  double min_altitude_h = 1e9;
  double min_tilt_h = 1e9;
  bool cut = false;
  int infeasible = 0;
  int filtered = 0;
};

SafetyRecord fly(const VehicleParams& p, ControllerKind kind, const Scenario& sc, const CbfConfig& cfg) {
  auto ctrl = test::makeOrDie(p, kind, cfg);
  ctrl->setGoal(sc.goal);
  SimulationSettings s;
  s.steps = 1000;
  FlightLog log;
  const FlightSummary sum = ClosedLoopSimulator(p, s).run(*ctrl, sc.initial_state, &log);
  SafetyRecord r;
  r.cut = sum.cut();
  r.infeasible = sum.infeasible_steps;
  r.filtered = sum.filtered_steps;
  for (const State& x : log.states) {
    const BarrierValues b = barrierValues(x, cfg);
    r.min_altitude_h = std::min(r.min_altitude_h, b.altitude);
    r.min_tilt_h = std::min(r.min_tilt_h, b.tilt);
  }
  return r;
}

// Over sampled flights, find those where the LQR alone leaves the safe set; the CBF-QP
// must keep h ≥ 0 on every one that starts inside the HOCBF safe set (to the
// discretisation's O(dt²) slack).
TEST(CbfQp, KeepsTheSafeSetWhereLqrAloneViolatesIt) {
  const VehicleParams p = nominalParams();
  const CbfConfig cfg;
  SamplingRanges ranges;
  ranges.goal_z = {0.5, 0.8};  // goals near the floor so that LQR overshoots below it
  int lqr_altitude_violations = 0, lqr_tilt_violations = 0, checked = 0;
  for (std::uint64_t seed = 0; seed < 300; ++seed) {
    Rng rng(seed, 0);
    const Scenario sc = sampleScenario(ranges, rng);
    // The HOCBF guarantees invariance of C₁ ∩ C₂ = {h ≥ 0, ḣ + α₁h ≥ 0}; a start outside it
    // (say at the floor, descending) may dip below the floor whatever the controller does.
    CbfRows rows;
    computeCbfRows(RigidBodyModel::fromParams(p), cfg, sc.initial_state, rows);
    const Eigen::Vector2d alpha1(cfg.altitude_alpha1, cfg.tilt_alpha1);
    if ((rows.h.array() < 0.0).any() || ((rows.hdot + alpha1.cwiseProduct(rows.h)).array() < 0.0).any()) continue;
    const SafetyRecord lqr = fly(p, ControllerKind::kLqr, sc, cfg);
    const bool violates = lqr.min_altitude_h < 0.0 || lqr.min_tilt_h < 0.0;
    if (!violates) continue;
    lqr_altitude_violations += lqr.min_altitude_h < 0.0;
    lqr_tilt_violations += lqr.min_tilt_h < 0.0;
    ++checked;
    const SafetyRecord cbf = fly(p, ControllerKind::kCbfQp, sc, cfg);
    EXPECT_FALSE(cbf.cut) << "seed " << seed;
    EXPECT_EQ(cbf.infeasible, 0) << "seed " << seed;
    EXPECT_GT(cbf.filtered, 0) << "seed " << seed;
    EXPECT_GE(cbf.min_altitude_h, -1e-4) << "seed " << seed;
    EXPECT_GE(cbf.min_tilt_h, -1e-4) << "seed " << seed;
  }
  std::printf("[ measured ] %d of 300 flights where LQR alone left the safe set (altitude %d, tilt %d)\n", checked,
              lqr_altitude_violations, lqr_tilt_violations);
  EXPECT_GE(lqr_altitude_violations, 3);
  EXPECT_GE(lqr_tilt_violations, 3);
}

TEST(CbfQp, InfeasibleStepFallsBackVisibly) {
  const VehicleParams p = nominalParams();
  CbfQpController ctrl(p, designLqr(p, LqrConfig::bryson(), 0.002).gain, CbfConfig{});
  ctrl.setGoal(Vec3(0, 0, 1));
  // Just above the floor, falling at 4 m/s: stopping needs more than the motors can give.
  State x = test::hoverState(Vec3(0, 0, 0.52));
  x(idx::kVz) = -4.0;
  ControlStep out;
  ctrl.compute(x, out);
  EXPECT_EQ(out.status, ControlStatus::kQpInfeasible);
  EXPECT_TRUE((out.u_cmd.array() >= p.min_thrust).all() && (out.u_cmd.array() <= p.max_thrust).all());
  // The fallback is the clipped LQR command.
  EXPECT_EQ(out.u_cmd, out.u_nominal.cwiseMax(p.min_thrust).cwiseMin(p.max_thrust));
}

TEST(CbfQp, InactiveFilterReturnsTheLqrCommand) {
  const VehicleParams p = nominalParams();
  const GainMatrix k = designLqr(p, LqrConfig::bryson(), 0.002).gain;
  CbfQpController cbf(p, k, CbfConfig{});
  LqrController lqr(p, k);
  cbf.setGoal(Vec3(0.1, 0, 1.2));
  lqr.setGoal(Vec3(0.1, 0, 1.2));
  State x = test::hoverState(Vec3(0, 0.05, 1.1));
  x(idx::kRoll) = 0.05;
  ControlStep a, b;
  cbf.compute(x, a);
  lqr.compute(x, b);
  EXPECT_EQ(a.status, ControlStatus::kOk);
  EXPECT_LT((a.u_cmd - b.u_cmd).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace quadfdi
