// Flight logs through the command line: `detect --input LOG` (format from the content, --format
// to override), `import LOG -o telemetry.csv` and its report, `detect --plot`, and one-line errors
// for real logs that are too coarse or incomplete, wrong magic, unknown and truncated input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_support.h"
#include "logs/mission_writers.h"

namespace {

using quadfdi::test::CommandResult;
CommandResult run(const std::string& args, bool merge_stderr = true) { return quadfdi::test::runQuadfdi(args, merge_stderr); }
std::string temp(const std::string& name) { return quadfdi::test::scratchPath("logcli", name); }
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
int countLines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }
const std::string kReal = QUADFDI_SOURCE_DIR "/../shared/logs/";
bool exists(const std::string& path) { return std::ifstream(path).good(); }

void writeBytes(const std::string& path, const std::vector<std::uint8_t>& b) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}
using quadfdi::test::readFile;

// Motor 3 fails completely at 4 s; written once as a PX4 ULog.
const std::string& faultyUlog() {
  static const std::string path = [] {
    const std::string p = temp("faulty.ulg");
    writeBytes(p, quadfdi::test::writePx4Mission(quadfdi::test::simulateMission(3, 0.0, 4.0)));
    return p;
  }();
  return path;
}

TEST(LogCli, DetectReadsAPx4LogByItsMagicAndNamesTheFaultAndThePhase) {
  const std::string out = temp("faulty.jsonl");
  const CommandResult r = run("detect --input " + faultyUlog() + " --max-thrust 0.15 --output " + out);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "FAULT in motor 3 at t = 4.0")) << r.out;
  // quadfdi's back-left motor 3 is PX4's motor 2: the pilot is told which one to replace.
  EXPECT_TRUE(contains(r.out, "detect: motor 3 is the back-left motor: PX4 motor 2\n")) << r.out;
  EXPECT_TRUE(contains(readFile(out), "\"motor\": 3, \"severity\": \"failed\"")) << "no failed line";
  EXPECT_TRUE(contains(readFile(out), "\"motor_position\": \"back-left\", \"autopilot_motor\": 2}"));
  EXPECT_TRUE(contains(r.out, "PX4 ULog, evaluated 1 of 1 airborne phase")) << r.out;
  EXPECT_TRUE(contains(r.out, "thrust fractions (actuator_motors) × the motor's maximum thrust 0.15 N")) << r.out;
  EXPECT_GT(countLines(readFile(out)), 500);
}

TEST(LogCli, AHealthyCrazyflieFlightFromTheGroundRaisesNoAlarmAndNamesItsPhase) {
  const std::string log = temp("healthy_cf00");
  writeBytes(log, quadfdi::test::writeCrazyflieMission(quadfdi::test::simulateMission(0, 1.0, -1.0)));
  const CommandResult r = run("detect --input " + log + " --output " + temp("healthy.jsonl"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "detect: no fault:")) << r.out;
  EXPECT_TRUE(contains(r.out, "Crazyflie micro-SD, evaluated 1 of 1 airborne phase (no armed/landed events")) << r.out;
  EXPECT_TRUE(contains(r.out, "the log's commands are thrust per motor in newtons")) << r.out;
}

TEST(LogCli, CsvNumberingOnALogIsRefused) {
  const std::string vehicle = std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/quad450.toml";
  const CommandResult r = run("detect --input " + faultyUlog() + " --vehicle " + vehicle + " --csv-numbering vehicle");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, "--csv-numbering: reads a telemetry CSV; a ulog log carries its autopilot's own motor numbering")) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
}

TEST(LogCli, CsvFrameOnALogIsRefused) {
  const CommandResult r = run("detect --input " + faultyUlog() + " --csv-frame ned");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, "--csv-frame: reads a telemetry CSV; a ulog log's frames are its autopilot's")) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
  const CommandResult speeds = run("detect --input " + faultyUlog() + " --csv-commands rotor-speed");
  EXPECT_EQ(speeds.exit_code, 1);
  EXPECT_TRUE(contains(speeds.out, "--csv-commands: reads a telemetry CSV; a ulog log's commands are converted by its reader")) << speeds.out;
  EXPECT_EQ(countLines(speeds.out), 1) << speeds.out;
  const CommandResult quaternion = run("detect --input " + faultyUlog() + " --csv-quaternion xyzw");
  EXPECT_EQ(quaternion.exit_code, 1);
  EXPECT_TRUE(contains(quaternion.out, "--csv-quaternion: reads a telemetry CSV; a ulog log names its own fields and units")) << quaternion.out;
  EXPECT_EQ(countLines(quaternion.out), 1) << quaternion.out;
}

TEST(LogCli, FormatCsvOnALogSaysWhatTheFileIs) {
  const CommandResult r = run("detect --format csv --input " + faultyUlog());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, faultyUlog() + ": byte 0: --format csv, but the file starts with the ulog magic")) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
}

TEST(LogCli, ImportWritesCsvThatDetectsTheSameAndPrintsTheReport) {
  const std::string csv = temp("imported.csv");
  const CommandResult r = run("import " + faultyUlog() + " --max-thrust 0.15 -o " + csv);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  for (const char* part : {"format: PX4 ULog", "attitude: vehicle_attitude", "250 Hz", "position: vehicle_local_position",
                           "50.0 Hz", "commands: actuator_motors", "zero-order hold", "thrust: thrust fractions",
                           "phases (the autopilot's armed/landed events)", "take-off at", "rows written to",
                           "motors (quadfdi's number: position, the autopilot's number): 1: front-right, PX4 motor 1; "
                           "2: back-right, PX4 motor 4; 3: back-left, PX4 motor 2; 4: front-left, PX4 motor 3\n"})
    EXPECT_TRUE(contains(r.out, part)) << part << "\n" << r.out;
  // The log's motor numbering rides along in a comment, so detect names the motor as on the log.
  EXPECT_EQ(readFile(csv).rfind("# motor_numbering: PX4 = 1 4 2 3\nt,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n", 0), 0u);
  const CommandResult d = run("detect --input " + csv + " --output " + temp("imported.jsonl"));
  ASSERT_EQ(d.exit_code, 0) << d.out;
  EXPECT_TRUE(contains(d.out, "detect: motor 3 is the back-left motor: PX4 motor 2\n")) << d.out;
  const CommandResult l = run("detect --input " + faultyUlog() + " --max-thrust 0.15 --output " + temp("direct.jsonl"));
  const auto fault = [](const std::string& s) { return s.substr(s.find("FAULT in motor"), 32); };
  ASSERT_TRUE(contains(d.out, "FAULT in motor")) << d.out;
  EXPECT_EQ(fault(d.out), fault(l.out));
}

// A log piped in on standard input (`zcat log.ulg.gz | quadfdi detect --format ulog`) or
// redirected from a file reads as the file does: the same decisions, sample for sample, named
// <stdin>. Without --format, standard input is CSV; a log there says so in one line.
TEST(LogCli, ALogOnStandardInputReadsAsTheFile) {
  const std::string direct = temp("stdin-direct.jsonl"), piped = temp("stdin-piped.jsonl"), redirected = temp("stdin-redirected.jsonl");
  ASSERT_EQ(run("detect -q --input " + faultyUlog() + " --max-thrust 0.15 --output " + direct).exit_code, 0);
  const CommandResult p = quadfdi::test::runCommand("cat " + faultyUlog() + " | " QUADFDI_EXE " detect --format ulog --input - --max-thrust 0.15 --output " + piped + " 2>&1");
  ASSERT_EQ(p.exit_code, 0) << p.out;
  EXPECT_TRUE(contains(p.out, "FAULT in motor 3 at t = 4.0")) << p.out;
  const CommandResult r = run("detect -q --format ulog --input - --max-thrust 0.15 --output " + redirected + " < " + faultyUlog());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(readFile(piped), readFile(direct));
  EXPECT_EQ(readFile(redirected), readFile(direct));
  // import the same way: the same CSV as from the file.
  const std::string from_file = temp("stdin-import-file.csv"), from_pipe = temp("stdin-import-pipe.csv");
  ASSERT_EQ(run("import -q " + faultyUlog() + " --max-thrust 0.15 -o " + from_file).exit_code, 0);
  const CommandResult i = quadfdi::test::runCommand("cat " + faultyUlog() + " | " QUADFDI_EXE " import -q --format ulog - --max-thrust 0.15 -o " + from_pipe + " 2>&1");
  ASSERT_EQ(i.exit_code, 0) << i.out;
  EXPECT_EQ(readFile(from_pipe), readFile(from_file));
  // Damage names <stdin> and the byte; without --format, the log is read as CSV and refused so.
  const CommandResult cut = quadfdi::test::runCommand("head -c 300 " + faultyUlog() + " | " QUADFDI_EXE " detect -q --format ulog --input - 2>&1");
  EXPECT_EQ(cut.exit_code, 1) << cut.out;
  EXPECT_EQ(countLines(cut.out), 1) << cut.out;
  EXPECT_TRUE(contains(cut.out, "<stdin>: byte ")) << cut.out;
  const CommandResult unnamed = run("detect -q --input - < " + faultyUlog());
  EXPECT_EQ(unnamed.exit_code, 1) << unnamed.out;
  EXPECT_EQ(countLines(unnamed.out), 1) << unnamed.out;
  EXPECT_TRUE(contains(unnamed.out, "<stdin>:1: binary, not CSV telemetry (the ulog magic: a flight log; read it with --format ulog)"))
      << unnamed.out;
}

// ArduPilot's log as text (Mission Planner's .log beside the .BIN): read by its first line, or
// with --format dataflash on standard input, it gives the binary log's decisions sample for
// sample; a line it cannot read is named by its line and skipped.
TEST(LogCli, AnArdupilotLogAsTextDetectsAsItsBinaryLog) {
  const quadfdi::test::DataflashWriter w = quadfdi::test::ardupilotMissionLog(quadfdi::test::simulateMission(2, 0.0, 4.0));
  const std::string bin = temp("faulty.BIN"), text = temp("faulty.log"), damaged = temp("damaged.log");
  writeBytes(bin, w.bytes);
  std::string crlf;  // as Mission Planner writes it on Windows
  for (char c : w.text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  { std::ofstream(text, std::ios::binary) << crlf; }
  const std::string from_bin = temp("text-bin.jsonl"), from_text = temp("text-text.jsonl"), from_stdin = temp("text-stdin.jsonl");
  ASSERT_EQ(run("detect -q --input " + bin + " --max-thrust 0.15 --output " + from_bin).exit_code, 0);
  const CommandResult r = run("detect --input " + text + " --max-thrust 0.15 --output " + from_text);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "FAULT in motor 2 at t = 4.0")) << r.out;
  EXPECT_TRUE(contains(r.out, "ArduPilot DataFlash")) << r.out;
  EXPECT_EQ(readFile(from_text), readFile(from_bin));
  ASSERT_EQ(run("detect -q --format dataflash --input - --max-thrust 0.15 --output " + from_stdin + " < " + text).exit_code, 0);
  EXPECT_EQ(readFile(from_stdin), readFile(from_bin));
  // import says which form it read, and writes the .BIN's samples.
  const std::string csv_bin = temp("text-bin.csv"), csv_text = temp("text-text.csv");
  ASSERT_EQ(run("import -q " + bin + " --max-thrust 0.15 -o " + csv_bin).exit_code, 0);
  const CommandResult imported = run("import " + text + " --max-thrust 0.15 -o " + csv_text);
  ASSERT_EQ(imported.exit_code, 0) << imported.out;
  EXPECT_TRUE(contains(imported.out, "log: the DataFlash log as text (Mission Planner's .log)")) << imported.out;
  EXPECT_EQ(readFile(csv_text), readFile(csv_bin));
  // Standard input without --format is CSV: the text log is named and the flag given.
  const CommandResult unnamed = run("detect -q --input - < " + text);
  EXPECT_EQ(unnamed.exit_code, 1);
  EXPECT_EQ(unnamed.out, "quadfdi: error: <stdin>:1: an ArduPilot DataFlash log as text (Mission Planner's .log), not CSV telemetry: read it with "
                         "--format dataflash\n");
  // A damaged line: named with its line, skipped; the rest still reads.
  std::string bad = w.text;
  const std::size_t rcou = bad.find("\nRCOU, ") + 1;
  bad.insert(bad.find(", ", rcou + 6) + 2, "x");
  const std::size_t line = static_cast<std::size_t>(std::count(bad.begin(), bad.begin() + static_cast<long>(rcou), '\n')) + 1;
  { std::ofstream(damaged, std::ios::binary) << bad; }
  const CommandResult d = run("detect --input " + damaged + " --max-thrust 0.15 --output " + temp("text-damaged.jsonl"));
  ASSERT_EQ(d.exit_code, 0) << d.out;
  EXPECT_TRUE(contains(d.out, damaged + ": line " + std::to_string(line) + ": RCOU.C1: 'x")) << d.out;
  EXPECT_TRUE(contains(d.out, "FAULT in motor 2 at t = 4.0")) << d.out;
  // What is neither form, read as DataFlash: one line naming both.
  const std::string csv = temp("not-dataflash.log");
  { std::ofstream(csv) << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n"; }
  const CommandResult n = run("detect --format dataflash --input " + csv);
  EXPECT_EQ(n.exit_code, 1);
  EXPECT_EQ(n.out, "quadfdi: error: " + csv + ": byte 0: not a DataFlash log: no 0xA3 0x95 header, nor a first line \"FMT, …\" of the log as text\n");
}

TEST(LogCli, VehicleDescriptionScalesTheThrustAndExplicitFlagsWin) {
  const std::string vehicle = std::string(QUADFDI_SOURCE_DIR) + "/configs/vehicles/crazyflie2.toml";
  CommandResult r = run("import " + faultyUlog() + " --vehicle " + vehicle + " -o " + temp("vehicle.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "the motor's maximum thrust 0.159166 N")) << r.out;
  r = run("import " + faultyUlog() + " --vehicle " + vehicle + " --max-thrust 0.15 -o " + temp("vehicle.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "the motor's maximum thrust 0.15 N")) << r.out;
  // A broken description is one line naming file and line.
  const std::string bad = temp("bad-vehicle.toml");
  writeBytes(bad, std::vector<std::uint8_t>{'[', 'm', 'o', 't', 'o', 'r', '.', '1', ']', '\n', 'x', ' ', '=', ' ', '1', '\n'});
  r = run("import " + faultyUlog() + " --vehicle " + bad + " -o " + temp("vehicle.csv"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, bad + ":2: missing 'name'")) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
}

TEST(LogCli, PlotDrawsAPng) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "no gnuplot";
  const std::string png = temp("detections.png");
  std::remove(png.c_str());
  const CommandResult r = run("detect --input " + faultyUlog() + " --max-thrust 0.15 --output " + temp("p.jsonl") + " --plot " + png);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const std::string img = readFile(png);
  ASSERT_GT(img.size(), 1000u);
  EXPECT_EQ(img.substr(1, 3), "PNG");
}

TEST(LogCli, PlotWithoutGnuplotFailsClearlyBeforeAnyWork) {
  const std::string out = temp("nognuplot.jsonl");
  std::remove(out.c_str());
  // With PATH pointing nowhere, gnuplot cannot be found.
  const std::string cmd = "PATH=/nonexistent " + std::string(QUADFDI_EXE) + " detect --input " + faultyUlog() +
                          " --max-thrust 0.15 --output " + out + " --plot " + temp("x.png") + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string text;
  char buf[512];
  while (fgets(buf, sizeof buf, p)) text += buf;
  const int status = pclose(p);
  EXPECT_NE(status, 0);
  EXPECT_TRUE(contains(text, "--plot needs gnuplot")) << text;
  EXPECT_EQ(countLines(text), 1) << text;
  EXPECT_FALSE(exists(out));  // checked before any work: no detections written
}

// Thrust fractions need a scale only for a model that reads newtons: the default (scale-free)
// model's output is the same with or without --max-thrust, and another model is refused naming
// what to give.
TEST(LogCli, ThrustFractionsNeedAScaleOnlyForAModelThatReadsNewtons) {
  const CommandResult unscaled = run("detect --input " + faultyUlog() + " --output " + temp("noscale.jsonl"));
  ASSERT_EQ(unscaled.exit_code, 0) << unscaled.out;
  EXPECT_TRUE(contains(unscaled.out, "detect: thrust: thrust fractions (actuator_motors) used as they are (× 1 N)")) << unscaled.out;
  EXPECT_TRUE(contains(unscaled.out, "FAULT in motor 3 at t = 4.0")) << unscaled.out;
  const CommandResult scaled = run("detect --input " + faultyUlog() + " --max-thrust 0.15 --output " + temp("scaled.jsonl"));
  ASSERT_EQ(scaled.exit_code, 0) << scaled.out;
  EXPECT_EQ(readFile(temp("noscale.jsonl")), readFile(temp("scaled.jsonl")));
  const std::string newtons = std::string(QUADFDI_SOURCE_DIR) + "/models/tcn-model-free.qfdw";
  const CommandResult r = run("detect --model " + newtons + " --input " + faultyUlog() + " --output " + temp("refused.jsonl"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, faultyUlog() + ": topic actuator_motors: ")) << r.out;
  EXPECT_TRUE(contains(r.out, "--max-thrust")) << r.out;
  EXPECT_TRUE(contains(r.out, "a scale-free model (every shipped randomised one) needs neither")) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
  // import writes newtons: it still needs the scale.
  const CommandResult i = run("import " + faultyUlog() + " -o " + temp("noscale.csv"));
  EXPECT_EQ(i.exit_code, 1);
  EXPECT_TRUE(contains(i.out, "--max-thrust")) << i.out;
}

TEST(LogCli, RealPx4LogsAreRefusedForTheirHeldPositionAndActuatorOutputsRate) {
  for (const char* name : {"px4/sample_log_small.ulg", "px4/sample_logging_tagged_and_default_params.ulg"}) {
    if (!exists(kReal + name)) GTEST_SKIP() << "no real logs";
    const std::string out = temp("real.jsonl");
    { std::ofstream(out) << "keep me\n"; }
    const CommandResult r = run("detect --input " + kReal + name + " --max-thrust 5 --output " + out);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(countLines(r.out), 1) << r.out;
    // Flown without horizontal aiding (EKF2 held x, y): refused for that, naming the coarse outputs too.
    EXPECT_TRUE(contains(r.out, "topic vehicle_local_position: xy_valid is false in all ")) << r.out;
    EXPECT_TRUE(contains(r.out, "also, topic actuator_outputs is logged at ")) << r.out;
    EXPECT_EQ(r.out.find("also, topic actuator_outputs"), r.out.rfind("also, topic actuator_outputs"))
        << "named once, whatever its instances: " << r.out;
    EXPECT_TRUE(contains(r.out, "SDLOG_PROFILE")) << r.out;
    EXPECT_EQ(readFile(out), "keep me\n");  // nothing already written is lost
  }
}

TEST(LogCli, RealCrazyflieMotorLogNamesTheMissingPitchAndItsRate) {
  const std::string path = kReal + "crazyflie-usd/motor_normal_flight_E8_log00";
  if (!exists(path)) GTEST_SKIP() << "no real logs";
  const CommandResult r = run("import " + path + " -o " + temp("cf.csv"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(countLines(r.out), 1) << r.out;
  EXPECT_TRUE(contains(r.out, path + ": topic stateEstimate.pitch: the log has no stateEstimate.pitch")) << r.out;
  EXPECT_TRUE(contains(r.out, "event 'fixedFrequency' is logged at 10")) << r.out;
  EXPECT_TRUE(contains(r.out, "deck's logging frequency")) << r.out;
}

TEST(LogCli, BadInputGetsOneLineNamingFileAndByte) {
  // Unknown binary.
  const std::string junk = temp("junk.bin");
  writeBytes(junk, {0x00, 0x01, 0x02, 0xFF, 0x10, 0x00, 0x41});
  CommandResult r = run("detect --input " + junk);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, junk + ": unknown format")) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
  // Wrong magic for the format asked for.
  r = run("detect --format ulog --input " + junk);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, junk + ": byte 0")) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
  // A CSV asked to be read as DataFlash.
  const std::string csv = temp("tiny.csv");
  { std::ofstream(csv) << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,1,0,0,0,0.07,0.07,0.07,0.07\n"; }
  r = run("import --format dataflash " + csv);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, csv + ": byte 0")) << r.out;
  // Truncated: a ULog cut inside its definitions.
  const std::vector<std::uint8_t> whole = quadfdi::test::writePx4Mission(quadfdi::test::simulateMission(0, 1.0, -1.0));
  const std::string cut = temp("cut.ulg");
  writeBytes(cut, std::vector<std::uint8_t>(whole.begin(), whole.begin() + 12));
  r = run("detect --input " + cut + " --max-thrust 0.15");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, cut + ": byte ")) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
  // A log with no flight.
  quadfdi::test::Mission ground = quadfdi::test::simulateMission(0, 1.0, -1.0);
  ground.samples.resize(400);
  ground.takeoff_at = 100.0;
  ground.landed_at = -1.0;
  const std::string idle = temp("ground.BIN");
  writeBytes(idle, quadfdi::test::writeArdupilotMission(ground));
  r = run("detect --input " + idle + " --max-thrust 0.15");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, idle + ": no flight found")) << r.out;
  EXPECT_EQ(countLines(r.out), 1) << r.out;
}

// A flight-log option the input's reader does not read is refused in one line naming the flag,
// before any output is written, rather than ignored (a CSV with --max-thrust would otherwise run
// unscaled, without a word).
TEST(LogCli, OptionsTheFormatDoesNotReadAreRefused) {
  const std::string csv = temp("newtons.csv");
  { std::ofstream(csv) << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n0,0,0,1,0,0,0,0.07,0.07,0.07,0.07\n"; }
  const std::string ulog = faultyUlog();
  const std::string out = temp("refused.jsonl");
  { std::ofstream(out) << "keep me\n"; }
  const struct {
    std::string command, flag, why;
  } cases[] = {
      {"detect --input " + csv + " --max-thrust 0.15 --output " + out, "--max-thrust: ", "a telemetry CSV's u1..u4 are newtons"},
      {"detect --input " + csv + " --ekf-core 1 --output " + out, "--ekf-core: ", "a telemetry CSV's u1..u4 are newtons"},
      {"detect --input " + ulog + " --max-thrust 0.15 --ekf-core 1 --output " + out, "--ekf-core: ", "is ArduPilot's (DataFlash); this log is ulog"},
      {"import " + ulog + " --max-thrust 0.15 --cf-thrust-map duty -o " + out, "--cf-thrust-map: ", "is the Crazyflie's; this log is ulog"},
      {"import " + ulog + " --max-thrust 0.15 --mass 0.03 -o " + out, "--mass: ", "unused with --max-thrust unless --hover-calibrate"},
      {"detect --input " + ulog + " --max-thrust 0.15 --csv-time-unit ns --output " + out, "--csv-time-unit: ", "a ulog log names its own fields"},
  };
  for (const auto& c : cases) {
    const CommandResult r = run(c.command);
    EXPECT_EQ(r.exit_code, 1) << c.command;
    EXPECT_EQ(countLines(r.out), 1) << r.out;
    EXPECT_TRUE(contains(r.out, c.flag)) << r.out;
    EXPECT_TRUE(contains(r.out, c.why)) << r.out;
    EXPECT_EQ(readFile(out), "keep me\n");
  }
  // The readers' own options stay accepted: the ULog with --max-thrust and --mass for the hover.
  EXPECT_EQ(run("import " + ulog + " --max-thrust 0.15 --mass 0.03 --hover-calibrate -q -o " + temp("hover.csv")).exit_code, 0);
}

}  // namespace
