// Metrics of the sequential rule (issue 14, docs/decisions.md "Evaluating the sequential rule"):
// per flight a dense Θ̂ stream (one MotorTheta per model sample) and the truth; the rule runs over
// each stream and the outcomes are summed. No I/O; the caller simulates or reads the flights.
#pragma once

#include <cstdint>
#include <vector>

#include "detection/sequential.h"

namespace quadfdi {

struct FlightTruth {
  int motor = 0;            // 1..4, 0 for a healthy flight
  double theta = 1.0;       // [-] Θ of that motor from the fault on
  long fault_sample = -1;   // [samples] index in the stream of the first faulty sample; −1 healthy
};

struct FlightThetaStream {
  std::vector<MotorTheta> theta;         // Θ̂ per model sample
  std::vector<std::uint8_t> observable;  // per Θ̂ sample, the CommandGate mask the rule is given; empty: all observable
  FlightTruth truth;
};

struct SequentialEvaluationConfig {
  SequentialConfig rule;
  double dt = 0.002;             // [s] model sample period
  long flown_through = 100;      // [samples] after the fault, the network's window holds only faulty samples (T)
  long isolation_early = 25;     // [samples] first isolation check after the fault (50 ms at 500 Hz)
  long isolation_late = 150;     // [samples] second check (300 ms: issue 14's bound for mild faults)
  double confidence = 0.95;      // [-] one-sided, for the false-alarm rate's Poisson upper bound
  long start_samples = 0;        // [samples] false alarms raised this early in a stream are also counted apart
                                 //     (a simulated flight's start: the recovery from its random initial state)
};

struct SeverityDetection {
  int flights = 0;            // faulty flights whose true Θ is below this severity's level
  int detected = 0;           // … in which this severity (or worse) named the true motor after the fault
  double delay_median = 0.0;  // [s] fault → first such decision, over the detected
  double delay_p95 = 0.0;     // [s] nearest rank
};

// One false alarm, for finding what the flights that raise them have in common.
struct FalseAlarm {
  int flight = 0;                       // index into the evaluated streams
  long sample = 0;                      // [samples] stream index at which it was raised
  int motor = 0;                        // 1–4
  Severity severity = Severity::kHealthy;  // as raised: degraded or straight at failed
  double theta_est = 1.0;               // [-] the rule's estimate of that motor then
};

struct SequentialEvaluation {
  SeverityDetection degraded, failed;
  int isolation_flights = 0;          // faulty flights, whatever their Θ (issue 13 scores Θ ≤ 0.8 at the 0.8 level too)
  // A simulated flight's recording ends where the vehicle leaves the state bounds (model/integrator.h
  // StateBounds: tilt past 1.5 rad, the ground): a complete fault on a small vehicle often ends it
  // within 300 ms, and there is no decision left to score. The fractions are of the flights still
  // recorded at the check.
  int recorded_early = 0;             // faulty flights recorded at fault + isolation_early
  int recorded_late = 0;              // … at fault + isolation_late
  int named_early = 0;                // … of them, naming the true motor (any severity) there
  int named_late = 0;                 // … at fault + isolation_late
  int severity_named_late = 0;        // … with the right severity for the true Θ
  double isolated_early = 0.0;        // [-] named_early / recorded_early (0 when none)
  double isolated_late = 0.0;         // [-] named_late / recorded_late
  double severity_right_late = 0.0;   // [-] severity_named_late / recorded_late
  long estimate_samples = 0;          // samples after flown_through with the alarm on the true motor
  double theta_mae = 0.0;             // [-] mean |theta_est − Θ| over them
  double theta_max_error = 0.0;       // [-] largest
  double coverage = 0.0;              // [-] fraction with theta_lo ≤ Θ ≤ theta_hi
  long false_alarms = 0;              // alarms raised in healthy time (healthy flights, before a fault)
  long false_alarms_at_start = 0;     // … of them, raised in a stream's first start_samples samples
  // What a pilot would have been told: a false `failed` asks for a landing now, a false `degraded`
  // for a check after the flight, so the two are counted apart.
  long false_alarms_failed = 0;       // … of false_alarms, raised straight at `failed`
  long false_escalations = 0;         // false alarms raised as degraded that escalated to failed (once each)
  double healthy_hours = 0.0;         // [h] healthy flight time
  double false_alarms_per_hour = 0.0;       // [1/h]
  double false_alarms_upper_bound = 0.0;    // [1/h] one-sided Poisson (Garwood) bound at `confidence`
  // False alarms cluster by flight (a flight at the envelope's edge can raise several), so the
  // alarm count's Poisson bound is optimistic; flights, not alarms, are the independent units.
  int flights_with_false_alarm = 0;         // flights raising at least one false alarm
  double alarmed_flights_per_hour = 0.0;    // [1/h] of them, per healthy flight hour
  double alarmed_flights_upper_bound = 0.0; // [1/h] one-sided Poisson bound on that count
  std::vector<FalseAlarm> false_alarm_list; // every false alarm, in flight and sample order
};

SequentialEvaluation evaluateSequential(const std::vector<FlightThetaStream>& flights, const SequentialEvaluationConfig& config);

}  // namespace quadfdi
