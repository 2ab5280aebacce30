// Small helpers shared by the subcommands (edge code: they throw one-line errors).
#pragma once

#include <sys/stat.h>

#include <cerrno>
#include <stdexcept>
#include <string>

namespace quadfdi::cli {

inline void require(bool ok, const std::string& problem) {
  if (!ok) throw std::runtime_error(problem);
}

// Creates `path` and its missing parents (like mkdir -p).
inline void ensureDirectory(const std::string& path) {
  for (std::size_t slash = path.find('/', 1); ; slash = path.find('/', slash + 1)) {
    const std::string prefix = path.substr(0, slash);
    if (!prefix.empty() && mkdir(prefix.c_str(), 0755) != 0 && errno != EEXIST)
      throw std::runtime_error(prefix + ": cannot create the folder");
    if (slash == std::string::npos) break;
  }
  struct stat st {};
  if (stat(path.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) throw std::runtime_error(path + ": not a folder");
}

}  // namespace quadfdi::cli
