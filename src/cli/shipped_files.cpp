#include "cli/shipped_files.h"

#include <filesystem>
#include <system_error>

#include "cli/detect_command.h"

// Set by src/CMakeLists.txt: the source tree's models folder, and the installed models folder
// relative to the installed executable's (GNUInstallDirs' bin and share, e.g. ../share/quadfdi/models).
#ifndef QUADFDI_SOURCE_MODELS_DIR
#define QUADFDI_SOURCE_MODELS_DIR "models"
#endif
#ifndef QUADFDI_INSTALLED_MODELS_FROM_BIN
#define QUADFDI_INSTALLED_MODELS_FROM_BIN "../share/quadfdi/models"
#endif

namespace quadfdi::cli {

std::string executablePath(const char* argv0) {
  std::error_code error;
  std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error && argv0 != nullptr) self = std::filesystem::absolute(argv0, error);
  return error ? std::string() : self.string();
}

std::string shippedModelsDir() {
  const std::string self = executablePath(nullptr);
  if (!self.empty()) {
    const std::filesystem::path installed =
        (std::filesystem::path(self).parent_path() / QUADFDI_INSTALLED_MODELS_FROM_BIN).lexically_normal();
    std::error_code ec;  // unreadable is "not installed": the source tree's folder serves
    if (std::filesystem::is_regular_file(installed / kGeneralModelName, ec)) return installed.string();
  }
  return QUADFDI_SOURCE_MODELS_DIR;
}

}  // namespace quadfdi::cli
