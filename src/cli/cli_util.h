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

// Creates `path` unless it already exists.
inline void ensureDirectory(const std::string& path) {
  if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST) throw std::runtime_error(path + ": cannot create the folder");
}

}  // namespace quadfdi::cli
