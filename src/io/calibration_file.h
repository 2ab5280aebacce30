// The sequential rule's calibration (detection/calibration.h) as a JSON sidecar file next to the
// model (docs/decisions.md "Calibration file"): `quadfdi calibrate` writes it, `quadfdi detect
// --calibration FILE` reads it. A sidecar, not a key in the .qfdw metadata: a calibration belongs
// to a model *and* the flights it was measured on, and is redone without retraining.
#pragma once

#include <string>

#include "detection/calibration.h"

namespace quadfdi {

std::string calibrationToJson(const DecisionCalibration& c);  // pretty-printed, one key per line
// Throws ConfigError("WHERE: problem") for bad JSON, a missing key or a value out of range.
DecisionCalibration calibrationFromJson(const std::string& text, const std::string& where);

DecisionCalibration readCalibrationFile(const std::string& path);        // ConfigError("PATH: problem")
void writeCalibrationFile(const std::string& path, const DecisionCalibration& c);  // atomically

}  // namespace quadfdi
