#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace quadfdi::cli {

struct ReproduceOptions {
  std::string scale = "quick";  // quick | default | paper
  std::string output = "reproduction";
  unsigned long long seed = 1;
  int threads = 0;
  std::string device = "cpu";
  bool quiet = false;
};

CLI::App* addReproduceCommand(CLI::App& app, ReproduceOptions& options);
int runReproduce(const ReproduceOptions& options, const std::string& command_line);

}  // namespace quadfdi::cli
