// Runs the real executable: options, one-line errors, exit codes, files.
#include <gtest/gtest.h>

#include "cli/cli_support.h"
#include "core/frames.h"
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <utility>

namespace {

using quadfdi::test::CommandResult;
CommandResult run(const std::string& args, bool merge_stderr = true) { return quadfdi::test::runQuadfdi(args, merge_stderr); }

std::string tempPath(const std::string& name) { return quadfdi::test::scratchPath("cli", name); }

int countLines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST(GenerateCli, TinyDatasetAndOneLineErrors) {
  const std::string path = tempPath("tiny.h5");
  const CommandResult ok = run("generate --scale tiny --seed 2 --threads 2 --output " + path);
  ASSERT_EQ(ok.exit_code, 0) << ok.out;
  EXPECT_NE(ok.out.find("44 trajectories (4 initial conditions x 1 motors x 11 thetas)"), std::string::npos) << ok.out;
  std::ifstream f(path, std::ios::binary);
  char magic[8] = {};
  f.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "HDF");

  const std::string cfg = tempPath("gen.toml");
  std::ofstream(cfg) << "scale = \"tiny\"\nthetas = [0, 1]\nwindow = 10\nbogus = 3\n";
  for (const std::string& args :
       {std::string("generate --thetas 1.5 -o ") + path, std::string("generate --motors 5 -o ") + path,
        std::string("generate --scale huge -o ") + path, std::string("generate --window 0 -o ") + path,
        std::string("generate --config ") + cfg + " -o " + path, std::string("generate --scale tiny")}) {
    const CommandResult r = run(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(countLines(r.out), 1) << args << "\n" << r.out;
  }
  EXPECT_NE(run("generate --config " + cfg + " -o " + path).out.find(cfg + ":4: unknown key 'bogus'"), std::string::npos);
  // The shipped config works (scale overridden on the command line).
  const CommandResult shipped = run("generate --config " + std::string(QUADFDI_SOURCE_DIR) +
                                    "/configs/generate-default.toml --scale tiny -o " + path);
  EXPECT_EQ(shipped.exit_code, 0) << shipped.out;
}

TEST(SimulateCli, HelpDocumentsEveryOption) {
  const CommandResult r = run("simulate --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* opt : {"--controller", "--controller-config", "--params", "--controller-params", "--lqr-weights", "--motor", "--theta",
                          "--fault-step", "--steps", "--seed", "--integrator", "--output", "--full-state", "--goal",
                          "--start", "--position-noise", "--attitude-noise", "--rate-noise", "--rates", "--cbf-min-altitude", "--cbf-max-tilt",
                          "--quiet", "--trajectory", "--speed", "--radius", "--yaw-mode", "--yaw-rate-max", "--yaw-sweep", "--rotor-drag", "--wind-speed",
                          "--wind-direction", "--turbulence", "--turbulence-tau", "--gust-rate", "--gust-peak", "--gust-duration"})
    EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
}

// One option path: a config file and the flags fill the same options, the flags win, and bad
// input is one line naming the flag or FILE:LINE, exit 1 (usage errors stay exit 2).
TEST(SimulateCli, ConfigFileAndFlagsAreOnePath) {
  const std::string flags = "--motor 3 --theta 0.4 --fault-step 100 --steps 200 --seed 4 --controller cbf";
  const CommandResult by_flags = run("simulate " + flags + " --output -", false);
  ASSERT_EQ(by_flags.exit_code, 0);
  const std::string cfg = tempPath("simulate.toml");
  std::ofstream(cfg) << "motor = 3\ntheta = 0.4\nfault_step = 100\nsteps = 200\nseed = 4\ncontroller = \"lqr\"\n";
  const CommandResult by_file = run("simulate --config " + cfg + " --controller cbf --output -", false);
  ASSERT_EQ(by_file.exit_code, 0);
  EXPECT_EQ(by_file.out, by_flags.out);  // the same flight; --controller on the command line won

  std::ofstream(cfg) << "motor = 3\n# a comment\nmotors = [3]\n";
  CommandResult r = run("simulate --config " + cfg + " --output /dev/null");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "quadfdi: error: " + cfg + ":3: unknown key 'motors'\n");
  std::ofstream(cfg) << "integrator = \"rk45\"\n";
  r = run("simulate --config " + cfg + " --output /dev/null");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "quadfdi: error: " + cfg + ":1: integrator: 'rk45' is not one of: rk4, euler\n");
  r = run("simulate --integrator rk45 --output /dev/null");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "quadfdi: error: --integrator: 'rk45' is not one of: rk4, euler\n");
  r = run("simulate --motor 5 --output /dev/null");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "quadfdi: error: --motor: must be in [1, 4], got 5\n");
  EXPECT_EQ(run("simulate --bogus").exit_code, 2);
  for (const char* command : {"generate", "train", "evaluate", "reproduce"}) {
    r = run(std::string(command) + " --scale huge -o /dev/null");
    EXPECT_EQ(r.exit_code, 1) << command;
    EXPECT_EQ(r.out, "quadfdi: error: --scale: 'huge' is not one of: tiny, quick, default, paper\n") << command;
  }
}

TEST(SimulateCli, FaultyFlightToStdoutAndSummaryToStderr) {
  const CommandResult r = run("simulate --motor 3 --theta 0.4 --fault-step 100 --steps 200 --seed 4 --output -", false);
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.rfind("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n", 0), 0u);
  EXPECT_EQ(countLines(r.out), 201);
  const CommandResult s = run("simulate --motor 3 --theta 0.4 --fault-step 100 --steps 200 --seed 4 --output /dev/null");
  EXPECT_NE(s.out.find("fault: motor 3 at theta 0.400 from step 100"), std::string::npos) << s.out;
  // Same seed, same bytes.
  EXPECT_EQ(run("simulate --motor 3 --theta 0.4 --fault-step 100 --steps 200 --seed 4 --output -", false).out, r.out);
}

TEST(SimulateCli, CbfAndFileParamsAndFullState) {
  const std::string path = tempPath("cbf.csv");
  const CommandResult r = run("simulate --controller cbf --params " + std::string(QUADFDI_SOURCE_DIR) +
                    "/configs/vehicle-example.toml --controller-config " + std::string(QUADFDI_SOURCE_DIR) +
                    "/configs/controller-example.toml --steps 50 --full-state --output " + path);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("CBF filtered"), std::string::npos);
  std::ifstream f(path);
  std::string header;
  std::getline(f, header);
  EXPECT_EQ(header, "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,vx,vy,vz,p,q,r,f1,f2,f3,f4,status");
}

TEST(SimulateCli, PidFliesACircle) {
  const CommandResult r = run("simulate --controller pid --trajectory circle --speed 1 --radius 1 --yaw-mode velocity "
                              "--start 0 0 1 0 0 0 0 0 1.5708 0 0 0 --goal -1 0 1 --steps 5000 --output /dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("pid controller"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("trajectory: circle at 1.00 m/s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("completed 5000 steps"), std::string::npos) << r.out;
  const std::string cfg = tempPath("pid.toml");
  std::ofstream(cfg) << "controller = \"pid\"\n[pid]\nrate_divisor = 0\n";
  const CommandResult bad = run("simulate --controller-config " + cfg + " -o /dev/null");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.out.find(cfg + ":3: 'pid.rate_divisor' must be an integer"), std::string::npos) << bad.out;
}

// A heading sweep on a hover: the logged yaw swings about the held heading by about the amplitude
// (the PID tracks it with its yaw-rate feed-forward), the position stays put; bad values are one line.
TEST(SimulateCli, AYawSweepTurnsTheHover) {
  const CommandResult r = run("simulate --controller pid --yaw-sweep 0.6 4 --start 0 0 1 0 0 0 0 0 0 0 0 0 --goal 0 0 1 "
                              "--steps 5000 --output -",
                              false);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  double low = 0.0, high = 0.0, drift = 0.0;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) v.push_back(std::stod(cell));
    ASSERT_GE(v.size(), 7u);
    low = std::min(low, v[6]);
    high = std::max(high, v[6]);
    drift = std::max(drift, std::hypot(v[1], v[2]));
  }
  EXPECT_NEAR(high, 0.6, 0.06);
  EXPECT_NEAR(low, -0.6, 0.06);
  EXPECT_LT(drift, 0.05);
  const CommandResult bad = run("simulate --yaw-sweep 0.5 0 --output /dev/null");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("--yaw-sweep: needs an amplitude in [0, pi] rad and a period > 0 s"), std::string::npos) << bad.out;
}

// A circle of 2 rad/s flown nose first: the nose follows the path, or with --yaw-rate-max 1 turns at
// 1 rad/s (an autopilot's mission yaw slew); the limit needs the nose-first mode and no figure-eight.
TEST(SimulateCli, AYawRateLimitSlowsTheNoseOnACircle) {
  const auto mean_yaw_rate = [](const std::string& csv) {  // [rad/s] from 2.5 s to the end, unwrapped
    std::istringstream in(csv);
    std::string line;
    std::getline(in, line);
    double first_t = -1.0, t = 0.0, turned = 0.0, previous = 0.0;
    while (std::getline(in, line)) {
      std::vector<double> v;
      std::istringstream row(line);
      for (std::string cell; std::getline(row, cell, ',');) v.push_back(std::stod(cell));
      if (v.size() < 7 || v[0] < 2.5) continue;
      if (first_t >= 0.0) turned += quadfdi::wrapAngle(v[6] - previous);
      else first_t = v[0];
      t = v[0];
      previous = v[6];
    }
    return t > first_t ? turned / (t - first_t) : 0.0;
  };
  const std::string circle = "simulate --controller pid --trajectory circle --speed 1 --radius 0.5 --yaw-mode velocity "
                             "--start 0 0 1 0 0 0 0 0 1.5708 0 0 0 --goal -0.5 0 1 --steps 5000 --output -";
  const CommandResult free = run(circle, false), slewed = run(circle + " --yaw-rate-max 1", false);
  ASSERT_EQ(free.exit_code, 0) << free.out;
  ASSERT_EQ(slewed.exit_code, 0) << slewed.out;
  EXPECT_NEAR(mean_yaw_rate(free.out), 2.0, 0.1);
  EXPECT_NEAR(mean_yaw_rate(slewed.out), 1.0, 0.05);
  const CommandResult fixed = run("simulate --trajectory circle --yaw-rate-max 1 --output /dev/null");
  EXPECT_NE(fixed.exit_code, 0);
  EXPECT_NE(fixed.out.find("--yaw-rate-max: limits the nose's turn along the path: give --yaw-mode velocity"), std::string::npos) << fixed.out;
  const CommandResult eight = run("simulate --trajectory figure-eight --yaw-mode velocity --yaw-rate-max 1 --output /dev/null");
  EXPECT_NE(eight.exit_code, 0);
  EXPECT_NE(eight.out.find("a figure-eight's heading along the path is not slewed"), std::string::npos) << eight.out;
}

// A steady wind toward +x pushes a hovering LQR flight downwind and it leans into it (negative
// pitch is nose up in FLU, i.e. tilting the thrust toward −x); the same seed with gusts repeats
// byte for byte; wind without rotor drag is refused in one line.
TEST(SimulateCli, WindPushesTheFlightAndNeedsRotorDrag) {
  auto lastRow = [](const std::string& csv) {
    std::istringstream in(csv);
    std::string line, last;
    while (std::getline(in, line))
      if (!line.empty()) last = line;
    std::vector<double> v;
    std::istringstream row(last);
    for (std::string cell; std::getline(row, cell, ',');) v.push_back(std::stod(cell));
    return v;
  };
  const std::string base = "simulate --start 0 0 1 0 0 0 0 0 0 0 0 0 --goal 0 0 1 --steps 3000 --output - ";
  const CommandResult still = run(base + "--rotor-drag 0.26", false);
  const CommandResult windy = run(base + "--rotor-drag 0.26 --wind-speed 4", false);
  ASSERT_EQ(still.exit_code, 0) << still.out;
  ASSERT_EQ(windy.exit_code, 0) << windy.out;
  const std::vector<double> s = lastRow(still.out), w = lastRow(windy.out);
  ASSERT_EQ(w.size(), 11u);
  EXPECT_NEAR(s[1], 0.0, 1e-6);
  EXPECT_GT(w[1], 0.005);  // downwind of the goal: the LQR has no integrator
  // Steady lean: tan θ = c·|w| / (m g) = 0.26 · 4 / 9.8 (pitch about −0.106 rad for a push toward +x).
  EXPECT_NEAR(std::abs(w[5]), std::atan(0.26 * 4.0 / 9.8), 0.01);
  const std::string gusty = base + "--rotor-drag 0.26 --turbulence 1 --gust-rate 1 --gust-peak 3 --seed 3";
  const CommandResult g1 = run(gusty, false), g2 = run(gusty, false);
  ASSERT_EQ(g1.exit_code, 0) << g1.out;
  EXPECT_EQ(g1.out, g2.out);
  EXPECT_NE(g1.out, windy.out);
  const CommandResult refused = run("simulate --wind-speed 3 -o /dev/null");
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_EQ(countLines(refused.out), 1) << refused.out;
  EXPECT_NE(refused.out.find("--rotor-drag"), std::string::npos) << refused.out;
}

TEST(SimulateCli, BadArgumentsGiveOneLineErrorsAndNonZeroExit) {
  const std::string missing_params = tempPath("missing.toml");
  for (const std::string& args :
       {std::string("simulate --motor 5"), std::string("simulate --theta 1.5 --motor 1"),
        std::string("simulate --controller mpc"), std::string("simulate --steps 0"),
        std::string("simulate --trajectory square"), std::string("simulate --trajectory circle --speed 0"),
        std::string("simulate --steps ten"), std::string("simulate --integrator rk45"),
        std::string("simulate --params ") + missing_params, std::string("simulate --bogus"),
        std::string("simulate --start 0 0 1"), std::string("simulate --start 0 0 1 0 0 0 2 0 0 0 0 0 -o /dev/null"),
        std::string("simulate --output /nonexistent-dir/x.csv"), std::string("")}) {
    const CommandResult r = run(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(countLines(r.out), 1) << args << "\n" << r.out;
    EXPECT_NE(r.out.find("error"), std::string::npos) << args << "\n" << r.out;
  }
  const CommandResult r = run("simulate --params " + missing_params);
  EXPECT_NE(r.out.find(missing_params + ": cannot open for reading"), std::string::npos) << r.out;
}

TEST(SimulateCli, BadParameterFileNamesFileAndLine) {
  const std::string path = tempPath("bad.toml");
  std::ofstream(path) << "base = \"nominal\"\nmass = 0.03\ninertia_xx = lots\n";
  const CommandResult r = run("simulate --params " + path + " -o /dev/null");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.out.find(path + ":3: 'inertia_xx' needs a finite number, got 'lots'"), std::string::npos) << r.out;
}

TEST(SimulateCli, FailedRunLeavesTheExistingOutputIntact) {
  const std::string path = tempPath("keep.csv");
  std::ofstream(path) << "precious\n";
  const CommandResult r = run("simulate --params /nonexistent.toml --output " + path);
  EXPECT_NE(r.exit_code, 0);
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  EXPECT_EQ(ss.str(), "precious\n");
}

// A full disk, simulated with a file-size limit (the write fails with EFBIG; SIGXFSZ ignored):
// a one-line error, no output file, no temporary file, and an existing file kept.
TEST(SimulateCli, AFullDiskIsReportedAndLosesNothing) {
  const std::string path = tempPath("full-disk.csv");
  { std::ofstream(path) << "precious\n"; }
  const std::string cmd = "sh -c \"ulimit -f 8; trap '' XFSZ; exec " + std::string(QUADFDI_EXE) +
                          " simulate --steps 5000 --output " + path + "\" 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string out;
  char buf[512];
  while (fgets(buf, sizeof buf, pipe)) out += buf;
  const int status = pclose(pipe);
  EXPECT_EQ(WEXITSTATUS(status), 1) << out;
  EXPECT_NE(out.find(path + ": write failed (disk full or I/O error)"), std::string::npos) << out;
  std::ifstream kept(path);
  std::string first;
  std::getline(kept, first);
  EXPECT_EQ(first, "precious");
}

// An option this flight would not read is refused in one line naming it, not ignored (a flight
// "with a fault" that never happens, a speed for a hover, an LQR weighting for the PID).
TEST(SimulateCli, OptionsTheFlightWouldNotReadAreRefused) {
  const std::string out = tempPath("never-written.csv");
  const std::pair<std::string, std::string> cases[] = {
      {"--theta 0.5", "--theta: needs --motor N"},
      {"--fault-step 100", "--fault-step: needs --motor N"},
      {"--motor 2 --fault-step 300 --steps 300", "--fault-step 300 is not before --steps 300"},
      {"--speed 2", "--speed: applies to --trajectory point-to-point, circle or figure-eight"},
      {"--trajectory point-to-point --radius 2", "--radius: is the circle's and the figure-eight's"},
      {"--controller pid --lqr-weights authors", "--lqr-weights: is the LQR's"},
      {"--cbf-max-tilt 0.4", "--cbf-max-tilt: is the CBF-QP filter's"},
      {"--rotor-drag 0.2 --gust-rate 0.5", "--gust-rate: needs --gust-peak > 0"},
      {"--rotor-drag 0.2 --gust-peak 2", "--gust-peak: needs --gust-rate > 0"},
      {"--rate-noise 0.02", "--rate-noise: is noise on the body-rate columns, which only --rates or --full-state writes"},
  };
  for (const auto& [args, message] : cases) {
    const CommandResult r = run("simulate " + args + " --output " + out);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.out;
    EXPECT_EQ(countLines(r.out), 1) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  }
  EXPECT_FALSE(std::ifstream(out).good());
  // The same options where the flight reads them still run.
  EXPECT_EQ(run("simulate --controller cbf --cbf-max-tilt 0.4 --motor 2 --theta 0.5 --fault-step 100 --steps 150 -q --output " + out).exit_code, 0);
  EXPECT_EQ(run("simulate --rates --rate-noise 0.02 --steps 150 -q --output " + out).exit_code, 0);
  std::ifstream written(out);
  std::string header;
  std::getline(written, header);
  EXPECT_EQ(header, "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,p,q,r");
}

// generate --randomise draws each flight's plant, controller and pre-roll: the fixed ones are refused.
TEST(GenerateCli, FixedPlantOptionsAreRefusedWithARandomisation) {
  const std::string randomise = std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-default.toml";
  for (const char* option : {"--params perturbed", "--controller cbf", "--preroll 1"}) {
    const CommandResult r = run("generate --scale tiny --randomise " + randomise + " " + option + " -o " + tempPath("never.h5"));
    EXPECT_EQ(r.exit_code, 1) << option << "\n" << r.out;
    EXPECT_EQ(countLines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("has no effect with --randomise"), std::string::npos) << r.out;
  }
}

}  // namespace
