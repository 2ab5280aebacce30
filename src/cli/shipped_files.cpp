#include "cli/shipped_files.h"

#include <algorithm>
#include <filesystem>
#include <system_error>
#include <vector>

// Set by src/CMakeLists.txt: the source tree's root, and the installed data folder relative to the
// installed executable's (GNUInstallDirs' bin and share: ../share/quadfdi).
#ifndef QUADFDI_SOURCE_DATA_DIR
#define QUADFDI_SOURCE_DATA_DIR "."
#endif
#ifndef QUADFDI_INSTALLED_DATA_FROM_BIN
#define QUADFDI_INSTALLED_DATA_FROM_BIN "../share/quadfdi"
#endif

namespace quadfdi::cli {
namespace fs = std::filesystem;

namespace {
// The error_code overloads: a name the file system rejects (too long, …) is "not there", never
// an exception; the reader then refuses it in one line.
bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

bool isBareName(const std::string& path) { return !path.empty() && path.find('/') == std::string::npos; }
}  // namespace

std::string executablePath(const char* argv0) {
  std::error_code error;
  fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error && argv0 != nullptr) self = fs::absolute(argv0, error);
  return error ? std::string() : self.string();
}

std::string shippedDataDir() {
  const std::string self = executablePath(nullptr);
  if (!self.empty()) {
    const fs::path installed = (fs::path(self).parent_path() / QUADFDI_INSTALLED_DATA_FROM_BIN).lexically_normal();
    if (isFile(installed / "models" / kGeneralModelName)) return installed.string();
  }
  return QUADFDI_SOURCE_DATA_DIR;
}

std::string shippedModelsDir() { return (fs::path(shippedDataDir()) / "models").string(); }

std::string vehicleLibraryDir() { return (fs::path(shippedDataDir()) / "configs" / "vehicles").string(); }

std::string shippedFile(const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute() || isFile(path)) return path;
  const fs::path shipped = fs::path(shippedDataDir()) / path;
  return isFile(shipped) ? shipped.string() : path;
}

std::string vehicleFile(const std::string& path, std::string* problem) {
  const std::string found = shippedFile(path);
  if (found != path || !isBareName(path) || isFile(path)) return found;
  const fs::path given(path);
  const std::string name = given.extension() == ".toml" ? given.stem().string() : path;
  const fs::path library_dir = vehicleLibraryDir();
  const fs::path library = library_dir / (name + ".toml");
  if (isFile(library)) return library.string();
  if (problem) {
    std::vector<std::string> names;
    std::error_code ec;
    for (fs::directory_iterator it(library_dir, ec), end; !ec && it != end; it.increment(ec))
      if (it->path().extension() == ".toml" && isFile(it->path())) names.push_back(it->path().stem().string());
    std::sort(names.begin(), names.end());
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    *problem = "no such file, and no vehicle " + name + " in the library " + library_dir.string() + ": " +
               (list.empty() ? "it is empty" : list);
  }
  return path;
}

}  // namespace quadfdi::cli
