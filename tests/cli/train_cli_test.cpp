// quadfdi train through the executable: a tiny run, one-line errors, and a run killed with
// SIGKILL mid-way that --resume completes.
#include <gtest/gtest.h>

#include "cli/cli_support.h"
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

namespace {

using Result = quadfdi::test::CommandResult;
Result run(const std::string& args) { return quadfdi::test::runQuadfdi(args); }

std::string temp(const std::string& name) { return ::testing::TempDir() + "quadfdi_train_cli_" + name; }
bool exists(const std::string& path) { return access(path.c_str(), F_OK) == 0; }
const char* kFast = " --scale tiny --batch-size 64 --max-minibatches 2 --threads 2 -q";

TEST(TrainCli, TinyRunWritesModelLogAndCheckpoint) {
  const std::string model = temp("tiny.qfdi");
  const Result r = run("train --max-iterations 1 -o " + model + kFast);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(exists(model));
  EXPECT_TRUE(exists(model + ".ckpt"));
  std::ifstream f(model);
  std::string first;
  std::getline(f, first);
  EXPECT_EQ(first, "quadfdi-model 1");
}

TEST(TrainCli, BadArgumentsGiveOneLineErrors) {
  const std::string model = temp("bad.qfdi");
  for (const std::string& args : {std::string("train --architecture gru -o ") + model,
                                  std::string("train --features everything -o ") + model,
                                  std::string("train --scale huge -o ") + model,
                                  std::string("train --device tpu -o ") + model,
                                  std::string("train --thetas 2 -o ") + model, std::string("train")}) {
    const Result r = run(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << args << "\n" << r.out;
  }
}

TEST(TrainCli, KilledRunResumesFromItsCheckpoint) {
  const std::string model = temp("killed.qfdi"), ckpt = model + ".ckpt", log = model + ".log.csv";
  std::remove(model.c_str());
  std::remove(ckpt.c_str());
  const std::string args = "train --max-iterations 4 --min-iterations 4 -o " + model + kFast;
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", (std::string("exec ") + QUADFDI_EXE + " " + args + " 2>/dev/null").c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  // Kill it as soon as the first checkpoint is there (mid-way through iteration 2).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!exists(ckpt) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(exists(ckpt)) << "no checkpoint within the deadline";
  EXPECT_FALSE(exists(model)) << "the run finished before it could be killed";
  const Result resumed = run(args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out;
  EXPECT_TRUE(exists(model));
  std::ifstream f(log);
  std::string line;
  int rows = -1;  // header
  while (std::getline(f, line)) ++rows;
  EXPECT_EQ(rows, 4);
}

}  // namespace
