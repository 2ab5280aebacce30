#include "cli/detection_summary.h"

#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "detection/sequential.h"

namespace quadfdi::cli {

void AlarmEpisodes::add(const DetectorOutput& d) {
  if (last_t_ && d.t - *last_t_ <= max_gap_) decided_seconds_ += d.t - *last_t_;
  last_t_ = d.t;
  if (open_ && (!d.alarm || d.motor != episodes_.back().motor)) {
    episodes_.back().t_cleared = d.t;
    open_ = false;
  }
  if (!d.alarm) return;
  const bool opened = !open_;
  if (opened) {
    AlarmEpisode e;
    e.t_raised = d.t;
    e.motor = d.motor;
    e.severity_raised = d.severity;
    episodes_.push_back(e);
    open_ = true;
  }
  AlarmEpisode& e = episodes_.back();
  if (static_cast<int>(d.severity) > static_cast<int>(e.severity_worst)) e.severity_worst = d.severity;
  e.theta_lowest = std::min(e.theta_lowest, static_cast<double>(d.theta[static_cast<std::size_t>(d.motor - 1)]));
  e.theta_est = d.theta_est;
  e.theta_lo = d.theta_lo;
  e.theta_hi = d.theta_hi;
  if (opened || d.theta_est < e.theta_est_lowest) {
    e.theta_est_lowest = d.theta_est;
    e.theta_lo_lowest = d.theta_lo;
    e.theta_hi_lowest = d.theta_hi;
  }
}

std::string sequentialFirstAlarmLine(const AlarmEpisode& first, double interval_level, long alarms, long samples) {
  char estimate[160];
  if (first.t_cleared)
    std::snprintf(estimate, sizeof estimate, "Θ̂ as low as %.2f (%.0f %% interval %.2f … %.2f), until t = %.3f s",
                  first.theta_est_lowest, 100.0 * interval_level, first.theta_lo_lowest, first.theta_hi_lowest, *first.t_cleared);
  else
    std::snprintf(estimate, sizeof estimate, "Θ̂ = %.2f (%.0f %% interval %.2f … %.2f)", first.theta_est, 100.0 * interval_level,
                  first.theta_lo, first.theta_hi);
  char line[320];
  std::snprintf(line, sizeof line, "detect: FAULT in motor %d at t = %.3f s: %s, %s; %ld alarm%s over %ld samples\n", first.motor,
                first.t_raised, toString(first.severity_worst), estimate, alarms, alarms == 1 ? "" : "s", samples);
  return line;
}

std::string detectionSummaryJson(const DetectionSummaryInputs& in) {
  using nlohmann::json;
  const DetectorSummary& s = *in.detector;
  const bool sequential = in.rule == "sequential";
  json alarms = json::array();
  for (const AlarmEpisode& e : in.episodes->episodes()) {
    json a;
    a["t_raised"] = e.t_raised;
    a["t_cleared"] = e.t_cleared ? json(*e.t_cleared) : json(nullptr);
    a["motor"] = e.motor;
    a["motor_position"] = motorPosition(*in.numbering, e.motor);
    a["autopilot_motor"] = in.numbering->autopilot_motor[static_cast<std::size_t>(e.motor - 1)];
    if (sequential) {
      a["severity_raised"] = toString(e.severity_raised);
      a["severity"] = toString(e.severity_worst);
      a["theta_est"] = e.theta_est;
      a["theta_lo"] = e.theta_lo;
      a["theta_hi"] = e.theta_hi;
      a["theta_est_lowest"] = e.theta_est_lowest;
      a["theta_lo_lowest"] = e.theta_lo_lowest;
      a["theta_hi_lowest"] = e.theta_hi_lowest;
    } else {  // the persistence rule has no severity, estimate or interval
      a["severity_raised"] = nullptr;
      a["severity"] = nullptr;
      a["theta_est"] = nullptr;
      a["theta_lo"] = nullptr;
      a["theta_hi"] = nullptr;
      a["theta_est_lowest"] = nullptr;
      a["theta_lo_lowest"] = nullptr;
      a["theta_hi_lowest"] = nullptr;
    }
    a["theta_lowest"] = e.theta_lowest;
    alarms.push_back(std::move(a));
  }
  json j;
  j["verdict"] = s.outputs == 0 ? "no decision" : in.episodes->episodes().empty() ? "no fault" : "fault";
  j["input"] = in.input;
  j["format"] = in.format;
  j["model"] = in.model;
  j["calibration"] = in.calibration.empty() ? json(nullptr) : json(in.calibration);
  j["vehicle"] = in.vehicle.empty() ? json(nullptr) : json(in.vehicle);
  j["rule"] = in.rule;
  j["motor_numbering"] = in.numbering->isQuadfdis() ? std::string("quadfdi") : in.numbering->name;
  if (in.numbering_check) {
    const NumberingCheckResult& c = *in.numbering_check;
    json check;
    check["verdict"] = toString(c.verdict);
    check["seconds"] = c.seconds;
    check["from"] = c.rates_used ? "body rates" : "attitude";
    json fit = json::array();  // row by row: GCC 12 at -O3 warns (wrongly) inside nlohmann's std::array conversion
    for (const std::array<double, 3>& row : c.fit) fit.push_back({row[0], row[1], row[2]});
    check["fit"] = std::move(fit);
    check["tilt_fit"] = c.tilt_fit;
    const bool another = c.verdict == NumberingVerdict::kOtherNumbering || (c.verdict == NumberingVerdict::kUpsideDown && !c.best.isRead());
    check["fits_best"] = another ? json(c.best.describe()) : json(nullptr);
    check["text"] = c.text();
    j["motor_numbering_check"] = std::move(check);
  }
  if (in.quaternion_check) {
    const QuaternionCheck& c = *in.quaternion_check;
    json check;
    check["verdict"] = toString(c.verdict);
    check["read"] = c.read.name();
    check["fits_best"] = c.verdict == QuaternionVerdict::kOtherReading ? json(c.best.name()) : json(nullptr);
    check["sense_untold"] = c.sense_untold;
    check["seconds"] = c.seconds;
    json readings = json::array(), tilt = json::array(), in_order = json::array();
    for (std::size_t k = 0; k < kQuaternionReadings.size(); ++k) {
      readings.push_back(kQuaternionReadings[k].name());
      tilt.push_back(c.tilt_fit[k]);
      in_order.push_back(static_cast<bool>(c.rates_in_order[k]));
    }
    check["readings"] = std::move(readings);
    check["tilt_fit"] = std::move(tilt);
    check["rates_in_order"] = c.rates_compared ? std::move(in_order) : json(nullptr);
    check["text"] = c.text();
    j["quaternion_check"] = std::move(check);
  }
  j["samples"] = s.input_samples;
  j["decisions"] = s.outputs;
  j["decided_seconds"] = in.episodes->decidedSeconds();
  j["restarts"] = s.restarts;
  json phases = json::array();
  for (const auto& [begin, end] : in.evaluated_phases) phases.push_back({begin, end});
  j["evaluated_phases"] = phases;
  j["alarms"] = std::move(alarms);
  j["warnings"] = in.warnings;
  return j.dump() + "\n";
}

}  // namespace quadfdi::cli
