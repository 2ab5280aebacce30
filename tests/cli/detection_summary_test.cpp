// detect --summary (cli/detection_summary.h): alarm episodes from hand-made output sequences
// (rise, severity escalation, a move to another motor, clearing, a hole, held to the end), the
// JSON they make, and end to end: the summary agrees with the JSON Lines of the same run, a
// healthy flight's says so, and a run that fails replaces neither file.
#include "cli/detection_summary.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/cli_support.h"

namespace quadfdi::cli {
namespace {

using nlohmann::json;
using test::readFile;

DetectorOutput output(double t, int motor, Severity severity = Severity::kDegraded, float theta = 0.5f) {
  DetectorOutput d;
  d.t = t;
  d.alarm = motor > 0;
  d.motor = motor;
  if (motor > 0) {
    d.theta[static_cast<std::size_t>(motor - 1)] = theta;
    d.severity = severity;
    d.theta_est = static_cast<double>(theta);
    d.theta_lo = d.theta_est - 0.1;
    d.theta_hi = d.theta_est + 0.1;
  }
  return d;
}

TEST(AlarmEpisodes, RiseEscalateMoveClearAndHoldToTheEnd) {
  AlarmEpisodes a(0.02);
  a.add(output(1.000, 0));
  a.add(output(1.002, 2, Severity::kDegraded, 0.6f));  // rises degraded
  a.add(output(1.004, 2, Severity::kFailed, 0.1f));    // escalates
  a.add(output(1.006, 2, Severity::kFailed, 0.2f));    // latest estimate, lowest stays 0.1
  a.add(output(1.008, 3, Severity::kDegraded, 0.7f));  // moves: a new episode
  a.add(output(1.010, 0));                              // clears
  a.add(output(1.012, 0));
  a.add(output(2.000, 1, Severity::kDegraded, 0.8f));  // after a hole: rises again, held to the end
  a.add(output(2.002, 1, Severity::kDegraded, 0.75f));
  const std::vector<AlarmEpisode>& e = a.episodes();
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(e[0].motor, 2);
  EXPECT_DOUBLE_EQ(e[0].t_raised, 1.002);
  ASSERT_TRUE(e[0].t_cleared.has_value());
  EXPECT_DOUBLE_EQ(*e[0].t_cleared, 1.008);
  EXPECT_EQ(e[0].severity_raised, Severity::kDegraded);
  EXPECT_EQ(e[0].severity_worst, Severity::kFailed);
  EXPECT_NEAR(e[0].theta_est, 0.2, 1e-6);
  EXPECT_NEAR(e[0].theta_lowest, 0.1, 1e-6);
  EXPECT_NEAR(e[0].theta_est_lowest, 0.1, 1e-6);  // the lowest estimate stated, with its own interval
  EXPECT_NEAR(e[0].theta_lo_lowest, 0.0, 1e-6);
  EXPECT_NEAR(e[0].theta_hi_lowest, 0.2, 1e-6);
  EXPECT_NEAR(e[1].theta_est_lowest, 0.7, 1e-6);  // an episode of one output: its own estimate
  EXPECT_EQ(e[1].motor, 3);
  EXPECT_DOUBLE_EQ(*e[1].t_cleared, 1.010);
  EXPECT_EQ(e[2].motor, 1);
  EXPECT_FALSE(e[2].t_cleared.has_value());
  EXPECT_NEAR(e[2].theta_lowest, 0.75, 1e-6);
  // 1.000–1.012 and 2.000–2.002: the 0.988 s hole is not decided time.
  EXPECT_NEAR(a.decidedSeconds(), 0.014, 1e-12);
}

TEST(AlarmEpisodes, TheJsonNamesTheVerdictAndEveryAlarm) {
  AlarmEpisodes a(0.02);
  DetectorSummary s;
  MotorNumbering px4;
  px4.name = "PX4 quad X";
  px4.autopilot_motor = {1, 4, 2, 3};
  DetectionSummaryInputs in;
  in.input = "flight.ulg";
  in.format = "PX4 ULog";
  in.model = "models/tcn-randomised.qfdw";
  in.rule = "sequential";
  in.detector = &s;
  in.episodes = &a;
  in.numbering = &px4;
  EXPECT_EQ(json::parse(detectionSummaryJson(in))["verdict"], "no decision");  // no output at all
  s.outputs = 2;
  a.add(output(0.5, 0));
  EXPECT_EQ(json::parse(detectionSummaryJson(in))["verdict"], "no fault");
  a.add(output(0.502, 3, Severity::kFailed, 0.05f));
  in.evaluated_phases = {{0.4, 0.6}};
  const json j = json::parse(detectionSummaryJson(in));
  EXPECT_EQ(j["verdict"], "fault");
  EXPECT_EQ(j["motor_numbering"], "PX4 quad X");
  EXPECT_TRUE(j["calibration"].is_null());
  ASSERT_EQ(j["alarms"].size(), 1u);
  const json& alarm = j["alarms"][0];
  EXPECT_EQ(alarm["motor"], 3);
  EXPECT_EQ(alarm["autopilot_motor"], 2);  // PX4's motor 2 is quadfdi's 3 (back-left)
  EXPECT_EQ(alarm["motor_position"], "back-left");
  EXPECT_EQ(alarm["severity"], "failed");
  EXPECT_TRUE(alarm["t_cleared"].is_null());
  EXPECT_NEAR(alarm["theta_est_lowest"].get<double>(), 0.05, 1e-6);
  EXPECT_NEAR(alarm["theta_hi_lowest"].get<double>(), 0.15, 1e-6);
  EXPECT_EQ(j["evaluated_phases"], json::parse("[[0.4, 0.6]]"));
  in.rule = "persistence";  // no severity, estimate or interval; the lowest Θ̂ still
  const json p = json::parse(detectionSummaryJson(in))["alarms"][0];
  EXPECT_TRUE(p["severity"].is_null());
  EXPECT_TRUE(p["theta_est"].is_null());
  EXPECT_TRUE(p["theta_est_lowest"].is_null());
  EXPECT_NEAR(p["theta_lowest"].get<double>(), 0.05, 1e-6);
}

// An alarm that ended: the estimate at its end is back at the level, so detect's last line states
// the lowest one and when it ended, not "degraded, Θ̂ = 1.00".
TEST(AlarmEpisodes, AnEndedFirstAlarmIsReportedByItsLowestEstimate) {
  AlarmEpisodes a(0.02);
  a.add(output(0.412, 0));
  a.add(output(0.414, 1, Severity::kDegraded, 0.66f));
  a.add(output(0.416, 1, Severity::kDegraded, 0.64f));
  a.add(output(0.782, 1, Severity::kDegraded, 0.95f));  // recovered, about to clear
  a.add(output(0.784, 0));
  ASSERT_EQ(a.episodes().size(), 1u);
  EXPECT_EQ(sequentialFirstAlarmLine(a.episodes().front(), 0.9, 1, 2500),
            "detect: FAULT in motor 1 at t = 0.414 s: degraded, Θ̂ as low as 0.64 (90 % interval 0.54 … 0.74), until t = 0.784 s; "
            "1 alarm over 2500 samples\n");
  // Held to the end, the line states the latest estimate (the quick start's form).
  AlarmEpisodes held(0.02);
  held.add(output(1.046, 1, Severity::kDegraded, 0.2f));
  held.add(output(1.048, 1, Severity::kFailed, 0.0f));
  held.add(output(1.050, 1, Severity::kFailed, 0.15f));
  EXPECT_EQ(sequentialFirstAlarmLine(held.episodes().front(), 0.9, 2, 820),
            "detect: FAULT in motor 1 at t = 1.046 s: failed, Θ̂ = 0.15 (90 % interval 0.05 … 0.25); 2 alarms over 820 samples\n");
}

TEST(DetectSummaryCli, AgreesWithTheJsonLinesAndIsWrittenWithThemOrNotAtAll) {
  using quadfdi::test::runQuadfdi;
  const auto temp = [](const std::string& name) { return quadfdi::test::scratchPath("summary", name); };
  const std::string csv = temp("faulty.csv"), out = temp("out.jsonl"), summary = temp("summary.json");
  ASSERT_EQ(runQuadfdi("simulate --motor 3 --theta 0 --fault-step 500 --steps 800 --seed 4 --output " + csv).exit_code, 0);
  const test::CommandResult r = runQuadfdi("detect --vehicle quad450 --input " + csv + " --output " + out + " --summary " + summary);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const json j = json::parse(readFile(summary));
  std::vector<json> lines;
  std::istringstream text(readFile(out));
  for (std::string l; std::getline(text, l);) lines.push_back(json::parse(l));
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(j["verdict"], "fault");
  EXPECT_EQ(j["decisions"].get<std::size_t>(), lines.size());
  EXPECT_NEAR(j["decided_seconds"].get<double>(), lines.back()["t"].get<double>() - lines.front()["t"].get<double>(), 1e-9);
  EXPECT_NE(j["model"].get<std::string>().find("models/tcn-quad450.qfdw"), std::string::npos);
  EXPECT_NE(j["calibration"].get<std::string>().find("models/tcn-quad450.calibration.json"), std::string::npos);
  ASSERT_EQ(j["alarms"].size(), 1u);
  const json& alarm = j["alarms"][0];
  // The episode is the JSON Lines' alarm: the first line with it, its motor and autopilot number,
  // its last line's severity and interval.
  std::size_t first = 0;
  while (first < lines.size() && !lines[first]["alarm"].get<bool>()) ++first;
  ASSERT_LT(first, lines.size());
  EXPECT_EQ(alarm["t_raised"], lines[first]["t"]);
  EXPECT_EQ(alarm["motor"], 3);
  EXPECT_EQ(alarm["autopilot_motor"], lines[first]["autopilot_motor"]);
  EXPECT_EQ(alarm["severity"], lines.back()["severity"]);
  EXPECT_NEAR(alarm["theta_hi"].get<double>(), lines.back()["theta_hi"].get<double>(), 5e-5);
  EXPECT_TRUE(alarm["t_cleared"].is_null());
  EXPECT_NE(r.out.find("FAULT in motor 3 at t = " + std::to_string(alarm["t_raised"].get<double>()).substr(0, 5)), std::string::npos)
      << r.out;
  // A healthy flight: no fault, no alarm; to standard output with the lines in a file.
  const std::string healthy = temp("healthy.csv");
  ASSERT_EQ(runQuadfdi("simulate --steps 1500 --seed 8 --output " + healthy).exit_code, 0);
  const test::CommandResult h = runQuadfdi("detect -q --input " + healthy + " --output " + out + " --summary -", false);
  ASSERT_EQ(h.exit_code, 0);
  const json hj = json::parse(h.out);
  EXPECT_EQ(hj["verdict"], "no fault");
  EXPECT_TRUE(hj["alarms"].empty());
  // A run that fails replaces neither file; both to standard output is refused.
  const std::string before_out = readFile(out), before_summary = readFile(summary);
  std::ofstream(temp("header-only.csv")) << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n";
  const test::CommandResult bad = runQuadfdi("detect --input " + temp("header-only.csv") + " --output " + out + " --summary " + summary);
  EXPECT_EQ(bad.exit_code, 1) << bad.out;
  EXPECT_EQ(readFile(out), before_out);
  EXPECT_EQ(readFile(summary), before_summary);
  const test::CommandResult both = runQuadfdi("detect --input " + csv + " --summary -");
  EXPECT_EQ(both.exit_code, 1);
  EXPECT_EQ(both.out, "quadfdi: error: --summary -: the JSON Lines already go to standard output (--output FILE)\n");
}

}  // namespace
}  // namespace quadfdi::cli
