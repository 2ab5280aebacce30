// quadfdi detect end to end: simulate → detect (file and pipe), and the documented behaviour
// for every kind of messy or bad telemetry.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <utility>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/cli_support.h"
#include "cli/detect_command.h"
#include "cli/shipped_files.h"
#include "data/features.h"
#include "io/calibration_file.h"
#include "io/model_file.h"
#include "io/vehicle_file.h"
#include "core/frames.h"
#include "logs/quaternion_check.h"

namespace {

using quadfdi::test::CommandResult;
CommandResult run(const std::string& args, bool merge_stderr = true) { return quadfdi::test::runQuadfdi(args, merge_stderr); }
std::string temp(const std::string& name) { return quadfdi::test::scratchPath("detect", name); }
std::string exe() { return QUADFDI_EXE; }
int countLines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

using quadfdi::test::readFile;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// Detector output with the motor numbers of a --vehicle description's numbering left out: what
// must not change when the description only renames the motors.
std::string withoutAutopilotNumbers(std::string s) {
  const std::string key = ", \"autopilot_motor\": ";
  for (std::size_t at = s.find(key); at != std::string::npos; at = s.find(key, at)) {
    const std::size_t end = at + key.size();
    if (end < s.size() && s[end] >= '0' && s[end] <= '9') s.erase(at, key.size() + 1);  // one digit: motors 1..4
    else at = end;
  }
  return s;
}

// The cells of one CSV row (no quoting in telemetry CSV).
std::vector<std::string> csvCells(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream row(line);
  for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
  return cells;
}

// A faulty flight of motor 3 (complete failure at 1.0 s), simulated once for the suite.
const std::string& faultyCsv() {
  static const std::string path = [] {
    const std::string p = temp("faulty.csv");
    const CommandResult r = run("simulate --motor 3 --theta 0 --fault-step 500 --steps 800 --seed 4 --output " + p);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    return p;
  }();
  return path;
}

TEST(DetectCli, FindsTheFaultyMotorAndWritesOneLinePerSample) {
  const std::string out = temp("faulty.jsonl");
  const CommandResult r = run("detect --input " + faultyCsv() + " --output " + out);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("FAULT in motor 3 at t = 1.0"), std::string::npos) << r.out;
  const std::vector<std::string> json = lines(readFile(out));
  const int rows = countLines(readFile(faultyCsv())) - 1;
  EXPECT_EQ(static_cast<int>(json.size()), rows - 99);  // from the first full window on
  EXPECT_EQ(json.front().rfind("{\"t\": 0.198, \"theta\": [", 0), 0u) << json.front();
  EXPECT_NE(json.front().find("\"alarm\": false, \"motor\": null, \"severity\": \"healthy\", \"theta_est\": null, "
                              "\"theta_lo\": null, \"theta_hi\": null, \"motor_position\": null, \"autopilot_motor\": null}"),
            std::string::npos)
      << json.front();
  EXPECT_NE(json.back().find("\"alarm\": true, \"motor\": 3, \"severity\": \"failed\", \"theta_est\": 0."), std::string::npos)
      << json.back();
  // Which motor to look at: a CSV is in quadfdi's numbering, so its own number and position.
  EXPECT_NE(json.back().find(", \"motor_position\": \"back-left\", \"autopilot_motor\": 3}"), std::string::npos) << json.back();
  EXPECT_NE(r.out.find(": failed, Θ̂ = 0."), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("detect: motor 3 is the back-left motor (quadfdi's numbering: 1 front-right"), std::string::npos) << r.out;
}

// Issue 14: the sequential rule adds keys after the four old ones; the persistence rule writes
// exactly the old four; bad values of the new options are refused with "--flag: problem", exit 1.
TEST(DetectCli, SequentialKeysAreAddedAndPersistenceKeepsTheOldOnes) {
  const CommandResult seq = run("detect -q --input " + faultyCsv(), false);
  const CommandResult per = run("detect -q --rule persistence --input " + faultyCsv(), false);
  ASSERT_EQ(seq.exit_code, 0);
  ASSERT_EQ(per.exit_code, 0);
  const std::vector<std::string> a = lines(seq.out), b = lines(per.out);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    // The same t in the same order (theta may differ where the rules schedule evaluations differently).
    const std::size_t cut = b[i].find(", \"theta\"");
    ASSERT_NE(cut, std::string::npos);
    EXPECT_EQ(a[i].substr(0, cut), b[i].substr(0, cut)) << i;
    EXPECT_EQ(b[i].find("severity"), std::string::npos) << b[i];
    EXPECT_NE(a[i].find("\"motor\": "), std::string::npos);
    EXPECT_NE(a[i].find(", \"severity\": \""), std::string::npos) << a[i];
    EXPECT_NE(a[i].find(", \"theta_hi\": "), std::string::npos) << a[i];
  }
  // Every alarm names a severity and an interval around its estimate.
  for (const std::string& l : a)
    if (l.find("\"alarm\": true") != std::string::npos) {
      const double est = std::stod(l.substr(l.find("\"theta_est\": ") + 13));
      const double lo = std::stod(l.substr(l.find("\"theta_lo\": ") + 12));
      const double hi = std::stod(l.substr(l.find("\"theta_hi\": ") + 12));
      EXPECT_LE(lo, est);
      EXPECT_LE(est, hi);
    }
}

TEST(DetectCli, RefusesBadSequentialOptions) {
  for (const std::string& bad : {std::string("--degraded-below 1.5"), std::string("--failed-below 0"),
                                 std::string("--false-alarms-per-hour 0"), std::string("--rule bogus"),
                                 std::string("--false-alarms-per-hour ten")}) {
    const CommandResult r = run("detect --input " + faultyCsv() + " " + bad);
    EXPECT_EQ(r.exit_code, 1) << bad << ": " << r.out;
    EXPECT_NE(r.out.find(bad.substr(0, bad.find(' ')) + ": "), std::string::npos) << r.out;
  }
  const CommandResult order = run("detect --input " + faultyCsv() + " --degraded-below 0.3 --failed-below 0.5");
  EXPECT_EQ(order.exit_code, 1);
  EXPECT_NE(order.out.find("--failed-below must be below --degraded-below"), std::string::npos) << order.out;
  const std::string bad_cal = temp("bad-calibration.json");
  std::ofstream(bad_cal) << "{\"format\": \"something else\"}";
  const CommandResult cal = run("detect --input " + faultyCsv() + " --calibration " + bad_cal);
  EXPECT_EQ(cal.exit_code, 1);
  EXPECT_NE(cal.out.find(bad_cal + ": not a quadfdi decision calibration"), std::string::npos) << cal.out;
}

// calibrate → detect --calibration: a short run writes a calibration the detector accepts.
TEST(DetectCli, CalibrateWritesACalibrationDetectUses) {
  const std::string cal = temp("calibration.json");
  const CommandResult c = run("calibrate --model " + std::string(QUADFDI_SOURCE_DIR) +
                              "/models/tcn-model-free.qfdw --flights 2 --flight-seconds 4 --faulty-flights 3 --output " + cal);
  ASSERT_EQ(c.exit_code, 0) << c.out;
  EXPECT_NE(c.out.find("calibrate: level 0.80, cap 0.1: h = "), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("calibrate: level 0.30, cap inf: h = "), std::string::npos) << c.out;
  EXPECT_NE(readFile(cal).find("\"format\": \"quadfdi-decision-calibration-1\""), std::string::npos);
  EXPECT_NE(readFile(cal).find("\"increment_cap\": 0.1"), std::string::npos);  // the cap the thresholds were fitted for
  EXPECT_NE(readFile(cal).find("\"reference\": \"others\""), std::string::npos);  // the default: each motor against its siblings
  EXPECT_NE(c.out.find("flight hours healthy: Θ̂ (others) mean "), std::string::npos) << c.out;
  const CommandResult r = run("detect --model " + std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw --calibration " + cal +
                              " --input " + faultyCsv() + " --output " + temp("calibrated.jsonl"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("FAULT in motor 3"), std::string::npos) << r.out;
}

// calibrate names the healthy flights its thresholds stand on: the largest excursions, with what was
// drawn for each randomised flight (a few long dips can set h alone).
TEST(DetectCli, CalibrateNamesTheFlightsOfItsLargestExcursions) {
  const std::string source = QUADFDI_SOURCE_DIR;
  const CommandResult c = run("calibrate --model " + source + "/models/tcn-randomised.qfdw --randomise " + source +
                              "/configs/randomisation-heading.toml --flights 3 --flight-seconds 4 --settle 1 --faulty-flights 0 "
                              "--degraded-below 0.999 --output " + temp("calibration-named.json"));
  ASSERT_EQ(c.exit_code, 0) << c.out;
  const std::size_t at = c.out.find("calibrate: largest excursions at level 1.00: ");
  ASSERT_NE(at, std::string::npos) << c.out;
  const std::string line = c.out.substr(at, c.out.find('\n', at) - at);
  EXPECT_NE(line.find(" in healthy flight "), std::string::npos) << line;
  EXPECT_NE(line.find(", motor "), std::string::npos) << line;
  EXPECT_TRUE(line.find("(crazyflie2, ") != std::string::npos || line.find("(racer250, ") != std::string::npos ||
              line.find("(quad450, ") != std::string::npos)
      << line;
  EXPECT_NE(line.find(" m/s)"), std::string::npos) << line;  // the wind closes each flight's words
}

// A calibration records the CRC-32 its model's weights file ends with; detect refuses it with any
// other model in one line naming both, and accepts a file written before the key existed.
TEST(DetectCli, ACalibrationIsRefusedWithAnotherModel) {
  const std::string src = QUADFDI_SOURCE_DIR, cal = temp("crc-calibration.json");
  const std::string tcn = src + "/models/tcn-model-free.qfdw", lstm = src + "/models/lstm-model-free.qfdw";
  ASSERT_EQ(run("calibrate -q --model " + tcn + " --flights 2 --flight-seconds 4 --faulty-flights 0 --output " + cal).exit_code, 0);
  const std::string hex = quadfdi::crc32Hex(quadfdi::readModelFile(tcn).file_crc32);  // WeightsFile tests: the file's CRC
  EXPECT_NE(readFile(cal).find("\"model_crc32\": \"" + hex + "\""), std::string::npos) << readFile(cal);
  const std::string input = " --input " + faultyCsv() + " --output " + temp("crc.jsonl");
  EXPECT_EQ(run("detect -q --model " + tcn + " --calibration " + cal + input).exit_code, 0);
  const CommandResult other = run("detect --model " + lstm + " --calibration " + cal + input);
  EXPECT_NE(other.exit_code, 0);
  EXPECT_NE(other.out.find(cal + ": made for another model (weights file CRC-32 " + hex + ", this model's 0x"), std::string::npos) << other.out;
  EXPECT_EQ(lines(other.out).size(), 1u) << other.out;
  // evaluate reads calibrations the same way.
  const CommandResult evaluated = run("evaluate -e decisions --model-free " + lstm + " --calibration " + cal + " -o " + temp("crc-eval"));
  EXPECT_NE(evaluated.exit_code, 0);
  EXPECT_NE(evaluated.out.find(cal + ": made for another model"), std::string::npos) << evaluated.out;
  // Without the key (files before 2026-11-27) nothing is checked.
  std::string old = readFile(cal);
  const std::size_t at = old.find(",\n  \"model_crc32\"");
  ASSERT_NE(at, std::string::npos) << old;
  old.erase(at + 1, old.find('\n', at + 2) - (at + 1));  // the key's line; the line before keeps its comma
  std::ofstream(temp("crc-old.json")) << old;
  EXPECT_EQ(run("detect -q --model " + lstm + " --calibration " + temp("crc-old.json") + input).exit_code, 0);
}

// --failed-cap: the failed level is fitted on the capped statistic and the file keeps the cap.
TEST(DetectCli, CalibrateCapsTheFailedStatisticWhenAsked) {
  const std::string cal = temp("failed-cap.json");
  const CommandResult c = run("calibrate --model " + std::string(QUADFDI_SOURCE_DIR) +
                              "/models/tcn-model-free.qfdw --flights 2 --flight-seconds 4 --faulty-flights 3 --failed-cap 0.15 --output " + cal);
  ASSERT_EQ(c.exit_code, 0) << c.out;
  const std::size_t at = c.out.find("calibrate: level 0.30, cap 0.15: h = ");
  ASSERT_NE(at, std::string::npos) << c.out;
  // The line states the capped statistic's floor: ⌈h / 0.15⌉ samples of 2 ms.
  double h = 0.0;
  ASSERT_EQ(std::sscanf(c.out.c_str() + at, "calibrate: level 0.30, cap 0.15: h = %lf", &h), 1);
  const long floor = static_cast<long>(std::ceil(h / 0.15 * (1.0 - 1e-12)));
  const std::string line = c.out.substr(at, c.out.find('\n', at) - at);
  EXPECT_NE(line.find("no alarm sooner than " + std::to_string(floor) + " samples (" + std::to_string(2 * floor) + " ms)"), std::string::npos)
      << line;
  EXPECT_NE(readFile(cal).find("\"increment_cap\": 0.15"), std::string::npos);
  const CommandResult bad = run("calibrate --model " + std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw --failed-cap -1 --output " + cal);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("--failed-cap: must be >= 0, got -1"), std::string::npos) << bad.out;
}

// Several --failed-cap values: each is calibrated and scored on the faulty flights below the failed
// level, one is kept, its cap is the file's and the choice is in its provenance.
TEST(DetectCli, CalibrateChoosesAFailedCap) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw", cal = temp("cap-chosen.json");
  const CommandResult c = run("calibrate --model " + model + " --flights 2 --flight-seconds 4 --faulty-flights 6 --failed-cap 0.15 0 --output " + cal);
  ASSERT_EQ(c.exit_code, 0) << c.out;
  EXPECT_NE(c.out.find("calibrate: failed cap 0.15: h = "), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("calibrate: failed cap none: h = "), std::string::npos) << c.out;
  const std::size_t mark = c.out.find(" (chosen)");
  ASSERT_NE(mark, std::string::npos) << c.out;
  const std::string line = c.out.substr(c.out.rfind('\n', mark) + 1, mark - c.out.rfind('\n', mark) - 1);
  const std::string text = readFile(cal);
  EXPECT_NE(text.find("failed cap chosen from 0.15 (h "), std::string::npos) << text;
  // The file's failed level carries the chosen cap; an uncapped one has none.
  const std::size_t failed = text.find("\"failed\"");
  ASSERT_NE(failed, std::string::npos) << text;
  const bool capped = text.find("\"increment_cap\": 0.15", failed) != std::string::npos &&
                      text.find("\"increment_cap\": 0.15", failed) < text.find('}', failed);
  EXPECT_EQ(capped, line.find("failed cap 0.15") != std::string::npos) << line;
  // Several caps cannot be told apart without faulty flights; a budget with one cap chooses nothing.
  const CommandResult none =
      run("calibrate --model " + model + " --flights 2 --flight-seconds 4 --faulty-flights 0 --failed-cap 0.15 0.3 --output " + temp("never-written.json"));
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_EQ(countLines(none.out), 1) << none.out;
  EXPECT_NE(none.out.find("choosing among several --failed-cap needs --faulty-flights > 0"), std::string::npos) << none.out;
}

// A calibration file's command share of 1 (at byte `at`) replaced by 0 (no gate) and by 4 (a share no
// motor reaches while the others fly), each written beside the tests and run by detect on the faulty
// flight: {with 0, with 4}.
const std::string kShareOfOne = "\"min_command_share\": 1.0";
std::pair<CommandResult, CommandResult> detectWithShareAt(const std::string& model, const std::string& file, std::size_t at,
                                                          const std::string& stem) {
  CommandResult results[2];
  const char* shares[2] = {"0.0", "4.0"};
  for (int i = 0; i < 2; ++i) {
    std::string edited = file;
    edited.replace(at, kShareOfOne.size(), std::string("\"min_command_share\": ") + shares[i]);
    const std::string cal = temp(stem + "-" + shares[i] + ".json");
    std::ofstream(cal) << edited;
    results[i] = run("detect -q --model " + model + " --calibration " + cal + " --input " + faultyCsv() + " --output -", false);
  }
  return {results[0], results[1]};
}

// --failed-min-share: the calibration records the command share its failed excursions were gated
// at, and detect gates with it. A share no motor's command reaches (4: four times the mean, the
// other three at zero; this flight's failed motor peaks near 3.9) withholds every failed sample, so
// the complete failure that the same thresholds call `failed` without the share stays `degraded`.
TEST(DetectCli, TheFailedShareTravelsFromCalibrateToDetect) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw", cal = temp("failed-share.json");
  const CommandResult c = run("calibrate -q --model " + model + " --flights 2 --flight-seconds 4 --faulty-flights 3 --failed-min-share 1 --output " + cal);
  ASSERT_EQ(c.exit_code, 0) << c.out;
  const std::string file = readFile(cal);
  EXPECT_NE(file.find("\"min_command_share\": 1.0"), std::string::npos) << file;
  EXPECT_NE(file.find(", failed evidence at command shares from 1;"), std::string::npos) << file;  // and in `source`
  // The same thresholds with no share, and with one of 4.
  const std::size_t at = file.find(kShareOfOne);
  ASSERT_NE(at, std::string::npos);
  const auto [a, b] = detectWithShareAt(model, file, at, "failed-share");
  ASSERT_EQ(a.exit_code, 0) << a.out.substr(0, 400);
  ASSERT_EQ(b.exit_code, 0) << b.out.substr(0, 400);
  EXPECT_NE(a.out.find("\"motor\": 3, \"severity\": \"failed\""), std::string::npos);
  EXPECT_EQ(b.out.find("\"severity\": \"failed\""), std::string::npos);
  EXPECT_NE(b.out.find("\"motor\": 3, \"severity\": \"degraded\""), std::string::npos);
  // Out of range: refused in one line, nothing written.
  const CommandResult bad = run("calibrate --model " + model + " --flights 2 --failed-min-share 5 --output " + temp("never-written-share.json"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_EQ(countLines(bad.out), 1) << bad.out;
  EXPECT_NE(bad.out.find("--failed-min-share"), std::string::npos) << bad.out;
}

// --degraded-min-share: the calibration's degraded level records it and detect gates all evidence
// with it. A share of 4 leaves no motor observable, so the complete failure raises nothing.
TEST(DetectCli, TheDegradedShareTravelsFromCalibrateToDetect) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw", cal = temp("degraded-share.json");
  const CommandResult c = run("calibrate -q --model " + model + " --flights 2 --flight-seconds 4 --faulty-flights 3 --degraded-min-share 1 --output " + cal);
  ASSERT_EQ(c.exit_code, 0) << c.out;
  const std::string file = readFile(cal);
  const std::size_t at = file.find(kShareOfOne), degraded = file.find("\"degraded\""), failed = file.find("\"failed\"");
  ASSERT_NE(at, std::string::npos) << file;
  EXPECT_TRUE(degraded < at && at < failed) << file;  // the degraded level's, the only one
  EXPECT_EQ(file.find(kShareOfOne, at + 1), std::string::npos) << file;
  EXPECT_NE(file.find(", all evidence at command shares from 1;"), std::string::npos) << file;  // and in `source`
  const auto [a, b] = detectWithShareAt(model, file, at, "degraded-share");
  ASSERT_EQ(a.exit_code, 0) << a.out.substr(0, 400);
  ASSERT_EQ(b.exit_code, 0) << b.out.substr(0, 400);
  EXPECT_NE(a.out.find("\"motor\": 3, \"severity\": \"failed\""), std::string::npos);
  EXPECT_EQ(b.out.find("\"severity\": \"degraded\""), std::string::npos);
  EXPECT_EQ(b.out.find("\"severity\": \"failed\""), std::string::npos);
  const CommandResult bad = run("calibrate --model " + model + " --flights 2 --degraded-min-share 5 --output " + temp("never-written-dshare.json"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_EQ(countLines(bad.out), 1) << bad.out;
  EXPECT_NE(bad.out.find("--degraded-min-share"), std::string::npos) << bad.out;
}

// --reference absolute calibrates Θ̂ as the network gives it (the paper's models); the file says
// which, detect follows it, and an unknown reference is refused in one line. --estimate-reference
// changes what the estimate reads and nothing the statistics decide.
TEST(DetectCli, CalibrateRecordsItsReferencesAndDetectFollowsThem) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw";
  const char* references[3][2] = {{"absolute", "absolute"}, {"others", "others"}, {"others", "absolute"}};
  std::string outputs[3];
  for (int i = 0; i < 3; ++i) {
    const std::string rule = references[i][0], estimate = references[i][1];
    const std::string cal = temp("reference-" + rule + "-" + estimate + ".json");
    const CommandResult c = run("calibrate -q --model " + model + " --flights 2 --flight-seconds 4 --faulty-flights 3 --reference " + rule +
                                " --estimate-reference " + estimate + " --output " + cal);
    ASSERT_EQ(c.exit_code, 0) << c.out;
    const std::string file = readFile(cal);
    EXPECT_NE(file.find("\"reference\": \"" + rule + "\""), std::string::npos);
    EXPECT_NE(file.find("\"estimate_reference\": \"" + estimate + "\""), std::string::npos);
    EXPECT_EQ(file.find("\"estimate_noise\"") != std::string::npos, rule != estimate);
    EXPECT_NE(file.find("reference " + rule + ", estimate " + estimate + ";"), std::string::npos);  // and in `source`
    const CommandResult r = run("detect -q --model " + model + " --calibration " + cal + " --input " + faultyCsv() + " --output -", false);
    ASSERT_EQ(r.exit_code, 0) << r.out.substr(0, 400);
    outputs[i] = r.out;
  }
  EXPECT_TRUE(outputs[0] != outputs[1]);  // the estimates are of different quantities
  // Same statistics, thresholds and data: every line's decision is the same, the estimate not.
  const std::vector<std::string> relative = lines(outputs[1]), split = lines(outputs[2]);
  ASSERT_EQ(relative.size(), split.size());
  int estimates_differ = 0, alarmed = 0;
  for (std::size_t i = 0; i < relative.size(); ++i) {
    const std::size_t at = relative[i].find("\"theta_est\"");
    ASSERT_NE(at, std::string::npos) << relative[i];
    ASSERT_EQ(relative[i].substr(0, at), split[i].substr(0, at)) << i;
    estimates_differ += relative[i].substr(at) != split[i].substr(at);
    alarmed += relative[i].find("\"alarm\": true") != std::string::npos;
  }
  EXPECT_GT(alarmed, 0);
  EXPECT_GT(estimates_differ, 0);
  for (const char* option : {"--reference", "--estimate-reference"}) {
    const CommandResult bad =
        run("calibrate -q --model " + model + " --flights 2 " + option + " median --output " + temp("never-reference.json"));
    EXPECT_NE(bad.exit_code, 0);
    EXPECT_EQ(countLines(bad.out), 1) << bad.out;
    EXPECT_NE(bad.out.find(option), std::string::npos) << bad.out;
  }
}

// --settle: each healthy flight's first seconds (the recovery from its random initial state) are
// left out of the calibrated flight time; a settle that leaves nothing of a flight is refused.
TEST(DetectCli, CalibrateCountsHealthyFlightsFromTheSettleTimeOn) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw";
  auto hours = [&](const std::string& settle) {
    const std::string cal = temp("settle-" + settle + ".json");
    const CommandResult c = run("calibrate -q --model " + model + " --flights 2 --flight-seconds 4 --faulty-flights 0 --settle " + settle + " --output " + cal);
    EXPECT_EQ(c.exit_code, 0) << c.out;
    const std::string json = readFile(cal);
    EXPECT_NE(json.find("counted from " + settle + " s on"), std::string::npos) << json;
    const std::size_t at = json.find("\"flight_hours\": ");
    return at == std::string::npos ? -1.0 : std::stod(json.substr(at + 16));
  };
  const double all = hours("0"), settled = hours("1.5");
  EXPECT_NEAR(all - settled, 2 * 1.5 / 3600.0, 1e-9);  // 1.5 s of each of the 2 flights
  const CommandResult refused = run("calibrate -q --model " + model + " --flights 2 --flight-seconds 4 --settle 4 --output " + temp("never.json"));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_EQ(countLines(refused.out), 1) << refused.out;
  EXPECT_NE(refused.out.find("--settle must leave some of each --flight-seconds flight"), std::string::npos) << refused.out;
}

// --vehicle only chooses the vehicles of a randomisation: alone it is refused in one line rather
// than ignored (which would calibrate the nominal Crazyflie under the airframe's name).
TEST(DetectCli, CalibrateRefusesAVehicleWithoutARandomisation) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw";
  const std::string cal = temp("vehicle-alone.json");
  const CommandResult c = run("calibrate -q --model " + model + " --vehicle " + std::string(QUADFDI_SOURCE_DIR) +
                              "/configs/vehicles/racer250.toml --flights 2 --flight-seconds 4 --output " + cal);
  EXPECT_EQ(c.exit_code, 1);
  EXPECT_EQ(countLines(c.out), 1) << c.out;
  EXPECT_NE(c.out.find("--vehicle: needs --randomise FILE"), std::string::npos) << c.out;
  EXPECT_FALSE(std::filesystem::exists(cal));
}

// Several degraded levels: each is calibrated and scored on the faulty flights, one is kept, and
// detect then runs at the calibration's level unless told otherwise.
TEST(DetectCli, CalibrateChoosesALevelThatDetectThenUses) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw", cal = temp("chosen-calibration.json");
  const CommandResult c = run("calibrate --model " + model + " --flights 2 --flight-seconds 4 --faulty-flights 4 --degraded-below 0.8 0.9 --output " + cal);
  ASSERT_EQ(c.exit_code, 0) << c.out;
  EXPECT_NE(c.out.find("calibrate: degraded level 0.8: h = "), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("calibrate: degraded level 0.9: h = "), std::string::npos) << c.out;
  const std::size_t mark = c.out.find(" (chosen)");
  ASSERT_NE(mark, std::string::npos) << c.out;
  const std::string line = c.out.substr(c.out.rfind('\n', mark) + 1, mark - c.out.rfind('\n', mark) - 1);
  const std::string chosen = line.substr(std::string("calibrate: degraded level ").size(), 3);  // "0.8" or "0.9"
  ASSERT_TRUE(chosen == "0.8" || chosen == "0.9") << line;
  EXPECT_NE(readFile(cal).find("degraded level chosen from 0.8 (h "), std::string::npos);  // provenance in `source`
  // A mild fault (Θ = 0.6), where the degraded level decides the output.
  const std::string mild = temp("mild.csv");
  ASSERT_EQ(run("simulate --motor 2 --theta 0.6 --fault-step 500 --steps 1200 --seed 5 --output " + mild).exit_code, 0);
  const std::string base = "detect -q --model " + model + " --calibration " + cal + " --input " + mild + " --output -";
  const CommandResult by_default = run(base, false), named = run(base + " --degraded-below " + chosen, false);
  ASSERT_EQ(by_default.exit_code, 0) << by_default.out.substr(0, 400);
  EXPECT_TRUE(by_default.out == named.out);  // the calibration's level is the default
  EXPECT_TRUE(by_default.out != run(base + " --degraded-below 0.5", false).out);  // and another level is not ignored
  // Several levels cannot be told apart without faulty flights: refused in one line.
  const CommandResult none = run("calibrate --model " + model + " --flights 2 --flight-seconds 4 --faulty-flights 0 --degraded-below 0.8 0.9 --output " +
                                 temp("never-written.json"));
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_EQ(countLines(none.out), 1) << none.out;
  EXPECT_NE(none.out.find("needs --faulty-flights > 0"), std::string::npos) << none.out;
}

// The calibration's target rate is detect's default, as its levels are: a calibration made for
// 2000 false alarms an hour at level 0.95 (several in its 12 s of flight, so h comes from its own tail) runs at
// that rate's thresholds unless --false-alarms-per-hour says otherwise.
TEST(DetectCli, TheCalibrationsTargetRateIsTheDefault) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw", cal = temp("rate-calibration.json");
  ASSERT_EQ(run("calibrate -q --model " + model + " --flights 2 --flight-seconds 6 --faulty-flights 4 --degraded-below 0.95 --false-alarms-per-hour 2000 --output " + cal)
                .exit_code,
            0);
  EXPECT_NE(readFile(cal).find("\"target_rate_per_hour\": 2000"), std::string::npos);
  const std::string mild = temp("rate-mild.csv");
  ASSERT_EQ(run("simulate --motor 2 --theta 0.6 --fault-step 500 --steps 1200 --seed 5 --output " + mild).exit_code, 0);
  const std::string base = "detect -q --model " + model + " --calibration " + cal + " --input " + mild + " --output -";
  const CommandResult by_default = run(base, false);
  ASSERT_EQ(by_default.exit_code, 0) << by_default.out.substr(0, 400);
  EXPECT_TRUE(by_default.out == run(base + " --false-alarms-per-hour 2000", false).out);
  EXPECT_TRUE(by_default.out != run(base + " --false-alarms-per-hour 0.001", false).out);
}

// --refit-interval: the faulty flights are flown again and only the interval is refitted; the
// noise model, levels and thresholds are the file's. A belt is fitted (complete failures flown for
// its node at 0) and detect states it. A missing file is refused in one line naming it.
TEST(DetectCli, CalibrateRefitsOnlyTheInterval) {
  using quadfdi::DecisionCalibration;
  using quadfdi::readCalibrationFile;
  using quadfdi::calibrationToJson;
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw";
  const std::string cal = temp("refit-spread.json"), belt = temp("refit-belt.json"), again = temp("refit-again.json");
  ASSERT_EQ(run("calibrate -q --model " + model + " --flights 2 --flight-seconds 4 --faulty-flights 3 --output " + cal).exit_code, 0);
  const CommandResult r = run("calibrate --model " + model + " --faulty-flights 3 --refit-interval " + cal + " --interval belt --output " + belt);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("calibrate: interval of " + cal + " refitted (belt, "), std::string::npos) << r.out;
  const DecisionCalibration before = readCalibrationFile(cal), after = readCalibrationFile(belt);
  EXPECT_EQ(after.degraded.threshold, before.degraded.threshold);
  EXPECT_EQ(after.failed.threshold, before.failed.threshold);
  EXPECT_EQ(after.noise.sigma, before.noise.sigma);
  EXPECT_EQ(after.flight_hours, before.flight_hours);
  EXPECT_EQ(after.source.rfind(before.source, 0), 0u);  // the file's provenance, then the refit's
  EXPECT_NE(after.source.find("interval refitted (belt) on 3 faulty flights and 60 complete failures, LQR, nominal Crazyflie, goal every "),
            std::string::npos)
      << after.source;  // the refit names its own flights, which may differ from the file's
  ASSERT_FALSE(quadfdi::estimateNoise(after).belt.empty());
  EXPECT_EQ(quadfdi::estimateNoise(after).belt.front().theta, 0.0);
  EXPECT_TRUE(quadfdi::estimateNoise(before).belt.empty());
  // Refitting the spread on the same flights gives the file back, but for its provenance.
  ASSERT_EQ(run("calibrate -q --model " + model + " --faulty-flights 3 --refit-interval " + cal + " --output " + again).exit_code, 0);
  DecisionCalibration same = readCalibrationFile(again);
  same.source = before.source;
  EXPECT_EQ(calibrationToJson(same), calibrationToJson(before));
  const CommandResult d = run("detect --model " + model + " --calibration " + belt + " --input " + faultyCsv() + " --output " + temp("belt.jsonl"));
  ASSERT_EQ(d.exit_code, 0) << d.out;
  EXPECT_NE(d.out.find("FAULT in motor 3"), std::string::npos) << d.out;
  const CommandResult missing = run("calibrate -q --model " + model + " --refit-interval " + temp("no-such.json"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.out.find(temp("no-such.json") + ": "), std::string::npos) << missing.out;
  EXPECT_EQ(std::count(missing.out.begin(), missing.out.end(), '\n'), 1) << missing.out;
}

TEST(DetectCli, APipelineFromSimulateGivesTheFileModeOutput) {
  const CommandResult file = run("detect --input " + faultyCsv(), false);
  const CommandResult pipe =
      run("simulate --motor 3 --theta 0 --fault-step 500 --steps 800 --seed 4 --output - 2>/dev/null | " + exe() +
              " detect --input -",
          false);
  ASSERT_EQ(file.exit_code, 0);
  ASSERT_EQ(pipe.exit_code, 0);
  EXPECT_GT(countLines(file.out), 600);
  EXPECT_EQ(file.out, pipe.out);
}

// Copies a `simulate` CSV (header t,x,y,z,roll,pitch,yaw,u1..u4, then p,q,r with --rates) with
// each row's cells changed by `edit`.
void rewriteRows(const std::string& from, const std::string& to, const std::function<void(std::vector<std::string>&)>& edit) {
  std::istringstream in(readFile(from));
  std::ofstream out(to);
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line.rfind("t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4", 0), 0u);
  const std::size_t columns = line == "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4" ? 11u : 14u;
  out << line << "\n";
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string c; std::getline(row, c, ',');) cells.push_back(c);
    ASSERT_EQ(cells.size(), columns);
    edit(cells);
    for (std::size_t i = 0; i < cells.size(); ++i) out << (i ? "," : "") << cells[i];
    out << "\n";
  }
}

// A quadfdi-ordered telemetry CSV rewritten with u1..u4 in PX4's quad-X numbering (the library
// quad450's): PX4 motor m sits at quadfdi motor (1, 3, 4, 2)[m − 1], so column u_m is written from that one.
void writeInPx4Order(const std::string& ours, const std::string& px4) {
  rewriteRows(ours, px4, [](std::vector<std::string>& cells) {
    const int quadfdi_of_px4[] = {1, 3, 4, 2};
    const std::vector<std::string> read = cells;
    for (int m = 0; m < 4; ++m) cells[static_cast<std::size_t>(7 + m)] = read[static_cast<std::size_t>(6 + quadfdi_of_px4[m])];
  });
}

// A quadfdi telemetry CSV rewritten as a NED/FRD simulator writes it: y, z, pitch and yaw change
// sign (both frames turned 180° about x).
void writeAsNed(const std::string& ours, const std::string& ned) {
  rewriteRows(ours, ned, [](std::vector<std::string>& cells) {
    for (std::size_t i : {2u, 3u, 5u, 6u}) cells[i] = cells[i][0] == '-' ? cells[i].substr(1) : "-" + cells[i];
  });
}

// The library quad450 (`vehicle`) flown by the PID with motor 2 failing at 1 s: `ours` in quadfdi's
// motor order, `px4` the same rows in PX4's (writeInPx4Order).
void simulateQuadMotor2Failure(const std::string& vehicle, const std::string& ours, const std::string& px4) {
  ASSERT_EQ(run("simulate --controller pid --params " + vehicle + " --motor 2 --theta 0 --fault-step 500 --steps 1000 --seed 3 "
                "--output " + ours).exit_code, 0);
  writeInPx4Order(ours, px4);
}

// A props-out airframe (every propeller spinning the other way) is the standard X seen from axes
// turned 90° (docs/vehicles.md#plus-and-props-out-frames). The quad's flight, written as the
// props-out airframe's own telemetry (its attitude in its own axes, u1..u4 in its PX4 numbering),
// is read through its description in the turned axes: the same Θ̂ as the X's file, the same motor,
// named where it sits on the props-out airframe.
TEST(DetectCli, APropsOutAirframesOwnTelemetryIsReadAsTheStandardX) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const std::string vehicle = src + "/configs/vehicles/quad450.toml";
  const std::string ours = temp("quad-x.csv"), px4 = temp("quad-x-px4.csv"), own = temp("quad-props-out.csv");
  simulateQuadMotor2Failure(vehicle, ours, px4);
  // The description with every spin reversed, under the library's file name so that the quad's model runs.
  std::filesystem::create_directories(temp("props-out"));
  const std::string props_out = temp("props-out") + "/quad450.toml";
  {
    std::string text = readFile(vehicle);
    for (std::size_t at = 0; (at = text.find("spin = \"", at)) != std::string::npos; at += 8)
      text.replace(at + 8, text.compare(at + 8, 3, "ccw") == 0 ? 3 : 2, text.compare(at + 8, 3, "ccw") == 0 ? "cw" : "ccw");
    std::ofstream(props_out) << text;
  }
  const quadfdi::VehicleDescription d = quadfdi::loadVehicleDescription(props_out);
  ASSERT_EQ(d.body_turn.eighths, 2);
  rewriteRows(ours, own, [&](std::vector<std::string>& cells) {
    const std::vector<std::string> read = cells;
    const quadfdi::EulerZyx x_axes{std::stod(read[4]), std::stod(read[5]), std::stod(read[6])};
    const quadfdi::EulerZyx airframe = quadfdi::attitudeOfTurnedAxes(x_axes, quadfdi::BodyTurn{-2});
    char buf[3][32];
    std::snprintf(buf[0], sizeof buf[0], "%.17g", airframe.roll);
    std::snprintf(buf[1], sizeof buf[1], "%.17g", airframe.pitch);
    std::snprintf(buf[2], sizeof buf[2], "%.17g", airframe.yaw);
    for (int k = 0; k < 3; ++k) cells[static_cast<std::size_t>(4 + k)] = buf[k];
    for (std::size_t m = 0; m < 4; ++m) cells[7 + m] = read[static_cast<std::size_t>(6 + d.quadfdi_motor_of_autopilot_motor[m])];
  });
  const CommandResult reference = run("detect -q --vehicle " + vehicle + " --input " + ours, false);
  const CommandResult turned = run("detect -q --vehicle " + props_out + " --csv-numbering vehicle --input " + own, false);
  ASSERT_EQ(reference.exit_code, 0);
  ASSERT_EQ(turned.exit_code, 0) << turned.out;
  // Line by line: Θ̂ to the printed digit, save the motor's name and number.
  std::istringstream a(reference.out), b(turned.out);
  std::string la, lb;
  int lines = 0, failed = 0;
  while (std::getline(a, la) && std::getline(b, lb)) {
    ++lines;
    const auto head = [](const std::string& l) { return l.substr(0, l.find(", \"motor_position\"")); };
    ASSERT_EQ(head(lb), head(la)) << "line " << lines;
    if (la.find("\"motor\": 2, \"severity\": \"failed\"") != std::string::npos) {
      ++failed;
      EXPECT_NE(la.find("\"motor_position\": \"back-right\", \"autopilot_motor\": 4}"), std::string::npos) << la;
      EXPECT_NE(lb.find("\"motor_position\": \"front-right\", \"autopilot_motor\": 1}"), std::string::npos) << lb;
    }
  }
  EXPECT_FALSE(std::getline(a, la) || std::getline(b, lb));  // as many lines
  EXPECT_GT(lines, 200);
  EXPECT_GT(failed, 0);
  // Read in quadfdi's own conventions instead (no --csv-numbering), the airframe's axes are taken
  // for the X's: the attitude is a quarter turn off, which the output shows.
  const CommandResult unturned = run("detect -q --vehicle " + props_out + " --input " + own, false);
  EXPECT_NE(unturned.out, turned.out);
  // The quad's levers swap in the turned axes (|x|/|y| 0.62 → 1.62), outside what its model flew: said.
  const CommandResult said = run("detect --vehicle " + props_out + " --csv-numbering vehicle --input " + own + " --output " +
                                 temp("props-out.jsonl"));
  EXPECT_NE(said.out.find("detect: warning: the vehicle's rotor levers |x|/|y| = 1.62 (a props-out X, read in axes turned 90°: its "
                          "x and y levers swap) lie outside those "),
            std::string::npos)
      << said.out;
  EXPECT_NE(said.out.find("was trained on (0.62–0.62: quad450)"), std::string::npos) << said.out;
  const CommandResult x = run("detect --vehicle " + vehicle + " --input " + ours + " --output " + temp("x.jsonl"));
  EXPECT_EQ(x.out.find("rotor levers"), std::string::npos) << x.out;
}

// A simulator of another autopilot writes u1..u4 in that autopilot's numbering. Read as quadfdi's,
// the commands land on the wrong rotors and the alarm names the wrong motor; with
// --csv-numbering vehicle the description's [motor.N] table reorders them, and the output is the
// quadfdi-ordered file's byte for byte.
TEST(DetectCli, ACsvInTheVehiclesOwnNumberingIsReorderedByItsDescription) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const std::string vehicle = src + "/configs/vehicles/quad450.toml";  // written in PX4's numbering
  const std::string ours = temp("quad-quadfdi-order.csv"), px4 = temp("quad-px4-order.csv");
  simulateQuadMotor2Failure(vehicle, ours, px4);
  const CommandResult reference = run("detect -q --vehicle " + vehicle + " --input " + ours, false);
  const CommandResult reordered = run("detect -q --vehicle " + vehicle + " --csv-numbering vehicle --input " + px4, false);
  ASSERT_EQ(reference.exit_code, 0);
  ASSERT_EQ(reordered.exit_code, 0);
  EXPECT_EQ(reordered.out, reference.out);
  EXPECT_NE(reference.out.find("\"motor\": 2, \"severity\": \"failed\""), std::string::npos);
  EXPECT_NE(reference.out.find("\"motor_position\": \"back-right\", \"autopilot_motor\": 4}"), std::string::npos);
  // Unread, the PX4 order names another motor.
  const CommandResult misread = run("detect -q --vehicle " + vehicle + " --input " + px4, false);
  ASSERT_EQ(misread.exit_code, 0);
  EXPECT_EQ(misread.out.find("\"motor\": 2, \"severity\": \"failed\""), std::string::npos);
  // Read as a merged export, and imported: the same reordering, and the vehicle's numbers in the comment.
  const std::string numbered = " --vehicle " + vehicle + " --csv-numbering vehicle --format csv-merged ";
  const CommandResult merged = run("detect -q" + numbered + "--input " + px4, false);
  ASSERT_EQ(merged.exit_code, 0);
  EXPECT_NE(merged.out.find("\"motor\": 2, \"severity\": \"failed\""), std::string::npos);
  const CommandResult imported = run("import" + numbered + px4 + " -o " + temp("px4-imported.csv"));
  ASSERT_EQ(imported.exit_code, 0) << imported.out;
  EXPECT_NE(imported.out.find("u1..u4 in the vehicle's numbering (PX4 quad X, --csv-numbering vehicle), put in quadfdi's (motor ← column): "
                              "1 ← u1, 2 ← u4, 3 ← u2, 4 ← u3"),
            std::string::npos)
      << imported.out;
  EXPECT_NE(imported.out.find("2: back-right, PX4 quad X motor 4"), std::string::npos) << imported.out;
  EXPECT_EQ(readFile(temp("px4-imported.csv")).rfind("# motor_numbering: PX4 quad X = 1 4 2 3\n", 0), 0u);
  ASSERT_EQ(run("import --format csv-merged " + ours + " -o " + temp("ours-imported.csv")).exit_code, 0);
  const CommandResult back = run("detect -q --vehicle " + vehicle + " --input " + temp("px4-imported.csv"), false);
  const CommandResult ours_back = run("detect -q --vehicle " + vehicle + " --input " + temp("ours-imported.csv"), false);
  ASSERT_EQ(back.exit_code, 0);
  EXPECT_EQ(back.out, ours_back.out);
  EXPECT_EQ(back.out, merged.out);
  EXPECT_EQ(run("import --csv-numbering vehicle --format csv-merged " + px4 + " -o " + temp("x.csv")).exit_code, 1);
  // Refused, in one line, without a description (on a flight log: LogCli.CsvNumberingOnALogIsRefused).
  const CommandResult alone = run("detect --csv-numbering vehicle --input " + ours);
  EXPECT_EQ(alone.exit_code, 1);
  EXPECT_NE(alone.out.find("--csv-numbering vehicle: needs --vehicle FILE"), std::string::npos) << alone.out;
  EXPECT_EQ(countLines(alone.out), 1) << alone.out;
}

// Telemetry in another autopilot's motor order, read as quadfdi's, names every fault on the wrong
// motor and is otherwise a consistent file. The check of the columns against the flight's rotation
// (detection/numbering_check.h) says so: a warning naming PX4's order, in the summary too; the same
// rows in quadfdi's order, or read through the vehicle's numbering, are consistent.
TEST(DetectCli, AMotorOrderThatDoesNotTurnTheVehicleIsWarnedAbout) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const std::string vehicle = src + "/configs/vehicles/quad450.toml";  // written in PX4's numbering
  const std::string ours = temp("quad-circle.csv"), px4 = temp("quad-circle-px4.csv");
  // In turbulence, as every real flight is: a smooth reference flown on the true state alone
  // excites too little to tell (docs/conventions.md#checking-the-motor-numbering).
  ASSERT_EQ(run("simulate --controller pid --params " + vehicle + " --trajectory circle --speed 1.5 --steps 6000 --seed 3 "
                "--attitude-noise 0.002 --rotor-drag 0.2 --wind-speed 3 --turbulence 1.5 --output " + ours).exit_code, 0);
  writeInPx4Order(ours, px4);
  const CommandResult right = run("detect --input " + ours + " --output " + temp("circle.jsonl"));
  ASSERT_EQ(right.exit_code, 0) << right.out;
  EXPECT_NE(right.out.find("detect: motor numbering: consistent over 11."), std::string::npos) << right.out;
  const std::string summary = temp("circle-px4-summary.json");
  const CommandResult wrong = run("detect --input " + px4 + " --output " + temp("circle-px4.jsonl") + " --summary " + summary);
  ASSERT_EQ(wrong.exit_code, 0) << wrong.out;
  EXPECT_NE(wrong.out.find("detect: warning: " + px4 + ": motor numbering: another numbering over 11."), std::string::npos) << wrong.out;
  EXPECT_NE(wrong.out.find(": PX4's and ArduPilot's quad X order (u1..u4 = front-right, back-left, front-left, back-right) ("),
            std::string::npos)
      << wrong.out;
  EXPECT_NE(wrong.out.find("a file in that order is read with --csv-numbering vehicle"), std::string::npos) << wrong.out;
  const nlohmann::json j = nlohmann::json::parse(readFile(summary));
  EXPECT_EQ(j["motor_numbering_check"]["verdict"], "another numbering");
  EXPECT_EQ(j["motor_numbering_check"]["from"], "attitude");
  EXPECT_EQ(j["motor_numbering_check"]["fits_best"], "PX4's and ArduPilot's quad X order (u1..u4 = front-right, back-left, front-left, back-right)");
  EXPECT_LT(j["motor_numbering_check"]["fit"][0][0].get<double>(), 0.1);
  ASSERT_EQ(j["warnings"].size(), 1u);
  EXPECT_NE(j["warnings"][0].get<std::string>().find("motor numbering: another numbering"), std::string::npos);
  const CommandResult reordered = run("detect --vehicle " + vehicle + " --csv-numbering vehicle --input " + px4 + " --output " +
                                      temp("circle-reordered.jsonl") + " --summary " + temp("circle-reordered.json"));
  ASSERT_EQ(reordered.exit_code, 0) << reordered.out;
  EXPECT_NE(reordered.out.find("detect: motor numbering: consistent"), std::string::npos) << reordered.out;
  EXPECT_EQ(nlohmann::json::parse(readFile(temp("circle-reordered.json")))["motor_numbering_check"]["verdict"], "consistent");
  // The same rows written as a NED/FRD simulator writes them, read as z-up: upside down, and the
  // flag to give; read with it, consistent.
  const std::string ned = temp("quad-circle-ned.csv");
  writeAsNed(ours, ned);
  const CommandResult misread = run("detect --input " + ned + " --output " + temp("circle-ned.jsonl"));
  ASSERT_EQ(misread.exit_code, 0) << misread.out;
  EXPECT_NE(misread.out.find("motor numbering: upside down over 11."), std::string::npos) << misread.out;
  EXPECT_NE(misread.out.find("its frames are upside down (a NED/FRD file read as z-up, or a z-up one read as NED); read it with "
                             "--csv-frame ned"),
            std::string::npos)
      << misread.out;
  const CommandResult as_ned = run("detect --csv-frame ned --input " + ned + " --output " + temp("circle-ned-read.jsonl"));
  EXPECT_NE(as_ned.out.find("detect: motor numbering: consistent"), std::string::npos) << as_ned.out;
  // Both errors at once (a NED file in PX4's order): upside down, and turned back PX4's order; read
  // with both flags, consistent.
  const std::string ned_px4 = temp("quad-circle-ned-px4.csv"), both_summary = temp("circle-ned-px4.json");
  writeAsNed(px4, ned_px4);
  const CommandResult both = run("detect --input " + ned_px4 + " --output " + temp("circle-ned-px4.jsonl") + " --summary " + both_summary);
  ASSERT_EQ(both.exit_code, 0) << both.out;
  EXPECT_NE(both.out.find("motor numbering: upside down over 11."), std::string::npos) << both.out;
  EXPECT_NE(both.out.find("; turned back, PX4's and ArduPilot's quad X order (u1..u4 = front-right, back-left, front-left, back-right) ("),
            std::string::npos)
      << both.out;
  const nlohmann::json b = nlohmann::json::parse(readFile(both_summary));
  EXPECT_EQ(b["motor_numbering_check"]["verdict"], "upside down");
  EXPECT_EQ(b["motor_numbering_check"]["fits_best"], "PX4's and ArduPilot's quad X order (u1..u4 = front-right, back-left, front-left, back-right)");
  const CommandResult both_read = run("detect --csv-frame ned --vehicle " + vehicle + " --csv-numbering vehicle --input " + ned_px4 +
                                      " --output " + temp("circle-ned-px4-read.jsonl"));
  EXPECT_NE(both_read.out.find("detect: motor numbering: consistent"), std::string::npos) << both_read.out;
  // A flight too short to tell (1.6 s) is said to be so, and warns of nothing.
  const CommandResult short_flight = run("detect --input " + faultyCsv() + " --output " + temp("short.jsonl"));
  EXPECT_NE(short_flight.out.find("detect: motor numbering: too short to check ("), std::string::npos) << short_flight.out;
  EXPECT_EQ(short_flight.out.find("warning"), std::string::npos) << short_flight.out;
}

// A file's p,q,r checked against its own attitude's turn (logs/rate_agreement.h): as simulated,
// they agree; in FRD beside z-up attitude, or in degrees per second, a warning names what they
// hold, the model that does not read rates runs instead of the body-rates one, and the numbering
// check takes its turn from the attitude.
TEST(DetectCli, BodyRatesThatDoNotAgreeWithTheAttitudeAreWarnedAbout) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const std::string flight = temp("circle-rates.csv"), frd = temp("circle-rates-frd.csv"), deg = temp("circle-rates-deg.csv");
  ASSERT_EQ(run("simulate --rates --controller pid --params " + src + "/configs/vehicles/quad450.toml --trajectory circle --speed 1.5 "
                "--steps 6000 --seed 3 --attitude-noise 0.002 --rate-noise 0.02 --rotor-drag 0.2 --wind-speed 3 --turbulence 1.5 "
                "--output " + flight).exit_code, 0);
  rewriteRows(flight, frd, [](std::vector<std::string>& c) {
    for (std::size_t i : {12u, 13u}) c[i] = c[i][0] == '-' ? c[i].substr(1) : "-" + c[i];
  });
  rewriteRows(flight, deg, [](std::vector<std::string>& c) {
    for (std::size_t i : {11u, 12u, 13u}) c[i] = std::to_string(std::stod(c[i]) * 180.0 / M_PI);
  });
  const CommandResult agrees = run("detect --input " + flight + " --output " + temp("circle-rates.jsonl"));
  ASSERT_EQ(agrees.exit_code, 0) << agrees.out;
  EXPECT_NE(agrees.out.find("detect: body rates: p,q,r agree with the attitude's own turn over 599 windows"), std::string::npos) << agrees.out;
  EXPECT_NE(agrees.out.find("(the telemetry carries body rates: the general body-rates model)"), std::string::npos) << agrees.out;
  const std::string summary = temp("circle-rates-frd.json");
  const CommandResult turned = run("detect --input " + frd + " --output " + temp("circle-rates-frd.jsonl") + " --summary " + summary);
  ASSERT_EQ(turned.exit_code, 0) << turned.out;
  EXPECT_NE(turned.out.find("detect: warning: " + frd + ": body rates: the attitude turns as (p, −q, −r) would, not as p,q,r read"),
            std::string::npos)
      << turned.out;
  EXPECT_NE(turned.out.find("FRD rates (PX4, ArduPilot, Gazebo) beside attitude in quadfdi's frames?"), std::string::npos) << turned.out;
  EXPECT_NE(turned.out.find("the general model, which does not read them, not"), std::string::npos) << turned.out;
  EXPECT_NE(turned.out.find("detect: heading: not checked for estimator resets the log does not record: the gyro columns do not agree"),
            std::string::npos)
      << turned.out;
  EXPECT_NE(turned.out.find("detect: motor numbering: consistent over 11.7 s of flight (its angular acceleration, from the attitude"),
            std::string::npos)
      << turned.out;
  const nlohmann::json j = nlohmann::json::parse(readFile(summary));
  EXPECT_NE(j["model"].get<std::string>().find("tcn-randomised.qfdw"), std::string::npos) << j["model"];
  ASSERT_EQ(j["warnings"].size(), 1u);
  EXPECT_NE(j["warnings"][0].get<std::string>().find("body rates: the attitude turns as (p, −q, −r)"), std::string::npos);
  const CommandResult degrees = run("detect --input " + deg + " --output " + temp("circle-rates-deg.jsonl"));
  EXPECT_NE(degrees.out.find("p,q,r look like degrees per second read as radians (--csv-rate-unit deg/s"), std::string::npos) << degrees.out;
}

// Copies a `simulate` CSV with its roll,pitch,yaw written as the columns qw,qx,qy,qz of `writer`'s
// reading (the same numbers in other places), p,q,r kept or dropped.
void writeWithQuaternion(const std::string& from, const std::string& to, const quadfdi::QuaternionReading& writer, bool keep_rates) {
  std::istringstream in(readFile(from));
  std::ofstream out(to);
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line, "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,p,q,r");
  out << "t,x,y,z,qw,qx,qy,qz,u1,u2,u3,u4" << (keep_rates ? ",p,q,r" : "") << "\n";
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) c.push_back(cell);
    ASSERT_EQ(c.size(), 14u);
    const std::array<double, 4> q =
        quadfdi::columnsOfQuaternion(quadfdi::quaternionOfEuler({std::stod(c[4]), std::stod(c[5]), std::stod(c[6])}), writer);
    char cells[120];
    std::snprintf(cells, sizeof cells, "%.9f,%.9f,%.9f,%.9f", q[0], q[1], q[2], q[3]);
    out << c[0] << "," << c[1] << "," << c[2] << "," << c[3] << "," << cells;
    for (std::size_t i = 7; i < (keep_rates ? 14u : 11u); ++i) out << "," << c[i];
    out << "\n";
  }
}

// A quaternion written scalar last (Eigen, ROS) or as the inverse rotation reads as a plausible
// attitude of another flight: detect names the reading that fits, from the tilt alone and with the
// rates, and the flag it names reads the file as the one written in quadfdi's reading, byte for byte.
TEST(DetectCli, AQuaternionWrittenInAnotherReadingIsNamed) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const std::string flight = temp("yawing-rates.csv"), ours = temp("yawing-wxyz.csv"), last = temp("yawing-xyzw.csv"),
                    inverse = temp("yawing-inverse.csv");
  ASSERT_EQ(run("simulate --rates --controller pid --params " + src + "/configs/vehicles/quad450.toml --trajectory figure-eight --yaw-mode velocity --speed 1.5 "
                "--steps 6000 --seed 5 --attitude-noise 0.002 --rate-noise 0.02 --rotor-drag 0.2 --wind-speed 3 --turbulence 1.5 "
                "--output " + flight).exit_code, 0);
  writeWithQuaternion(flight, ours, {}, true);
  writeWithQuaternion(flight, last, {true, false}, false);
  writeWithQuaternion(flight, inverse, {false, true}, true);
  const CommandResult right = run("detect --input " + ours + " --output " + temp("yawing-wxyz.jsonl"));
  ASSERT_EQ(right.exit_code, 0) << right.out;
  EXPECT_NE(right.out.find("detect: attitude quaternion: read as w,x,y,z body → world it fits the flight ("), std::string::npos) << right.out;
  EXPECT_NE(right.out.find("detect: body rates: p,q,r agree"), std::string::npos) << right.out;
  const std::string summary = temp("yawing-xyzw.json");
  const CommandResult misread = run("detect --input " + last + " --output " + temp("yawing-xyzw.jsonl") + " --summary " + summary);
  ASSERT_EQ(misread.exit_code, 0) << misread.out;
  EXPECT_NE(misread.out.find("detect: warning: " + last + ": attitude quaternion: the columns qw,qx,qy,qz fit the flight read as x,y,z,w "
                             "body → world, not as w,x,y,z body → world ("),
            std::string::npos)
      << misread.out;
  EXPECT_NE(misread.out.find("): read them with --csv-quaternion xyzw (docs/conventions.md#attitude-as-a-quaternion)"), std::string::npos)
      << misread.out;
  const nlohmann::json j = nlohmann::json::parse(readFile(summary));
  ASSERT_GE(j["warnings"].size(), 1u);
  EXPECT_NE(j["warnings"][0].get<std::string>().find("attitude quaternion: the columns qw,qx,qy,qz fit the flight read as x,y,z,w"),
            std::string::npos);
  const nlohmann::json& q = j["quaternion_check"];
  EXPECT_EQ(q["verdict"], "another reading");
  EXPECT_EQ(q["read"], "w,x,y,z body → world");
  EXPECT_EQ(q["fits_best"], "x,y,z,w body → world");
  EXPECT_EQ(q["readings"][2], "x,y,z,w body → world");
  EXPECT_GT(std::abs(q["tilt_fit"][2].get<double>()), 0.9) << q;
  EXPECT_TRUE(q["rates_in_order"].is_null());  // written without p,q,r
  const CommandResult inverted = run("detect --input " + inverse + " --output " + temp("yawing-inverse.jsonl"));
  ASSERT_EQ(inverted.exit_code, 0) << inverted.out;
  EXPECT_NE(inverted.out.find("read them with --csv-quaternion wxyz-world-to-body"), std::string::npos) << inverted.out;
  EXPECT_NE(inverted.out.find("detect: body rates and heading resets: not checked (against an attitude read otherwise than written"),
            std::string::npos)
      << inverted.out;
  // Read as written: the same detection as quadfdi's own reading.
  const CommandResult reference = run("detect -q --input " + ours, false);
  const CommandResult reread = run("detect -q --csv-quaternion wxyz-world-to-body --input " + inverse, false);
  ASSERT_EQ(reference.exit_code, 0);
  EXPECT_GT(countLines(reference.out), 600);
  EXPECT_EQ(reread.out, reference.out);
  const CommandResult told = run("detect --csv-quaternion xyzw --input " + last + " --output " + temp("yawing-xyzw-read.jsonl"));
  EXPECT_NE(told.out.find("detect: attitude quaternion: read as x,y,z,w body → world it fits the flight"), std::string::npos) << told.out;
  // The flag on Euler angles, or on a flight log, reads nothing: refused.
  const CommandResult euler = run("detect --csv-quaternion xyzw --input " + flight + " --output " + temp("yawing-euler.jsonl"));
  EXPECT_EQ(euler.exit_code, 1);
  EXPECT_NE(euler.out.find("--csv-quaternion: " + flight + "'s header has roll, pitch, yaw, which are read"), std::string::npos) << euler.out;
}

// A simulator of PX4 or ArduPilot writes NED positions and FRD angles. Read with --csv-frame ned,
// the output is that of the same flight in quadfdi's frames, byte for byte; the flag is refused on
// a flight log (whose frames its reader knows).
TEST(DetectCli, ANedCsvIsReadInItsFrame) {
  const std::string ours = faultyCsv(), ned = temp("faulty-ned.csv");
  writeAsNed(ours, ned);
  const CommandResult reference = run("detect -q --input " + ours, false);
  const CommandResult turned = run("detect -q --csv-frame ned --input " + ned, false);
  ASSERT_EQ(reference.exit_code, 0);
  ASSERT_EQ(turned.exit_code, 0);
  EXPECT_GT(countLines(reference.out), 600);
  EXPECT_EQ(turned.out, reference.out);
  const CommandResult misread = run("detect -q --input " + ned, false);  // the flight upside down: other Θ̂
  ASSERT_EQ(misread.exit_code, 0);
  EXPECT_NE(misread.out, reference.out);
}

// Angles written in degrees: refused as radians with the flag to use; read with it, the same fault.
TEST(DetectCli, AnglesInDegreesAreReadWithTheirUnit) {
  const std::string deg = temp("faulty-deg.csv");
  rewriteRows(faultyCsv(), deg, [](std::vector<std::string>& cells) {
    for (std::size_t i : {4u, 5u, 6u}) {
      std::ostringstream v;
      v.precision(17);
      v << std::stod(cells[i]) * 180.0 / M_PI;
      cells[i] = v.str();
    }
  });
  const CommandResult reference = run("detect --input " + faultyCsv() + " --output " + temp("rad.jsonl"));
  const CommandResult read = run("detect --csv-angle-unit deg --input " + deg + " --output " + temp("deg.jsonl"));
  ASSERT_EQ(reference.exit_code, 0) << reference.out;
  ASSERT_EQ(read.exit_code, 0) << read.out;
  const auto fault = [](const std::string& s) { return s.substr(s.find("FAULT in motor"), 26); };
  ASSERT_TRUE(reference.out.find("FAULT in motor 3") != std::string::npos) << reference.out;
  EXPECT_EQ(fault(read.out), fault(reference.out));
  const CommandResult misread = run("detect --input " + deg + " --output " + temp("deg.jsonl"));
  EXPECT_EQ(misread.exit_code, 1);
  EXPECT_TRUE(misread.out.find("(degrees? --csv-angle-unit deg") != std::string::npos) << misread.out;
}

// A merged export of an estimator that reset its heading by 8° at 1.2 s (a ROS bag of an EKF's
// pose and its gyro): the gyro (p, q, r rows) does not show the step, so the conventions layer
// finds it and takes it out; import says so and writes the reset-free yaw.
TEST(DetectCli, AMergedExportsHeadingResetIsTakenOutWithItsGyro) {
  const std::string flight = temp("rates-flight.csv"), merged = temp("merged-heading-reset.csv"),
                    reference = temp("merged-no-reset.csv");
  ASSERT_EQ(run("simulate --rates --steps 1000 --seed 6 --output " + flight).exit_code, 0);
  {
    std::istringstream in(readFile(flight));
    std::ofstream out(merged), plain(reference);
    std::string line;
    std::getline(in, line);
    out << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,p,q,r\n";
    plain << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,p,q,r\n";
    for (int k = 0; std::getline(in, line); ++k) {
      const std::vector<std::string> c = csvCells(line);
      ASSERT_EQ(c.size(), 14u);
      const double t = std::stod(c[0]);
      char yaw[32];
      std::snprintf(yaw, sizeof yaw, "%.17g", std::stod(c[6]) + (t >= 1.2 ? 8.0 * M_PI / 180.0 : 0.0));
      for (int file = 0; file < 2; ++file) {
        std::ofstream& o = file == 0 ? out : plain;
        if (k % 10 == 0) o << c[0] << "," << c[1] << "," << c[2] << "," << c[3] << ",,,,,,,,,,\n";
        if (k % 2 == 0) o << c[0] << ",,,," << c[4] << "," << c[5] << "," << (file == 0 ? std::string(yaw) : c[6]) << ",,,,,,,\n";
        o << c[0] << ",,,,,,," << c[7] << "," << c[8] << "," << c[9] << "," << c[10] << ",,,\n";
        if (k % 2 == 1) o << c[0] << ",,,,,,,,,,," << c[11] << "," << c[12] << "," << c[13] << "\n";
      }
    }
  }
  const CommandResult read = run("import --format csv-merged " + merged + " -o " + temp("merged-reset-imported.csv"));
  ASSERT_EQ(read.exit_code, 0) << read.out;
  EXPECT_TRUE(read.out.find("heading: 1 yaw step that the gyro (columns p,q,r) does not show") != std::string::npos) << read.out;
  EXPECT_TRUE(read.out.find("(largest 8° at 1.200 s;") != std::string::npos) << read.out;
  const CommandResult clean = run("import --format csv-merged " + reference + " -o " + temp("merged-clean-imported.csv"));
  ASSERT_EQ(clean.exit_code, 0) << clean.out;
  EXPECT_TRUE(clean.out.find("no estimator reset the log does not record") != std::string::npos) << clean.out;
  // The yaw written: the reset-free file's, to the step's estimate through the 250 Hz rows.
  const std::vector<std::string> a = lines(readFile(temp("merged-reset-imported.csv"))),
                                 b = lines(readFile(temp("merged-clean-imported.csv")));
  ASSERT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].empty() || a[i][0] == '#' || a[i][0] == 't') continue;
    const std::vector<std::string> x = csvCells(a[i]), y = csvCells(b[i]);
    ASSERT_EQ(x.size(), y.size());
    worst = std::max(worst, std::abs(std::remainder(std::stod(x[6]) - std::stod(y[6]), 2.0 * M_PI)));
  }
  EXPECT_LT(worst, 1e-6);
}

// The same reset in a plain telemetry CSV with its gyro columns, which detect reads row by row: a
// file is first read whole to find it (io/telemetry_heading.h), then streamed with it taken out —
// the same JSON Lines as the reset-free file, and a warning that says what was taken out. A pipe
// is read once and not checked; a file without p,q,r has nothing to check with.
TEST(DetectCli, APlainCsvsHeadingResetIsTakenOutWithItsGyro) {
  const std::string flight = temp("rates-failure.csv"), stepped = temp("rates-failure-reset.csv");
  ASSERT_EQ(run("simulate --rates --motor 2 --theta 0 --fault-step 1500 --steps 2000 --seed 6 --output " + flight).exit_code, 0);
  rewriteRows(flight, stepped, [](std::vector<std::string>& c) {
    char yaw[32];
    std::snprintf(yaw, sizeof yaw, "%.17g", std::stod(c[6]) + (std::stod(c[0]) >= 1.2 ? 8.0 * M_PI / 180.0 : 0.0));
    c[6] = yaw;
  });
  const CommandResult clean = run("detect --input " + flight + " --output " + temp("rates-failure.jsonl"));
  ASSERT_EQ(clean.exit_code, 0) << clean.out;
  EXPECT_NE(clean.out.find("detect: heading: each of 1723 attitude steps checked against the gyro (columns p,q,r): no estimator "
                           "reset"),
            std::string::npos)
      << clean.out;
  const std::string summary = temp("rates-failure-reset.json");
  const CommandResult taken_out =
      run("detect --input " + stepped + " --output " + temp("rates-failure-reset.jsonl") + " --summary " + summary);
  ASSERT_EQ(taken_out.exit_code, 0) << taken_out.out;
  EXPECT_NE(taken_out.out.find("detect: warning: " + stepped + ": heading: 1 yaw step that the gyro (columns p,q,r) does not show"),
            std::string::npos)
      << taken_out.out;
  EXPECT_NE(taken_out.out.find("(largest 8° at 1.200 s;"), std::string::npos) << taken_out.out;
  EXPECT_NE(taken_out.out.find("FAULT in motor 2"), std::string::npos) << taken_out.out;
  EXPECT_EQ(readFile(temp("rates-failure-reset.jsonl")), readFile(temp("rates-failure.jsonl")));
  const nlohmann::json j = nlohmann::json::parse(readFile(summary));
  ASSERT_EQ(j["warnings"].size(), 1u);
  EXPECT_NE(j["warnings"][0].get<std::string>().find("heading: 1 yaw step"), std::string::npos);
  // Piped, the step stays in: other Θ̂ around it, and no heading line.
  const CommandResult piped = run("detect --input - --output " + temp("rates-failure-piped.jsonl") + " < " + stepped);
  ASSERT_EQ(piped.exit_code, 0) << piped.out;
  EXPECT_EQ(piped.out.find("heading:"), std::string::npos) << piped.out;
  EXPECT_NE(readFile(temp("rates-failure-piped.jsonl")), readFile(temp("rates-failure.jsonl")));
  const CommandResult no_rates = run("detect --input " + faultyCsv() + " --output " + temp("no-rates.jsonl"));
  ASSERT_EQ(no_rates.exit_code, 0) << no_rates.out;
  EXPECT_EQ(no_rates.out.find("heading:"), std::string::npos) << no_rates.out;
}

// A merged export (PlotJuggler, a ROS bag): each row holds one signal — position at 50 Hz,
// attitude at 250 Hz, commands at 500 Hz — and another topic's column has rows of its own.
// Refused as plain CSV with what to do; read with --format csv-merged, each signal from its own
// rows onto the model's clock (attitude and position interpolated, commands held), it names the
// same motor with Θ̂ within a few thousandths of the whole file's; --csv-frame reaches it; import
// writes the clock's samples, which detect reads back to the same output byte for byte.
TEST(DetectCli, AMergedExportIsReadSignalBySignal) {
  const std::string merged = temp("merged-export.csv"), merged_ned = temp("merged-export-ned.csv");
  {
    std::istringstream in(readFile(faultyCsv()));
    std::ofstream out(merged), ned(merged_ned);
    std::string line;
    std::getline(in, line);
    out << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,battery\n";
    ned << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,battery\n";
    for (int k = 0; std::getline(in, line); ++k) {
      const std::vector<std::string> c = csvCells(line);
      ASSERT_EQ(c.size(), 11u);
      auto flip = [](const std::string& v) { return v[0] == '-' ? v.substr(1) : "-" + v; };
      if (k % 10 == 0) {
        out << c[0] << "," << c[1] << "," << c[2] << "," << c[3] << ",,,,,,,,\n";
        ned << c[0] << "," << c[1] << "," << flip(c[2]) << "," << flip(c[3]) << ",,,,,,,,\n";
      }
      if (k % 2 == 0) {
        out << c[0] << ",,,," << c[4] << "," << c[5] << "," << c[6] << ",,,,,\n";
        ned << c[0] << ",,,," << c[4] << "," << flip(c[5]) << "," << flip(c[6]) << ",,,,,\n";
      }
      const std::string commands = c[0] + ",,,,,,," + c[7] + "," + c[8] + "," + c[9] + "," + c[10] + ",\n";
      out << commands;
      ned << commands;
      if (k % 7 == 0) {
        out << c[0] << ",,,,,,,,,,,3.9\n";
        ned << c[0] << ",,,,,,,,,,,3.9\n";
      }
    }
  }
  const CommandResult plain = run("detect --input " + merged + " --output " + temp("merged-plain.jsonl"));
  EXPECT_EQ(plain.exit_code, 1);
  EXPECT_TRUE(plain.out.find("read it with --format csv-merged") != std::string::npos) << plain.out;

  const CommandResult whole = run("detect --input " + faultyCsv() + " --output " + temp("whole.jsonl"));
  const CommandResult read = run("detect --format csv-merged --input " + merged + " --output " + temp("merged.jsonl"));
  ASSERT_EQ(whole.exit_code, 0) << whole.out;
  ASSERT_EQ(read.exit_code, 0) << read.out;
  EXPECT_TRUE(read.out.find("detect: merged telemetry CSV, evaluated 1 of 1 airborne phase (a telemetry CSV: the whole file)") !=
              std::string::npos)
      << read.out;
  const auto fault = [](const std::string& s) { return s.substr(s.find("FAULT in motor"), 26); };
  ASSERT_TRUE(whole.out.find("FAULT in motor 3") != std::string::npos) << whole.out;
  EXPECT_EQ(fault(read.out), fault(whole.out));
  // Θ̂ at the times both evaluate: the interpolated position and attitude move it by little.
  auto thetas = [](const std::string& path) {
    std::vector<std::pair<std::string, std::vector<double>>> rows;
    for (const std::string& l : lines(readFile(path))) {
      const std::size_t t = l.find("\"t\": "), th = l.find("\"theta\": [");
      if (t == std::string::npos || th == std::string::npos) continue;
      std::vector<double> v;
      std::istringstream cells(l.substr(th + 10, l.find(']', th) - th - 10));
      for (std::string c; std::getline(cells, c, ',');) v.push_back(std::stod(c));
      rows.emplace_back(l.substr(t + 5, l.find(',', t) - t - 5), v);
    }
    return rows;
  };
  const auto a = thetas(temp("whole.jsonl")), b = thetas(temp("merged.jsonl"));
  ASSERT_GT(b.size(), 200u);
  std::size_t compared = 0;
  double largest = 0.0;
  for (std::size_t i = 0, j = 0; i < a.size() && j < b.size();) {
    if (std::stod(a[i].first) < std::stod(b[j].first) - 1e-6) ++i;
    else if (std::stod(b[j].first) < std::stod(a[i].first) - 1e-6) ++j;
    else {
      for (std::size_t k = 0; k < 4; ++k) largest = std::max(largest, std::abs(a[i].second[k] - b[j].second[k]));
      ++compared, ++i, ++j;
    }
  }
  EXPECT_GT(compared, 200u);
  EXPECT_LT(largest, 0.02);
  EXPECT_GT(largest, 0.0);  // interpolated, not the same samples

  const CommandResult ned = run("detect -q --format csv-merged --csv-frame ned --input " + merged_ned, false);
  const CommandResult zup = run("detect -q --format csv-merged --input " + merged, false);
  ASSERT_EQ(ned.exit_code, 0);
  EXPECT_EQ(ned.out, zup.out);
  const CommandResult piped = run("detect -q --format csv-merged --input - < " + merged, false);  // read to its end first
  ASSERT_EQ(piped.exit_code, 0);
  EXPECT_EQ(piped.out, zup.out);

  // The export's own column names and a ROS clock in nanoseconds, read by --csv-columns and --csv-time-unit.
  {
    std::istringstream in(readFile(merged));
    std::ofstream out(temp("merged-named.csv"));
    std::string line;
    std::getline(in, line);
    out << "__time,/pose/x,/pose/y,/pose/z,roll,pitch,yaw,/motors/0,/motors/1,/motors/2,/motors/3,battery\n";
    while (std::getline(in, line)) {
      const std::size_t comma = line.find(',');
      out << std::llround(std::stod(line.substr(0, comma)) * 1e9) << line.substr(comma) << "\n";
    }
  }
  const std::string names = " --csv-columns t=__time x=/pose/x y=/pose/y z=/pose/z u1=/motors/0 u2=/motors/1 u3=/motors/2 u4=/motors/3";
  const CommandResult named = run("detect -q --format csv-merged --csv-time-unit ns" + names + " --input " + temp("merged-named.csv"), false);
  ASSERT_EQ(named.exit_code, 0);
  EXPECT_EQ(named.out, zup.out);
  const CommandResult unnamed = run("detect -q --format csv-merged --input " + temp("merged-named.csv"));
  EXPECT_EQ(unnamed.exit_code, 1);
  EXPECT_TRUE(unnamed.out.find("the header lacks column 't' (needs t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4, or qw,qx,qy,qz for the "
                               "attitude; others are ignored; --csv-columns reads a column named otherwise)") != std::string::npos)
      << unnamed.out;
  const CommandResult bad = run("detect --format csv-merged --csv-columns vx=/twist/x --input " + merged);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(countLines(bad.out), 1) << bad.out;
  EXPECT_TRUE(bad.out.find("'vx' is no telemetry column") != std::string::npos) << bad.out;

  const CommandResult imported = run("import -q --format csv-merged " + merged + " -o " + temp("merged-imported.csv"));
  ASSERT_EQ(imported.exit_code, 0) << imported.out;
  const CommandResult again = run("detect -q --input " + temp("merged-imported.csv"), false);
  ASSERT_EQ(again.exit_code, 0);
  EXPECT_EQ(again.out, zup.out);

  // Commands every 10 ms are too coarse: one line naming the columns and their rate.
  {
    std::istringstream in(readFile(merged));
    std::ofstream out(temp("merged-coarse.csv"));
    std::string line;
    for (int k = 0; std::getline(in, line);) {
      const bool commands = line.find(",,,,,,,0") != std::string::npos || line.find(",,,,,,,1") != std::string::npos;
      if (!commands || k++ % 5 == 0) out << line << "\n";
    }
  }
  const CommandResult coarse = run("detect --format csv-merged --input " + temp("merged-coarse.csv") + " --output " + temp("c.jsonl"));
  EXPECT_EQ(coarse.exit_code, 1);
  EXPECT_EQ(countLines(coarse.out), 1) << coarse.out;
  EXPECT_TRUE(coarse.out.find("merged-coarse.csv: columns u1,u2,u3,u4 (commands) is logged at 100.0 Hz") != std::string::npos)
      << coarse.out;
}

// One topic per motor (a simulator publishing each rotor's command on its own): each motor on rows
// of its own at the times of the whole file's rows gives its output byte for byte; a quarter
// period apart, the same motor at the same time; each motor at 100 Hz is refused as the slowest
// motor's rate, though the four together change every 2.5 ms.
TEST(DetectCli, MotorsOnRowsOfTheirOwnAreReadEachAlone) {
  // `motor_shift`: motor m's rows `motor_shift`·(m − 1) after the row's t; every `every`-th row's commands.
  auto writeExport = [&](const std::string& path, bool apart, double motor_shift, int every) {
    std::istringstream in(readFile(faultyCsv()));
    std::vector<std::pair<double, std::string>> rows;  // put in time order at the end
    std::string line;
    std::getline(in, line);
    for (int k = 0; std::getline(in, line); ++k) {
      const std::vector<std::string> c = csvCells(line);
      const double t = std::stod(c[0]);
      if (k % 10 == 0) rows.emplace_back(t, c[0] + "," + c[1] + "," + c[2] + "," + c[3] + ",,,,,,,");
      rows.emplace_back(t, c[0] + ",,,," + c[4] + "," + c[5] + "," + c[6] + ",,,,");
      if (k % every != 0) continue;
      if (!apart) {
        rows.emplace_back(t, c[0] + ",,,,,,," + c[7] + "," + c[8] + "," + c[9] + "," + c[10]);
        continue;
      }
      for (int m = 0; m < 4; ++m) {
        char shifted[40];
        std::snprintf(shifted, sizeof shifted, "%.17g", t + motor_shift * m);
        rows.emplace_back(t + motor_shift * m, (m == 0 ? c[0] : std::string(shifted)) + ",,,,,,," +
                                                   std::string(static_cast<std::size_t>(m), ',') + c[7 + m] +
                                                   std::string(static_cast<std::size_t>(3 - m), ','));
      }
    }
    std::stable_sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::ofstream out(path);
    out << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n";
    for (const auto& r : rows) out << r.second << "\n";
  };
  writeExport(temp("motors-together.csv"), false, 0.0, 1);
  writeExport(temp("motors-apart.csv"), true, 0.0, 1);
  writeExport(temp("motors-staggered.csv"), true, 0.0005, 1);
  writeExport(temp("motors-coarse.csv"), true, 0.0025, 5);
  const CommandResult together = run("detect -q --format csv-merged --input " + temp("motors-together.csv"), false);
  const CommandResult apart = run("detect -q --format csv-merged --input " + temp("motors-apart.csv"), false);
  ASSERT_EQ(together.exit_code, 0) << together.out;
  ASSERT_EQ(apart.exit_code, 0) << apart.out;
  EXPECT_EQ(apart.out, together.out);
  const CommandResult told = run("detect --format csv-merged --input " + temp("motors-apart.csv") + " --output " + temp("apart.jsonl"));
  ASSERT_EQ(told.exit_code, 0) << told.out;
  const CommandResult staggered = run("detect --format csv-merged --input " + temp("motors-staggered.csv") + " --output " + temp("staggered.jsonl"));
  ASSERT_EQ(staggered.exit_code, 0) << staggered.out;
  const auto fault = [](const std::string& s) { return s.substr(s.find("FAULT in motor"), 26); };
  ASSERT_NE(told.out.find("FAULT in motor 3"), std::string::npos) << told.out;
  EXPECT_EQ(fault(staggered.out), fault(told.out));
  const CommandResult coarse = run("detect --format csv-merged --input " + temp("motors-coarse.csv") + " --output " + temp("c.jsonl"));
  EXPECT_EQ(coarse.exit_code, 1);
  EXPECT_EQ(countLines(coarse.out), 1) << coarse.out;
  EXPECT_NE(coarse.out.find("motors-coarse.csv: column u1 (commands) is logged at 100.0 Hz"), std::string::npos) << coarse.out;
}

// Simulators write rotor speeds. Read as thrust, a Θ = 0.6 fault (its rotor at √0.6 of the speed
// commanded) is sized as 0.79; with --csv-commands rotor-speed the speeds are squared and the output
// is the thrust file's, byte for byte, whatever the speed's unit. A model that reads newtons is
// refused, as is the flag on a flight log (LogCli.CsvFrameOnALogIsRefused).
TEST(DetectCli, RotorSpeedCommandsAreReadAsTheirSquares) {
  const std::string thrust = temp("mild-thrust.csv"), speed = temp("mild-speed.csv");
  ASSERT_EQ(run("simulate --motor 2 --theta 0.6 --fault-step 500 --steps 1500 --seed 4 --output " + thrust).exit_code, 0);
  rewriteRows(thrust, speed, [](std::vector<std::string>& cells) {
    for (std::size_t i = 7; i < 11; ++i) {
      char text[40];
      std::snprintf(text, sizeof text, "%.17g", 1000.0 * std::sqrt(std::stod(cells[i])));  // √N, in any unit
      cells[i] = text;
    }
  });
  const CommandResult reference = run("detect --input " + thrust);
  const CommandResult squared = run("detect --csv-commands rotor-speed --input " + speed);
  ASSERT_EQ(reference.exit_code, 0) << reference.out;
  ASSERT_EQ(squared.exit_code, 0) << squared.out;
  EXPECT_EQ(squared.out, reference.out);
  EXPECT_NE(reference.out.find("detect: FAULT in motor 2 at t = 1.180 s: degraded, Θ̂ = 0.62"), std::string::npos) << reference.out;
  const CommandResult misread = run("detect --input " + speed);
  ASSERT_EQ(misread.exit_code, 0) << misread.out;
  EXPECT_NE(misread.out.find("degraded, Θ̂ = 0.79"), std::string::npos) << misread.out;
  const CommandResult newtons = run("detect --csv-commands rotor-speed --model " + std::string(QUADFDI_SOURCE_DIR) +
                                    "/models/tcn-model-free.qfdw --input " + speed);
  EXPECT_EQ(newtons.exit_code, 1);
  EXPECT_NE(newtons.out.find("--csv-commands rotor-speed: gives thrust only up to a constant factor"), std::string::npos) << newtons.out;
  EXPECT_EQ(countLines(newtons.out), 1) << newtons.out;
}

// A simulator or autopilot that logs the motor command (a throttle in [0, 1], or the ESC pulse)
// is read through the vehicle description's thrust curve: the same output as the file of thrusts,
// byte for byte. The quad's curve is far from linear (model_factor 0.806), so the command read as
// thrust would size every fault wrongly; without --vehicle there is no curve, and it is refused.
TEST(DetectCli, ThrottleAndPwmCommandsAreReadThroughTheVehiclesThrustCurve) {
  const std::string vehicle = std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/quad450.toml";
  const double kMax = 7.0664, kFactor = 0.806;  // quad450.toml [thrust] max, model_factor
  const std::string thrust = temp("quad-thrust.csv"), throttle = temp("quad-throttle.csv"), pwm = temp("quad-pwm.csv");
  ASSERT_EQ(run("simulate --params " + vehicle + " --motor 2 --theta 0.6 --fault-step 500 --steps 1500 --seed 4 --output " +
                thrust)
                .exit_code,
            0);
  auto commandOf = [&](const std::string& cell) {  // the root in [0, 1] of k c² + (1 − k) c = f / max
    const double r = std::stod(cell) / kMax;
    EXPECT_LE(r, 1.0) << "a simulated command above the motor's maximum";
    return (-(1.0 - kFactor) + std::sqrt((1.0 - kFactor) * (1.0 - kFactor) + 4.0 * kFactor * r)) / (2.0 * kFactor);
  };
  auto writeCommands = [&](const std::string& to, double zero, double full) {  // u = zero + (full − zero)·c
    rewriteRows(thrust, to, [&](std::vector<std::string>& cells) {
      for (std::size_t i = 7; i < 11; ++i) {
        char text[40];
        std::snprintf(text, sizeof text, "%.17g", zero + (full - zero) * commandOf(cells[i]));
        cells[i] = text;
      }
    });
  };
  writeCommands(throttle, 0.0, 1.0);
  writeCommands(pwm, 1100.0, 1900.0);
  const CommandResult reference = run("detect --vehicle " + vehicle + " --input " + thrust);
  const CommandResult from_throttle = run("detect --vehicle " + vehicle + " --csv-commands throttle --input " + throttle);
  const CommandResult from_pwm = run("detect --vehicle " + vehicle +
                                     " --csv-commands pwm --csv-pwm-min 1100 --csv-pwm-max 1900 --input " + pwm);
  ASSERT_EQ(reference.exit_code, 0) << reference.out;
  EXPECT_NE(reference.out.find("detect: FAULT in motor 2"), std::string::npos) << reference.out;
  EXPECT_EQ(from_throttle.out, reference.out);
  EXPECT_EQ(from_pwm.out, reference.out);
  const CommandResult misread = run("detect --vehicle " + vehicle + " --input " + throttle);
  ASSERT_EQ(misread.exit_code, 0) << misread.out;
  EXPECT_NE(misread.out, reference.out);
  const std::size_t at = misread.out.find("detect: FAULT");
  std::printf("[ measured ] quad450, motor 2 at Θ = 0.6: %s | throttle read as thrust: %s\n",
              reference.out.substr(reference.out.find("detect: FAULT"), 72).c_str(),
              at == std::string::npos ? "no alarm" : misread.out.substr(at, 72).c_str());

  const CommandResult no_vehicle = run("detect --csv-commands throttle --input " + throttle);
  EXPECT_EQ(no_vehicle.exit_code, 1);
  EXPECT_NE(no_vehicle.out.find("--csv-commands throttle: needs --vehicle FILE, whose [thrust] max and model_factor"),
            std::string::npos)
      << no_vehicle.out;
  const CommandResult stray = run("detect --csv-pwm-min 900 --input " + thrust);
  EXPECT_EQ(stray.exit_code, 1);
  EXPECT_NE(stray.out.find("--csv-pwm-min: is read only with --csv-commands pwm"), std::string::npos) << stray.out;
  const CommandResult as_pwm = run("detect --vehicle " + vehicle + " --csv-commands pwm --input " + throttle);
  EXPECT_EQ(as_pwm.exit_code, 0) << as_pwm.out;  // 0–1 µs: pulses below the range, read as no thrust, and warned of
  EXPECT_EQ(as_pwm.out.find("detect: FAULT"), std::string::npos) << as_pwm.out;
  EXPECT_NE(as_pwm.out.find("1500 of 1500 samples command no thrust from any motor"), std::string::npos) << as_pwm.out;
  EXPECT_EQ(reference.out.find("command no thrust"), std::string::npos) << reference.out;
}

// Logs stamped with seconds since 1970 are read as they are: the same Θ̂ and alarms as on the
// flight's own clock, each output's t moved by the offset and printed to its millisecond.
TEST(DetectCli, AnAbsoluteClockGivesTheSameDetections) {
  const double kOffset = 1764370000.0;  // [s] 2025-11-28 22:46:40 UTC
  const std::string absolute = temp("faulty-epoch.csv");
  rewriteRows(faultyCsv(), absolute, [&](std::vector<std::string>& cells) {
    char text[40];
    std::snprintf(text, sizeof text, "%.3f", kOffset + std::stod(cells[0]));
    cells[0] = text;
  });
  const CommandResult reference = run("detect -q --input " + faultyCsv(), false);
  const CommandResult moved = run("detect -q --input " + absolute, false);
  ASSERT_EQ(reference.exit_code, 0);
  ASSERT_EQ(moved.exit_code, 0);
  std::istringstream a(reference.out), b(moved.out);
  int lines = 0;
  for (std::string la, lb; std::getline(a, la);) {
    ASSERT_TRUE(std::getline(b, lb)) << "line " << lines;
    const std::size_t ta = la.find(", \"theta\""), tb = lb.find(", \"theta\"");
    ASSERT_NE(ta, std::string::npos);
    ASSERT_NE(tb, std::string::npos);
    EXPECT_EQ(la.substr(ta), lb.substr(tb)) << "line " << lines;
    EXPECT_NEAR(std::stod(lb.substr(6, tb - 6)) - kOffset, std::stod(la.substr(6, ta - 6)), 1e-6) << lb;
    ++lines;
  }
  EXPECT_GT(lines, 600);
  EXPECT_NE(moved.out.find("\"t\": 1764370001.0000, "), std::string::npos);  // every digit of a millisecond clock
}

// A 5 m height reset in the middle of a healthy flight (an estimator switching its height source)
// raised a false `failed` when read as flight; it restarts the detector, with a warning naming the line.
TEST(DetectCli, AnEstimatorResetRestartsTheDetectorInsteadOfAlarming) {
  const std::string healthy = temp("healthy-2500.csv"), reset = temp("height-reset.csv");
  ASSERT_EQ(run("simulate --steps 2500 --seed 4 --output " + healthy).exit_code, 0);
  int row = 0;
  rewriteRows(healthy, reset, [&](std::vector<std::string>& cells) {
    if (++row > 1500) cells[3] = std::to_string(std::stod(cells[3]) + 5.0);
  });
  const CommandResult r = run("detect --input " + reset + " --output " + temp("height-reset.jsonl"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("height-reset.csv:1502: the state estimate jumped (5.00 m, 0.0° in 2.0 ms: an estimator reset?); the "
                       "detector starts again"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("detect: no fault"), std::string::npos) << r.out;
}

// Issue 13: a library vehicle is detected with its own shipped model (models/tcn-STEM.qfdw), a
// vehicle without one with the general model; --model still wins. A racer flown by the PID that
// loses half of motor 2's thrust (quadfdi numbering) at 1 s is found by its own model.
TEST(DetectCli, AVehicleRunsItsOwnShippedModel) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const std::string csv = temp("racer.csv");
  ASSERT_EQ(run("simulate --controller pid --params " + src + "/configs/vehicles/racer250.toml --motor 2 --theta 0.5 "
                "--fault-step 500 --steps 1200 --seed 3 --output " + csv).exit_code, 0);
  const CommandResult own = run("detect --vehicle " + src + "/configs/vehicles/racer250.toml --input " + csv + " --output -", true);
  ASSERT_EQ(own.exit_code, 0) << own.out;
  EXPECT_NE(own.out.find("/models/tcn-racer250.qfdw (for --vehicle"), std::string::npos) << own.out;
  EXPECT_NE(own.out.find("FAULT in motor 2 at t = 1."), std::string::npos) << own.out.substr(own.out.size() - 400);
  // The racer's description numbers its motors as Betaflight does: quadfdi's back-right motor 2 is
  // its motor 1, in the summary and in every alarmed line.
  EXPECT_NE(own.out.find("detect: motor 2 is the back-right motor: Betaflight QUAD X motor 1\n"), std::string::npos)
      << own.out.substr(own.out.size() - 400);
  EXPECT_NE(own.out.find("\"motor_position\": \"back-right\", \"autopilot_motor\": 1}"), std::string::npos);
  EXPECT_EQ(own.out.find("\"motor_position\": \"back-right\", \"autopilot_motor\": 2}"), std::string::npos);
  // The same description under a name no shipped model has (a user's own vehicle): the general model.
  const std::string mine = temp("my-racer.toml");
  std::ofstream(mine) << readFile(src + "/configs/vehicles/racer250.toml");
  const CommandResult general = run("detect -q --vehicle " + mine + " --input " + csv, false);
  const CommandResult plain = run("detect -q --input " + csv, false);
  ASSERT_EQ(general.exit_code, 0);
  // No shipped model for that file name: the general model, the same output but for the motor
  // numbers the description's Betaflight numbering gives.
  EXPECT_NE(general.out, plain.out);
  EXPECT_EQ(withoutAutopilotNumbers(general.out), withoutAutopilotNumbers(plain.out));
  const CommandResult told = run("detect --vehicle " + mine + " --input " + csv + " --output -", true);
  EXPECT_NE(told.out.find("/models/tcn-randomised.qfdw (the general model: no tcn-" + std::filesystem::path(mine).stem().string() +
                             ".qfdw in " + src + "/models for --vehicle " + mine + ")"),
            std::string::npos)
      << told.out.substr(0, 400);
  const CommandResult named =
      run("detect -q --model " + src + "/models/tcn-randomised.qfdw --vehicle " + src + "/configs/vehicles/racer250.toml --input " + csv, false);
  EXPECT_EQ(withoutAutopilotNumbers(named.out), withoutAutopilotNumbers(plain.out));
  EXPECT_NE(named.out, run("detect -q --vehicle " + src + "/configs/vehicles/racer250.toml --input " + csv, false).out);
  // A description that does not read is refused in one line naming it, whatever the input, and
  // an existing output is kept.
  const std::string bad = temp("bad-vehicle.toml"), out = temp("vehicle-kept.jsonl");
  std::ofstream(bad) << "name = \"x\"\nmass = abc\n";
  std::ofstream(out) << "kept\n";
  for (const std::string& vehicle : {bad, temp("no-such-vehicle.toml")}) {
    const CommandResult r = run("detect --vehicle " + vehicle + " --input " + csv + " --output " + out);
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_EQ(countLines(r.out), 1) << r.out;
    EXPECT_EQ(r.out.rfind("quadfdi: error: " + vehicle, 0), 0u) << r.out;
  }
  EXPECT_EQ(readFile(out), "kept\n");
}

// A vehicle with a body-rates model of its own (tcn-STEM-rates.qfdw) besides its other model: the
// choice holds both, and which runs is the input's to say; a rates model alone stands beside the
// general one; --model and $QUADFDI_MODEL still win and bring no rates model. A pair that would
// open the input differently is refused, naming why.
TEST(DetectCli, AVehiclesBodyRatesModelIsTheChoiceBesideItsOtherModel) {
  using quadfdi::cli::DetectModelChoice;
  using quadfdi::cli::detectModelPath;
  namespace fs = std::filesystem;
  unsetenv("QUADFDI_MODEL");
  const fs::path dir = temp("rates-models");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto touch = [&](const std::string& name) { std::ofstream((dir / name).string()) << "x"; };
  const std::string quad = "configs/vehicles/quad450.toml", racer = "/somewhere/racer250.toml";
  touch("tcn-quad450.qfdw");
  touch("tcn-quad450-rates.qfdw");
  touch("tcn-racer250-rates.qfdw");
  DetectModelChoice c = detectModelPath("", quad, dir.string());
  EXPECT_EQ(c.source, DetectModelChoice::Source::kVehicle);
  EXPECT_EQ(c.path, (dir / "tcn-quad450.qfdw").string());
  EXPECT_EQ(c.rates_path, (dir / "tcn-quad450-rates.qfdw").string());
  c = detectModelPath("", racer, dir.string());  // a rates model and no other: the general model without rates
  EXPECT_EQ(c.source, DetectModelChoice::Source::kGeneral);
  EXPECT_EQ(c.path, (dir / "tcn-randomised.qfdw").string());
  EXPECT_EQ(c.rates_path, (dir / "tcn-racer250-rates.qfdw").string());
  c = detectModelPath("", "my-quad.toml", dir.string());
  EXPECT_EQ(c.source, DetectModelChoice::Source::kGeneral);
  EXPECT_TRUE(c.rates_path.empty());
  // The general model on rates stands in where the general model runs, and only there: a vehicle with
  // a model of its own keeps it, and a vehicle's own rates model wins.
  touch("tcn-randomised-rates.qfdw");
  touch("tcn-crazyflie2.qfdw");
  for (const std::string vehicle : {"", "my-quad.toml"}) {
    c = detectModelPath("", vehicle, dir.string());
    EXPECT_EQ(c.source, DetectModelChoice::Source::kGeneral) << vehicle;
    EXPECT_EQ(c.path, (dir / "tcn-randomised.qfdw").string()) << vehicle;
    EXPECT_EQ(c.rates_path, (dir / "tcn-randomised-rates.qfdw").string()) << vehicle;
  }
  EXPECT_EQ(detectModelPath("", racer, dir.string()).rates_path, (dir / "tcn-racer250-rates.qfdw").string());
  EXPECT_EQ(detectModelPath("", quad, dir.string()).rates_path, (dir / "tcn-quad450-rates.qfdw").string());
  c = detectModelPath("", "crazyflie2", dir.string());
  EXPECT_EQ(c.source, DetectModelChoice::Source::kVehicle);
  EXPECT_TRUE(c.rates_path.empty());
  fs::remove(dir / "tcn-randomised-rates.qfdw");
  c = detectModelPath("mine.qfdw", quad, dir.string());
  EXPECT_EQ(c.source, DetectModelChoice::Source::kOption);
  EXPECT_EQ(c.path, "mine.qfdw");
  EXPECT_TRUE(c.rates_path.empty());
  setenv("QUADFDI_MODEL", "env.qfdw", 1);
  c = detectModelPath("", quad, dir.string());
  unsetenv("QUADFDI_MODEL");
  EXPECT_EQ(c.source, DetectModelChoice::Source::kEnvironment);
  EXPECT_TRUE(c.rates_path.empty());

  quadfdi::ModelMetadata plain, rates;
  plain.features = quadfdi::FeatureSet::kScaleFree;
  rates.features = quadfdi::FeatureSet::kScaleFreeRates;
  EXPECT_EQ(quadfdi::cli::ratesModelPairProblem(plain, rates), "");
  quadfdi::ModelMetadata slow = rates;
  slow.dt = 0.004;
  EXPECT_NE(quadfdi::cli::ratesModelPairProblem(plain, slow).find("it runs at dt = 0.004000 s"), std::string::npos);
  EXPECT_NE(quadfdi::cli::ratesModelPairProblem(plain, plain).find("it reads no body rates (features scale-free)"), std::string::npos);
  quadfdi::ModelMetadata newtons = plain;
  newtons.features = quadfdi::FeatureSet::kModelFreeHeading;
  EXPECT_NE(quadfdi::cli::ratesModelPairProblem(newtons, rates).find("read commands differently"), std::string::npos);

  // Every shipped body-rates model pairs with the model detect runs on the same vehicle without
  // rates (its own, else the general one): a pair that does not would refuse every input.
  int shipped = 0;
  const fs::path models = fs::path(QUADFDI_SOURCE_DIR) / "models";
  for (const auto& entry : fs::directory_iterator(models)) {
    const std::string name = entry.path().filename().string(), suffix = "-rates.qfdw";
    if (name.size() <= suffix.size() || name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
    ++shipped;
    const std::string stem = name.substr(4, name.size() - 4 - suffix.size());  // tcn-STEM-rates.qfdw
    const bool general = name == quadfdi::cli::kGeneralRatesModelName;      // beside the general model, for no vehicle
    const DetectModelChoice pair = detectModelPath("", general ? "" : stem + ".toml", models.string());
    ASSERT_EQ(pair.rates_path, entry.path().string());
    EXPECT_EQ(quadfdi::cli::ratesModelPairProblem(quadfdi::readModelFile(pair.path).metadata,
                                                  quadfdi::readModelFile(pair.rates_path).metadata), "") << name;
  }
  EXPECT_GE(shipped, 1);  // the 1.5 kg quad's
}

// --fault-exit-code N: a run that raised an alarm exits N once every output is written; a healthy
// one exits 0; without the option a fault exits 0 as before. 1, 2 and 130 keep their meaning
// (error, usage, interrupt), so the option refuses them, in one line, as any out-of-range value.
TEST(DetectCli, AFaultExitsWithTheStatusAskedForAfterItsOutputIsWritten) {
  const std::string healthy = temp("exit-healthy.csv"), out = temp("exit-fault.jsonl"), summary = temp("exit-fault.json");
  ASSERT_EQ(run("simulate --steps 800 --seed 4 --output " + healthy).exit_code, 0);
  const CommandResult fault = run("detect -q --fault-exit-code 3 --input " + faultyCsv() + " --output " + out + " --summary " + summary);
  EXPECT_EQ(fault.exit_code, 3) << fault.out;
  EXPECT_NE(readFile(out).find("\"alarm\": true"), std::string::npos);
  EXPECT_NE(readFile(summary).find("\"verdict\":\"fault\""), std::string::npos) << readFile(summary).substr(0, 300);
  EXPECT_EQ(run("detect -q --input " + faultyCsv() + " --output " + out).exit_code, 0);
  const CommandResult quiet = run("detect -q --fault-exit-code 3 --input " + healthy + " --output " + out);
  EXPECT_EQ(quiet.exit_code, 0) << quiet.out;
  EXPECT_EQ(readFile(out).find("\"alarm\": true"), std::string::npos);
  for (const std::string reserved : {"1", "2", "130"}) {
    const CommandResult r = run("detect -q --fault-exit-code " + reserved + " --input " + healthy + " --output " + out);
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_EQ(r.out, "quadfdi: error: --fault-exit-code: must be in [3, 125], got " + reserved + "\n");
  }
}

// One simulated flight written twice, with body-rate columns p,q,r (gyro noise 0.02 rad/s) and
// without: {with rates, without}. `flight` is simulate's options up to the output.
std::pair<std::string, std::string> flightWithAndWithoutRates(const std::string& flight, const std::string& stem) {
  const std::string with_rates = temp(stem + "-rates.csv"), without = temp(stem + "-no-rates.csv");
  EXPECT_EQ(run(flight + " --rates --rate-noise 0.02 --output " + with_rates).exit_code, 0);
  EXPECT_EQ(run(flight + " --output " + without).exit_code, 0);
  return {with_rates, without};
}

// t of the first JSON line of detect's output that holds `alarm` (its prefix from "\"alarm\": true"); -1 when none does.
double firstAlarmTime(const std::string& out, const std::string& alarm) {
  const std::size_t at = out.find(alarm);
  if (at == std::string::npos) return -1.0;
  const std::size_t line = out.rfind("{\"t\": ", at);
  return std::stod(out.substr(line + 6, 12));
}

// The 1.5 kg quad ships a body-rates model beside its other one (models/README.md): a flight that
// logs p,q,r runs it, the same flight without them runs the other and says why. A mild fault
// (motor 1 at 80 %) under the PID is named `degraded` by the rates model within 0.3 s.
TEST(DetectCli, TheQuadRunsItsBodyRatesModelWhereTheTelemetryHasRates) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const auto [with_rates, without] = flightWithAndWithoutRates("simulate --params " + src + "/configs/vehicles/quad450.toml --controller pid "
                                                               "--motor 1 --theta 0.8 --fault-step 500 --steps 1000 --seed 2 --attitude-noise 0.002",
                                                               "quad");
  ASSERT_FALSE(HasFailure());
  const std::string detect = "detect --vehicle quad450 --output - --input ";
  const CommandResult rates = run(detect + with_rates, true);
  ASSERT_EQ(rates.exit_code, 0) << rates.out;
  EXPECT_NE(rates.out.find("/models/tcn-quad450-rates.qfdw (the telemetry carries body rates: the body-rates model for --vehicle"),
            std::string::npos) << rates.out.substr(0, 400);
  EXPECT_NE(rates.out.find("detect: FAULT in motor 1 at t = 1."), std::string::npos) << rates.out.substr(rates.out.size() - 600);
  // The first alarm: degraded, within 0.3 s of the fault at t = 1 s.
  const double first = firstAlarmTime(rates.out, "\"alarm\": true, \"motor\": 1, \"severity\": \"degraded\"");
  ASSERT_GE(first, 0.0);
  EXPECT_LT(first, 1.3);
  const CommandResult plain = run(detect + without, true);
  ASSERT_EQ(plain.exit_code, 0) << plain.out;
  EXPECT_NE(plain.out.find("/models/tcn-quad450.qfdw (for --vehicle"), std::string::npos) << plain.out.substr(0, 400);
  EXPECT_NE(plain.out.find("detect: the telemetry has no body rates: " + src + "/models/tcn-quad450-rates.qfdw, which reads them, is not run"),
            std::string::npos) << plain.out.substr(0, 600);
  EXPECT_EQ(plain.out.find("\"severity\": \"failed\""), std::string::npos);
  // A named model is run whatever the input: no rates model comes with it.
  const CommandResult named = run("detect -q --model " + src + "/models/tcn-quad450.qfdw --vehicle quad450 --input " + with_rates, false);
  EXPECT_EQ(named.exit_code, 0);
  EXPECT_EQ(named.out, run("detect -q --vehicle quad450 --input " + without, false).out);
}

// The general body-rates model ships beside the general model (models/README.md, 2026-12-05): on
// an airframe no model was trained on (the held-out X500), telemetry with p,q,r runs it and says
// so, and a complete failure of motor 2 under the PID is named `failed` on motor 2 within 0.1 s;
// the same flight without rates runs the general model and names the same motor.
TEST(DetectCli, TelemetryWithRatesRunsTheGeneralBodyRatesModelWithoutAVehicle) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const auto [with_rates, without] = flightWithAndWithoutRates("simulate --params " + src + "/configs/vehicles/held-out/x500.toml --controller pid "
                                                               "--motor 2 --theta 0 --fault-step 500 --steps 1000 --seed 2 --attitude-noise 0.002",
                                                               "x500");
  ASSERT_FALSE(HasFailure());
  const CommandResult rates = run("detect --output - --input " + with_rates, true);
  ASSERT_EQ(rates.exit_code, 0) << rates.out;
  EXPECT_NE(rates.out.find("detect: model " + src + "/models/tcn-randomised-rates.qfdw (the telemetry carries body rates: the general "
                           "body-rates model)"),
            std::string::npos) << rates.out.substr(0, 400);
  const double first = firstAlarmTime(rates.out, "\"alarm\": true, \"motor\": 2, \"severity\": \"failed\"");
  ASSERT_GE(first, 0.0) << rates.out.substr(rates.out.size() - 600);
  EXPECT_LT(first, 1.1);
  EXPECT_EQ(rates.out.find("\"alarm\": true, \"motor\": 1"), std::string::npos);
  const CommandResult plain = run("detect --output - --input " + without, true);
  ASSERT_EQ(plain.exit_code, 0) << plain.out;
  EXPECT_EQ(plain.out.find("general body-rates model"), std::string::npos) << plain.out.substr(0, 400);
  EXPECT_NE(plain.out.find("detect: FAULT in motor 2 at t = 1.0"), std::string::npos) << plain.out.substr(plain.out.size() - 600);
}

// A model's calibration for one airframe (MODEL.STEM.calibration.json beside MODEL.qfdw) is what
// detect --vehicle STEM.toml runs with, and says so; without such a file, the model's own sidecar.
TEST(DetectCli, AVehicleRunsTheModelsCalibrationForIt) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const std::string model = temp("vcal-m.qfdw"), sidecar = temp("vcal-m.calibration.json"), own = temp("vcal-m.racer250.calibration.json");
  std::filesystem::copy_file(src + "/models/tcn-model-free.qfdw", model, std::filesystem::copy_options::overwrite_existing);
  const std::string calibration = readFile(src + "/models/tcn-model-free.calibration.json");
  std::ofstream(sidecar) << calibration;
  std::string frequent = calibration;  // the same data re-solved for 1000 alarms an hour: other thresholds
  const std::size_t at = frequent.find("\"target_rate_per_hour\": ") + 24;
  frequent.replace(at, frequent.find_first_of(",\n", at) - at, "1000");
  std::ofstream(own) << frequent;
  const std::string racer = src + "/configs/vehicles/racer250.toml", base = "detect --model " + model + " --input " + faultyCsv() + " --output -";
  const CommandResult picked = run(base + " --vehicle " + racer, true);
  ASSERT_EQ(picked.exit_code, 0) << picked.out.substr(0, 400);
  EXPECT_NE(picked.out.find("detect: calibration " + own + " (for --vehicle " + racer + ")"), std::string::npos) << picked.out.substr(0, 400);
  EXPECT_TRUE(withoutAutopilotNumbers(run(base + " -q --vehicle " + racer, false).out) ==
              withoutAutopilotNumbers(run(base + " -q --calibration " + own, false).out));
  const CommandResult other = run(base + " -q --vehicle " + src + "/configs/vehicles/crazyflie2.toml", false);  // no file for it
  EXPECT_TRUE(other.out == run(base + " -q --calibration " + sidecar, false).out);
  EXPECT_TRUE(other.out != run(base + " -q --calibration " + own, false).out);
  // A vehicle that chose neither the model (--model is given) nor a calibration is said to only
  // name the motors.
  const std::string crazyflie = src + "/configs/vehicles/crazyflie2.toml";
  EXPECT_NE(run(base + " --vehicle " + crazyflie, true).out.find("detect: warning: --vehicle " + crazyflie + " only names the motors"),
            std::string::npos);
  EXPECT_EQ(picked.out.find("only names the motors"), std::string::npos);
}

TEST(DetectCli, AHealthyFlightRaisesNoAlarm) {
  const std::string csv = temp("healthy.csv");
  ASSERT_EQ(run("simulate --steps 1500 --seed 8 --output " + csv).exit_code, 0);
  const CommandResult r = run("detect --input " + csv + " --output " + temp("healthy.jsonl"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("no fault"), std::string::npos) << r.out;
  EXPECT_EQ(readFile(temp("healthy.jsonl")).find("\"alarm\": true"), std::string::npos);
}

TEST(DetectCli, ToleratesExtraColumnsReorderingAndNaNRows) {
  // simulate --full-state adds columns; then shuffle the column order and blank a few cells.
  const std::string full = temp("full.csv");
  ASSERT_EQ(run("simulate --motor 1 --theta 0 --fault-step 500 --steps 700 --seed 2 --full-state --output " + full).exit_code, 0);
  std::vector<std::string> rows = lines(readFile(full));
  std::ofstream messy(temp("messy.csv"));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::string row = rows[i];
    const std::size_t comma = row.find(',');  // move t to the end
    row = row.substr(comma + 1) + "," + row.substr(0, comma);
    if (i == 300) row.replace(row.find(','), 0, "");  // unchanged
    if (i == 300 || i == 301) row = "nan" + row.substr(row.find(','));  // x is NaN
    if (i == 302) row = row.substr(0, row.find(',') + 1) + row.substr(row.find(',', row.find(',') + 1));  // y empty
    messy << row << "\r\n";  // Windows line ends
  }
  messy.close();
  const CommandResult r = run("detect --input " + temp("messy.csv") + " --output " + temp("messy.jsonl"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("messy.csv:301: column 'x' is nan; row skipped"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("messy.csv:303: column 'y' is empty; row skipped"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("FAULT in motor 1"), std::string::npos) << r.out;
}

// A time written twice (a variable-step solver's log at an event, a logger repeating a row) is
// skipped with a warning naming its line, the first row kept: the detections are the file's
// without the repeat, byte for byte. A time that goes back stays an error (below).
TEST(DetectCli, ARepeatedTimeIsSkippedTheFirstRowKept) {
  std::istringstream in(readFile(faultyCsv()));
  std::ostringstream twice;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    twice << line << "\n";
    if (n == 400)  // the same time, another x: an event's second value
      twice << line.substr(0, line.find(',')) << ",9" << line.substr(line.find(',', line.find(',') + 1)) << "\n";
  }
  const std::string path = temp("repeated-time.csv");
  std::ofstream(path) << twice.str();
  const CommandResult once = run("detect --input " + faultyCsv() + " --output " + temp("once.jsonl"));
  const CommandResult read = run("detect --input " + path + " --output " + temp("twice.jsonl"));
  ASSERT_EQ(once.exit_code, 0) << once.out;
  ASSERT_EQ(read.exit_code, 0) << read.out;
  EXPECT_NE(read.out.find("repeated-time.csv:401: t repeats the previous row's time; row skipped (the first one is kept)"),
            std::string::npos)
      << read.out;
  EXPECT_NE(read.out.find("FAULT in motor 3"), std::string::npos) << read.out;
  EXPECT_EQ(readFile(temp("twice.jsonl")), readFile(temp("once.jsonl")));
}

TEST(DetectCli, BadTelemetryGetsOneLineNamingFileAndLine) {
  const std::string good_header = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n";
  const std::string row0 = "0,0,0,1,0,0,0,0.07,0.07,0.07,0.07\n", row1 = "0.002,0,0,1,0,0,0,0.07,0.07,0.07,0.07\n";
  struct Case {
    std::string name, text, expect;
  };
  const std::vector<Case> cases = {
      {"empty", "", "empty.csv: empty input"},
      {"header-only", good_header, "header-only.csv: no telemetry rows after the header"},
      {"missing-column", "t,x,y,z,roll,pitch,yaw,u1,u2,u4\n" + row0, "missing-column.csv:1: the header lacks column 'u3'"},
      {"backwards", good_header + row0 + row1 + row0, "backwards.csv:4: time goes backwards"},
      {"text", good_header + row0 + "0.002,0,zero,1,0,0,0,0.07,0.07,0.07,0.07\n", "text.csv:3: column 'y': 'zero' is not a number"},
      {"short-row", good_header + row0 + "0.002,0,0,1\n", "short-row.csv:3: 4 cells, the header has 11"},
      // Angles in degrees: outside the radians' domain of ZYX Euler angles, whatever the flight.
      {"pitch-degrees", good_header + row0 + "0.002,0,0,1,4.5,-2.1,30,0.07,0.07,0.07,0.07\n",
       "pitch-degrees.csv:3: pitch = -2.1 is outside ±π/2: roll, pitch, yaw are ZYX Euler angles in radians (degrees?"},
      {"roll-degrees", good_header + row0 + "0.002,0,0,1,185,1.2,0,0.07,0.07,0.07,0.07\n", "roll-degrees.csv:3: roll = 185 is outside ±π"},
      // Motor commands as PWM pulse widths, not newtons.
      {"pwm", good_header + row0 + "0.002,0,0,1,0,0,0,1500,1520,1480,1500\n", "pwm.csv:3: column 'u1' = 1500 is no thrust in newtons"},
  };
  for (const Case& c : cases) {
    const std::string path = temp(c.name + ".csv");
    std::ofstream(path) << c.text;
    const CommandResult r = run("detect --input " + path + " --output " + temp("bad.jsonl"));
    EXPECT_EQ(r.exit_code, 1) << c.name << ": " << r.out;
    EXPECT_EQ(countLines(r.out), 1) << c.name << ": " << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.name << ": " << r.out;
  }
  // A merged export of asynchronous signals: every row lacks some cells. Refused with what to do
  // (AMergedExportIsReadSignalBySignal reads one).
  auto writeAlternating = [&](const std::string& name, int rows, double dt, const char* even, const char* odd) {
    std::ostringstream text;
    text << good_header;
    for (int k = 0; k < rows; ++k) text << dt * k << (k % 2 ? odd : even);
    std::ofstream(temp(name)) << text.str();
  };
  writeAlternating("merged.csv", 40, 0.002, ",0,0,1,0,0,0,,,,\n", ",,,,,,,0.07,0.07,0.07,0.07\n");
  const CommandResult m = run("detect --input " + temp("merged.csv") + " --output " + temp("bad.jsonl"));
  EXPECT_EQ(m.exit_code, 1) << m.out;
  EXPECT_NE(m.out.find("merged.csv: no telemetry rows after the header: all 40 rows have an empty or non-finite cell; an "
                       "export that merges signals logged at different times (PlotJuggler, a ROS bag)"),
            std::string::npos)
      << m.out;
  // Half merged: complete rows every 2 ms between rows of states alone. Read, with the same hint.
  writeAlternating("half-merged.csv", 300, 0.001, ",0,0,1,0,0,0,0.07,0.07,0.07,0.07\n", ",0,0,1,0,0,0,,,,\n");
  const CommandResult h = run("detect --input " + temp("half-merged.csv") + " --output " + temp("half.jsonl"));
  EXPECT_EQ(h.exit_code, 0) << h.out;
  EXPECT_NE(h.out.find("half-merged.csv: 150 of 300 rows skipped for an empty or non-finite cell; an export that merges"),
            std::string::npos)
      << h.out;
  // A header-only log does not replace an existing output either.
  std::ofstream(temp("kept-header.jsonl")) << "precious\n";
  EXPECT_EQ(run("detect --input " + temp("header-only.csv") + " --output " + temp("kept-header.jsonl")).exit_code, 1);
  EXPECT_EQ(readFile(temp("kept-header.jsonl")), "precious\n");
  // A log at 100 Hz is refused; nothing already written is lost.
  std::ostringstream coarse;
  coarse << good_header;
  for (int k = 0; k < 40; ++k) coarse << 0.01 * k << ",0,0,1,0,0,0,0.07,0.07,0.07,0.07\n";
  std::ofstream(temp("coarse.csv")) << coarse.str();
  std::ofstream(temp("kept.jsonl")) << "precious\n";
  const CommandResult r = run("detect --input " + temp("coarse.csv") + " --output " + temp("kept.jsonl"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("coarse.csv:11: the log is sampled too coarsely"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("milliseconds"), std::string::npos) << r.out;  // 10 ms apart: a rate, not a unit
  EXPECT_NE(r.out.find("a 100 Hz log is read with --max-input-period 0.011, at a measured cost"), std::string::npos) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
  EXPECT_EQ(readFile(temp("kept.jsonl")), "precious\n");
  // The same log with t in milliseconds: the refusal says what the intervals suggest.
  std::ostringstream in_ms;
  in_ms << good_header;
  for (int k = 0; k < 40; ++k) in_ms << 2 * k << ",0,0,1,0,0,0,0.07,0.07,0.07,0.07\n";
  std::ofstream(temp("in-ms.csv")) << in_ms.str();
  const CommandResult ms = run("detect -q --input " + temp("in-ms.csv") + " --output " + temp("kept.jsonl"));
  EXPECT_EQ(ms.exit_code, 1);
  EXPECT_EQ(countLines(ms.out), 1) << ms.out;
  EXPECT_NE(ms.out.find("(its samples are 2 s apart: is t in milliseconds or microseconds? --csv-time-unit ms or us)"), std::string::npos) << ms.out;
  const CommandResult in_unit = run("detect -q --csv-time-unit ms --input " + temp("in-ms.csv") + " --output " + temp("in-ms.jsonl"));
  EXPECT_EQ(in_unit.exit_code, 0) << in_unit.out;
  EXPECT_EQ(readFile(temp("kept.jsonl")), "precious\n");
}

// Every file detect reads whole is bounded: a device (read without end), a folder, or a CSV
// line past the reader's bound is refused in one line naming it, and the output is kept.
TEST(DetectCli, DevicesAndFoldersAreRefusedInOneLineWhereverAFileIsRead) {
  const std::string log = temp("device-log.csv");
  std::ofstream(log) << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,1,0,0,0,0.07,0.07,0.07,0.07\n";
  const std::string folder = temp("device-folder");
  std::filesystem::create_directories(folder);
  const std::string kept = temp("device-kept.jsonl");
  std::ofstream(kept) << "precious\n";
  const std::string device = "/dev/zero: is a device or socket, not ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--vehicle /dev/zero --input " + log, device + "a vehicle"},
      {"--config /dev/zero --input " + log, device + "a configuration file"},
      {"--calibration /dev/zero --input " + log, device + "a calibration file"},
      {"--model /dev/zero --input " + log, device + "a model file"},
      {"--format ulog --input /dev/zero", device + "a flight log"},
      {"--format csv --input /dev/zero", "/dev/zero:1: a line longer than 1048576 bytes: not CSV telemetry"},
      {"--input /dev/zero", "/dev/zero: unknown format: binary, but no ULog, DataFlash or Crazyflie micro-SD magic at byte 0"},
      {"--input " + folder, folder + ": is a folder, not a flight log or telemetry CSV"},
      {"--vehicle " + folder + " --input " + log, folder + ": is a folder, not a vehicle"},
  };
  for (const auto& [arguments, expect] : cases) {
    const CommandResult r = run("detect -q " + arguments + " --output " + kept);
    EXPECT_EQ(r.exit_code, 1) << arguments << ": " << r.out;
    EXPECT_EQ(countLines(r.out), 1) << arguments << ": " << r.out;
    EXPECT_NE(r.out.find(expect), std::string::npos) << arguments << ": " << r.out;
  }
  EXPECT_EQ(readFile(kept), "precious\n");
  std::filesystem::remove_all(folder);
}

// A thread that writes `text` into the pipe `fifo` once, as soon as a reader has opened it, then
// closes it: a second open by the reader would wait for a writer that never comes. Gives up after
// 10 s, so that a reader that never comes fails the test rather than hanging it.
std::thread writeOnceToFirstReader(const std::string& fifo, const std::string& text) {
  return std::thread([fifo, text] {
    for (int attempt = 0; attempt < 1000; ++attempt) {
      // Non-blocking, the open succeeds only once a reader holds the pipe; then blocking, so that
      // text longer than the pipe's buffer is written whole.
      if (const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK); fd >= 0) {
        ASSERT_EQ(::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK), 0);
        EXPECT_EQ(::write(fd, text.data(), text.size()), static_cast<ssize_t>(text.size()));
        ::close(fd);
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
}

// A pipe (`--input <(zcat log.csv.gz)`) gives its bytes once. Its format is not sniffed (that
// would eat the header): named, it is read whole; left to auto, refused. A calibration file, which
// a run may read more than once, is refused unopened (opening a pipe waits for its writer).
TEST(DetectCli, APipeIsReadWithANamedFormatAndRefusedWhereItWouldBeReadTwice) {
  const std::string fifo = temp("input.fifo");
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer = writeOnceToFirstReader(
      fifo, "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,1,0,0,0,0.07,0.07,0.07,0.07\n0.002,0,0,1,0,0,0,0.07,0.07,0.07,0.07\n");
  const CommandResult named = run("detect --format csv --input " + fifo + " --output " + temp("fifo.jsonl"));
  writer.join();
  EXPECT_EQ(named.exit_code, 0) << named.out;  // the header and both rows were read: one window is more
  EXPECT_NE(named.out.find("shorter than one window"), std::string::npos) << named.out;

  const CommandResult sniffed = run("detect -q --input " + fifo);
  EXPECT_EQ(sniffed.exit_code, 1) << sniffed.out;
  EXPECT_NE(sniffed.out.find(fifo + ": a pipe: its format cannot be told from its first bytes without losing them; name it with --format"),
            std::string::npos) << sniffed.out;
  const std::string log = temp("pipe-log.csv");
  std::ofstream(log) << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,1,0,0,0,0.07,0.07,0.07,0.07\n";
  const CommandResult calibration = run("detect -q --calibration " + fifo + " --input " + log);
  EXPECT_EQ(calibration.exit_code, 1) << calibration.out;
  EXPECT_NE(calibration.out.find(fifo + ": is a pipe, not a calibration file"), std::string::npos) << calibration.out;
  std::remove(fifo.c_str());
}

// detect reads --vehicle once and hands the description to everything that needs it (the motor
// numbering, a CSV's column order, a log's thrust scale), so a pipe serves as the file does: the
// pipe is written once, and a second read would wait for ever (here: until `timeout` ends it).
// The pipe is named quad450.toml so that it picks the same shipped model as the file.
TEST(DetectCli, TheVehicleDescriptionIsReadOnceSoAPipeServesAsTheFile) {
  const std::string src = QUADFDI_SOURCE_DIR;
  const std::string vehicle = src + "/configs/vehicles/quad450.toml";  // written in PX4's numbering
  const std::string ours = temp("once-quadfdi-order.csv"), px4 = temp("once-px4-order.csv");
  simulateQuadMotor2Failure(vehicle, ours, px4);
  const std::string folder = temp("once-pipe");
  std::filesystem::create_directories(folder);
  const std::string fifo = folder + "/quad450.toml";
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string format : {"csv", "csv-merged"}) {
    const std::string args = " --csv-numbering vehicle --format " + format + " --input " + px4 + " 2>/dev/null";
    const CommandResult from_file = quadfdi::test::runCommand(exe() + " detect -q --vehicle " + vehicle + args);
    ASSERT_EQ(from_file.exit_code, 0) << format;
    EXPECT_NE(from_file.out.find("\"motor\": 2, \"severity\": \"failed\""), std::string::npos) << format;
    std::thread writer = writeOnceToFirstReader(fifo, readFile(vehicle));
    const CommandResult from_pipe = quadfdi::test::runCommand("timeout 60 " + exe() + " detect -q --vehicle " + fifo + args);
    writer.join();
    ASSERT_EQ(from_pipe.exit_code, 0) << format;  // 124: a second read of the pipe waited
    EXPECT_TRUE(from_pipe.out == from_file.out) << format << ": the pipe's output differs from the file's";
  }
  std::remove(fifo.c_str());
}

TEST(DetectCli, ShortLogsModelsAndOptionsAreCheckedUpFront) {
  const std::string path = temp("short.csv");
  std::ofstream(path) << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,1,0,0,0,0.07,0.07,0.07,0.07\n";
  const CommandResult shortlog = run("detect --input " + path);
  EXPECT_EQ(shortlog.exit_code, 0) << shortlog.out;
  EXPECT_NE(shortlog.out.find("shorter than one window"), std::string::npos) << shortlog.out;

  std::ofstream(temp("bogus.qfdi")) << "not a model";
  const CommandResult bad_model = run("detect --model " + temp("bogus.qfdi") + " --input " + path);
  EXPECT_EQ(bad_model.exit_code, 1);
  EXPECT_EQ(countLines(bad_model.out), 1) << bad_model.out;
  const CommandResult based = run("detect --model " QUADFDI_SOURCE_DIR "/models/lstm-model-based.qfdw --input " + path);
  EXPECT_EQ(based.exit_code, 1);
  EXPECT_NE(based.out.find("needs a model-free"), std::string::npos) << based.out;
  const CommandResult stride = run("detect --stride 0 --input " + path);
  EXPECT_EQ(stride.exit_code, 1);
  EXPECT_NE(stride.out.find("--stride: "), std::string::npos) << stride.out;
  EXPECT_EQ(run("detect --raise-below 0.9 --clear-above 0.5 --input " + path).exit_code, 1);
  EXPECT_EQ(run("detect --input /nonexistent/log.csv").exit_code, 1);
}

// The other calibrate modes' options are refused in one line rather than ignored: the nominal
// flights' noise and goals under a randomisation, a refit's healthy-flight and level settings.
TEST(DetectCli, CalibrateRefusesOptionsItsModeWouldNotRead) {
  const std::string model = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw";
  const std::string randomise = std::string(QUADFDI_SOURCE_DIR) + "/configs/randomisation-default.toml";
  const std::string shipped = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.calibration.json";
  const std::pair<std::string, std::string> cases[] = {
      {"--randomise " + randomise + " --attitude-noise 0.01", "--attitude-noise: applies only without --randomise"},
      {"--randomise " + randomise + " --goal-period 5", "--goal-period: applies only without --randomise"},
      {"--refit-interval " + shipped + " --degraded-below 0.9", "--degraded-below: --refit-interval keeps the file's levels"},
      {"--refit-interval " + shipped + " --flights 10", "--flights: --refit-interval keeps the file's levels"},
      {"--delay-budget 0.2", "--delay-budget: only chooses among several --degraded-below levels"},
      {"--failed-delay-budget 0.04", "--failed-delay-budget: only chooses among several --failed-cap values"},
      {"--faulty-flights 0 --interval belt", "--interval: belt needs --faulty-flights > 0"},
  };
  for (const auto& [args, message] : cases) {
    const std::string cal = temp("refused.json");
    const CommandResult c = run("calibrate -q --model " + model + " " + args + " --output " + cal);
    EXPECT_EQ(c.exit_code, 1) << args << "\n" << c.out;
    EXPECT_EQ(countLines(c.out), 1) << c.out;
    EXPECT_NE(c.out.find(message), std::string::npos) << args << "\n" << c.out;
    EXPECT_FALSE(std::filesystem::exists(cal));
  }
}

}  // namespace
