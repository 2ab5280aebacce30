// Where the files quadfdi ships with are found at run time: the installed layout
// (PREFIX/bin/quadfdi beside PREFIX/share/quadfdi/models, `cmake --install`), else the source
// tree the executable was built from. Edge code: it reads the file system.
#pragma once

#include <string>

namespace quadfdi::cli {

// This process's executable, links resolved (/proc/self/exe); ARGV0 made absolute where that
// cannot be read.
std::string executablePath(const char* argv0);

// The folder of the shipped models: PREFIX/share/quadfdi/models when this executable runs from
// PREFIX/bin and that folder holds the general model; else the source tree's models/.
std::string shippedModelsDir();

}  // namespace quadfdi::cli
