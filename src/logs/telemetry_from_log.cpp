// The conventions layer: see telemetry_from_log.h and docs/logs/README.md.
#include "logs/telemetry_from_log.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "core/frames.h"
#include "logs/heading_resets.h"

namespace quadfdi {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Every caller passes a literal with one double conversion.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
std::string num(double v, const char* f = "%.3g") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}
#pragma GCC diagnostic pop
std::string hz(double v) { return num(v, v >= 100 ? "%.0f Hz" : "%.1f Hz"); }
std::string ms(double s) { return num(1000.0 * s, "%.3g ms"); }
std::string sec(double s) { return num(s, "%.3f"); }

struct Span {
  double a = 0.0, b = 0.0;
  double length() const { return b - a; }
};

// What to change on each autopilot so that a signal is logged fast enough.
std::string advice(LogFormat f, const std::string& what, const std::string& topic) {
  switch (f) {
    case LogFormat::kUlog:
      if (what == "position")
        return "log vehicle_local_position at ≥ 20 Hz (PX4's default profile logs it at ~100 Hz; check "
               "etc/logging/logger_topics.txt)";
      return "set the high-rate bit of SDLOG_PROFILE (bit 4, +16: e.g. SDLOG_PROFILE = 17) so that PX4 logs " + topic +
             " at full rate, or list it in etc/logging/logger_topics.txt with interval 0";
    case LogFormat::kDataflash:
      if (what == "attitude")
        return "set LOG_BITMASK bit 0 (ATTITUDE_FAST) so that ArduPilot logs ATT at the main loop rate (bit 1, "
               "ATTITUDE_MED, alone gives 10 Hz)";
      if (what == "commands")
        return "set LOG_BITMASK bit 10 (RCOUT) and bit 0 (ATTITUDE_FAST) so that RCOU is logged at the main loop rate";
      return "log the EKF position (" + topic + ") at ≥ 20 Hz (LOG_BITMASK, EKF logging: ArduPilot writes XKF1 at "
             "~25 Hz by default)";
    case LogFormat::kCrazyflieUsd:
      return "raise the uSD deck's logging frequency for event '" + topic +
             "' in config.txt (on:fixedFrequency, e.g. 500 Hz, mode 1)";
    case LogFormat::kMergedCsv:
      return "export the " + what + " at least that often (the rate is that of the rows holding them)";
    case LogFormat::kUnknown: break;
  }
  return "log " + topic + " faster";
}

std::string limitFlag(const std::string& what) {
  return what == "attitude" ? "--min-rate-attitude" : what == "commands" ? "--min-rate-command" : "--min-rate-position";
}

// Index of the last time ≤ t (t within [times.front(), times.back()]); `cursor` only moves forward.
// A sample within 1 ns of t counts as at t (log times are whole µs; grid times carry rounding).
std::size_t seek(const std::vector<double>& times, double t, std::size_t& cursor) {
  while (cursor + 1 < times.size() && times[cursor + 1] <= t + 1e-9) ++cursor;
  return cursor;
}

template <int N>
std::array<double, N> linear(const SignalSeries<N>& s, double t, std::size_t& cursor, bool angles) {
  const std::size_t i = seek(s.t, t, cursor);
  if (i + 1 >= s.t.size() || t <= s.t[i]) return s.v[i];
  const double w = (t - s.t[i]) / (s.t[i + 1] - s.t[i]);
  std::array<double, N> v{};
  for (std::size_t k = 0; k < static_cast<std::size_t>(N); ++k) {
    const double a = s.v[i][k], b = s.v[i + 1][k];
    v[k] = angles ? wrapAngle(a + w * wrapAngle(b - a)) : a + w * (b - a);
  }
  return v;
}

template <int N>
std::array<double, N> held(const SignalSeries<N>& s, double t, std::size_t& cursor) {
  return s.v[seek(s.t, t, cursor)];
}

// Removes from `spans` every hole of `t` longer than `limit`.
void cutHoles(std::vector<Span>& spans, const std::vector<double>& t, double limit, int& holes) {
  std::vector<Span> out;
  for (const Span& s : spans) {
    Span cur = s;
    auto it = std::upper_bound(t.begin(), t.end(), cur.a);
    std::size_t i = it == t.begin() ? 0 : static_cast<std::size_t>(it - t.begin()) - 1;
    for (; i + 1 < t.size() && t[i] < cur.b; ++i) {
      if (t[i + 1] - t[i] > limit) {
        ++holes;
        if (t[i] > cur.a) out.push_back({cur.a, t[i]});
        cur.a = t[i + 1];
        if (cur.a >= cur.b) break;
      }
    }
    if (cur.b > cur.a) out.push_back(cur);
  }
  spans.swap(out);
}

// Removes from `spans` every break's stretch, from its last sample before the jump (or `half`
// before the jump, if earlier) to `half` after it: nothing evaluated is interpolated across the
// jump, and the two sides stay apart (≥ 2·half > restart_gap), so the detector restarts.
// `first` is the first break that cut anything.
void cutBreaks(std::vector<Span>& spans, const std::vector<SignalBreak>& breaks, double half, int& cuts,
               const SignalBreak*& first) {
  for (const SignalBreak& b : breaks) {
    const double from = std::min(b.t - half, b.last_before), to = b.t + half;
    std::vector<Span> out;
    for (const Span& s : spans) {
      if (to <= s.a || from >= s.b) {
        out.push_back(s);
        continue;
      }
      if (cuts++ == 0) first = &b;
      if (from > s.a) out.push_back({s.a, from});
      if (to < s.b) out.push_back({to, s.b});
    }
    spans.swap(out);
  }
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(std::clamp(p, 0.0, 1.0) * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

double totalCommand(const std::array<double, kMotors>& u) { return u[0] + u[1] + u[2] + u[3]; }

}  // namespace

double medianInterval(const std::vector<double>& t) {
  if (t.size() < 2) return 0.0;
  std::vector<double> d(t.size() - 1);
  for (std::size_t i = 0; i + 1 < t.size(); ++i) d[i] = t[i + 1] - t[i];
  return percentile(std::move(d), 0.5);
}

std::string ImportReport::phasesLine() const {
  int evaluated = 0;
  std::string spans;
  double total = 0.0;
  for (const PhaseReport& p : phases) {
    if (!p.evaluated) continue;
    ++evaluated;
    spans += (spans.empty() ? "" : ", ") + sec(p.eval_begin) + "–" + sec(p.eval_end) + " s";
    total += p.eval_end - p.eval_begin;
  }
  return "evaluated " + std::to_string(evaluated) + " of " + std::to_string(phases.size()) + " airborne phase" +
         (phases.size() == 1 ? "" : "s") + " (" + phase_rule + "): " + (spans.empty() ? "none" : spans) + " (" +
         num(total, "%.2f") + " s)";
}

std::string ImportReport::text() const {
  std::string s = "format: " + format + "\nsignals:\n";
  for (const SignalReport& r : signals)
    s += "  " + r.name + ": " + r.source.topic + (r.source.fields.empty() ? "" : " " + r.source.fields) + ", " + std::to_string(r.samples) + " samples, " +
         hz(r.rate_hz) + " (median interval " + ms(r.median_interval) + "), " + sec(r.t_first) + "–" + sec(r.t_last) +
         " s; " + r.method + (r.source.note.empty() ? "" : "; " + r.source.note) + "\n";
  s += "conventions:\n";
  for (const std::string& c : conventions) s += "  - " + c + "\n";
  s += "motors (quadfdi's number: position, the autopilot's number):";
  for (int m = 1; m <= kMotors; ++m) s += std::string(m > 1 ? ";" : "") + " " + std::to_string(m) + ": " + motorForPilot(numbering, m);
  s += "\n";
  s += "thrust: " + thrust + "\n";
  s += "phases (" + phase_rule + "):\n";
  for (std::size_t i = 0; i < phases.size(); ++i) {
    const PhaseReport& p = phases[i];
    s += "  " + std::to_string(i + 1) + ". airborne " + sec(p.t_begin) + "–" + sec(p.t_end) + " s: ";
    s += p.evaluated ? "evaluated " + sec(p.eval_begin) + "–" + sec(p.eval_end) + " s" : std::string("not evaluated");
    s += (p.note.empty() ? "" : " (" + p.note + ")") + "\n";
  }
  s += phasesLine() + "\n";
  s += "samples: " + std::to_string(samples) + " on a " + ms(dt) + " clock\n";
  for (const std::string& w : warnings) s += "warning: " + w + "\n";
  return s;
}

std::string coarseTopicsNote(const DecodedLog& log, const ImportOptions& o) {
  std::string note;
  std::set<std::string> named;  // a topic's other instances are not named again
  const double need = std::max(o.min_rate_attitude, o.min_rate_command);
  for (const LogTopic& t : log.topics) {
    bool relevant = false;
    if (log.format == LogFormat::kCrazyflieUsd)
      relevant = t.fieldIndex("motor.m1") >= 0 || t.fieldIndex("stateEstimate.roll") >= 0 ||
                 t.fieldIndex("stabilizer.roll") >= 0 || t.fieldIndex("stateEstimate.qw") >= 0 ||
                 t.fieldIndex("stateEstimateZ.quat") >= 0 || t.fieldIndex("pwm.m1_pwm") >= 0;
    else if (log.format == LogFormat::kUlog)
      relevant = t.name == "vehicle_attitude" || t.name == "actuator_motors" || t.name == "actuator_outputs";
    else if (log.format == LogFormat::kDataflash)
      relevant = t.name == "ATT" || t.name == "RCOU";
    if (!relevant || t.rows() < 2) continue;
    std::vector<double> times(t.rows());
    for (std::size_t r = 0; r < t.rows(); ++r) times[r] = static_cast<double>(t.timestamp_us[r]) * 1e-6;
    const double dt = medianInterval(times);
    if (!(dt > 0.0) || 1.0 / dt >= need) continue;
    if (!named.insert(t.name).second) continue;
    note += "; also, " + std::string(log.format == LogFormat::kCrazyflieUsd ? "event '" : "topic ") + t.name +
            (log.format == LogFormat::kCrazyflieUsd ? "'" : "") + " is logged at " + hz(1.0 / dt) + " (median interval " +
            ms(dt) + "), below the " + hz(need) + " attitude and motor commands need: " +
            advice(log.format, "commands", t.name);
  }
  return note;
}

ImportRefusal buildLogSampleSource(FlightSignals signals, LogFormat format, const ImportOptions& o, LogSampleSource& out) {
  ImportReport& rep = out.report_;
  rep.format = toString(format);
  rep.dt = o.dt;
  rep.conventions = signals.conventions;
  rep.numbering = signals.numbering;
  if (!(o.dt > 0.0)) return {"", "the model's sample period must be > 0"};
  // A plus or props-out frame: the attitude and body rates of the turned axes the model reads it in
  // (core/quad_layout.h); the extractor has numbered the motors in them.
  if (const BodyTurn turn = signals.numbering.body_turn; !turn.none()) {
    for (std::array<double, 3>& a : signals.attitude.v) {
      const EulerZyx e = attitudeOfTurnedAxes({a[0], a[1], a[2]}, turn);
      a = {e.roll, e.pitch, e.yaw};
    }
    for (std::array<double, 3>& w : signals.rates.v) w = bodyVectorInTurnedAxes(w, turn);
  }

  // --- Rates. ---
  struct Check {
    const char* what;
    const std::vector<double>* t;
    const SignalSource* source;
    double min_rate;
    const char* method;
    double default_rate;  // [Hz] read below this (the limit lowered), a warning says what it costs; 0: none
  };
  // Motors given at times of their own: the commands are as fast as the slowest motor (the four
  // together change more often than any one does), which the checks name.
  const std::vector<std::vector<double>>& motor_times = signals.command_times_per_motor;
  const std::vector<double>* command_times = &signals.command.t;
  SignalSource command_source = signals.command.source;
  double slowest = -1.0;
  std::vector<double> motor_hole_limit;  // each motor's, as hole_limit below is each signal's
  for (std::size_t i = 0; i < motor_times.size(); ++i) {
    const double d = motor_times[i].size() < 2 ? std::numeric_limits<double>::infinity() : medianInterval(motor_times[i]);
    motor_hole_limit.push_back(std::max(o.max_hole, o.hole_intervals * d));
    if (d <= slowest) continue;
    slowest = d;
    command_times = &motor_times[i];
    command_source.topic = "column u" + std::to_string(i + 1);
    command_source.fields = "(the slowest of u1..u4, each on rows of its own)";
  }
  const Check checks[] = {
      {"attitude", &signals.attitude.t, &signals.attitude.source, o.min_rate_attitude,
       "interpolated linearly per Euler angle, each the short way round", ImportOptions{}.min_rate_attitude},
      {"position", &signals.position.t, &signals.position.source, o.min_rate_position, "interpolated linearly", 0.0},
      {"commands", command_times, &command_source, o.min_rate_command,
       "held from one logged command to the next (zero-order hold)", ImportOptions{}.min_rate_command},
  };
  std::vector<double> hole_limit;
  for (const Check& c : checks) {
    const std::string what = c.what;
    SignalReport r;
    r.name = c.what;
    r.source = *c.source;
    r.samples = c.t->size();
    r.method = c.method;
    if (c.t->size() < 2)
      return {c.source->topic, std::string(c.what) + " (" + c.source->topic + ") has " + std::to_string(c.t->size()) +
                                   " sample" + (c.t->size() == 1 ? "" : "s") + ": nothing to put on a clock"};
    r.t_first = c.t->front();
    r.t_last = c.t->back();
    r.median_interval = medianInterval(*c.t);
    r.rate_hz = r.median_interval > 0.0 ? 1.0 / r.median_interval : 0.0;
    rep.signals.push_back(r);
    hole_limit.push_back(std::max(o.max_hole, o.hole_intervals * r.median_interval));
    if (r.rate_hz < c.min_rate)
      return {c.source->topic, c.source->topic + " (" + c.what + ") is logged at " + hz(r.rate_hz) + " (median interval " +
                                   ms(r.median_interval) + "), too coarse for a sound detection: " + c.what + " need" +
                                   (what == "position" ? "s" : "") + " ≥ " + hz(c.min_rate) + " (" +
                                   ms(1.0 / c.min_rate) + "); " + advice(format, c.what, c.source->topic) +
                                   " (or lower " + limitFlag(c.what) +
                                   (c.default_rate > 0.0 ? ", at a measured cost: docs/results/log-rates/README.md)" : " at your own risk)")};
    // Read below the default because the limit was lowered: say what that was measured to cost.
    if (r.rate_hz < c.default_rate)
      rep.warnings.push_back(c.source->topic + " (" + what + ") is logged at " + hz(r.rate_hz) + ", below the default " + hz(c.default_rate) +
                             ", and read as " + limitFlag(what) + " allows: from a 100 Hz log complete failures were named about 10 ms "
                             "later, and at 50 Hz false alarms appeared (docs/results/log-rates/README.md)");
  }

  // --- Body rates: optional (only a model on body rates reads them), so a log without them, or
  // with them too coarse to carry a fault's first samples, is read without them, saying so. ---
  double rates_hole_limit = 0.0;
  // Estimator heading resets the log does not record, found with the gyro and taken out
  // (heading_resets.h), whether or not the model reads the rates.
  rep.conventions.push_back(headingResetsLine(takeOutHeadingResets(signals.attitude, signals.rates), signals.rates));
  if (!o.read_rates) signals.rates = {};
  {
    // A rate beyond any gyro's range (flight controllers' saturate at 2000 °/s, 35 rad/s) is a
    // corrupt row or another unit, not flight, as the CSV reader holds (isUsableBodyRate): left out, counted.
    SignalSeries<3>& r = signals.rates;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < r.t.size(); ++i) {
      if (!isUsableBodyRate(r.v[i])) continue;
      r.t[kept] = r.t[i];
      r.v[kept] = r.v[i];
      ++kept;
    }
    if (kept < r.t.size())
      rep.conventions.push_back(r.source.topic + ": " + std::to_string(r.t.size() - kept) +
                                " body-rate rows not finite or beyond 100 rad/s (no gyro measures that) left out");
    r.t.resize(kept);
    r.v.resize(kept);
  }
  if (!signals.rates.empty()) {
    SignalReport r;
    r.name = "body rates";
    r.source = signals.rates.source;
    r.samples = signals.rates.t.size();
    r.method = "interpolated linearly";
    r.median_interval = medianInterval(signals.rates.t);
    r.rate_hz = r.median_interval > 0.0 ? 1.0 / r.median_interval : 0.0;
    r.t_first = signals.rates.t.front();
    r.t_last = signals.rates.t.back();
    if (r.samples < 2 || r.rate_hz < o.min_rate_attitude) {
      rep.warnings.push_back(r.source.topic + " (body rates) is logged at " + hz(r.rate_hz) + ", below the " +
                             hz(o.min_rate_attitude) + " attitude needs: not read (a model on body rates refuses this log)");
      signals.rates = {};
    } else {
      rep.signals.push_back(r);
      rates_hole_limit = std::max(o.max_hole, o.hole_intervals * r.median_interval);
    }
  }

  // --- Where all signals exist. ---
  const bool rates = !signals.rates.empty();
  const double data_begin = std::max({signals.attitude.t.front(), signals.position.t.front(), signals.command.t.front(),
                                      rates ? signals.rates.t.front() : -std::numeric_limits<double>::infinity()});
  const double data_end = std::min({signals.attitude.t.back(), signals.position.t.back(), signals.command.t.back(),
                                    rates ? signals.rates.t.back() : std::numeric_limits<double>::infinity()});
  if (!(data_end > data_begin))
    return {"", std::string("the attitude, position") + (rates ? ", body rate" : "") + " and command series do not overlap in time (" + sec(data_begin) + " s … " +
                    sec(data_end) + " s)"};
  const double edge = 0.05;  // [s] a phase starting/ending this close to the data's edge was cut by the log, not flown

  // --- Airborne phases. ---
  std::vector<Span> airborne;
  const bool events = o.use_events && !signals.states.empty();
  std::string no_flight_why;
  if (events) {
    rep.phase_rule = format == LogFormat::kMergedCsv ? "a telemetry CSV: the whole file" : "the autopilot's armed/landed events";
    bool in = false;
    double start = 0.0;
    for (const FlightStateEvent& e : signals.states) {
      const bool up = e.armed && !e.landed;
      if (up && !in) {
        in = true;
        start = e.t;
      } else if (!up && in) {
        in = false;
        airborne.push_back({start, e.t});
      }
    }
    if (in) airborne.push_back({start, std::numeric_limits<double>::infinity()});
    no_flight_why = "the armed/landed events never show the vehicle armed and not landed";
  } else {
    const SignalSeries<3>& p = signals.position;
    std::vector<double> z(p.v.size()), finite_z;
    for (std::size_t i = 0; i < z.size(); ++i) {
      z[i] = p.v[i][2];
      if (std::isfinite(z[i])) finite_z.push_back(z[i]);
    }
    const double ground = percentile(finite_z, 0.01);
    std::size_t cursor = 0;
    std::vector<double> total(p.t.size(), 0.0);
    std::vector<double> high_totals;
    for (std::size_t i = 0; i < p.t.size(); ++i) {
      if (p.t[i] < signals.command.t.front()) continue;
      total[i] = totalCommand(held(signals.command, p.t[i], cursor));
      if (z[i] - ground > o.airborne_height && std::isfinite(total[i])) high_totals.push_back(total[i]);
    }
    const double ref = percentile(high_totals, 0.5);
    rep.phase_rule = "no armed/landed events: airborne while " + num(o.airborne_height, "%g") + " m above the ground level (" +
                     num(ground, "%.3g") + " m) with the total command above " +
                     num(o.airborne_thrust_fraction, "%g") + " × its airborne median, for ≥ " +
                     num(o.airborne_min_duration, "%g") + " s";
    bool in = false;
    double start = 0.0, last = 0.0;
    for (std::size_t i = 0; i < p.t.size(); ++i) {
      const bool up = p.t[i] >= signals.command.t.front() && z[i] - ground > o.airborne_height &&
                      total[i] > o.airborne_thrust_fraction * ref && ref > 0.0;
      if (up && !in) {
        in = true;
        start = p.t[i];
      }
      if (!up && in) {
        in = false;
        if (last - start >= o.airborne_min_duration) airborne.push_back({start, p.t[i]});
      }
      if (up) last = p.t[i];
    }
    if (in && last - start >= o.airborne_min_duration) airborne.push_back({start, std::numeric_limits<double>::infinity()});
    no_flight_why = high_totals.empty() ? "the height never exceeds the ground level by " + num(o.airborne_height, "%g") + " m"
                                        : "no stretch of ≥ " + num(o.airborne_min_duration, "%g") +
                                              " s is high enough with enough thrust";
  }
  // Clip to the data and keep what overlaps it.
  std::vector<Span> clipped;
  for (const Span& s : airborne)
    if (s.b > data_begin && s.a < data_end) clipped.push_back(s);
  if (clipped.empty())
    return {"", "no flight found: " + no_flight_why + " (data " + sec(data_begin) + "–" + sec(data_end) + " s)"};

  // --- Margins, holes, minimum length. ---
  std::vector<Span> pieces;
  for (const Span& s : clipped) {
    PhaseReport ph;
    ph.t_begin = std::max(s.a, data_begin);
    ph.t_end = std::min(s.b, data_end);
    std::vector<std::string> notes;
    Span e{ph.t_begin, ph.t_end};
    if (s.a > data_begin + edge) {
      e.a = s.a + o.settle_after_takeoff;
      notes.push_back("take-off at " + sec(s.a) + " s, " + num(o.settle_after_takeoff, "%g") + " s skipped");
    } else {
      notes.push_back("airborne from the log's start");
    }
    if (s.b < data_end - edge) {
      // Controlled landing or crash? A crash (or flip) tilts the vehicle: keep its last moments.
      double tilt = 0.0;
      const double from = std::max(s.b - o.settle_before_landing, data_begin);
      for (std::size_t i = 0; i < signals.attitude.t.size(); ++i) {
        const double t = signals.attitude.t[i];
        if (t < from || t > s.b) continue;
        tilt = std::max({tilt, std::abs(signals.attitude.v[i][0]), std::abs(signals.attitude.v[i][1])});
      }
      if (tilt > o.landing_max_tilt) {
        notes.push_back("ends at " + sec(s.b) + " s tilted " + num(tilt * 180.0 / kPi, "%.0f") +
                        "°: a crash or flip, not a controlled landing, so no margin");
      } else {
        e.b = s.b - o.settle_before_landing;
        notes.push_back("landing at " + sec(s.b) + " s, " + num(o.settle_before_landing, "%g") + " s skipped");
      }
    } else {
      notes.push_back("airborne to the log's end");
    }
    std::vector<Span> mine;
    if (e.b > e.a) mine.push_back(e);
    int holes = 0;
    cutHoles(mine, signals.attitude.t, hole_limit[0], holes);
    cutHoles(mine, signals.position.t, hole_limit[1], holes);
    if (rates) cutHoles(mine, signals.rates.t, rates_hole_limit, holes);
    if (motor_times.empty()) cutHoles(mine, signals.command.t, hole_limit[2], holes);
    for (std::size_t i = 0; i < motor_times.size(); ++i) cutHoles(mine, motor_times[i], motor_hole_limit[i], holes);
    if (holes) notes.push_back(std::to_string(holes) + " hole" + (holes == 1 ? "" : "s") + " in the signals: not bridged");
    int cuts = 0;
    const SignalBreak* first_cut = nullptr;
    cutBreaks(mine, signals.breaks, std::max({o.restart_gap, o.max_hole, o.dt}), cuts, first_cut);
    if (cuts) notes.push_back(std::to_string(cuts) + " jump" + (cuts == 1 ? "" : "s") + " the log does not size (" +
                              first_cut->why + (cuts > 1 ? "; …" : "") + "): cut there");
    std::vector<Span> kept;
    for (const Span& m : mine)
      if (m.length() >= o.min_phase) kept.push_back(m);
    if (kept.size() < mine.size() || mine.empty())
      notes.push_back("stretches shorter than " + num(o.min_phase, "%g") + " s dropped");
    if (!kept.empty()) {
      ph.evaluated = true;
      ph.eval_begin = kept.front().a;
      ph.eval_end = kept.back().b;
      pieces.insert(pieces.end(), kept.begin(), kept.end());
    }
    for (std::size_t i = 0; i < notes.size(); ++i) ph.note += (i ? "; " : "") + notes[i];
    rep.phases.push_back(ph);
  }
  if (pieces.empty())
    return {"", "no flight found long enough to evaluate: " + std::to_string(rep.phases.size()) + " airborne phase" +
                    (rep.phases.size() == 1 ? "" : "s") + ", none with ≥ " + num(o.min_phase, "%g") +
                    " s left after the settling margins (" + num(o.settle_after_takeoff, "%g") + " s after take-off, " +
                    num(o.settle_before_landing, "%g") + " s before landing)"};
  // Pieces closer than restart_gap are one for the detector: merge them.
  std::vector<Span> merged;
  for (const Span& p : pieces) {
    if (!merged.empty() && p.a - merged.back().b <= o.restart_gap) merged.back().b = p.b;
    else merged.push_back(p);
  }

  // --- Thrust scale. ---
  const std::string& ctopic = signals.command.source.topic;
  double scale = 1.0;
  if (signals.command_kind == CommandKind::kThrustNewton) {
    rep.thrust = "the log's commands are thrust per motor in newtons (" + ctopic + "): used as they are";
  } else {
    const bool calibrate = o.mass > 0.0 && (o.hover_calibrate || !(o.max_thrust > 0.0));
    if (o.hover_calibrate && !(o.mass > 0.0))
      return {ctopic, "hover calibration needs the vehicle's mass (--mass KG)"};
    const bool unscaled = !calibrate && !(o.max_thrust > 0.0);
    if (unscaled && !o.scale_free_model)
      return {ctopic, "the commands (" + ctopic + ") are thrust fractions and nothing scales them to newtons: give the "
                      "motor's maximum thrust (--max-thrust N per motor) or the vehicle's mass (--mass KG, to calibrate "
                      "from a steady hover in the log); a scale-free model (every shipped randomised one) needs neither"};
    if (unscaled) {
      scale = 1.0;
      rep.thrust = "thrust fractions (" + ctopic + ") used as they are (× 1 N): the model's scale-free features read each "
                   "command as a share of their mean, which no constant scale changes (--max-thrust or --mass would not "
                   "change its output)";
    } else if (calibrate) {
      // Steady hover: level, neither climbing nor sinking, sampled every 20 ms in the evaluated stretches.
      const double step = 0.02, half = 0.25;
      double best_sum = 0.0, best_len = 0.0, best_a = 0.0, run_sum = 0.0, run_a = 0.0;
      long best_n = 0, run_n = 0;
      std::size_t ca = 0, cp2 = 0, cp3 = 0, cc = 0;
      for (const Span& m : merged) {
        run_n = 0;
        run_sum = 0.0;
        for (double t = m.a + half; t <= m.b - half; t += step) {
          const auto a = linear<3>(signals.attitude, t, ca, true);
          const auto pa = linear<3>(signals.position, t - half, cp2, false);
          const auto pb = linear<3>(signals.position, t + half, cp3, false);
          const double vz = (pb[2] - pa[2]) / (2.0 * half);
          const bool steady = std::abs(a[0]) < o.hover_max_tilt && std::abs(a[1]) < o.hover_max_tilt &&
                              std::abs(vz) < o.hover_max_climb_rate;
          if (steady) {
            if (run_n == 0) run_a = t;
            run_sum += totalCommand(held(signals.command, t, cc)) / kMotors * std::cos(a[0]) * std::cos(a[1]);
            ++run_n;
            const double len = static_cast<double>(run_n) * step;
            if (len > best_len) {
              best_len = len;
              best_sum = run_sum;
              best_n = run_n;
              best_a = run_a;
            }
          } else {
            run_n = 0;
            run_sum = 0.0;
          }
        }
      }
      if (best_len < o.hover_min_duration || best_n == 0 || !(best_sum > 0.0))
        return {ctopic, "no steady hover of ≥ " + num(o.hover_min_duration, "%g") + " s (tilt < " +
                            num(o.hover_max_tilt, "%g") + " rad, vertical speed < " + num(o.hover_max_climb_rate, "%g") +
                            " m/s) in the evaluated flight to calibrate the thrust from the mass: give the motor's "
                            "maximum thrust (--max-thrust N per motor)"};
      const double mean = best_sum / static_cast<double>(best_n);
      const double per_motor = o.mass * o.gravity / kMotors;
      scale = per_motor / mean;
      rep.hover_calibrated = true;
      rep.thrust = "thrust fractions (" + ctopic + ") × " + num(scale, "%.4g") + " N, calibrated from the log's steady hover " +
                   sec(best_a) + "–" + sec(best_a + best_len) + " s: mean command " + num(mean, "%.4g") +
                   " (tilt-corrected) ↔ m·g/4 = " + num(per_motor, "%.4g") + " N per motor (m = " + num(o.mass, "%g") +
                   " kg)";
      if (o.max_thrust > 0.0)
        rep.thrust += "; the given --max-thrust " + num(o.max_thrust, "%g") + " N differs by " +
                      num(100.0 * (scale - o.max_thrust) / o.max_thrust, "%+.1f") + " %";
    } else {
      scale = o.max_thrust;
      rep.thrust = "thrust fractions (" + ctopic + ") × the motor's maximum thrust " + num(scale, "%g") + " N (given)";
    }
  }
  rep.thrust_factor = scale;

  // --- The clock. ---
  long total = 0;
  for (const Span& m : merged) {
    const double count = std::floor(m.length() / o.dt + 1e-9) + 1.0;
    if (!(count < 1e12))  // 63 years at 500 Hz: a damaged clock, not a flight
      return {"", "an evaluated stretch of " + num(m.length(), "%g") + " s is implausibly long (damaged timestamps?)"};
    const auto n = static_cast<long>(count);
    out.stretches_.push_back({m.a, n});
    total += n;
  }
  rep.samples = static_cast<std::size_t>(total);
  rep.conventions.push_back("clock: every " + ms(o.dt) + " (the model's period) within each evaluated stretch; the "
                            "clock jumps between stretches, so the detector restarts there");
  out.signals_ = std::move(signals);
  out.scale_ = scale;
  out.dt_ = o.dt;
  return {};
}

SampleSource::Next LogSampleSource::next(TelemetrySample& sample, std::string& problem) {
  while (stretch_ < stretches_.size() && index_ >= stretches_[stretch_].count) {
    ++stretch_;
    index_ = 0;
  }
  if (stretch_ >= stretches_.size()) return Next::kEnd;
  const double t = stretches_[stretch_].begin + static_cast<double>(index_) * dt_;
  ++index_;
  const auto p = linear<3>(signals_.position, t, ip_, false);
  const auto a = linear<3>(signals_.attitude, t, ia_, true);
  const auto u = held(signals_.command, t, ic_);
  sample.t = t;
  for (std::size_t k = 0; k < 3; ++k) {
    sample.y[k] = p[k];
    sample.y[k + 3] = a[k];
  }
  for (std::size_t k = 0; k < kMotors; ++k) sample.u[k] = u[k] * scale_;
  sample.rates = signals_.rates.empty() ? std::array<double, 3>{} : linear<3>(signals_.rates, t, ir_, false);
  last_t_ = t;
  // Extractors pass what the log holds; a non-finite value is dropped like a bad CSV row.
  const char* bad = nullptr;
  for (std::size_t k = 0; k < 3 && !bad; ++k) {
    if (!std::isfinite(p[k])) bad = "position";
    else if (!std::isfinite(a[k])) bad = "attitude";
    else if (!std::isfinite(sample.rates[k])) bad = "body rate";
  }
  for (std::size_t k = 0; k < kMotors && !bad; ++k)
    if (!std::isfinite(sample.u[k])) bad = "commands";
  if (bad) {
    problem = where() + ": non-finite " + bad + " value: sample dropped";
    return Next::kSkipped;
  }
  return Next::kSample;
}

std::string LogSampleSource::where() const { return name_ + " (t = " + num(last_t_, "%.3f") + " s)"; }

}  // namespace quadfdi
