#include <gtest/gtest.h>

#include <fstream>

#include "config_refusal.h"
#include "io/key_value.h"
#include "io/params_file.h"

namespace quadfdi {
namespace {

TEST(ParamsFile, NamedSetsAndRoundTrip) {
  EXPECT_EQ(loadVehicleParams("perturbed").mass, 0.02);
  VehicleParams p = perturbedStrongParams();
  p.motor_time_constant = 0.025;
  const VehicleParams back = vehicleParamsFromText(vehicleParamsToText(p), "mem");
  EXPECT_EQ(vehicleParamsToText(back), vehicleParamsToText(p));
  EXPECT_EQ(back.motor_time_constant, 0.025);
}

TEST(ParamsFile, BaseSetWithOverrides) {
  const VehicleParams p = vehicleParamsFromText("base = \"perturbed\"\nmass = 0.025\n", "v.toml");
  EXPECT_EQ(p.mass, 0.025);
  EXPECT_EQ(p.inertia_xx, 2.0e-5);
}

TEST(ParamsFile, BadInputIsAOneLineErrorWithFileAndLine) {
  auto err = [](const std::string& text) {
    return test::configRefusal([&] { vehicleParamsFromText(text, "v.toml"); });
  };
  EXPECT_EQ(err("mass = 0.03\nmas = 1\n").rfind("v.toml:2: unknown parameter 'mas'", 0), 0u);
  EXPECT_EQ(err("mass = heavy\n"), "v.toml:1: 'mass' needs a finite number, got 'heavy'");
  EXPECT_EQ(err("base = \"huge\"\n"), "v.toml:1: unknown base parameter set 'huge' (nominal, perturbed, perturbed-strong)");
  EXPECT_EQ(err("mass = -1\n"), "v.toml: invalid vehicle: mass must be finite and > 0, got -1");
}

TEST(ParamsFile, ShippedExampleLoads) {
  const VehicleParams p = loadVehicleParams(std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicle-example.toml");
  EXPECT_EQ(validate(p), "");
}

}  // namespace
}  // namespace quadfdi
