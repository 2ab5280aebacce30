#include <gtest/gtest.h>

#include <cmath>

#include "data/rollout.h"
#include "io/key_value.h"
#include "io/randomisation_file.h"

namespace quadfdi {
namespace {

const std::string kDefault = std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-default.toml";

TEST(RandomisationFile, LoadsTheShippedRandomisationWithItsVehicles) {
  const Randomisation r = loadRandomisation(kDefault);
  ASSERT_EQ(r.vehicles.size(), 3u);
  EXPECT_EQ(r.vehicle_names[0], "crazyflie2");
  EXPECT_EQ(r.parameters.mass.lo, 0.85);
  EXPECT_EQ(r.sensors.delay_steps_max, 5);
  EXPECT_EQ(r.manoeuvres.figure_eight, 0.0);
  // The text form keeps every range (vehicles by name).
  const std::string text = randomisationToText(r);
  EXPECT_NE(text.find("parameters.mass = [0.84999999999999998, 1.1499999999999999]"), std::string::npos) << text;
  EXPECT_NE(text.find("vehicles = [\"crazyflie2\", \"racer250\", \"quad450\"]"), std::string::npos) << text;
}

TEST(RandomisationFile, RefusesBadInputWithFileAndLine) {
  auto message = [](const std::string& text) {
    try {
      randomisationFromText(text, "r.toml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("vehicles = [\"nominal\"]\nspeed = 3\n"), "r.toml:2: unknown key 'speed'");
  EXPECT_EQ(message("vehicles = [\"nominal\"]\n[parameters]\nmass = [1.1]\n"), "r.toml:3: 'parameters.mass' needs [lo, hi]");
  EXPECT_EQ(message("vehicles = [\"nominal\"]\n[sensors]\nrate_std = [0.1, 0.01]\n"), "r.toml:3: 'sensors.rate_std' needs 0 <= lo <= hi");
  EXPECT_NE(message("vehicles = [\"no-such-file.toml\"]\n").find("r.toml:1: vehicle:"), std::string::npos);
  EXPECT_NE(message("vehicles = [\"nominal\"]\n[controllers]\nlqr = 0\n").find("controller weight"), std::string::npos);
  // A name the file system refuses (longer than NAME_MAX) is a one-line error, not an exception
  // escaping from std::filesystem (found by the fuzz target).
  EXPECT_NE(message("vehicles = [\"" + std::string(300, 'x') + "\"]\n").find("r.toml:1: vehicle:"), std::string::npos);
    EXPECT_EQ(message(""), "r.toml: no 'vehicles = [\"FILE\", …]': a randomisation needs at least one vehicle");
  EXPECT_EQ(message("[sensors]\ndelay_steps_max = 2\n"), "r.toml: no 'vehicles = [\"FILE\", …]': a randomisation needs at least one vehicle");
}

// Every library vehicle flown by every controller through every manoeuvre, healthy: the flights
// stay up, and the batch does not depend on the thread count.
TEST(RandomisationFile, RandomisedHealthyFlightsStayUpAndAreThreadIndependent) {
  RolloutConfig c;
  c.randomisation = loadRandomisation(kDefault);
  c.randomisation.manoeuvres.figure_eight = 0.2;
  c.randomisation.controllers.gain_scale = {0.5, 2.0};  // E7's held-out gains included
  c.seed = 3;
  c.post_fault_steps = 300;
  const RolloutEngine engine(c);
  ASSERT_EQ(engine.error(), "");
  const std::vector<TrajectoryJob> jobs = algorithm1Jobs(0, 90, {1.0}, {2});
  TrajectoryBatch one, two;
  ASSERT_TRUE(engine.run(jobs, 1, one));
  ASSERT_TRUE(engine.run(jobs, 2, two));
  EXPECT_EQ(one.outputs, two.outputs);
  EXPECT_EQ(one.inputs, two.inputs);
  int cut = 0;
  for (int t = 0; t < one.count; ++t) {
    const bool was_cut = one.length[static_cast<std::size_t>(t)] < one.samples;
    cut += was_cut;
    if (was_cut) {
      const FlightDraw d = engine.flightDraw(one.scenario_index[static_cast<std::size_t>(t)]);
      ADD_FAILURE() << "cut: vehicle " << c.randomisation.vehicle_names[static_cast<std::size_t>(d.vehicle)] << " controller "
                    << toString(d.controller) << " gain " << d.gain_scale << " manoeuvre " << toString(d.manoeuvre.kind)
                    << " speed " << d.manoeuvre.speed << " size " << d.manoeuvre.size << " length "
                    << one.length[static_cast<std::size_t>(t)] << " status " << int(one.end_status[static_cast<std::size_t>(t)]);
    }
  }
  EXPECT_EQ(cut, 0);
  // Commands stay finite and inside a plausible band around hover (no runaway controller).
  for (float u : one.inputs) ASSERT_TRUE(std::isfinite(u));
}

}  // namespace
}  // namespace quadfdi
