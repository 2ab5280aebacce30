// Randomisation files (configs/randomisation-*.toml, docs/data.md#randomisation): which vehicles
// to fly and how widely to spread the plant, the estimator, the controllers and the manoeuvres.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "data/randomisation.h"

namespace quadfdi {

// `vehicles = ["configs/vehicles/crazyflie2.toml", …]` are resolved relative to the file's folder
// when relative and not found from the working directory. `base = "FILE"`, if given as the first
// key, starts from that randomisation (relative to this file's folder; it must be valid on its own)
// and every key of this file overrides it — `vehicles` replaces the base's list. Throws
// ConfigError("FILE:LINE: problem") on unknown keys, bad values, a vehicle or a base that cannot be
// loaded (a base's own error follows "FILE:LINE: base: ").
// `resolve`, when given, finds a vehicle that is neither a file nor beside this one by its name:
// the model files record the library's vehicles by name ("quad450"), which only the executable
// knows where to find (cli::vehicleFile); it returns the description's path, or "" for none.
using VehicleNameResolver = std::function<std::string(const std::string& name)>;
Randomisation randomisationFromText(const std::string& text, const std::string& source,
                                    const VehicleNameResolver& resolve = {});
Randomisation loadRandomisation(const std::string& path);

// `--vehicle FILE …` of train and calibrate: these vehicles are flown instead of the file's, and
// without its synthetic airframes (a user naming a vehicle means that vehicle). Throws as
// loadVehicleParams on a file it cannot load.
void flyOnlyVehicles(Randomisation& r, const std::vector<std::string>& vehicle_files);

// The file form (vehicles by name, as recorded in model files); round-trips the ranges.
std::string randomisationToText(const Randomisation& r);

}  // namespace quadfdi
