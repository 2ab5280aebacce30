// quadfdi evaluate on a tiny scale: the report generator writes every file, and names what
// it could not run.
#include <gtest/gtest.h>

#include "cli/cli_support.h"
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

namespace {

std::string run(const std::string& args, int* code) {
  const quadfdi::test::CommandResult r = quadfdi::test::runQuadfdi(args);
  *code = r.exit_code;
  return r.out;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(EvaluateCli, TinyReportWithTablesFiguresAndSkippedExperiments) {
  const std::string dir = ::testing::TempDir() + "quadfdi_eval_cli";
  const std::string model = dir + ".qfdi";
  int code = 0;
  const std::string trained =
      run("train --scale tiny --max-iterations 1 --max-minibatches 1 --batch-size 32 -q -o " + model, &code);
  ASSERT_EQ(code, 0) << trained;
  const std::string out = run("evaluate --model " + model + " -e e1 e4 --scale tiny -q -o " + dir, &code);
  ASSERT_EQ(code, 0) << out;
  const std::string report = slurp(dir + "/REPORT.md");
  EXPECT_NE(report.find("scale: tiny (3 test flights per class"), std::string::npos) << report;
  EXPECT_NE(report.find("### E1: complete failure of each motor"), std::string::npos);
  EXPECT_NE(report.find("| motor 4 | 3 |"), std::string::npos) << report;
  EXPECT_NE(report.find("### e4: not run — needs the model-based model"), std::string::npos);
  const std::string csv = slurp(dir + "/e1.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "faulty_length,faulty_time_ms,\"isolation: motor 1\",\"isolation: motor 2\",\"isolation: motor 3\","
            "\"isolation: motor 4\",\"identification: motor 1\",\"identification: motor 2\",\"identification: motor 3\","
            "\"identification: motor 4\"");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 102);  // header + L = 0 … 100
  EXPECT_NE(slurp(dir + "/e1.md").find("| condition | flights |"), std::string::npos);
  // Decisions on a flight's mean Θ̂: said in the report's header.
  const std::string averaged = run("evaluate --model " + model + " -e e1 --average-windows 4 --scale tiny -q -o " + dir + "-avg", &code);
  ASSERT_EQ(code, 0) << averaged;
  EXPECT_NE(slurp(dir + "-avg/REPORT.md").find("Θ_tol: 0.2, decisions on the mean Θ̂ of a flight's last 4 windows"), std::string::npos);
  // Bad input: one line, non-zero.
  const std::string bad = run("evaluate --model " + model + " -e e9 --scale tiny -o " + dir, &code);
  EXPECT_NE(code, 0);
  EXPECT_EQ(bad, "quadfdi: error: --experiments: 'e9' is not one of: e1, e2, e3, e4, e5, e6, e7, decisions\n");
  run("evaluate --model /nonexistent.qfdi -o " + dir, &code);
  EXPECT_NE(code, 0);
}

// The decisions experiment on a few healthy minutes and one faulty flight per (Θ, motor): every
// file is written, and the report names the flights' wind (configs/randomisation-default.toml has
// a [wind] section) and the false-alarm line with its bound.
TEST(EvaluateCli, DecisionsReportNamesItsWindAndFalseAlarmBound) {
  const std::string dir = ::testing::TempDir() + "quadfdi_eval_decisions";
  const std::string src = QUADFDI_SOURCE_DIR;
  int code = 0;
  const std::string out = run("evaluate -e decisions --model-free " + src + "/models/tcn-crazyflie2.qfdw --vehicle " + src +
                                  "/configs/vehicles/crazyflie2.toml --randomise " + src +
                                  "/configs/randomisation-default.toml --flights-per-class 1 --faulty-per-theta 2 --flight-hours 0.02 --scale tiny -q -o " + dir,
                              &code);
  ASSERT_EQ(code, 0) << out;
  const std::string md = slurp(dir + "/decisions.md");
  EXPECT_NE(md.find("; wind 0–5 m/s, turbulence σ ≤ 1.5 m/s, gusts ≤ 3.0 m/s, rotor drag 0.15–0.35 /s)"), std::string::npos) << md;
  // The controllers and manoeuvres named are the randomisation's (weight > 0).
  EXPECT_NE(md.find("(LQR, PID, CBF-QP; hover, point-to-point, circle; estimator noise"), std::string::npos) << md;
  EXPECT_NE(md.find("healthy flight hours (1 flights of 60 s)"), std::string::npos) << md;
  EXPECT_NE(md.find("one-sided 95 % upper bound"), std::string::npos) << md;
  // The rate counts from 1 s into each recording (as the calibration); the rest is reported apart.
  EXPECT_NE(md.find("counted from 1 s into each recording"), std::string::npos) << md;
  EXPECT_NE(md.find("alarms there in 1 flights ("), std::string::npos) << md;
  EXPECT_NE(md.find(" s into the flight, after its initial upset."), std::string::npos) << md;  // faults after it too
  EXPECT_EQ(md.find("telemetry logged at"), std::string::npos) << md;  // every model sample: no log rate to state
  const std::string csv = slurp(dir + "/decisions.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 11);  // header + Θ = 0, 0.1, …, 0.9
  EXPECT_NE(csv.find("\n0.5,2,"), std::string::npos) << csv;   // --faulty-per-theta flights at each Θ
  const std::string tradeoff = slurp(dir + "/tradeoff.csv");
  EXPECT_EQ(std::count(tradeoff.begin(), tradeoff.end(), '\n'), 9);  // header + eight target rates
  // Every false alarm counted in the report is a row of false_alarms.csv, with its flight's draw.
  const std::string alarms = slurp(dir + "/false_alarms.csv");
  EXPECT_EQ(alarms.rfind("flight,t_s,motor,severity,theta_est,vehicle,controller,gain_scale,manoeuvre,", 0), 0u) << alarms;
  const std::size_t count_at = md.find("**False alarms:** ");
  ASSERT_NE(count_at, std::string::npos) << md;
  const long counted = std::stol(md.substr(count_at + std::string("**False alarms:** ").size()));
  EXPECT_EQ(std::count(alarms.begin(), alarms.end(), '\n'), counted + 1) << alarms;
  EXPECT_EQ(md.find("**Alarmed flights**") != std::string::npos, counted > 0) << md;
}

// --log-rate logs the flights at that rate and resamples them as detect does; the report says so
// in its rule line, and the flights, shorter by the samples past the last logged one, still score.
TEST(EvaluateCli, DecisionsAtALogRateSayWhichAndScore) {
  const std::string dir = ::testing::TempDir() + "quadfdi_eval_log_rate";
  const std::string src = QUADFDI_SOURCE_DIR;
  int code = 0;
  const std::string out = run("evaluate -e decisions --model-free " + src + "/models/tcn-crazyflie2.qfdw --vehicle " + src +
                                  "/configs/vehicles/crazyflie2.toml --flights-per-class 1 --faulty-per-theta 2 --flight-hours 0.01 "
                                  "--scale tiny --log-rate 100 -q -o " + dir,
                              &code);
  ASSERT_EQ(code, 0) << out;
  const std::string md = slurp(dir + "/decisions.md");
  EXPECT_NE(md.find("**telemetry logged at 100 Hz** and resampled onto the model's 2 ms as `detect` does"), std::string::npos) << md;
  // Complete faults on the Crazyflie are still found through the resampler.
  EXPECT_NE(md.find("| 0.0 | 2 | 2/2, "), std::string::npos) << md;
  const std::string report = slurp(dir + "/REPORT.md");
  EXPECT_NE(report.find("--log-rate 100"), std::string::npos) << report.substr(0, 600);
}

// A calibration whose degraded level is raised to 0.999 (a healthy motor's Θ̂ sits below it half
// the time) raises false alarms in a few healthy minutes: the report lists the alarmed flights with
// what was drawn for them, and false_alarms.csv holds one row per alarm counted. The flights are
// configs/randomisation-geometric.toml's, whose one controller the report and the rows name.
TEST(EvaluateCli, DecisionsReportListsTheAlarmedFlights) {
  const std::string dir = ::testing::TempDir() + "quadfdi_eval_alarmed";
  const std::string src = QUADFDI_SOURCE_DIR;
  std::string calibration = slurp(src + "/models/tcn-crazyflie2.calibration.json");
  const std::size_t at = calibration.find("\"level\": ");  // the degraded level's: keys are sorted
  ASSERT_NE(at, std::string::npos);
  const std::size_t end = calibration.find_first_of(",\n", at);
  calibration.replace(at, end - at, "\"level\": 0.999");
  const std::string low = ::testing::TempDir() + "quadfdi_low_threshold.calibration.json";
  std::ofstream(low) << calibration;
  int code = 0;
  const std::string out = run("evaluate -e decisions --model-free " + src + "/models/tcn-crazyflie2.qfdw --calibration " + low +
                                  " --vehicle " + src + "/configs/vehicles/crazyflie2.toml --randomise " + src +
                                  "/configs/randomisation-geometric.toml --flights-per-class 1 --faulty-per-theta 1 --flight-hours 0.05 --scale tiny -q -o " + dir,
                              &code);
  ASSERT_EQ(code, 0) << out;
  const std::string md = slurp(dir + "/decisions.md");
  const std::size_t count_at = md.find("**False alarms:** ");
  ASSERT_NE(count_at, std::string::npos) << md;
  const long counted = std::stol(md.substr(count_at + std::string("**False alarms:** ").size()));
  ASSERT_GT(counted, 0) << md;
  EXPECT_NE(md.find("(geometric SE(3); hover, point-to-point, circle; estimator noise"), std::string::npos) << md;
  EXPECT_NE(md.find("**Alarmed flights**"), std::string::npos) << md;
  const std::string alarms = slurp(dir + "/false_alarms.csv");
  EXPECT_EQ(std::count(alarms.begin(), alarms.end(), '\n'), counted + 1) << alarms;
  // Rows name the vehicle flown and a severity, after the first second of the recording.
  std::istringstream rows(alarms);
  std::string row;
  std::getline(rows, row);  // header
  while (std::getline(rows, row)) {
    std::vector<std::string> f;
    std::stringstream cells(row);
    for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
    ASSERT_EQ(f.size(), 19u) << row;
    EXPECT_GE(std::stod(f[1]), 1.0) << row;  // counted from 1 s into the recording
    EXPECT_TRUE(f[3] == "degraded" || f[3] == "failed") << row;
    EXPECT_EQ(f[5], "crazyflie2") << row;
    EXPECT_EQ(f[6], "geometric") << row;
    EXPECT_NE(md.find("| " + f[0] + " | crazyflie2 | "), std::string::npos) << row;  // its flight is in the table
  }
}

// Options only some experiments read are refused when none of those runs, in one line naming the
// option (evaluate -e e1 --vehicle mine.toml would otherwise score the Crazyflie and say nothing).
TEST(EvaluateCli, OptionsTheChosenExperimentsWouldNotReadAreRefused) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-randomised.qfdw";
  const std::string vehicle = std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/racer250.toml";
  const std::string dir = ::testing::TempDir() + "quadfdi_eval_refused";
  const std::pair<std::string, std::string> cases[] = {
      {"-e e1 --vehicle " + vehicle, "--vehicle: only -e e7 and decisions read it"},
      {"-e e1 --flights-per-class 3", "--flights-per-class: only -e e7 and decisions read it"},
      {"-e e7 --flight-hours 1", "--flight-hours: only -e decisions reads it"},
      {"-e e7 --average-windows 5", "--average-windows: only E1-E6 read it"},
      {"-e e7 decisions --theta-tol 0.3", "--theta-tol: only E1-E6 read it"},
      {"-e e1 --log-rate 100", "--log-rate: only -e e7 and decisions read it"},
  };
  for (const auto& [args, message] : cases) {
    int code = 0;
    const std::string out = run("evaluate --model-free " + model + " --scale tiny -q " + args + " -o " + dir, &code);
    EXPECT_EQ(code, 1) << args << "\n" << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_NE(out.find(message), std::string::npos) << args << "\n" << out;
  }
  EXPECT_FALSE(std::ifstream(dir + "/REPORT.md").good());
}

}  // namespace
