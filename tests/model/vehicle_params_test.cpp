#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "model/vehicle_params.h"

namespace quadfdi {
namespace {

TEST(VehicleParams, NamedSetsMatchTheSpec) {
  const VehicleParams n = nominalParams();
  EXPECT_EQ(n.mass, 0.0299);
  EXPECT_EQ(n.inertia_zz, 2.173e-5);
  EXPECT_EQ(n.max_thrust, 0.15);
  const VehicleParams p = perturbedParams();
  EXPECT_EQ(p.mass, 0.02);
  EXPECT_EQ(p.inertia_xx, 2.0e-5);
  EXPECT_EQ(p.inertia_yy, 1.0e-5);
  EXPECT_EQ(p.arm_length, 0.05);
  const VehicleParams s = perturbedStrongParams();
  EXPECT_EQ(s.mass, 0.015);
  EXPECT_EQ(s.arm_length, 0.02);
  for (const char* name : {"nominal", "perturbed", "perturbed-strong"}) EXPECT_EQ(validate(namedParams(name)), "");
  EXPECT_THROW(namedParams("heavy"), std::invalid_argument);
}

TEST(VehicleParams, ValidateNamesTheFirstProblem) {
  VehicleParams p;
  p.mass = -1.0;
  EXPECT_NE(validate(p).find("mass"), std::string::npos);
  p = VehicleParams{};
  p.min_thrust = 0.2;
  EXPECT_NE(validate(p).find("min_thrust"), std::string::npos);
  p = VehicleParams{};
  p.mass = 0.1;  // hover 0.245 N per motor > 0.15 N
  EXPECT_NE(validate(p).find("hover"), std::string::npos);
}

}  // namespace
}  // namespace quadfdi

namespace quadfdi {
namespace {

TEST(VehicleParams, DefaultLeversAreTheSeedsSqrt2TimesArmBitForBit) {
  for (const char* name : {"nominal", "perturbed", "perturbed-strong"}) {
    const VehicleParams p = namedParams(name);
    EXPECT_EQ(p.rollLever(), std::sqrt(2.0) * p.arm_length) << name;
    EXPECT_EQ(p.pitchLever(), std::sqrt(2.0) * p.arm_length) << name;
    EXPECT_EQ(p.yawCoeff(), p.drag_coeff / p.thrust_coeff) << name;
  }
  VehicleParams r;
  r.rotor_x = 0.075;
  r.rotor_y = 0.10;
  r.yaw_moment_coeff = 0.022;
  EXPECT_EQ(r.pitchLever(), 0.075);  // |x| multiplies thrust differences in the pitch moment
  EXPECT_EQ(r.rollLever(), 0.10);    // |y| in the roll moment
  EXPECT_EQ(r.yawCoeff(), 0.022);
}

TEST(VehicleParams, ThrustCurveFollowsThrMdlFacAndInverts) {
  VehicleParams p;
  p.max_thrust = 10.0;
  p.thrust_model_factor = 0.0;
  EXPECT_EQ(p.thrustAtCommand(0.3), 3.0);
  p.thrust_model_factor = 1.0;
  EXPECT_DOUBLE_EQ(p.thrustAtCommand(0.5), 2.5);
  p.thrust_model_factor = 0.6;
  EXPECT_DOUBLE_EQ(p.thrustAtCommand(0.5), 10.0 * (0.4 * 0.5 + 0.6 * 0.25));
  EXPECT_EQ(p.thrustAtCommand(1.7), 10.0);  // clamped
  for (double k : {0.0, 0.3, 0.6, 1.0}) {
    p.thrust_model_factor = k;
    for (double c : {0.0, 1e-6, 0.1, 0.5, 0.93, 1.0})
      EXPECT_NEAR(p.commandForThrust(p.thrustAtCommand(c)), c, 1e-14) << "k " << k << " c " << c;
  }
}

TEST(VehicleParams, ValidateRefusesNewFieldsOutOfRange) {
  VehicleParams p;
  p.thrust_model_factor = 1.5;
  EXPECT_NE(validate(p).find("thrust_model_factor must lie in [0, 1]"), std::string::npos);
  p = VehicleParams{};
  p.thrust_model_factor = -0.1;
  EXPECT_NE(validate(p).find("thrust_model_factor"), std::string::npos);
  p = VehicleParams{};
  p.rotor_x = std::nan("");
  EXPECT_NE(validate(p).find("rotor_x"), std::string::npos);
  p = VehicleParams{};
  p.yaw_moment_coeff = -0.01;
  EXPECT_NE(validate(p).find("yaw_moment_coeff"), std::string::npos);
  p = VehicleParams{};
  p.mass = std::numeric_limits<double>::infinity();
  EXPECT_NE(validate(p).find("mass must be finite"), std::string::npos);
  p = VehicleParams{};
  p.drag_coeff = 0.0;  // no yaw authority at all
  EXPECT_NE(validate(p).find("yaw moment coefficient"), std::string::npos);
}

}  // namespace
}  // namespace quadfdi
