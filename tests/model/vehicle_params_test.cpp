#include <gtest/gtest.h>

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
