// quadfdi train through the executable: a tiny run, one-line errors, runs killed (SIGKILL) or
// interrupted (SIGINT, SIGTERM) mid-way that --resume completes, and no half-written files.
#include <gtest/gtest.h>

#include "cli/cli_support.h"
#include "io/model_file.h"
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <dirent.h>

#include <string>
#include <utility>
#include <vector>
#include <thread>

namespace {

using Result = quadfdi::test::CommandResult;
Result run(const std::string& args) { return quadfdi::test::runQuadfdi(args); }

std::string temp(const std::string& name) { return quadfdi::test::scratchPath("train_cli", name); }
bool exists(const std::string& path) { return access(path.c_str(), F_OK) == 0; }
const char* kFast = " --scale tiny --batch-size 64 --max-minibatches 2 --threads 2 -q";

TEST(TrainCli, TinyRunWritesModelLogAndCheckpoint) {
  const std::string model = temp("tiny.qfdw");
  const Result r = run("train --max-iterations 1 -o " + model + kFast);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(exists(model));
  EXPECT_TRUE(exists(model + ".ckpt"));
  // The model leaves training as a weights file that the LibTorch-free side reads.
  const quadfdi::TrainedModel loaded = quadfdi::readModelFile(model);
  EXPECT_EQ(loaded.metadata.iterations, 1);
  EXPECT_EQ(loaded.metadata.scale, "tiny");
}

// A network trained on body rates runs in detect on telemetry that has them (simulate's full
// state writes p, q, r; a merged export reads them too) and refuses, in one line and writing
// nothing, telemetry without them.
TEST(TrainCli, ABodyRatesModelDetectsOnTelemetryWithRatesAndRefusesItWithout) {
  const std::string model = temp("rates.qfdw"), full = temp("rates_full.csv"), plain = temp("rates_plain.csv"),
                    out = temp("rates_out.jsonl");
  ASSERT_EQ(run("train --max-iterations 1 --features scale-free-rates --architecture tcn --scale tiny --training windows "
                "--batch-size 64 --max-minibatches 2 --threads 2 -q -o " + model).exit_code, 0);
  ASSERT_EQ(run("simulate --motor 2 --steps 600 --full-state -q -o " + full).exit_code, 0);
  ASSERT_EQ(run("simulate --motor 2 --steps 600 -q -o " + plain).exit_code, 0);
  for (const char* format : {"csv", "csv-merged"}) {
    std::remove(out.c_str());
    const Result r = run("detect -q --model " + model + " --format " + format + " --input " + full + " --output " + out);
    EXPECT_EQ(r.exit_code, 0) << format << ": " << r.out;
    EXPECT_TRUE(exists(out)) << format;
  }
  std::remove(out.c_str());
  const Result refused = run("detect -q --model " + model + " --input " + plain + " --output " + out);
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_EQ(refused.out, "quadfdi: error: " + plain + ": the model " + model + " reads body rates (scale-free-rates features) and this "
                         "telemetry has none: give columns p,q,r [rad/s] (docs/conventions.md), a log that records them, or a model "
                         "on scale-free features\n");
  EXPECT_FALSE(exists(out));
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
  // A weight-averaging window longer than the run: named, before any flight is flown.
  const Result longer = run("train --scale tiny --max-iterations 2 --average-last 3 -o " + model);
  EXPECT_NE(longer.exit_code, 0);
  EXPECT_EQ(longer.out, "quadfdi: error: --average-last 3: more iterations than the run has (2)\n");
  EXPECT_FALSE(std::ifstream(model).good());
}

TEST(TrainCli, KilledRunResumesFromItsCheckpoint) {
  const std::string model = temp("killed.qfdi"), ckpt = model + ".ckpt", log = model + ".log.csv";
  std::remove(model.c_str());
  std::remove(ckpt.c_str());
  const std::string args = "train --max-iterations 3 --min-iterations 3 -o " + model + kFast;
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
  EXPECT_EQ(rows, 3);
}

// Starts quadfdi with `args` in the background; stderr goes to `err_path`.
pid_t start(const std::string& args, const std::string& err_path) {
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", (std::string("exec ") + QUADFDI_EXE + " " + args + " 2>" + err_path).c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

// Waits until `pid` has a handler for `signal_number` (Linux: SigCgt in /proc/PID/status), so a
// signal sent next meets the program's handler, not its start-up.
bool waitForHandler(pid_t pid, int signal_number) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("SigCgt:", 0) == 0 && (std::stoull(line.substr(7), nullptr, 16) >> (signal_number - 1)) & 1u)
        return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

int waitExit(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::string text, line;
  while (std::getline(f, line)) text += line + "\n";
  return text;
}

// Files in the temp folder whose name starts with `prefix` and holds ".tmp." (AtomicFileWriter's).
int leftoverTemps(const std::string& prefix) {
  int n = 0;
  DIR* d = opendir(::testing::TempDir().c_str());
  if (!d) return -1;
  while (const dirent* e = readdir(d)) {
    const std::string name = e->d_name;
    n += name.rfind(prefix, 0) == 0 && name.find(".tmp.") != std::string::npos;
  }
  closedir(d);
  return n;
}

TEST(TrainCli, SigintStopsAtASafePointAndResumeFinishes) {
  const std::string model = temp("sigint.qfdi"), ckpt = model + ".ckpt", err = temp("sigint.err");
  std::remove(model.c_str());
  std::remove(ckpt.c_str());
  const std::string args = "train --max-iterations 3 --min-iterations 3 -o " + model + kFast;
  const pid_t pid = start(args, err);
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!exists(ckpt) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, SIGINT);
  const int code = waitExit(pid);
  ASSERT_TRUE(exists(ckpt));
  if (exists(model)) GTEST_SKIP() << "the run finished before the signal arrived";
  EXPECT_EQ(code, 130) << slurp(err);
  EXPECT_NE(slurp(err).find("run again with --resume to continue"), std::string::npos) << slurp(err);
  EXPECT_EQ(leftoverTemps(temp("sigint").substr(::testing::TempDir().size())), 0);
  const Result resumed = run(args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out;
  EXPECT_TRUE(exists(model));
}

TEST(TrainCli, StartFromFineTunesAFinishedModelAndRefusesAnother) {
  const std::string base = temp("ft_base.qfdw"), tuned = temp("ft_tuned.qfdw");
  ASSERT_EQ(run("train --max-iterations 1 -o " + base + kFast).exit_code, 0);
  const Result r = run("train --max-iterations 1 --start-from " + base + " -o " + tuned + kFast);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const quadfdi::TrainedModel m = quadfdi::readModelFile(tuned);
  EXPECT_EQ(m.metadata.started_from.rfind(base + " (1 iterations", 0), 0u) << m.metadata.started_from;
  EXPECT_EQ(m.metadata.feature_mean, quadfdi::readModelFile(base).metadata.feature_mean);
  std::ifstream log(tuned + ".log.csv");
  std::string header, start, first;
  std::getline(log, header);
  std::getline(log, start);
  std::getline(log, first);
  EXPECT_EQ(start.rfind("0,nan,", 0), 0u) << start;  // the starting model's score, before training
  EXPECT_EQ(first.rfind("1,", 0), 0u) << first;

  const Result other = run("train --max-iterations 1 --features model-based --start-from " + base + " -o " +
                           temp("ft_other.qfdw") + kFast);
  EXPECT_NE(other.exit_code, 0);
  EXPECT_EQ(std::count(other.out.begin(), other.out.end(), '\n'), 1) << other.out;
  EXPECT_NE(other.out.find("--start-from " + base + ": the starting model's features are model-free"), std::string::npos)
      << other.out;
  const std::string missing = temp("ft_missing.qfdw");
  const Result absent = run("train --max-iterations 1 --start-from " + missing + " -o " + temp("ft_x.qfdw") + kFast);
  EXPECT_NE(absent.exit_code, 0);
  EXPECT_EQ(std::count(absent.out.begin(), absent.out.end(), '\n'), 1) << absent.out;
  EXPECT_NE(absent.out.find(missing), std::string::npos) << absent.out;
}

// --buffer-windows sets N_buf: the log's buffer column grows over iterations while it is large
// (minibatches then come from several iterations' flights) and stops at it once full.
TEST(TrainCli, BufferWindowsSetsTheBufferCapacity) {
  const auto bufferColumn = [](const std::string& log_path) {
    std::ifstream log(log_path);
    std::string line;
    std::getline(log, line);  // header: iteration,loss,heldout_loss,heldout_accuracy,buffer_windows,…
    std::vector<long> sizes;
    while (std::getline(log, line)) {
      std::size_t at = 0;
      for (int comma = 0; comma < 4; ++comma) at = line.find(',', at) + 1;
      sizes.push_back(std::stol(line.substr(at)));
    }
    return sizes;
  };
  const std::string large = temp("buffer_large.qfdw"), small = temp("buffer_small.qfdw");
  // Five tiny iterations fly more windows than the tiny scale's own buffer (20 000) keeps.
  const std::string args = "train --max-iterations 5 --min-iterations 5" + std::string(kFast);
  ASSERT_EQ(run(args + " --buffer-windows 10000000 -o " + large).exit_code, 0);
  const std::vector<long> grown = bufferColumn(large + ".log.csv");
  ASSERT_EQ(grown.size(), 5u);
  EXPECT_GT(grown[0], 1000);
  for (std::size_t i = 1; i < grown.size(); ++i)  // nothing dropped: each iteration's windows added
    EXPECT_GT(grown[i], grown[i - 1] + grown[0] / 2) << "iteration " << i + 1;
  EXPECT_GT(grown[4], 20000);
  ASSERT_EQ(run(args + " --buffer-windows 1000 -o " + small).exit_code, 0);
  EXPECT_EQ(bufferColumn(small + ".log.csv"), std::vector<long>(5, 1000));

  const Result zero = run("train --buffer-windows 0 -o " + temp("buffer_zero.qfdw") + kFast);
  EXPECT_NE(zero.exit_code, 0);
  EXPECT_EQ(std::count(zero.out.begin(), zero.out.end(), '\n'), 1) << zero.out;
  EXPECT_NE(zero.out.find("--buffer-windows"), std::string::npos) << zero.out;
}

TEST(GenerateCli, SigtermLeavesNoOutputAndNoTemporaryFile) {
  const std::string out = temp("sigterm.h5"), err = temp("sigterm.err");
  std::remove(out.c_str());
  // Big enough to be running when the signal comes (44 000 trajectories, seconds on one thread).
  const pid_t pid = start("generate --scale default --iterations 100 --threads 1 -o " + out, err);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(waitForHandler(pid, SIGTERM));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // into the generation
  kill(pid, SIGTERM);
  const int code = waitExit(pid);
  if (exists(out)) GTEST_SKIP() << "generation finished before the signal arrived";
  EXPECT_EQ(code, 130) << slurp(err);
  EXPECT_NE(slurp(err).find("was not written"), std::string::npos) << slurp(err);
  EXPECT_EQ(leftoverTemps(temp("sigterm").substr(::testing::TempDir().size())), 0);
}

// Options this training would not read are refused in one line naming them: a fixed plant or
// controller under --randomise, the other training mode's batch size, channels for an LSTM.
// (A --params beside one --vehicle is not refused: a config file may carry it; the vehicle is the
// plant, and the model file records it.)
TEST(TrainCli, OptionsTheTrainingWouldNotReadAreRefused) {
  const std::string randomise = std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-default.toml";
  const std::pair<std::string, std::string> cases[] = {
      {"--architecture tcn --features scale-free --randomise " + randomise + " --preroll 1", "--preroll: has no effect with --randomise"},
      {"--architecture tcn --features scale-free --randomise " + randomise + " --controller cbf", "--controller: has no effect with --randomise"},
      {"--batch-trajectories 8", "--batch-trajectories: is for --training sequences"},
      {"--architecture tcn --features model-free-heading --batch-size 64", "--batch-size: is for --training windows"},
      {"--tcn-channels 16", "--tcn-channels: only --architecture tcn has channels"},
  };
  for (const auto& [args, message] : cases) {
    const std::string model = temp("never.qfdw");
    const Result r = run("train --scale tiny -q " + args + " -o " + model);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
    EXPECT_FALSE(exists(model));
  }
}

}  // namespace
