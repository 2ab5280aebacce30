// The conventions layer (issue "Real logs in"): FlightSignals of any autopilot (each signal at
// its own native rate, already in quadfdi's frames and motor numbering) → TelemetrySample on the
// model's uniform clock, plus an import report that says what was done. No I/O. Design and
// numbers: docs/logs/README.md.
//
//  * Rates. Each signal's rate is its median sample interval over the whole log. Attitude and
//    motor commands need ≥ 125 Hz, position ≥ 20 Hz (defaults, see ImportOptions); a coarser
//    signal is refused with one sentence naming the topic, the measured rate and what to change
//    on that autopilot.
//  * Onto the clock (period dt, the model's): attitude interpolated linearly per Euler angle, each
//    the short way round (for the small steps of a ≥ 125 Hz log this is slerp to first order);
//    position and body rates (where the log has them) interpolated linearly; motor commands held
//    (zero-order hold, as the flight controller holds them). A hole in any signal longer than its
//    own hole limit splits the stretch: nothing is interpolated across it. Body rates are
//    optional: read only by models on body rates, left out (with a warning) when too coarse.
//  * Thrust. kThrustNewton as is. kThrustFraction × the motor's maximum thrust [N]: given
//    (max_thrust), or calibrated from the log's own steady hover (mass given: the mean command
//    over a steady airborne stretch ↔ m·g/4 per motor). Neither → × 1 for a scale-free model,
//    else a refusal naming what to give.
//  * Phases. Airborne = armed and not landed from the autopilot's own events where the log has
//    them; otherwise a rule on height and thrust (ImportOptions). A margin is skipped after each
//    take-off and before each controlled landing. Only airborne stretches become samples;
//    between two of them the clock jumps (a gap > the detector's max_gap), so the detector
//    restarts and never evaluates across a skipped stretch.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/sample_source.h"
#include "logs/decoded_log.h"
#include "logs/flight_signals.h"

namespace quadfdi {

struct ImportOptions {
  double dt = 0.002;  // [s] the model's sample period (from the model file)

  // --- Rates (1 / median interval). Attitude and commands: the detector needs a fault's first
  // model samples to be measured, not interpolated (README "quadfdi detect": 125 Hz = 8 ms, four
  // model samples). Position enters the model-free features only through slow translational
  // dynamics: after a complete motor failure the Crazyflie's position departs from a straight
  // line by ½·a·t² with a ≲ g, and linear interpolation between samples Δ apart errs by at most
  // a·Δ²/8 — 1.2 mm at 20 Hz (Δ = 50 ms), below the 2 mm position noise the shipped network was
  // shown to tolerate (README robustness table). Coarser position would exceed that.
  double min_rate_attitude = 125.0;  // [Hz]
  double min_rate_command = 125.0;   // [Hz]
  double min_rate_position = 20.0;   // [Hz]

  // --- Thrust scaling (kThrustFraction only). The vehicle: max thrust per motor, or mass.
  double max_thrust = 0.0;       // [N] per motor at command 1; 0 = not given
  double mass = 0.0;             // [kg]; 0 = not given
  bool hover_calibrate = false;  // calibrate from the log's hover even when max_thrust is given (needs mass)
  // The model reads commands only as shares of their mean and its relative change (scale-free
  // features, data/features.h): a constant thrust scale cannot change its output, so fractions
  // with neither max_thrust nor mass are used as they are (× 1 N) instead of refused.
  bool scale_free_model = false;
  // Body rates: read where the log has them (import writes them; a model on body rates needs
  // them); false leaves them out, so a rates topic's holes or late start cost a model that does
  // not read them no sample.
  bool read_rates = true;
  double gravity = 9.81;         // [m/s²]
  double hover_min_duration = 1.0;    // [s] steady stretch needed for the calibration
  double hover_max_tilt = 0.1;        // [rad] |roll|, |pitch| below this while steady
  double hover_max_climb_rate = 0.2;  // [m/s] |vertical speed| below this while steady (over 0.5 s)

  // --- Flight phases.
  double settle_after_takeoff = 1.0;  // [s] skipped after each take-off (ground effect, spool-up, climb-out)
  double settle_before_landing = 0.5; // [s] skipped before each controlled landing (ground effect, touchdown)
  double landing_max_tilt = 0.5;      // [rad] a stretch that ends tilted beyond this within the margin is a
                                      //     crash or a flip, not a landing: no margin (the fault is there)
  double min_phase = 0.5;             // [s] shorter evaluated stretches (after margins) are dropped
  // Rule when the log has no armed/landed events: airborne while the height above the ground level
  // (1st percentile of z over the log) exceeds airborne_height and the total command exceeds
  // airborne_thrust_fraction × its median while that high, for at least airborne_min_duration.
  double airborne_height = 0.1;          // [m]
  double airborne_thrust_fraction = 0.5; // [-]
  double airborne_min_duration = 0.5;    // [s]
  bool use_events = true;                // false: the rule even when the log has events

  // --- Holes. A hole longer than max(max_hole, hole_intervals × the signal's median interval)
  // splits the stretch there.
  double max_hole = 0.02;       // [s] the detector's default max_gap
  double hole_intervals = 3.0;  // [-]
  double restart_gap = 0.02;    // [s] stretches closer than this are merged (the detector could not tell them apart)
};

// One signal in the report.
struct SignalReport {
  std::string name;    // "attitude", "position", "commands"
  SignalSource source;
  std::size_t samples = 0;
  double rate_hz = 0.0;          // 1 / median interval
  double median_interval = 0.0;  // [s]
  double t_first = 0.0, t_last = 0.0;  // [s]
  std::string method;  // how it is put onto the clock
};

struct PhaseReport {
  double t_begin = 0.0, t_end = 0.0;           // [s] airborne as found
  double eval_begin = 0.0, eval_end = 0.0;     // [s] evaluated part (after margins); empty if !evaluated
  bool evaluated = false;
  std::string note;  // why not, or what was cut
};

struct ImportReport {
  std::string format;  // "PX4 ULog", …
  std::vector<SignalReport> signals;
  std::vector<std::string> conventions;  // the extractor's lines, then ours
  MotorNumbering numbering;              // the autopilot's motor numbers (FlightSignals::numbering)
  std::string thrust;                    // how commands became newtons
  double thrust_factor = 1.0;            // [N] per unit command (1 for kThrustNewton)
  bool hover_calibrated = false;
  std::string phase_rule;                // events or the rule, with its numbers
  std::vector<PhaseReport> phases;
  std::size_t samples = 0;               // emitted on the clock
  double dt = 0.0;                       // [s]
  std::vector<std::string> warnings;
  // Multi-line text for people (ends with a newline).
  std::string text() const;
  // One line naming the evaluated phases, e.g. "evaluated 1 of 1 airborne phase: 12.30–45.10 s (32.8 s)".
  std::string phasesLine() const;
};

// Why a log cannot be turned into telemetry. The CLI prints "FILE: topic T: message" (or
// "FILE: message" when topic is empty).
struct ImportRefusal {
  std::string topic;
  std::string message;
  bool refused() const { return !message.empty(); }
};

// The samples on the clock, produced lazily from the signals (no copy of the whole flight).
class LogSampleSource : public SampleSource {
 public:
  Next next(TelemetrySample& sample, std::string& problem) override;
  std::string where() const override;
  bool moreReady() const override { return true; }
  bool carriesRates() const override { return !signals_.rates.empty(); }

  const ImportReport& report() const { return report_; }
  void setName(std::string name) { name_ = std::move(name); }  // for where(): the log file
  std::size_t stretchCount() const { return stretches_.size(); }

 private:
  friend ImportRefusal buildLogSampleSource(FlightSignals signals, LogFormat format, const ImportOptions& options,
                                            LogSampleSource& out);
  struct Stretch {
    double begin = 0.0;
    long count = 0;  // grid samples
  };
  FlightSignals signals_;
  double scale_ = 1.0;  // [N] per command unit
  double dt_ = 0.002;
  std::vector<Stretch> stretches_;
  std::size_t stretch_ = 0;
  long index_ = 0;
  std::size_t ia_ = 0, ip_ = 0, ic_ = 0, ir_ = 0;  // cursors into attitude, position, command, rates
  double last_t_ = 0.0;
  std::string name_ = "log";
  ImportReport report_;
};

// FlightSignals + options → `out` (a freshly constructed source: ready, with its report), or a refusal (out then holds a
// partial report). `format` picks the autopilot-specific advice in refusals.
ImportRefusal buildLogSampleSource(FlightSignals signals, LogFormat format, const ImportOptions& options,
                                   LogSampleSource& out);

// Rate problems visible in a decoded log even when extraction failed (e.g. a Crazyflie event
// logged at 100 Hz that also lacks a variable): "; also, …" sentences, empty when none.
std::string coarseTopicsNote(const DecodedLog& log, const ImportOptions& options);

// Median interval [s] of increasing times (0 with fewer than two).
double medianInterval(const std::vector<double>& t);

}  // namespace quadfdi
