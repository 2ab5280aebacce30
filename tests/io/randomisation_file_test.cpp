#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "config_refusal.h"
#include "core/frames.h"
#include "data/rollout.h"
#include "io/key_value.h"
#include "io/params_file.h"
#include "io/randomisation_file.h"
#include "scratch_path.h"

namespace quadfdi {
namespace {

const std::string kDefault = std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-default.toml";
const std::string kAirframes = std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-airframes.toml";
const std::string kGeometric = std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-geometric.toml";
const std::string kHeading = std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-heading.toml";

// The one-line error randomisationFromText gives for `text` (read as "r.toml"), or test::kAccepted.
std::string refusalOf(const std::string& text) {
  return test::configRefusal([&] { randomisationFromText(text, "r.toml"); });
}

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

// A model file's randomisation names its vehicles ("quad450"), not their files: read back with a
// resolver (the executable's: the vehicle library), the same vehicles and ranges; without one, or
// when it knows no such vehicle, refused naming the vehicle.
TEST(RandomisationFile, VehiclesByNameAreReadBackThroughAResolver) {
  const Randomisation shipped = loadRandomisation(kAirframes);
  const std::string text = randomisationToText(shipped);
  const auto library = [](const std::string& name) {
    const std::string file = std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/" + name + ".toml";
    return std::filesystem::exists(file) ? file : std::string();
  };
  const Randomisation back = randomisationFromText(text, "model.qfdw", library);
  EXPECT_EQ(back.vehicle_names, shipped.vehicle_names);
  ASSERT_EQ(back.vehicles.size(), shipped.vehicles.size());
  for (std::size_t i = 0; i < back.vehicles.size(); ++i) EXPECT_EQ(back.vehicles[i].mass, shipped.vehicles[i].mass);
  EXPECT_EQ(back.airframes.count, shipped.airframes.count);
  EXPECT_EQ(back.airframes.aspect.hi, shipped.airframes.aspect.hi);
  EXPECT_EQ(randomisationToText(back), text);
  EXPECT_NE(refusalOf(text).find("r.toml:1: vehicle: "), std::string::npos) << refusalOf(text);
  EXPECT_THROW(randomisationFromText(text, "model.qfdw", [](const std::string&) { return std::string(); }), ConfigError);
}

// The held-out airframes (configs/vehicles/held-out/, docs/results/held-out-vehicles/) are held
// out only if the shipped training never flies them: not by name, and no training vehicle is the
// same airframe under another name (mass or inertia within the randomisation's spread).
// The synthetic airframes of randomisation-airframes.toml count as training vehicles too.
TEST(RandomisationFile, TheShippedTrainingFliesNoHeldOutAirframe) {
  for (const std::string& file : {kDefault, kAirframes}) {
    const Randomisation r = loadRandomisation(file);
    const std::vector<VehicleParams> described = describedVehicles(r);
    int airframes = 0;  // every file of the folder, so that one added later is checked too
    for (const auto& entry : std::filesystem::directory_iterator(std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/held-out")) {
      if (entry.path().extension() != ".toml") continue;
      ++airframes;
      const std::string stem = entry.path().stem().string();
      const VehicleParams held_out = loadVehicleParams(entry.path().string());
      for (std::size_t i = 0; i < described.size(); ++i) {
        EXPECT_NE(describedVehicleName(r, i), stem);
        const VehicleParams& trained = described[i];
        const bool same_mass = std::abs(held_out.mass / trained.mass - 1.0) <= 0.15;
        const bool same_roll_inertia = std::abs(held_out.inertia_xx / trained.inertia_xx - 1.0) <= 0.2;
        const bool same_yaw_moment = std::abs(held_out.yaw_moment_coeff / trained.yaw_moment_coeff - 1.0) <= 0.2;
        EXPECT_FALSE(same_mass && same_roll_inertia && same_yaw_moment) << stem << " is " << describedVehicleName(r, i) << " of " << file;
      }
    }
    EXPECT_GE(airframes, 2);  // x500 and solo at least
  }
}

TEST(RandomisationFile, AirframeKeysParseRoundTripAndAreLeftOutWithoutAirframes) {
  const Randomisation r = loadRandomisation(kAirframes);
  EXPECT_EQ(r.airframes.count, 48);
  EXPECT_EQ(r.airframes.share, 0.25);
  EXPECT_EQ(r.airframes.hover_fraction.hi, 0.65);
  EXPECT_EQ(describedVehicles(r).size(), 51u);
  EXPECT_EQ(describedVehicleName(r, 3), "airframe-1");
  // The text form (as model files record it) parses back to the same ranges, hence the same airframes.
  const std::string text = randomisationToText(r);
  const std::string library = "vehicles = [\"nominal\"]\n";
  const Randomisation back = randomisationFromText(library + text.substr(text.find('\n') + 1), "model");
  const std::string back_text = randomisationToText(back);
  EXPECT_EQ(back_text.substr(back_text.find('\n')), text.substr(text.find('\n')));
  const std::vector<VehicleParams> a = drawAirframes(r.airframes), b = drawAirframes(back.airframes);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].inertia_zz, b[i].inertia_zz);
  EXPECT_EQ(randomisationToText(loadRandomisation(kDefault)).find("airframes."), std::string::npos);
  auto message = [](const std::string& body) { return refusalOf("vehicles = [\"nominal\"]\n[airframes]\n" + body); };
  EXPECT_EQ(message("count = 1001\n"), "r.toml:3: airframes.count must be in 0 … 1000");
  EXPECT_EQ(message("size = [1, 2]\n"), "r.toml:3: unknown key 'airframes.size'");
  EXPECT_EQ(message("count = 4\nshare = 1.5\n"), "r.toml: randomisation: airframes: share must be in [0, 1]");
  EXPECT_EQ(message("count = 4\nhover_fraction = [0.5, 1.0]\n"),
            "r.toml: randomisation: airframes: hover_fraction must stay below 1 (a vehicle hovering at full thrust cannot be controlled)");
  EXPECT_EQ(message("count = 4\nidle_fraction = [0.0, 0.2]\nhover_fraction = [0.15, 0.5]\n"),
            "r.toml: randomisation: airframes: idle_fraction must be 0 <= lo <= hi < hover_fraction's lo");
  EXPECT_EQ(message("count = 4\nmass = [0.01, 5000]\n"), "r.toml: randomisation: airframes: mass must lie in [0.001, 1000] kg");
  EXPECT_EQ(message("count = 4\nmass = [0, 2]\n"),
            "r.toml: randomisation: airframes: mass, size_factor, aspect, inertia_factor, yaw_inertia_ratio, hover_fraction and "
            "yaw_moment_coeff need 0 < lo <= hi");
}

// train / calibrate --vehicle FILE fly that vehicle alone: the file's synthetic airframes go too.
TEST(RandomisationFile, FlyingOnlyNamedVehiclesDropsTheAirframes) {
  Randomisation r = loadRandomisation(kAirframes);
  flyOnlyVehicles(r, {std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/racer250.toml"});
  EXPECT_EQ(r.vehicle_names, std::vector<std::string>{"racer250"});
  EXPECT_EQ(describedVehicles(r).size(), 1u);
  EXPECT_EQ(randomisationToText(r).find("airframes."), std::string::npos);
  EXPECT_EQ(validate(r), "");
}

// Every synthetic airframe gets its controllers designed in setup, and a controller drawn on it
// flies it: the flyability probe keeps most first draws.
TEST(RandomisationFile, SyntheticAirframesAreDesignedForAndFlown) {
  RolloutConfig c;
  c.randomisation = loadRandomisation(kAirframes);
  c.randomisation.airframes.share = 1.0;
  c.seed = 4;
  c.post_fault_steps = 300;
  const RolloutEngine engine(c);
  ASSERT_EQ(engine.error(), "");
  int first_draw_kept = 0, synthetic = 0;
  const int n = 60;
  for (int i = 0; i < n; ++i) {
    int attempts = 0;
    const FlightDraw d = engine.flightDraw(static_cast<std::uint64_t>(i), &attempts);
    synthetic += d.vehicle >= 3;
    first_draw_kept += attempts == 1;
  }
  EXPECT_EQ(synthetic, n);
  EXPECT_GE(first_draw_kept, 0.9 * n);
  TrajectoryBatch batch;
  ASSERT_TRUE(engine.run(algorithm1Jobs(0, 40, {1.0}, {2}), 2, batch));
  for (int t = 0; t < batch.count; ++t) EXPECT_EQ(batch.length[static_cast<std::size_t>(t)], batch.samples) << "flight " << t;
}

TEST(RandomisationFile, RefusesBadInputWithFileAndLine) {
  auto message = [](const std::string& text) { return refusalOf(text); };
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

// `base = "FILE"`: a recipe names the randomisation it extends and only what it changes. The
// shipped slow-motors recipe is the airframe randomisation with both motor ranges widened, nothing else.
TEST(RandomisationFile, ABaseIsExtendedKeyByKey) {
  const std::string slow = std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-slow-motors.toml";
  Randomisation expected = loadRandomisation(kAirframes);
  expected.parameters.motor_time_constant = {0.005, 0.060};
  expected.airframes.motor_time_constant = {0.005, 0.060};
  const Randomisation r = loadRandomisation(slow);
  EXPECT_EQ(randomisationToText(r), randomisationToText(expected));
  EXPECT_EQ(r.vehicle_names, expected.vehicle_names);  // the base's, resolved beside the base
  ASSERT_EQ(describedVehicles(r).size(), describedVehicles(expected).size());
  EXPECT_EQ(describedVehicles(r).back().mass, describedVehicles(expected).back().mass);

  // Relative to the including file's folder; chains; this file's vehicles replace the base's.
  const std::filesystem::path folder = test::scratchPath("RandomisationFile", "base");
  std::filesystem::create_directories(folder / "recipes");
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(folder / name) << text;
    return (folder / name).string();
  };
  const std::string vehicles = std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/";
  write("root.toml", "vehicles = [\"" + vehicles + "crazyflie2.toml\", \"" + vehicles + "racer250.toml\"]\n[parameters]\nmass = [0.9, 1.1]\n");
  write("recipes/middle.toml", "base = \"../root.toml\"\n[sensors]\ndelay_steps_max = 3\n");
  const std::string leaf = write("recipes/leaf.toml", "base = \"middle.toml\"\nvehicles = [\"nominal\"]\n[parameters]\nmass = [0.95, 1.05]\n");
  const Randomisation chained = loadRandomisation(leaf);
  EXPECT_EQ(chained.vehicle_names, std::vector<std::string>{"nominal"});
  EXPECT_EQ(chained.parameters.mass.lo, 0.95);
  EXPECT_EQ(chained.sensors.delay_steps_max, 3);
  EXPECT_EQ(loadRandomisation(folder.string() + "/recipes/middle.toml").vehicle_names,
            (std::vector<std::string>{"crazyflie2", "racer250"}));

  // Refusals: one line naming the including file and line, then the base's own message.
  const std::string broken = write("broken.toml", "vehicles = [\"nominal\"]\nspeed = 3\n");
  EXPECT_EQ(test::configRefusal([&] { randomisationFromText("base = \"" + broken + "\"\n", "r.toml"); }),
            "r.toml:1: base: " + broken + ":2: unknown key 'speed'");
  EXPECT_EQ(refusalOf("vehicles = [\"nominal\"]\nbase = \"x.toml\"\n"), "r.toml:2: base must be the file's first key (before every section)");
  EXPECT_EQ(refusalOf("base = \"no-such-base.toml\"\n"), "r.toml:1: base: no-such-base.toml: cannot open for reading (No such file or directory)");
  EXPECT_EQ(refusalOf("base = \"/dev/zero\"\n"),
            "r.toml:1: base: /dev/zero: is a device or socket, not a randomisation file (it would be read without end)");
  EXPECT_EQ(refusalOf("base = \"" + folder.string() + "\"\n"), "r.toml:1: base: " + folder.string() + ": is a folder, not a randomisation file");
  EXPECT_EQ(refusalOf("base = \"\"\n"), "r.toml:1: base must name a randomisation file");
  const std::string large = write("large.toml", std::string((1u << 20) + 1, '#'));
  EXPECT_EQ(refusalOf("base = \"" + large + "\"\n"), "r.toml:1: base: " + large + ": larger than 1048576 bytes, not a randomisation file");
  const std::string loop = write("loop.toml", "base = \"loop.toml\"\n");
  const std::string loop_message = test::configRefusal([&] { loadRandomisation(loop); });
  EXPECT_EQ(loop_message.rfind(loop + ":1: base: " + loop + ":1: base: ", 0), 0u) << loop_message;
  EXPECT_NE(loop_message.find("more than 8 files deep"), std::string::npos) << loop_message;
  std::filesystem::remove_all(folder);
}

// Each shipped recipe is the default randomisation but for what its comment says it changes: the
// airframe randomisation adds synthetic airframes, the geometric one flies the geometric controller
// alone. (Written as `base` recipes, so the test holds them to it.)
TEST(RandomisationFile, TheShippedRecipesDifferFromTheDefaultOnlyWhereTheySay) {
  const Randomisation fallback = loadRandomisation(kDefault);
  const Randomisation airframe_recipe = loadRandomisation(kAirframes);
  Randomisation airframes = airframe_recipe;
  EXPECT_TRUE(airframes.airframes.enabled());
  airframes.airframes = fallback.airframes;
  EXPECT_EQ(randomisationToText(airframes), randomisationToText(fallback));
  Randomisation geometric = loadRandomisation(kGeometric);
  EXPECT_EQ(geometric.controllers.geometric, 1.0);
  EXPECT_EQ(geometric.controllers.lqr + geometric.controllers.pid + geometric.controllers.cbf, 0.0);
  EXPECT_EQ(geometric.controllers.gain_scale.lo, fallback.controllers.gain_scale.lo);
  EXPECT_EQ(geometric.controllers.gain_scale.hi, fallback.controllers.gain_scale.hi);
  geometric.controllers = fallback.controllers;
  EXPECT_EQ(randomisationToText(geometric), randomisationToText(fallback));
  Randomisation synthetic = loadRandomisation(std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-synthetic-airframes.toml");
  EXPECT_EQ(synthetic.airframes.share, 1.0);
  synthetic.airframes.share = airframe_recipe.airframes.share;
  EXPECT_EQ(randomisationToText(synthetic), randomisationToText(airframe_recipe));
  Randomisation heading = loadRandomisation(kHeading);
  EXPECT_TRUE(heading.manoeuvres.headingEnabled());
  EXPECT_EQ(heading.manoeuvres.figure_eight, 0.0);  // still held out for E7
  heading.manoeuvres.facing_velocity = heading.manoeuvres.yaw_sweep = 0.0;
  heading.manoeuvres.yaw_sweep_amplitude = fallback.manoeuvres.yaw_sweep_amplitude;
  heading.manoeuvres.yaw_sweep_period = fallback.manoeuvres.yaw_sweep_period;
  EXPECT_NEAR(heading.manoeuvres.facing_velocity_yaw_rate_max, 60.0 * M_PI / 180.0, 1e-15);  // ArduPilot ATC_SLEW_YAW's default
  heading.manoeuvres.facing_velocity_yaw_rate_max = 0.0;
  EXPECT_EQ(randomisationToText(heading), randomisationToText(fallback));
}

// The heading keys read, round trip through the text a model file records, are left out of it
// when no flight turns (every earlier model's text unchanged), and bad values are named.
TEST(RandomisationFile, HeadingKeysParseRoundTripAndAreLeftOutWhenNoFlightTurns) {
  const Randomisation r = randomisationFromText(
      "vehicles = [\"nominal\"]\n[manoeuvres]\nfacing_velocity = 0.25\nyaw_sweep = 0.5\nyaw_sweep_amplitude = [0.1, 0.9]\n"
      "yaw_sweep_period = [2, 6]\nfacing_velocity_yaw_rate_max = 0.785\n",
      "h.toml");
  EXPECT_EQ(r.manoeuvres.facing_velocity_yaw_rate_max, 0.785);
  EXPECT_EQ(r.manoeuvres.facing_velocity, 0.25);
  EXPECT_EQ(r.manoeuvres.yaw_sweep, 0.5);
  EXPECT_EQ(r.manoeuvres.yaw_sweep_amplitude.hi, 0.9);
  EXPECT_EQ(r.manoeuvres.yaw_sweep_period.lo, 2.0);
  const std::string text = randomisationToText(r);
  EXPECT_NE(text.find("manoeuvres.yaw_sweep_period = [2, 6]"), std::string::npos);
  EXPECT_NE(text.find("manoeuvres.facing_velocity_yaw_rate_max = 0.785"), std::string::npos);
  EXPECT_EQ(randomisationToText(randomisationFromText(text, "model")), text);
  Randomisation unlimited = r;  // a limit of 0 (none) is left out: earlier heading models' text unchanged
  unlimited.manoeuvres.facing_velocity_yaw_rate_max = 0.0;
  EXPECT_EQ(randomisationToText(unlimited).find("yaw_rate_max"), std::string::npos);
  EXPECT_EQ(randomisationToText(loadRandomisation(kDefault)).find("yaw_sweep"), std::string::npos);
  EXPECT_EQ(randomisationToText(loadRandomisation(kDefault)).find("facing_velocity"), std::string::npos);
  EXPECT_EQ(refusalOf("vehicles = [\"nominal\"]\n[manoeuvres]\nfacing_velocity = 2\n"),
            "r.toml: randomisation: manoeuvres.facing_velocity and manoeuvres.yaw_sweep are shares in [0, 1]");
  EXPECT_EQ(refusalOf("vehicles = [\"nominal\"]\n[manoeuvres]\nyaw_sweep = 0.5\nyaw_sweep_amplitude = [0, 4]\n"),
            "r.toml: randomisation: manoeuvres.yaw_sweep_amplitude must lie in [0, pi] rad");
  EXPECT_EQ(refusalOf("vehicles = [\"nominal\"]\n[manoeuvres]\nfacing_velocity = 0.5\nfacing_velocity_yaw_rate_max = -1\n"),
            "r.toml: randomisation: manoeuvres.facing_velocity_yaw_rate_max must be finite and >= 0 rad/s (0: no limit)");
}

TEST(RandomisationFile, WindKeysParseAndWindWithoutDragIsRefusedAtTheFile) {
  const Randomisation r = randomisationFromText(
      "vehicles = [\"nominal\"]\n[wind]\nrotor_drag = [0.2, 0.3]\nmean_speed = [1, 4]\nturbulence_std = [0, 1]\n"
      "turbulence_tau = [0.5, 2]\ngust_rate = [0, 0.1]\ngust_peak = [0, 3]\ngust_duration = [0.5, 1.5]\n",
      "w.toml");
  EXPECT_EQ(r.wind.rotor_drag.hi, 0.3);
  EXPECT_EQ(r.wind.mean_speed.lo, 1.0);
  EXPECT_EQ(r.wind.gust_duration.hi, 1.5);
  EXPECT_NE(randomisationToText(r).find("wind.gust_peak = [0, 3]"), std::string::npos);
  try {
    randomisationFromText("vehicles = [\"nominal\"]\n[wind]\nmean_speed = [1, 4]\n", "w.toml");
    ADD_FAILURE() << "wind without drag was taken";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "w.toml: randomisation: wind without rotor drag has no effect: set wind.rotor_drag");
  }
}

// The same flights in still air and in the default randomisation's wind: the wind moves the
// vehicle (its drawn drag and air differ per flight) and nothing else of the draw.
TEST(RandomisationFile, WindPushesTheFlightsOffTheirStillAirPath) {
  RolloutConfig windy;
  windy.randomisation = loadRandomisation(kDefault);
  ASSERT_TRUE(windy.randomisation.wind.enabled());
  windy.randomisation.wind.mean_speed = {4.0, 5.0};
  windy.seed = 5;
  windy.post_fault_steps = 200;
  RolloutConfig still = windy;
  still.randomisation.wind = WindRanges{};
  const RolloutEngine w(windy), s(still);
  const std::vector<TrajectoryJob> jobs = algorithm1Jobs(0, 6, {1.0}, {2});
  TrajectoryBatch bw, bs;
  ASSERT_TRUE(w.run(jobs, 1, bw));
  ASSERT_TRUE(s.run(jobs, 1, bs));
  for (int t = 0; t < bw.count; ++t) {
    int tries_w = 0, tries_s = 0;
    const FlightDraw dw = w.flightDraw(static_cast<std::uint64_t>(t), &tries_w), ds = s.flightDraw(static_cast<std::uint64_t>(t), &tries_s);
    EXPECT_GT(dw.plant.linear_drag, 0.0);
    if (tries_w == 1 && tries_s == 1) {  // a redraw (unflyable first draw) takes another stream
      EXPECT_EQ(dw.controller, ds.controller);
      EXPECT_EQ(dw.manoeuvre.kind, ds.manoeuvre.kind);
    }
  }
  double largest = 0.0;  // position difference over the batch [m]
  for (std::size_t i = 0; i < bw.outputs.size(); i += kOutputDim)
    for (int c = 0; c < 3; ++c) largest = std::max(largest, std::abs(double(bw.outputs[i + c]) - double(bs.outputs[i + c])));
  EXPECT_GT(largest, 0.01);
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

// The heading recipe's flights, healthy, every controller, nose along the path and sweeping: every
// one stays up and the yaw does move.
TEST(RandomisationFile, TurningFlightsStayUp) {
  RolloutConfig c;
  c.randomisation = loadRandomisation(kHeading);
  c.randomisation.manoeuvres.facing_velocity = 1.0;
  c.randomisation.manoeuvres.yaw_sweep = 1.0;
  c.seed = 5;
  c.post_fault_steps = 300;
  const RolloutEngine engine(c);
  ASSERT_EQ(engine.error(), "");
  TrajectoryBatch batch;
  ASSERT_TRUE(engine.run(algorithm1Jobs(0, 45, {1.0}, {2}), 2, batch));
  for (int t = 0; t < batch.count; ++t) {
    const FlightDraw d = engine.flightDraw(batch.scenario_index[static_cast<std::size_t>(t)]);
    EXPECT_GT(d.manoeuvre.yaw_sweep_amplitude, 0.0);
    EXPECT_EQ(batch.length[static_cast<std::size_t>(t)], batch.samples)
        << "cut: " << c.randomisation.vehicle_names[static_cast<std::size_t>(d.vehicle)] << " " << toString(d.controller)
        << " manoeuvre " << toString(d.manoeuvre.kind) << " sweep " << d.manoeuvre.yaw_sweep_amplitude << " rad / "
        << d.manoeuvre.yaw_sweep_period << " s";
  }
  for (float u : batch.inputs) ASSERT_TRUE(std::isfinite(u));
  int turning = 0;  // flights whose yaw moves over the recorded window (the sweep's slowest: 0.13 rad/s)
  for (int t = 0; t < batch.count; ++t) {
    const double first = double(batch.outputs[batch.sampleOffset(t, 0) * kOutputDim + 5]);
    double moved = 0.0;
    for (int k = 0; k < batch.samples; ++k)
      moved = std::max(moved, std::abs(wrapAngle(double(batch.outputs[batch.sampleOffset(t, k) * kOutputDim + 5]) - first)));
    turning += moved > 0.01;
  }
  EXPECT_GE(turning, batch.count * 3 / 4);
}

// E7 holds the geometric controller out: no shipped randomisation flies it, and the key reads.
TEST(RandomisationFile, TheShippedTrainingFliesNoGeometricControllerAndTheKeyReads) {
  for (const std::string& file : {kDefault, kAirframes}) EXPECT_EQ(loadRandomisation(file).controllers.geometric, 0.0) << file;
  const Randomisation r = randomisationFromText(
      "vehicles = [\"nominal\"]\ncontrollers.lqr = 0\ncontrollers.geometric = 2\n", "r.toml");
  EXPECT_EQ(r.controllers.geometric, 2.0);
  EXPECT_EQ(refusalOf("vehicles = [\"nominal\"]\ncontrollers.lqr = 0\n"),
            "r.toml: randomisation: some controller weight must be > 0");
}

// The same healthy flights as above under the geometric controller alone, its gains spread as
// E7's PID cells are (×0.5 … ×2): every one stays up, on every library vehicle.
TEST(RandomisationFile, GeometricControllerFliesTheRandomisedFlights) {
  RolloutConfig c;
  c.randomisation = loadRandomisation(kDefault);
  c.randomisation.manoeuvres.figure_eight = 0.2;
  c.randomisation.controllers.lqr = c.randomisation.controllers.pid = c.randomisation.controllers.cbf = 0.0;
  c.randomisation.controllers.geometric = 1.0;
  c.randomisation.controllers.gain_scale = {0.5, 2.0};
  c.seed = 3;
  c.post_fault_steps = 300;
  const RolloutEngine engine(c);
  ASSERT_EQ(engine.error(), "");
  TrajectoryBatch batch;
  ASSERT_TRUE(engine.run(algorithm1Jobs(0, 60, {1.0}, {2}), 2, batch));
  for (int t = 0; t < batch.count; ++t) {
    const FlightDraw d = engine.flightDraw(batch.scenario_index[static_cast<std::size_t>(t)]);
    ASSERT_EQ(d.controller, DrawnController::kGeometric);
    EXPECT_EQ(batch.length[static_cast<std::size_t>(t)], batch.samples)
        << "cut: " << c.randomisation.vehicle_names[static_cast<std::size_t>(d.vehicle)] << " gain " << d.gain_scale
        << " manoeuvre " << toString(d.manoeuvre.kind) << " speed " << d.manoeuvre.speed;
  }
  for (float u : batch.inputs) ASSERT_TRUE(std::isfinite(u));
}

}  // namespace
}  // namespace quadfdi
