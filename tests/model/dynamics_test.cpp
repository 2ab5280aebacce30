#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "control/lqr.h"
#include "model/dynamics.h"
#include "model/integrator.h"
#include "test_support.h"

namespace quadfdi {
namespace {

TEST(Dynamics, HoverIsAnEquilibriumAtMgOver4) {
  for (const char* name : {"nominal", "perturbed", "perturbed-strong"}) {
    const VehicleParams p = namedParams(name);
    const RigidBodyModel m = RigidBodyModel::fromParams(p);
    const Input f = Input::Constant(p.mass * p.gravity / 4.0);
    EXPECT_DOUBLE_EQ(p.hoverThrust(), f(0));
    State x = test::hoverState(Vec3(0.3, -0.2, 1.0));
    State dx;
    stateDerivative(m, x, f, dx);
    EXPECT_LT(dx.cwiseAbs().maxCoeff(), 1e-14) << name;
    // And it stays there under the integrator for 10 s.
    PlantState plant;
    plant.x = x;
    for (int k = 0; k < 5000; ++k) stepPlant(m, Integrator::kRk4, 0.002, 0.0, f, plant);
    EXPECT_LT((plant.x - x).cwiseAbs().maxCoeff(), 1e-12) << name;
  }
}

TEST(Dynamics, MixerProducesTheSeedsWrench) {
  const VehicleParams p = nominalParams();
  const RigidBodyModel m = RigidBodyModel::fromParams(p);
  const Input f(0.01, 0.02, 0.03, 0.05);
  const Wrench w = mix(m, f);
  const double l = std::sqrt(2.0) * p.arm_length, k = p.drag_coeff / p.thrust_coeff;
  EXPECT_NEAR(w.thrust, 0.11, 1e-15);
  EXPECT_NEAR(w.torque.x(), l * (-0.01 - 0.02 + 0.03 + 0.05), 1e-15);
  EXPECT_NEAR(w.torque.y(), l * (-0.01 + 0.02 + 0.03 - 0.05), 1e-15);
  EXPECT_NEAR(w.torque.z(), k * (-0.01 + 0.02 - 0.03 + 0.05), 1e-15);
}

TEST(Dynamics, RectangularXMixerUsesRotorYForRollAndRotorXForPitch) {
  VehicleParams p = nominalParams();
  p.rotor_x = 0.03;
  p.rotor_y = 0.05;
  p.yaw_moment_coeff = 0.006;
  const RigidBodyModel m = RigidBodyModel::fromParams(p);
  EXPECT_EQ(m.roll_lever, 0.05);
  EXPECT_EQ(m.pitch_lever, 0.03);
  const Input f(0.01, 0.02, 0.03, 0.05);
  const Wrench w = mix(m, f);
  // τ = Σ r_i × (0, 0, f_i) with r_i = (±0.03, ±0.05, 0) in FLU: τx = Σ y_i f_i, τy = −Σ x_i f_i.
  const double x[4] = {0.03, -0.03, -0.03, 0.03}, y[4] = {-0.05, -0.05, 0.05, 0.05};
  double tx = 0.0, ty = 0.0;
  for (int i = 0; i < 4; ++i) {
    tx += y[i] * f(i);
    ty -= x[i] * f(i);
  }
  EXPECT_NEAR(w.torque.x(), tx, 1e-17);
  EXPECT_NEAR(w.torque.y(), ty, 1e-17);
  EXPECT_NEAR(w.torque.z(), 0.006 * (-0.01 + 0.02 - 0.03 + 0.05), 1e-17);
}

TEST(Dynamics, RotationMatrixIsZyxAndOrthonormal) {
  const Mat3 r = rotationBodyToWorld(0.3, -0.2, 1.1);
  const Mat3 expected = (Eigen::AngleAxisd(1.1, Vec3::UnitZ()) * Eigen::AngleAxisd(-0.2, Vec3::UnitY()) *
                         Eigen::AngleAxisd(0.3, Vec3::UnitX()))
                            .toRotationMatrix();
  EXPECT_LT((r - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((r * r.transpose() - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-15);
}

// Position kinematics and gravity checked against the rotation matrix directly.
TEST(Dynamics, TranslationalEquationsMatchNewtonInTheWorldFrame) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  const RigidBodyModel m = RigidBodyModel::fromParams(nominalParams());
  for (int trial = 0; trial < 200; ++trial) {
    State x;
    for (int i = 0; i < kStateDim; ++i) x(i) = d(gen);
    const Input f = Input::Constant(0.07) + 0.02 * Input(d(gen), d(gen), d(gen), d(gen));
    State dx;
    stateDerivative(m, x, f, dx);
    const Mat3 r = rotationBodyToWorld(x(idx::kRoll), x(idx::kPitch), x(idx::kYaw));
    const Vec3 v = x.segment<3>(idx::kVel), w = x.segment<3>(idx::kRate);
    EXPECT_LT((dx.segment<3>(idx::kPos) - r * v).norm(), 1e-14);
    // World acceleration d/dt(R v) = R(v̇ + ω × v) must be gravity plus thrust along body z.
    const Vec3 accel_world = r * (dx.segment<3>(idx::kVel) + w.cross(v));
    const Vec3 expected = Vec3(0, 0, -m.gravity) + r.col(2) * (f.sum() * m.inv_mass);
    EXPECT_LT((accel_world - expected).norm(), 1e-12);
  }
}

// Angular momentum in the world frame L = R J ω and kinetic energy are invariants of a
// torque-free body. RK4's error must shrink as dt⁴.
struct SpinDrift {
  double momentum;
  double energy;
};

SpinDrift spinDrift(double dt) {
  VehicleParams p = nominalParams();
  p.gravity = 0.0;
  p.inertia_xx = 1.0e-5;  // Ixx ≠ Iyy ≠ Izz: a genuinely tumbling body
  p.inertia_yy = 1.6e-5;
  p.inertia_zz = 2.2e-5;
  const RigidBodyModel m = RigidBodyModel::fromParams(p);
  PlantState plant;
  plant.x(idx::kP) = 1.5;
  plant.x(idx::kQ) = -1.0;
  plant.x(idx::kR) = 6.0;
  auto invariants = [&](const State& x) {
    const Mat3 r = rotationBodyToWorld(x(idx::kRoll), x(idx::kPitch), x(idx::kYaw));
    const Vec3 jw = m.inertia.cwiseProduct(x.segment<3>(idx::kRate));
    return std::make_pair(Vec3(r * jw), 0.5 * x.segment<3>(idx::kRate).dot(jw));
  };
  const auto [l0, e0] = invariants(plant.x);
  const int steps = static_cast<int>(std::lround(1.0 / dt));
  for (int k = 0; k < steps; ++k) stepPlant(m, Integrator::kRk4, dt, 0.0, Input::Zero(), plant);
  const auto [l1, e1] = invariants(plant.x);
  return {(l1 - l0).norm() / l0.norm(), std::abs(e1 - e0) / e0};
}

TEST(Dynamics, TorqueFreeSpinConservesMomentumAndEnergyToFourthOrder) {
  const SpinDrift coarse = spinDrift(0.004), fine = spinDrift(0.002);
  EXPECT_LT(fine.momentum, 1e-7);
  EXPECT_LT(fine.energy, 1e-7);
  // Halving dt divides the error by ≈ 2⁴ = 16 for a fourth-order method.
  EXPECT_GT(coarse.momentum / fine.momentum, 12.0);
  EXPECT_LT(coarse.momentum / fine.momentum, 20.0);
  EXPECT_GT(coarse.energy / fine.energy, 12.0);
  EXPECT_LT(coarse.energy / fine.energy, 20.0);
}

TEST(Dynamics, ForwardEulerIsFirstOrder) {
  // Same free fall with known solution z(t) = z0 − g t²/2: Euler's error is g·dt·t/2.
  const VehicleParams p = nominalParams();
  const RigidBodyModel m = RigidBodyModel::fromParams(p);
  PlantState plant;
  plant.x(idx::kPz) = 10.0;
  for (int k = 0; k < 500; ++k) stepPlant(m, Integrator::kEuler, 0.002, 0.0, Input::Zero(), plant);
  const double exact = 10.0 - 0.5 * p.gravity * 1.0;
  EXPECT_NEAR(plant.x(idx::kPz) - exact, 0.5 * p.gravity * 0.002 * 1.0, 1e-9);
  PlantState rk;
  rk.x(idx::kPz) = 10.0;
  for (int k = 0; k < 500; ++k) stepPlant(m, Integrator::kRk4, 0.002, 0.0, Input::Zero(), rk);
  EXPECT_NEAR(rk.x(idx::kPz), exact, 1e-11);
}

TEST(Dynamics, AnalyticHoverJacobianMatchesFiniteDifferences) {
  for (const char* name : {"nominal", "perturbed"}) {
    VehicleParams p = namedParams(name);
    p.linear_drag = 1e-3;
    p.rotational_drag = 1e-7;
    const LinearModel lin = linearizeAtHover(p);
    const RigidBodyModel m = RigidBodyModel::fromParams(p);
    const State x0 = test::hoverState(Vec3(0, 0, 1));
    const Input u0 = Input::Constant(p.hoverThrust());
    StateMatrix a;
    InputMatrix b;
    State fp, fm;
    for (int j = 0; j < kStateDim; ++j) {
      const double h = 1e-6;
      State xp = x0, xm = x0;
      xp(j) += h;
      xm(j) -= h;
      stateDerivative(m, xp, u0, fp);
      stateDerivative(m, xm, u0, fm);
      a.col(j) = (fp - fm) / (2 * h);
    }
    for (int j = 0; j < kInputDim; ++j) {
      const double h = 1e-6;
      Input up = u0, um = u0;
      up(j) += h;
      um(j) -= h;
      stateDerivative(m, x0, up, fp);
      stateDerivative(m, x0, um, fm);
      b.col(j) = (fp - fm) / (2 * h);
    }
    EXPECT_LT((a - lin.A).cwiseAbs().maxCoeff(), 1e-6) << name;
    EXPECT_LT((b - lin.B).cwiseAbs().maxCoeff(), 1e-6 * lin.B.cwiseAbs().maxCoeff()) << name;
  }
}

// A weak motor k must tip the vehicle towards its own arm and yaw against its spin:
// motor 1 (front-right) → roll right (φ > 0) and pitch forward (θ > 0); yaw from κ signs.
TEST(Dynamics, WeakMotorTipsTowardsItsArm) {
  const VehicleParams p = nominalParams();
  const RigidBodyModel m = RigidBodyModel::fromParams(p);
  // Arm positions (x, y) and spin sign of each motor's yaw moment.
  const double arm_x[4] = {1, -1, -1, 1}, arm_y[4] = {-1, -1, 1, 1};
  for (int k = 0; k < 4; ++k) {
    PlantState plant;
    plant.x = test::hoverState(Vec3(0, 0, 1));
    Input f = Input::Constant(p.hoverThrust());
    f(k) *= 0.5;
    for (int step = 0; step < 10; ++step) stepPlant(m, Integrator::kRk4, 0.002, 0.0, f, plant);
    // Roll: right side (y < 0) down is φ > 0. Pitch: nose (x > 0) down is θ > 0.
    EXPECT_GT(plant.x(idx::kRoll) * -arm_y[k], 0.0) << "motor " << k + 1;
    EXPECT_GT(plant.x(idx::kPitch) * arm_x[k], 0.0) << "motor " << k + 1;
    // Losing a motor whose yaw moment sign is s leaves a net yaw of −s.
    EXPECT_GT(plant.x(idx::kYaw) * -kYawSign[k], 0.0) << "motor " << k + 1;
    // And the vehicle starts to sink.
    EXPECT_LT(plant.x(idx::kPz), 1.0);
  }
  // The closed loop too: motor 1 failing completely under LQR first rolls right and pitches forward.
  auto ctrl = test::makeOrDie(p, ControllerKind::kLqr);
  ctrl->setGoal(Vec3(0, 0, 1));
  SimulationSettings s;
  s.steps = 15;
  s.fault.theta(0) = 0.0;
  FlightLog log;
  ClosedLoopSimulator(p, s).run(*ctrl, test::hoverState(Vec3(0, 0, 1)), &log);
  ASSERT_EQ(log.size(), 15);
  EXPECT_GT(log.states.back()(idx::kRoll), 1e-4);
  EXPECT_GT(log.states.back()(idx::kPitch), 1e-4);
}

TEST(Integrator, MotorLagFollowsTheExactFirstOrderResponse) {
  VehicleParams p = nominalParams();
  p.motor_time_constant = 0.03;
  const RigidBodyModel m = RigidBodyModel::fromParams(p);
  PlantState plant;
  plant.x = test::hoverState(Vec3(0, 0, 1));
  plant.rotor_thrust = Input::Constant(p.hoverThrust());
  const Input cmd = Input::Constant(0.1);
  for (int k = 0; k < 15; ++k) stepPlant(m, Integrator::kRk4, 0.002, p.motor_time_constant, cmd, plant);
  const double expected = 0.1 + (p.hoverThrust() - 0.1) * std::exp(-0.03 / 0.03);
  EXPECT_NEAR(plant.rotor_thrust(0), expected, 1e-15);
  // Lag delays the climb compared with instant motors.
  PlantState instant;
  instant.x = test::hoverState(Vec3(0, 0, 1));
  for (int k = 0; k < 15; ++k) stepPlant(m, Integrator::kRk4, 0.002, 0.0, cmd, instant);
  EXPECT_LT(plant.x(idx::kPz), instant.x(idx::kPz));
  EXPECT_GT(plant.x(idx::kPz), 1.0);
}

TEST(Integrator, CheckStateFlagsEachKindOfBadState) {
  const StateBounds b;
  State x = test::hoverState(Vec3(0, 0, 1));
  EXPECT_EQ(checkState(x, b), StepStatus::kOk);
  State y = x;
  y(idx::kVx) = std::nan("");
  EXPECT_EQ(checkState(y, b), StepStatus::kNonFinite);
  y = x;
  y(idx::kPitch) = -1.6;
  EXPECT_EQ(checkState(y, b), StepStatus::kAttitudeLimit);
  y = x;
  y(idx::kRoll) = 1.51;
  EXPECT_EQ(checkState(y, b), StepStatus::kAttitudeLimit);
  y = x;
  y(idx::kPz) = -1e-9;
  EXPECT_EQ(checkState(y, b), StepStatus::kBelowGround);
}

}  // namespace
}  // namespace quadfdi
