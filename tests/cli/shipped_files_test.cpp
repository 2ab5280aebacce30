// Shipped files (cli/shipped_files.h) through the option table: a file option not found as given
// is opened from the shipped tree (this build tree's: the source root), a bare library name is
// the library's vehicle description, an unknown one is refused naming the library, and a file
// that is there as given, or an option not marked as a shipped file, is taken as given.
#include "cli/shipped_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cli/options.h"
#include "scratch_path.h"

namespace quadfdi::cli {
namespace {
namespace fs = std::filesystem;

struct FileOptions {
  std::string config, model, output, params = "nominal";
  std::vector<std::string> vehicles;
};

// Parses `args` for a command with a model (shipped file), vehicles and a plain output option.
FileOptions parsed(std::vector<std::string> args) {
  FileOptions o;
  CLI::App app{"test"};
  CLI::App* cmd = app.add_subcommand("demo", "A demo command");
  auto t = std::make_shared<OptionTable>();
  t->addConfigFile(o.config);
  t->add("--model", o.model, "Model").shippedFile();
  t->add("--vehicle", o.vehicles, "Vehicles").vehicleFile();
  t->add("--output", o.output, "Output");
  t->add("--params", o.params, "Plant").paramsFile();
  attachOptions(*cmd, t);
  args.insert(args.begin(), "demo");
  std::reverse(args.begin(), args.end());  // CLI11 takes them last-first
  app.parse(args);
  return o;
}

// Runs in a scratch folder away from the source tree, and goes back.
class ShippedFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    home_ = fs::current_path();
    here_ = quadfdi::test::scratchPath("shipped", "cwd");
    fs::create_directories(here_);
    fs::current_path(here_);
  }
  void TearDown() override {
    fs::current_path(home_);
    fs::remove_all(here_);
  }
  fs::path home_, here_;
};

const std::string kSource = QUADFDI_SOURCE_DIR;

TEST_F(ShippedFiles, ABuildTreeShipsItsSourceTree) {
  EXPECT_EQ(fs::canonical(shippedDataDir()), fs::canonical(kSource));
  EXPECT_EQ(fs::canonical(shippedModelsDir()), fs::canonical(kSource + "/models"));
  EXPECT_TRUE(fs::is_regular_file(fs::path(shippedModelsDir()) / kGeneralModelName));
}

TEST_F(ShippedFiles, AShippedPathIsFoundFromAnyFolderAndALibraryNameIsItsVehicle) {
  const FileOptions o = parsed({"--model", "models/tcn-quad450.qfdw", "--vehicle", "quad450", "--vehicle", "racer250.toml",
                               "--vehicle", "configs/vehicles/crazyflie2.toml", "--output", "models/tcn-quad450.qfdw"});
  EXPECT_EQ(fs::canonical(o.model), fs::canonical(kSource + "/models/tcn-quad450.qfdw"));
  ASSERT_EQ(o.vehicles.size(), 3u);
  EXPECT_EQ(fs::canonical(o.vehicles[0]), fs::canonical(kSource + "/configs/vehicles/quad450.toml"));
  EXPECT_EQ(fs::canonical(o.vehicles[1]), fs::canonical(kSource + "/configs/vehicles/racer250.toml"));
  EXPECT_EQ(fs::canonical(o.vehicles[2]), fs::canonical(kSource + "/configs/vehicles/crazyflie2.toml"));
  EXPECT_EQ(o.output, "models/tcn-quad450.qfdw");  // written where asked, never into the shipped tree
}

TEST_F(ShippedFiles, AFileThatIsHereWinsAndAMissingPathIsLeftForItsReader) {
  std::ofstream("quad450") << "# a user's own file, named like a library vehicle\n";
  fs::create_directories("models");
  std::ofstream("models/tcn-quad450.qfdw") << "mine";
  const FileOptions o = parsed({"--vehicle", "quad450", "--model", "models/tcn-quad450.qfdw"});
  EXPECT_EQ(o.vehicles, std::vector<std::string>{"quad450"});
  EXPECT_EQ(o.model, "models/tcn-quad450.qfdw");
  // Not here and not shipped: unchanged, so that the reader names it as given.
  EXPECT_EQ(parsed({"--model", "models/nope.qfdw", "--vehicle", "configs/vehicles/nope.toml"}).model, "models/nope.qfdw");
  EXPECT_EQ(shippedFile("/nowhere/models/tcn-quad450.qfdw"), "/nowhere/models/tcn-quad450.qfdw");  // absolute: as given
  EXPECT_EQ(shippedFile(""), "");
}

TEST_F(ShippedFiles, AnUnknownVehicleNameIsRefusedNamingTheLibrary) {
  try {
    parsed({"--vehicle", "x500"});
    ADD_FAILURE() << "no error";
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "--vehicle: no such file, and no vehicle x500 in the library " + vehicleLibraryDir() +
                                         ": crazyflie2, quad450, racer250");
  }
}

// --params: the named sets as they are, a library vehicle by name as --vehicle takes it.
TEST_F(ShippedFiles, PlantParametersTakeANamedSetOrALibraryVehicle) {
  EXPECT_EQ(parsed({"--params", "perturbed-strong"}).params, "perturbed-strong");
  EXPECT_EQ(fs::path(parsed({"--params", "quad450"}).params), fs::path(vehicleLibraryDir()) / "quad450.toml");
  try {
    parsed({"--params", "x500"});
    ADD_FAILURE() << "no error";
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "--params: not nominal, perturbed or perturbed-strong; no such file, and no vehicle "
                                     "x500 in the library " + vehicleLibraryDir() + ": crazyflie2, quad450, racer250");
  }
}

TEST_F(ShippedFiles, AConfigFileAndThePathsInItAreFoundInTheShippedTree) {
  std::ofstream("demo.toml") << "model = \"models/tcn-racer250.qfdw\"\nvehicle = [\"racer250\"]\n";
  const FileOptions o = parsed({"--config", "demo.toml"});
  EXPECT_EQ(fs::canonical(o.model), fs::canonical(kSource + "/models/tcn-racer250.qfdw"));
  ASSERT_EQ(o.vehicles.size(), 1u);
  EXPECT_EQ(fs::canonical(o.vehicles[0]), fs::canonical(kSource + "/configs/vehicles/racer250.toml"));
  // A shipped config file named by its path in the tree: read from there (its keys are train's,
  // unknown here, so the refusal names the shipped file).
  try {
    parsed({"--config", "configs/train-tcn-vehicle.toml"});
    ADD_FAILURE() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(kSource + "/configs/train-tcn-vehicle.toml:"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace quadfdi::cli
