// quadfdi links no LibTorch and hands train, reproduce and convert-model over to quadfdi-training
// (src/cli/hand_over.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli/cli_support.h"

namespace quadfdi::test {
namespace {

TEST(HandOver, QuadfdiLoadsNoLibTorchAndRunsTheTrainingCommandsThroughQuadfdiTraining) {
  // Library names only (ldd's first field): a load address may contain "c10".
  const CommandResult libraries = runCommand(std::string("ldd ") + QUADFDI_EXE + " | awk '{print $1}'");
  ASSERT_EQ(libraries.exit_code, 0) << libraries.out;
  EXPECT_NE(libraries.out.find("libc.so"), std::string::npos) << libraries.out;
  EXPECT_EQ(libraries.out.find("torch"), std::string::npos) << "quadfdi links LibTorch:\n" << libraries.out;
  EXPECT_EQ(libraries.out.find("c10"), std::string::npos) << libraries.out;

  const CommandResult help = runQuadfdi("--help");
  ASSERT_EQ(help.exit_code, 0) << help.out;
  for (const char* command : {"  train ", "  reproduce ", "  convert-model ", "  detect "})
    EXPECT_NE(help.out.find(command), std::string::npos) << command << " is not listed:\n" << help.out;

  // The option tables are quadfdi-training's: the hand-over kept the arguments.
  const CommandResult train_help = runQuadfdi("train --help");
  EXPECT_EQ(train_help.exit_code, 0) << train_help.out;
  EXPECT_NE(train_help.out.find("--architecture"), std::string::npos) << train_help.out;
  const CommandResult bad_scale = runQuadfdi("train --scale huge -o /nonexistent/model.qfdw");
  EXPECT_EQ(bad_scale.exit_code, 1) << bad_scale.out;
  EXPECT_EQ(bad_scale.out, "quadfdi: error: --scale: 'huge' is not one of: tiny, quick, default, paper\n");
  const CommandResult no_input = runQuadfdi("convert-model");
  EXPECT_EQ(no_input.exit_code, 2) << no_input.out;
  EXPECT_EQ(no_input.out, "quadfdi: error: input is required (see --help)\n");
}

TEST(HandOver, AMissingQuadfdiTrainingIsAOneLineErrorNamingIt) {
  // A copy of quadfdi alone in a folder: detect and the rest still run, train cannot.
  const std::filesystem::path folder = scratchPath("HandOver", "alone");
  std::filesystem::create_directories(folder);
  const std::filesystem::path alone = folder / "quadfdi";
  std::filesystem::copy_file(QUADFDI_EXE, alone, std::filesystem::copy_options::overwrite_existing);
  const CommandResult version = runCommand(alone.string() + " --version 2>&1");
  EXPECT_EQ(version.exit_code, 0) << version.out;
  const CommandResult train = runCommand(alone.string() + " train --scale tiny 2>&1");
  EXPECT_EQ(train.exit_code, 1) << train.out;
  EXPECT_EQ(train.out, "quadfdi: error: train runs in " + (folder / "quadfdi-training").string() +
                           ", which could not be started: No such file or directory\n");
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace quadfdi::test
