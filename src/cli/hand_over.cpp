#include "cli/hand_over.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "cli/shipped_files.h"

namespace quadfdi::cli {

int handOverToTraining(int argc, char** argv) {
  const char* command = argc > 1 ? argv[1] : "";
#ifdef QUADFDI_TRAINING_EXECUTABLE
  // Next to this executable's file, links resolved: the build tree and an installed copy keep
  // the two side by side, and a link to quadfdi elsewhere on the PATH still finds it.
  const std::string training = (std::filesystem::path(executablePath(argv[0])).parent_path() / QUADFDI_TRAINING_EXECUTABLE).string();
  ::execv(training.c_str(), argv);
  std::cerr << "quadfdi: error: " << command << " runs in " << training << ", which could not be started: "
            << std::strerror(errno) << "\n";
#else
  std::cerr << "quadfdi: error: " << command
            << " needs LibTorch, and this quadfdi was built without it (QUADFDI_WITH_TRAINING=OFF)\n";
#endif
  return 1;
}

}  // namespace quadfdi::cli
