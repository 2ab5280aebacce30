#include "io/merged_telemetry.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdio>
#include <limits>

namespace quadfdi {
namespace {

// Appends (t, v), or replaces the last sample when it is at the same t (two rows of one time):
// true when it replaced one.
template <class Series, class Value>
bool append(Series& s, double t, const Value& v) {
  if (!s.t.empty() && s.t.back() == t) {
    s.v.back() = v;
    return true;
  }
  s.t.push_back(t);
  s.v.push_back(v);
  return false;
}

// The four motors' commands, each given at times of its own, as one series: every time one of
// them was given, from the first time all four have been, each motor's held from its own last sample.
SignalSeries<kMotors> heldTogether(const std::array<SignalSeries<1>, kMotors>& motor) {
  SignalSeries<kMotors> all;
  double start = -std::numeric_limits<double>::infinity();
  for (const SignalSeries<1>& m : motor) {
    if (m.empty()) return all;
    start = std::max(start, m.t.front());
  }
  for (const SignalSeries<1>& m : motor) {  // each motor's times are in order: merged in linear time
    const auto merged = static_cast<std::ptrdiff_t>(all.t.size());
    all.t.insert(all.t.end(), std::lower_bound(m.t.begin(), m.t.end(), start), m.t.end());
    std::inplace_merge(all.t.begin(), all.t.begin() + merged, all.t.end());
  }
  all.t.erase(std::unique(all.t.begin(), all.t.end()), all.t.end());
  all.v.resize(all.t.size());
  std::array<std::size_t, kMotors> next{};
  for (std::size_t k = 0; k < all.t.size(); ++k)
    for (std::size_t i = 0; i < kMotors; ++i) {
      const SignalSeries<1>& m = motor[i];
      while (next[i] < m.t.size() && m.t[next[i]] <= all.t[k]) ++next[i];
      all.v[k][i] = m.v[next[i] - 1][0];  // next[i] ≥ 1: all.t[k] ≥ start ≥ m.t.front()
    }
  return all;
}

std::string plural(std::size_t n, const char* what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

}  // namespace

MergedTelemetryCounts readMergedTelemetry(TelemetryReader& reader, FlightSignals& out) {
  MergedTelemetryCounts counts;
  out = FlightSignals{};
  TelemetryRowParts row;
  std::string problem;
  double last_t = 0.0;  // of the last row holding a signal
  std::array<SignalSeries<1>, kMotors> motor;  // each motor's command from every row that gives it
  for (SampleSource::Next n; (n = reader.nextParts(row, problem)) != SampleSource::Next::kEnd;) {
    ++counts.rows;
    if (n == SampleSource::Next::kSkipped) {
      ++counts.without_time;
      if (counts.first_problem.empty()) counts.first_problem = problem;
      continue;
    }
    if (!out.states.empty() && row.t < last_t)
      throw TelemetryError(reader.where() + ": time goes backwards (t = " + std::to_string(row.t) + " s after " +
                           std::to_string(last_t) + " s): a merged export's rows must be in time order");
    if (!row.dropped.empty()) {
      ++counts.partial;
      if (counts.first_problem.empty()) counts.first_problem = row.dropped + "; that signal left out of the row";
    }
    const bool some_command = std::find(row.has_u.begin(), row.has_u.end(), true) != row.has_u.end();
    // A row of the gyro alone is a signal too (a ROS bag's IMU topic has rows of its own).
    if (!row.has_position && !row.has_attitude && !row.has_rates && !some_command) {
      ++counts.without_signal;
      continue;
    }
    if (out.states.empty()) out.states.push_back({row.t, true, false});  // the file is the flight, from its first signal
    last_t = row.t;
    if (row.has_position && append(out.position, row.t, row.position)) ++counts.repeated;
    if (row.has_attitude && append(out.attitude, row.t, row.attitude)) ++counts.repeated;
    if (row.has_rates && append(out.rates, row.t, row.rates)) ++counts.repeated;
    bool command_repeated = false;  // the commands are one signal, however many of their motors repeat
    for (std::size_t i = 0; i < kMotors; ++i)
      if (row.has_u[i] && append(motor[i], row.t, std::array<double, 1>{row.u[i]})) command_repeated = true;
    if (command_repeated) ++counts.repeated;
    if (some_command && !row.has_commands) ++counts.split_commands;
  }
  // Whole rows only: each motor has the rows' times, and the series is the rows' own.
  out.command = heldTogether(motor);
  if (counts.split_commands > 0)  // the motors at times of their own: the conventions layer checks each
    for (const SignalSeries<1>& m : motor) out.command_times_per_motor.push_back(m.t);
  // The "topic" of each signal is its columns: the refusals and the report name them.
  out.position.source = {"columns x,y,z", "", ""};
  out.attitude.source = {reader.quaternionAttitude() ? "columns qw,qx,qy,qz" : "columns roll,pitch,yaw", "",
                         reader.quaternionAttitude() ? "quaternion → ZYX Euler" : ""};
  if (reader.carriesRates()) out.rates.source = {"columns p,q,r", "", ""};
  out.command.source = {"columns u1,u2,u3,u4", "",
                        counts.split_commands > 0 ? "each motor held from its own rows to the others' times" : ""};
  out.command_kind = CommandKind::kThrustNewton;
  if (reader.numbering()) out.numbering = *reader.numbering();
  out.conventions.push_back("a merged telemetry CSV: " + plural(counts.rows, "row") + ", position in " +
                            std::to_string(out.position.t.size()) + ", attitude in " + std::to_string(out.attitude.t.size()) +
                            ", commands in " + std::to_string(out.command.t.size()) +
                            (reader.carriesRates() ? ", body rates in " + std::to_string(out.rates.t.size()) : std::string()) +
                            "; the whole file is the flight");
  if (counts.without_signal > 0)
    out.conventions.push_back(plural(counts.without_signal, "row") + " with none of the three signals (other columns only) passed over");
  if (counts.partial > 0)
    out.conventions.push_back(plural(counts.partial, "signal") + " left out of a row for lacking some of its cells or a bad command cell (first: " +
                              counts.first_problem + ")");
  if (counts.split_commands > 0)
    out.conventions.push_back(plural(counts.split_commands, "row") + " with some of u1..u4 and not all: each motor's command "
                              "read from the rows that give it, held to the times the others are given, from " +
                              (out.command.empty() ? std::string("the first time all four are (never)")
                                                   : "the first time all four are (t = " + std::to_string(out.command.t.front()) + " s)"));
  if (counts.repeated > 0)
    out.conventions.push_back(plural(counts.repeated, "signal") + " given twice at one time: the later row kept");
  return counts;
}

}  // namespace quadfdi
