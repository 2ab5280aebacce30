// The cascaded PID (src/control/pid.*): trajectory tracking with and without feed-forward, the
// integrator, loop-rate holding, the allocator's priorities, and no heap allocation in compute().
// Exact hover, gains that scale with the airframe and equivariance: tracking_controllers_test.cpp.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <new>
#include <vector>

#include "control/controller_factory.h"
#include "control/lqr.h"
#include "control/pid.h"
#include "core/frames.h"
#include "io/params_file.h"
#include "control/reference.h"
#include "model/integrator.h"
#include "simulation/closed_loop.h"
#include "symmetry/symmetry.h"
#include "closed_loop_support.h"
#include "heap_counter.h"  // include once per test executable: compute() must not allocate
#include "test_support.h"

namespace quadfdi {
namespace {

constexpr double kDt = test::kControlDt;
using test::Flight;
using test::fly;
using test::mapped;
using test::spec;
using test::startOf;
using test::trackingError;
using test::TrackingError;
using test::withoutFeedForward;

std::unique_ptr<Controller> makePid(const VehicleParams& design, const PidConfig& pid = {}) {
  ControllerConfig cc;
  cc.kind = ControllerKind::kPid;
  cc.pid = pid;
  return test::builtController(design, cc);
}

// The design model is 30 % too light: the velocity integrator supplies the missing thrust.
TEST(Pid, IntegratorRemovesTheOffsetOfAHeavierPlant) {
  const VehicleParams design = nominalParams();
  VehicleParams plant = design;
  plant.mass *= 1.3;
  auto ctrl = makePid(design);
  const Flight f = fly(*ctrl, plant, test::hoverState(Vec3(0, 0, 1)), 10000,
                       [](double) { return hoverReference(Vec3(0, 0, 1)); });
  ASSERT_FALSE(f.cut);
  double sag = 0.0;
  for (const State& x : f.states) sag = std::max(sag, 1.0 - x(idx::kPz));
  EXPECT_GT(sag, 0.05);  // the mismatch is felt ...
  EXPECT_LT(sag, 0.5);
  EXPECT_LT((f.states.back().head<3>() - Vec3(0, 0, 1)).norm(), 0.005);  // ... and removed
}

// Tolerances after the first 5 s (start transient of the circle and figure-eight, whose
// velocity jumps at t = 0): PX4's default gains leave the cascade a lag of about 0.2 s, which
// on a 1 m circle at 1 m/s (1 m/s² centripetal) costs about 0.1 m; without velocity and
// acceleration feed-forward the same gains fall behind by about a metre.
struct TrackingCase {
  TrajectoryKind kind;
  double speed;        // [m/s]
  double rms_limit;    // [m]
  double max_limit;    // [m]
};

TEST(Pid, TracksEachTrajectoryKindAndNeedsTheFeedForward) {
  const VehicleParams p = nominalParams();
  const TrackingCase cases[] = {{TrajectoryKind::kPointToPoint, 1.0, 0.03, 0.06},
                                {TrajectoryKind::kCircle, 0.5, 0.04, 0.07},
                                {TrajectoryKind::kCircle, 1.0, 0.15, 0.2},
                                {TrajectoryKind::kFigureEight, 1.0, 0.18, 0.3}};
  for (const TrackingCase& c : cases) {
    const TrajectorySpec s = spec(c.kind, c.speed);
    auto ctrl = makePid(p);
    const Flight with = fly(*ctrl, p, startOf(s), 7500, [&](double t) { return referenceAt(s, t); });
    const Flight without =
        fly(*ctrl, p, startOf(s), 7500, [&](double t) { return withoutFeedForward(referenceAt(s, t)); });
    ASSERT_FALSE(with.cut) << toString(c.kind);
    const TrackingError e = trackingError(with, 2500), e0 = trackingError(without, 2500);
    EXPECT_LT(e.rms, c.rms_limit) << toString(c.kind) << " at " << c.speed << " m/s";
    EXPECT_LT(e.max, c.max_limit) << toString(c.kind) << " at " << c.speed << " m/s";
    EXPECT_GT(e0.max, 2.0 * c.max_limit) << toString(c.kind) << " without feed-forward";
    // Facing the velocity: yaw follows the reference.
    EXPECT_LT(std::abs(wrapAngle(with.states.back()(idx::kYaw) - with.references.back().yaw)), 0.1);
  }
}

TEST(Pid, HoverTrajectoryIsSetGoal) {
  const VehicleParams p = nominalParams();
  TrajectorySpec s;
  s.start = Vec3(0.2, 0.1, 1.2);
  SimulationSettings settings;
  settings.steps = 600;
  FlightLog a, b;
  auto ctrl = makePid(p);
  ctrl->setGoal(s.start);
  const State x0 = test::hoverState(Vec3(0, 0, 1));
  ClosedLoopSimulator(p, settings).run(*ctrl, x0, &a);
  settings.trajectory = s;
  ClosedLoopSimulator(p, settings).run(*ctrl, x0, &b);
  ASSERT_EQ(a.size(), b.size());
  for (int k = 0; k < a.size(); ++k) ASSERT_EQ(a.states[static_cast<std::size_t>(k)], b.states[static_cast<std::size_t>(k)]);
}

TEST(Pid, EachLoopHoldsItsOutputBetweenUpdates) {
  const VehicleParams p = nominalParams();
  PidConfig config;  // position every 5th step, attitude every 2nd, rate every step
  config.rate_divisor = 1;
  PidController ctrl(p, config, kDt);
  const TrajectorySpec s = spec(TrajectoryKind::kCircle, 1.0);
  State x = startOf(s);
  x(idx::kRoll) = 0.1;
  const RigidBodyModel model = RigidBodyModel::fromParams(p);
  PlantState ps;
  ps.x = x;
  ps.rotor_thrust = Input::Constant(p.hoverThrust());
  ControlStep out;
  Vec3 thrust, rates, torque;
  int position_changes = 0, attitude_changes = 0;
  for (int k = 0; k < 60; ++k) {
    ctrl.setReference(referenceAt(s, k * kDt));
    ctrl.compute(ps.x, out);
    if (k > 0) {
      if (k % 5 != 0) {
        EXPECT_EQ(ctrl.thrustVector(), thrust) << "step " << k;
      } else {
        position_changes += ctrl.thrustVector() != thrust;
      }
      if (k % 2 != 0) {
        EXPECT_EQ(ctrl.rateSetpoint(), rates) << "step " << k;
      } else {
        attitude_changes += ctrl.rateSetpoint() != rates;
      }
      EXPECT_NE(ctrl.torqueCommand(), torque) << "step " << k;
    }
    thrust = ctrl.thrustVector();
    rates = ctrl.rateSetpoint();
    torque = ctrl.torqueCommand();
    stepPlant(model, Integrator::kRk4, kDt, 0.0, out.u_cmd, ps);
  }
  EXPECT_EQ(position_changes, 11);
  EXPECT_EQ(attitude_changes, 29);

  // A slower rate loop holds the motor commands too.
  config.rate_divisor = 3;
  PidController slow(p, config, kDt);
  slow.setReference(referenceAt(s, 0.0));
  Input previous = Input::Zero();
  ps.x = x;
  for (int k = 0; k < 30; ++k) {
    slow.compute(ps.x, out);
    if (k % 3 != 0) {
      EXPECT_EQ(out.u_cmd, previous) << "step " << k;
    }
    previous = out.u_cmd;
    stepPlant(model, Integrator::kRk4, kDt, 0.0, out.u_cmd, ps);
  }
}

// The D term of the velocity loop acts on the numerical velocity derivative low-passed at
// velocity_derivative_cutoff (first order, exactly discretised at the position loop's period, as
// PX4's MPC_VELD_LP): a velocity step of Δv gives α·Δv/period at its update and (1 − α)·α·Δv/period
// at the next, α = 1 − e^{−2π f_c·period}; with the cutoff at 0 the raw difference passes.
TEST(Pid, VelocityDerivativeIsLowPassed) {
  const VehicleParams p = nominalParams();
  PidConfig only_d;  // every other term of the horizontal acceleration off
  only_d.position_gain_xy = 0.0;
  only_d.velocity_gain_xy = 0.0;
  only_d.velocity_integral_xy = 0.0;
  const double period = kDt * only_d.position_divisor, dv = 0.1;  // [s], [m/s]
  const double kd = only_d.velocity_derivative_xy;
  auto thrustX = [&](const PidConfig& config) {
    PidController ctrl(p, config, kDt);
    Reference hover;
    hover.position = Vec3(0.0, 0.0, 1.0);
    ctrl.setReference(hover);
    State x = test::hoverState(hover.position);
    ControlStep out;
    std::vector<double> at_updates;
    for (int k = 0; k <= 2 * config.position_divisor; ++k) {
      x(idx::kVel) = k >= config.position_divisor ? dv : 0.0;  // body x = world x at zero attitude
      ctrl.compute(x, out);
      if (k % config.position_divisor == 0) at_updates.push_back(ctrl.thrustVector().x());
    }
    return at_updates;
  };
  const double alpha = 1.0 - std::exp(-2.0 * M_PI * only_d.velocity_derivative_cutoff * period);
  const std::vector<double> filtered = thrustX(only_d);
  EXPECT_EQ(filtered[0], 0.0);
  EXPECT_NEAR(filtered[1], -p.mass * kd * alpha * dv / period, 1e-12);
  EXPECT_NEAR(filtered[2], -p.mass * kd * (1.0 - alpha) * alpha * dv / period, 1e-12);
  PidConfig raw = only_d;
  raw.velocity_derivative_cutoff = 0.0;
  const std::vector<double> unfiltered = thrustX(raw);
  EXPECT_NEAR(unfiltered[1], -p.mass * kd * dv / period, 1e-12);
  EXPECT_EQ(unfiltered[2], 0.0);
}

TEST(Pid, ComputeDoesNotAllocate) {
  const VehicleParams p = nominalParams();
  PidController ctrl(p, PidConfig{}, kDt);
  const TrajectorySpec s = spec(TrajectoryKind::kFigureEight, 2.0);
  State x = startOf(s);
  ControlStep out;
  const long before = quadfdi::test::heap_allocations.load();
  for (int k = 0; k < 1000; ++k) {
    ctrl.setReference(referenceAt(s, k * kDt));
    x(idx::kRoll) = 0.3 * std::sin(0.01 * k);
    ctrl.compute(x, out);
  }
  EXPECT_EQ(quadfdi::test::heap_allocations.load(), before);
  const long probe_before = quadfdi::test::heap_allocations.load();
  void* probe = ::operator new(16);  // the counter itself works
  EXPECT_GT(quadfdi::test::heap_allocations.load(), probe_before);
  ::operator delete(probe);
}

TEST(PidAllocator, ExactInsideTheBoundsAndPrioritisedOutside) {
  const VehicleParams p = nominalParams();
  const RigidBodyModel model = RigidBodyModel::fromParams(p);
  const MotorAllocator alloc(model, p.min_thrust, p.max_thrust);
  Input f, raw;
  auto wrench = [&](const Input& u) {
    const Wrench w = mix(model, u);
    return Eigen::Vector4d(w.thrust, w.torque.x(), w.torque.y(), w.torque.z());
  };
  // Inside: the wrench is produced exactly.
  const Eigen::Vector4d inside(4 * p.hoverThrust(), 1e-4, -2e-4, 1e-5);
  EXPECT_FALSE(alloc.allocate(inside(0), inside.tail<3>(), f, raw));
  EXPECT_LT((wrench(f) - inside).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(f, raw);
  // Too much yaw at hover: roll, pitch and collective kept, yaw reduced.
  const Eigen::Vector4d yawy(4 * p.hoverThrust(), 1e-3, 0.0, 1e-2);
  EXPECT_TRUE(alloc.allocate(yawy(0), yawy.tail<3>(), f, raw));
  EXPECT_NEAR(wrench(f)(0), yawy(0), 1e-15);
  EXPECT_NEAR(wrench(f)(1), yawy(1), 1e-15);
  EXPECT_NEAR(wrench(f)(2), 0.0, 1e-15);
  EXPECT_GT(wrench(f)(3), 0.0);
  EXPECT_LT(wrench(f)(3), yawy(3));
  // Roll at full collective: roll kept, collective lowered.
  const Eigen::Vector4d high(4 * p.max_thrust, 3e-3, 0.0, 0.0);
  EXPECT_TRUE(alloc.allocate(high(0), high.tail<3>(), f, raw));
  EXPECT_NEAR(wrench(f)(1), high(1), 1e-15);
  EXPECT_LT(wrench(f)(0), high(0));
  EXPECT_NEAR(f.maxCoeff(), p.max_thrust, 1e-15);
  // More roll than the motors can make: scaled into the bounds, direction kept.
  EXPECT_TRUE(alloc.allocate(4 * p.hoverThrust(), Vec3(1.0, 0.5, 0.0), f, raw));
  EXPECT_TRUE((f.array() >= p.min_thrust).all() && (f.array() <= p.max_thrust).all());
  EXPECT_NEAR(wrench(f)(1) / wrench(f)(2), 2.0, 1e-9);
  EXPECT_TRUE(alloc.allocate(4 * p.hoverThrust(), Vec3(1.0, 0.0, 0.0), f, raw));
  EXPECT_NEAR(wrench(f)(1), alloc.maxTorque().x(), 1e-15);
  // The desaturation commutes with the symmetry group: the mapped wrench (T, det S·S·τ) gives
  // the permuted thrusts, saturated or not.
  const Eigen::Vector4d wrenches[] = {inside, yawy, high, Eigen::Vector4d(0.1, 4e-3, -3e-3, 8e-3),
                                      Eigen::Vector4d(0.5, -2e-3, 5e-3, -6e-3)};
  for (int motor = 1; motor <= 4; ++motor) {
    const SymmetryMap g = mapMotorToMotor2(motor, SymmetryMode::kExactGroup);
    const Vec3 torque_sign = g.state_map.diagonal().segment<3>(idx::kRate);  // ω and τ map alike
    for (const Eigen::Vector4d& w : wrenches) {
      Input fm, rawm;
      const bool s1 = alloc.allocate(w(0), w.tail<3>(), f, raw);
      const bool s2 = alloc.allocate(w(0), torque_sign.cwiseProduct(w.tail<3>()), fm, rawm);
      EXPECT_EQ(s1, s2);
      EXPECT_LT((g.applyToInput(f) - fm).cwiseAbs().maxCoeff(), 1e-15) << "motor " << motor;
    }
  }
}

TEST(Pid, RefusesBadConfigurations) {
  PidConfig c;
  EXPECT_EQ(validate(c), "");
  c.attitude_divisor = 0;
  EXPECT_EQ(validate(c), "PID loop divisors must be >= 1");
  c = PidConfig{};
  c.yaw_weight = 0.0;
  EXPECT_EQ(validate(c), "PID yaw_weight must lie in (0, 1]");
  ControllerConfig cc;
  cc.kind = ControllerKind::kPid;
  cc.pid.rate_gain_rp = -1.0;
  const ControllerBuild build = makeController(nominalParams(), cc, kDt);
  EXPECT_EQ(build.controller, nullptr);
  EXPECT_EQ(build.error, "PID gains and limits must be finite and >= 0");
}

// The LQR tracks a moving reference through x − x_ref (velocity rotated into the body frame).
TEST(LqrReference, TracksASlowCircle) {
  const VehicleParams p = nominalParams();
  auto lqr = test::makeOrDie(p, ControllerKind::kLqr);
  TrajectorySpec s = spec(TrajectoryKind::kCircle, 0.5);
  s.yaw_mode = YawMode::kFixed;
  const Flight with = fly(*lqr, p, startOf(s), 7500, [&](double t) { return referenceAt(s, t); });
  const Flight without = fly(*lqr, p, startOf(s), 7500, [&](double t) { return withoutFeedForward(referenceAt(s, t)); });
  ASSERT_FALSE(with.cut);
  const TrackingError e = trackingError(with, 2500), e0 = trackingError(without, 2500);
  EXPECT_LT(e.max, 0.1);
  EXPECT_LT(e.max, 0.5 * e0.max);
}

// Nose along the path and a heading sweep: the gain, designed at yaw 0, reads the position error in
// the reference heading's frame and tracks the yaw rate, so every library vehicle flies a circle
// and a figure-eight nose first (before 2026-12-07 the circle crashed within 3 s) and its yaw keeps
// up; at yaw 0 the command is the hover LQR's bit for bit.
TEST(LqrReference, FliesNoseFirstAndThroughAHeadingSweepOnEveryLibraryVehicle) {
  for (const char* name : {"crazyflie2", "racer250", "quad450"}) {
    const VehicleParams p = loadVehicleParams(std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/" + name + ".toml");
    for (const auto kind : {TrajectoryKind::kCircle, TrajectoryKind::kFigureEight}) {
      TrajectorySpec s = spec(kind, 1.0);
      s.radius = 1.5;
      s.yaw_sweep_amplitude = kind == TrajectoryKind::kCircle ? 0.0 : 0.5;
      s.yaw_sweep_period = 4.0;
      ControllerConfig cc;  // Bryson's weights for the vehicle, as simulate and the training flights design it
      cc.kind = ControllerKind::kLqr;
      cc.lqr = LqrConfig::brysonFor(p);
      auto lqr = test::builtController(p, cc);
      const Flight f = fly(*lqr, p, startOf(s), 7500, [&](double t) { return referenceAt(s, t); });
      ASSERT_FALSE(f.cut) << name << " " << toString(kind);
      const TrackingError e = trackingError(f, 2500);
      EXPECT_LT(e.max, 0.25) << name << " " << toString(kind);
      double yaw_error = 0.0;
      for (std::size_t k = 2500; k < f.states.size(); ++k)
        yaw_error = std::max(yaw_error, std::abs(wrapAngle(f.states[k](idx::kYaw) - f.references[k].yaw)));
      EXPECT_LT(yaw_error, 0.4) << name << " " << toString(kind);
      std::printf("[ measured ] %s %s: position error max %.3f m, yaw error max %.3f rad\n", name, toString(kind), e.max, yaw_error);
    }
  }
  const VehicleParams p = nominalParams();
  LqrController a(p, designLqr(p, LqrConfig::bryson(), kDt).gain), b = a;
  State x = test::hoverState(Vec3(0.3, -0.2, 1.1));
  x(idx::kYaw) = 0.2;
  x(idx::kR) = 0.4;
  a.setGoal(Vec3(0.0, 0.0, 1.0));
  b.setReference(hoverReference(Vec3(0.0, 0.0, 1.0)));
  ControlStep ua, ub;
  a.compute(x, ua);
  b.compute(x, ub);
  EXPECT_EQ(ua.u_cmd, ub.u_cmd);
}

}  // namespace
}  // namespace quadfdi
