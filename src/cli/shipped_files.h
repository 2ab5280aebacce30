// Where the files quadfdi ships with are found at run time: the installed layout
// (PREFIX/bin/quadfdi beside PREFIX/share/quadfdi/{models,configs}, `cmake --install`), else the
// source tree the executable was built from. Edge code: it reads the file system.
#pragma once

#include <string>

namespace quadfdi::cli {

// The shipped general model's file name (models/README.md).
inline constexpr const char* kGeneralModelName = "tcn-randomised.qfdw";
// The general model on body rates: run instead of kGeneralModelName where the telemetry carries
// p, q, r and no vehicle model was chosen, when that file lies beside it (none ships: models/README.md).
inline constexpr const char* kGeneralRatesModelName = "tcn-randomised-rates.qfdw";

// This process's executable, links resolved (/proc/self/exe); ARGV0 made absolute where that
// cannot be read (null: "" then).
std::string executablePath(const char* argv0);

// The folder holding the shipped models/ and configs/: PREFIX/share/quadfdi when this executable
// runs from PREFIX/bin and that folder holds the general model; else the source tree's root.
std::string shippedDataDir();
std::string shippedModelsDir();   // shippedDataDir()/models
std::string vehicleLibraryDir();  // shippedDataDir()/configs/vehicles

// A file option's value as it is opened: PATH itself when it names an existing file, is absolute
// or empty; else shippedDataDir()/PATH when that exists (so "configs/randomisation-default.toml"
// and "models/tcn-quad450.qfdw" work from any folder with an installed quadfdi, and inside config
// files); else PATH, for its reader to refuse.
std::string shippedFile(const std::string& path);

// A --vehicle value as it is opened: shippedFile(PATH), and a bare library name ("quad450", or
// "quad450.toml" where no such file is here) as vehicleLibraryDir()/NAME.toml. A bare name that is
// neither is returned as given, and PROBLEM (when given) says so, naming the library's vehicles
// ("no such file, and no vehicle x500 in the library DIR: crazyflie2, quad450, racer250").
std::string vehicleFile(const std::string& path, std::string* problem = nullptr);

}  // namespace quadfdi::cli
