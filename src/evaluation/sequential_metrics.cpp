#include "evaluation/sequential_metrics.h"

#include <algorithm>
#include <cmath>

#include "detection/calibration.h"

namespace quadfdi {
namespace {

void summarise(SeverityDetection& d, std::vector<double>& delays) {
  d.detected = static_cast<int>(delays.size());
  if (delays.empty()) return;
  std::sort(delays.begin(), delays.end());
  const std::size_t n = delays.size();
  d.delay_median = n % 2 ? delays[n / 2] : 0.5 * (delays[n / 2 - 1] + delays[n / 2]);
  d.delay_p95 = delays[static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(n))) - 1];
}

}  // namespace

SequentialEvaluation evaluateSequential(const std::vector<FlightThetaStream>& flights, const SequentialEvaluationConfig& config) {
  SequentialEvaluation r;
  SequentialRule rule(config.rule);
  std::vector<double> degraded_delays, failed_delays;
  long healthy_samples = 0, covered = 0;
  double abs_error = 0.0;
  const double degraded_below = config.rule.degraded_below, failed_below = config.rule.failed_below;
  for (int flight = 0; flight < static_cast<int>(flights.size()); ++flight) {
    const FlightThetaStream& f = flights[static_cast<std::size_t>(flight)];
    rule.reset();
    const FlightTruth& truth = f.truth;
    const bool faulty = truth.motor > 0 && truth.fault_sample >= 0;
    const bool is_degraded = faulty && truth.theta < degraded_below, is_failed = faulty && truth.theta < failed_below;
    r.degraded.flights += is_degraded;
    r.failed.flights += is_failed;
    r.isolation_flights += faulty;  // every fault is to be isolated, also one at or above the degraded level
    const Severity expected = is_failed ? Severity::kFailed : Severity::kDegraded;
    bool found_degraded = false, found_failed = false;
    const long false_alarms_before = r.false_alarms;
    bool degraded_alarm_open = false;  // a false alarm raised as degraded has not escalated yet
    for (long k = 0; k < static_cast<long>(f.theta.size()); ++k) {
      const SequentialStatus status = rule.update(
          f.theta[static_cast<std::size_t>(k)], 1, f.observable.empty() ? kAllMotorsObservable : f.observable[static_cast<std::size_t>(k)]);
      const SequentialState& s = rule.state();
      const bool after = faulty && k >= truth.fault_sample;
      if (!after) {
        ++healthy_samples;
        const bool raised = status == SequentialStatus::kRaised;
        r.false_alarms += raised;
        r.false_alarms_at_start += raised && k < config.start_samples;
        r.false_alarms_failed += raised && s.severity == Severity::kFailed;
        if (raised) r.false_alarm_list.push_back({flight, k, s.motor, s.severity, s.theta_est});
        // Once per alarm raised as degraded: a failed alarm that returns to degraded and fails again
        // is not a new escalation.
        if (raised) degraded_alarm_open = s.severity == Severity::kDegraded;
        if (status == SequentialStatus::kCleared) degraded_alarm_open = false;
        if (status == SequentialStatus::kEscalated && degraded_alarm_open) {
          ++r.false_escalations;
          degraded_alarm_open = false;
        }
        continue;
      }
      const long since = k - truth.fault_sample;
      const bool right = s.motor == truth.motor && s.severity != Severity::kHealthy;
      if (is_degraded && right && !found_degraded) {
        found_degraded = true;
        degraded_delays.push_back(static_cast<double>(since) * config.dt);
      }
      if (is_failed && right && s.severity == Severity::kFailed && !found_failed) {
        found_failed = true;
        failed_delays.push_back(static_cast<double>(since) * config.dt);
      }
      if (since == config.isolation_early) {
        ++r.recorded_early;
        r.named_early += right;
      }
      if (since == config.isolation_late) {
        ++r.recorded_late;
        r.named_late += right;
        r.severity_named_late += right && s.severity == expected;
      }
      if (right && since >= config.flown_through) {
        ++r.estimate_samples;
        const double e = std::abs(s.theta_est - truth.theta);
        abs_error += e;
        r.theta_max_error = std::max(r.theta_max_error, e);
        covered += s.theta_lo <= truth.theta && truth.theta <= s.theta_hi;
      }
    }
    r.flights_with_false_alarm += r.false_alarms > false_alarms_before;
  }
  summarise(r.degraded, degraded_delays);
  summarise(r.failed, failed_delays);
  if (r.recorded_early > 0) r.isolated_early = static_cast<double>(r.named_early) / r.recorded_early;
  if (r.recorded_late > 0) {
    r.isolated_late = static_cast<double>(r.named_late) / r.recorded_late;
    r.severity_right_late = static_cast<double>(r.severity_named_late) / r.recorded_late;
  }
  if (r.estimate_samples > 0) {
    r.theta_mae = abs_error / static_cast<double>(r.estimate_samples);
    r.coverage = static_cast<double>(covered) / static_cast<double>(r.estimate_samples);
  }
  r.healthy_hours = static_cast<double>(healthy_samples) * config.dt / 3600.0;
  if (r.healthy_hours > 0.0) {
    r.false_alarms_per_hour = static_cast<double>(r.false_alarms) / r.healthy_hours;
    r.false_alarms_upper_bound = poissonUpperBound(r.false_alarms, config.confidence) / r.healthy_hours;
    r.alarmed_flights_per_hour = r.flights_with_false_alarm / r.healthy_hours;
    r.alarmed_flights_upper_bound = poissonUpperBound(r.flights_with_false_alarm, config.confidence) / r.healthy_hours;
  }
  return r;
}

}  // namespace quadfdi
