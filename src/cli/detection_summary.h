// detect --summary FILE: one JSON object per run, the verdict a fleet script or a dashboard reads
// without scanning the per-sample JSON Lines: every alarm episode (when it rose and cleared, the
// motor in quadfdi's and the autopilot's numbering, its worst severity and latest Θ̂ interval),
// what was evaluated and with which model. Edge code: it formats; detect writes the file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/motor_numbering.h"
#include "detection/detector.h"
#include "detection/numbering_check.h"
#include "logs/quaternion_check.h"

namespace quadfdi::cli {

// One alarm, from the output it rose in to the output it cleared in (or the end of the input).
struct AlarmEpisode {
  double t_raised = 0.0;               // [s] first output with the alarm on this motor
  std::optional<double> t_cleared;     // [s] first output after it without it; empty: held to the end
  int motor = 0;                       // 1..4, quadfdi's numbering
  Severity severity_raised = Severity::kHealthy;  // sequential rule; persistence: kHealthy
  Severity severity_worst = Severity::kHealthy;   // the worst it reached while held
  double theta_est = 1.0, theta_lo = 1.0, theta_hi = 1.0;  // [-] sequential rule: the latest while held
  // [-] sequential rule: the lowest estimate stated while held, with its interval. For an alarm that
  // cleared, the latest is the estimate at clearing (back at its level), not what was found.
  double theta_est_lowest = 1.0, theta_lo_lowest = 1.0, theta_hi_lowest = 1.0;
  double theta_lowest = 1.0;           // [-] the network's lowest Θ̂ of the motor while held (either rule)
};

// The alarm episodes of a stream of outputs, and the flight time they decide. An alarm that
// moves to another motor closes its episode and opens one for the new motor.
class AlarmEpisodes {
 public:
  // `max_gap` [s]: outputs further apart than this are a hole in the log, not decided time.
  explicit AlarmEpisodes(double max_gap) : max_gap_(max_gap) {}
  void add(const DetectorOutput& d);
  const std::vector<AlarmEpisode>& episodes() const { return episodes_; }
  double decidedSeconds() const { return decided_seconds_; }  // [s] summed over the log's holes

 private:
  double max_gap_;
  std::vector<AlarmEpisode> episodes_;
  bool open_ = false;  // the last episode is still held
  std::optional<double> last_t_;
  double decided_seconds_ = 0.0;
};

struct DetectionSummaryInputs {
  std::string input, format;     // the file as given; "telemetry CSV", "PX4 ULog", …
  std::string model, calibration, vehicle, rule;  // calibration, vehicle: empty if none
  const DetectorSummary* detector = nullptr;
  const AlarmEpisodes* episodes = nullptr;
  const MotorNumbering* numbering = nullptr;
  const NumberingCheckResult* numbering_check = nullptr;  // the motor columns against the flight (optional)
  const QuaternionCheck* quaternion_check = nullptr;      // a CSV file's quaternion reading against the flight (optional)
  std::vector<std::pair<double, double>> evaluated_phases;  // [s] a flight log's; empty for a CSV
  std::vector<std::string> warnings;
};

// The JSON object, one line: {"verdict": "fault" | "no fault" | "no decision", …} (README, detect).
std::string detectionSummaryJson(const DetectionSummaryInputs& in);

// detect's verdict line for a run whose first alarm is `first` (sequential rule): its motor, time
// and worst severity; if it was held to the end, its latest estimate with the interval
// (interval_level two-sided); if it ended, the lowest estimate it stated with that estimate's
// interval and when it ended (the latest is then back at its level). `alarms` raised over
// `samples`. Ends with a newline.
std::string sequentialFirstAlarmLine(const AlarmEpisode& first, double interval_level, long alarms, long samples);

}  // namespace quadfdi::cli
