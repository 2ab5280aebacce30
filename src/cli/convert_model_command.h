#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace quadfdi::cli {

struct ConvertModelOptions {
  std::string input;   // a format-1 LibTorch model archive (.qfdi)
  std::string output;  // the weights file (.qfdw)
};

CLI::App* addConvertModelCommand(CLI::App& app, ConvertModelOptions& options);
int runConvertModel(const ConvertModelOptions& options);

}  // namespace quadfdi::cli
