// What every tracking controller (the cascaded PID, the geometric SE(3) law) must do, each checked
// on both: hover held exactly at equilibrium, gains that scale with the airframe, and equivariance
// under the exact symmetry group. Their own behaviour: pid_test.cpp, geometric_test.cpp.
#include <gtest/gtest.h>

#include "closed_loop_support.h"
#include "control/controller_factory.h"

namespace quadfdi {
namespace {

using test::Flight;
using test::fly;

std::unique_ptr<Controller> make(ControllerKind kind, const VehicleParams& design) {
  ControllerConfig cc;
  cc.kind = kind;
  return test::builtController(design, cc);
}

class TrackingController : public ::testing::TestWithParam<ControllerKind> {};

TEST_P(TrackingController, HoldsHoverAtEquilibriumExactly) {
  for (const VehicleParams& p : {nominalParams(), perturbedParams()}) {
    auto ctrl = make(GetParam(), p);
    const Vec3 goal(0.3, -0.2, 1.0);
    const Flight f = fly(*ctrl, p, test::hoverState(goal), 2000, [&](double) { return hoverReference(goal); });
    ASSERT_FALSE(f.cut);
    for (std::size_t k = 0; k < f.states.size(); ++k) {
      ASSERT_LT((f.states[k].head<3>() - goal).norm(), 1e-12) << "step " << k;
      ASSERT_LT((f.commands[k] - Input::Constant(p.hoverThrust())).cwiseAbs().maxCoeff(), 1e-15) << "step " << k;
    }
  }
}

// Gains are bandwidths: a vehicle twice as heavy, with twice the inertia and twice the thrust,
// flies the same path (same accelerations), to round-off, with the same default gains.
TEST_P(TrackingController, GainsScaleWithTheAirframe) {
  const VehicleParams p = nominalParams();
  VehicleParams heavy = p;
  for (double* v : {&heavy.mass, &heavy.inertia_xx, &heavy.inertia_yy, &heavy.inertia_zz, &heavy.min_thrust, &heavy.max_thrust})
    *v *= 2.0;
  State x0 = test::hoverState(Vec3(0.5, -0.4, 0.8));
  x0(idx::kRoll) = 0.2;
  x0(idx::kYaw) = 0.3;
  auto a = make(GetParam(), p), b = make(GetParam(), heavy);
  const auto goal = [](double) { return hoverReference(Vec3(0.0, 0.0, 1.0)); };
  const Flight fa = fly(*a, p, x0, 3000, goal), fb = fly(*b, heavy, x0, 3000, goal);
  ASSERT_FALSE(fa.cut);
  ASSERT_EQ(fa.states.size(), fb.states.size());
  for (std::size_t k = 0; k < fa.states.size(); ++k) {
    ASSERT_LT((fa.states[k] - fb.states[k]).cwiseAbs().maxCoeff(), 1e-9) << "step " << k;
    ASSERT_LT((2.0 * fa.commands[k] - fb.commands[k]).cwiseAbs().maxCoeff(), 1e-9) << "step " << k;
  }
  EXPECT_LT((fa.states.back().head<3>() - Vec3(0, 0, 1)).norm(), 0.03);
}

// Flying the mapped reference from the mapped start with the mapped fault gives the mapped
// flight and the permuted motor commands, for every element of the exact group.
TEST_P(TrackingController, EquivariantUnderTheExactSymmetryGroup) {
  const VehicleParams p = perturbedParams();  // Ixx ≠ Iyy: the group is still exact
  const TrajectorySpec s = test::spec(TrajectoryKind::kFigureEight, 1.5);
  State x0 = test::startOf(s);
  x0.segment<3>(idx::kVel) = Vec3(0.3, -0.2, 0.1);
  x0(idx::kRoll) = 0.15;
  x0(idx::kPitch) = -0.1;
  x0.segment<3>(idx::kRate) = Vec3(0.5, -0.3, 0.2);
  for (int motor = 1; motor <= 4; ++motor) {
    Input theta = Input::Ones();
    theta(motor - 1) = 0.8;
    const SymmetryMap g = mapMotorToMotor2(motor, SymmetryMode::kExactGroup);
    auto a = make(GetParam(), p), b = make(GetParam(), p);
    const Flight f = fly(*a, p, x0, 2500, [&](double t) { return referenceAt(s, t); }, theta);
    const Flight m = fly(*b, p, g.applyToState(x0), 2500, [&](double t) { return test::mapped(referenceAt(s, t), g); },
                         g.applyToTheta(theta));
    ASSERT_FALSE(f.cut) << "motor " << motor << " cut after " << f.states.size();
    ASSERT_EQ(f.states.size(), m.states.size());
    double worst_state = 0.0, worst_command = 0.0;
    for (std::size_t k = 0; k < f.states.size(); ++k) {
      worst_state = std::max(worst_state, (g.applyToState(f.states[k]) - m.states[k]).cwiseAbs().maxCoeff());
      worst_command = std::max(worst_command, (g.applyToInput(f.commands[k]) - m.commands[k]).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst_state, 1e-9) << "motor " << motor;
    EXPECT_LT(worst_command, 1e-9) << "motor " << motor;
  }
}

INSTANTIATE_TEST_SUITE_P(PidAndGeometric, TrackingController,
                         ::testing::Values(ControllerKind::kPid, ControllerKind::kGeometric),
                         [](const ::testing::TestParamInfo<ControllerKind>& param) {
                           return std::string(param.param == ControllerKind::kPid ? "Pid" : "Geometric");
                         });

}  // namespace
}  // namespace quadfdi
