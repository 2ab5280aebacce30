// The decision calibrations shipped in models/: every one reads and validates; the randomised
// models' read Θ̂ against the other motors and the paper's models' read it as given (the
// reproduction's rule); and a calibration for one airframe (MODEL.STEM.calibration.json, which
// detect --vehicle STEM.toml picks) names a model that exists and a described vehicle, so that a
// misspelt name cannot ship a calibration nothing ever runs; and each records the CRC of the
// weights file beside it.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "io/calibration_file.h"
#include "io/model_file.h"

namespace quadfdi {
namespace {

const std::filesystem::path kModels = std::filesystem::path(QUADFDI_SOURCE_DIR) / "models";
const std::string kSuffix = ".calibration.json";

TEST(ShippedCalibrations, ReadWithTheirReferencesAndNameWhatTheyCalibrate) {
  int files = 0, for_vehicles = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kModels)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= kSuffix.size() || name.compare(name.size() - kSuffix.size(), kSuffix.size(), kSuffix) != 0) continue;
    ++files;
    const DecisionCalibration c = readCalibrationFile(entry.path().string());  // throws on a bad file
    const std::string stem = name.substr(0, name.size() - kSuffix.size());     // MODEL or MODEL.VEHICLE
    const std::size_t dot = stem.find('.');
    const std::string model = stem.substr(0, dot);
    EXPECT_TRUE(std::filesystem::is_regular_file(kModels / (model + ".qfdw"))) << name << ": no model " << model << ".qfdw";
    if (dot != std::string::npos) {
      ++for_vehicles;
      const std::string vehicle = stem.substr(dot + 1);
      EXPECT_TRUE(std::filesystem::is_regular_file(kModels.parent_path() / "configs" / "vehicles" / (vehicle + ".toml")))
          << name << ": no configs/vehicles/" << vehicle << ".toml";
    }
    // The paper's models keep the paper's rule; every randomised model's calibration reads each
    // motor against its siblings and estimates on the network's own Θ̂ (docs/decisions.md).
    const bool paper = model == "tcn-model-free" || model == "lstm-model-free";
    EXPECT_EQ(c.reference, paper ? ThetaReference::kAbsolute : ThetaReference::kOthers) << name;
    EXPECT_EQ(c.estimate_reference, ThetaReference::kAbsolute) << name;
    // Made for the model beside it: a model replaced without recalibrating fails here, as detect
    // would refuse the pair.
    ASSERT_TRUE(c.model_crc32.has_value()) << name << ": no model_crc32";
    EXPECT_EQ(calibrationModelProblem(c, readModelFile((kModels / (model + ".qfdw")).string()).file_crc32), "") << name;
  }
  EXPECT_GE(files, 5);
  EXPECT_GE(for_vehicles, 1);
}

}  // namespace
}  // namespace quadfdi
