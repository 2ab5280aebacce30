// Vehicle parameter files: a named set or a key = value file (see configs/vehicle-example.toml).
#pragma once

#include <string>

#include "model/vehicle_params.h"

namespace quadfdi {

// `spec` is "nominal", "perturbed", "perturbed-strong" or a path to a file: a vehicle
// description (it has [motor.N] sections; io/vehicle_file.h, docs/vehicles.md) or a parameter file.
// A file may start from a named set with `base = "nominal"` and override any field of
// VehicleParams by name. Throws ConfigError("FILE:LINE: problem") on bad input.
VehicleParams loadVehicleParams(const std::string& spec);
VehicleParams vehicleParamsFromText(const std::string& text, const std::string& source);

// The file form of a parameter set (round-trips through vehicleParamsFromText).
std::string vehicleParamsToText(const VehicleParams& params);

}  // namespace quadfdi
