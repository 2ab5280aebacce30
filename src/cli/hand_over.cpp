#include "cli/hand_over.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <system_error>

namespace quadfdi::cli {

int handOverToTraining(int argc, char** argv) {
  const char* command = argc > 1 ? argv[1] : "";
#ifdef QUADFDI_TRAINING_EXECUTABLE
  // Next to this executable's file, links resolved: the build tree and an installed copy keep
  // the two side by side, and a link to quadfdi elsewhere on the PATH still finds it.
  std::error_code error;
  std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) self = std::filesystem::absolute(argv[0], error);
  const std::string training = (self.parent_path() / QUADFDI_TRAINING_EXECUTABLE).string();
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
