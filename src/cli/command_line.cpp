#include "cli/command_line.h"

#include <exception>
#include <iostream>

#include "cli/interrupt.h"

namespace quadfdi::cli {

int runCommandLine(CLI::App& app, int argc, char** argv, const std::function<int(const std::string&)>& run) {
  try {
    // Parsing also resolves the converted commands' option tables (cli/options.h): a bad value,
    // or a bad --config file, throws a one-line OptionError / ConfigError, reported below (exit 1).
    app.parse(argc, argv);
    std::string command_line = "quadfdi";
    for (int i = 1; i < argc; ++i) command_line += std::string(" ") + argv[i];
    return run(command_line);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {  // usage: unknown flag, wrong number of values, no subcommand
    std::cerr << "quadfdi: error: " << e.what() << " (see --help)\n";
    return 2;
  } catch (const Interrupted& e) {
    std::cerr << "quadfdi: interrupted: " << e.what() << "\n";
    return 130;
  } catch (const std::exception& e) {
    std::cerr << "quadfdi: error: " << e.what() << "\n";
    return 1;
  }
}

const CommandSummary* trainingCommand(const std::string& name) {
  for (const CommandSummary& command : kTrainingCommands)
    if (name == command.name) return &command;
  return nullptr;
}

}  // namespace quadfdi::cli
