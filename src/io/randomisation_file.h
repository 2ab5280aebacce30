// Randomisation files (configs/randomisation-*.toml, docs/data.md#randomisation): which vehicles
// to fly and how widely to spread the plant, the estimator, the controllers and the manoeuvres.
#pragma once

#include <string>

#include "data/randomisation.h"

namespace quadfdi {

// `vehicles = ["configs/vehicles/crazyflie2.toml", …]` are resolved relative to the file's folder
// when relative and not found from the working directory. Throws ConfigError("FILE:LINE: problem")
// on unknown keys, bad values or a vehicle that cannot be loaded.
Randomisation randomisationFromText(const std::string& text, const std::string& source);
Randomisation loadRandomisation(const std::string& path);

// The file form (vehicles by name, as recorded in model files); round-trips the ranges.
std::string randomisationToText(const Randomisation& r);

}  // namespace quadfdi
