#include "io/merged_telemetry.h"

#include <array>
#include <cstdio>

namespace quadfdi {
namespace {

// Appends (t, v), or replaces the last sample when it is at the same t (two rows of one time).
template <class Series, class Value>
void append(Series& s, double t, const Value& v, std::size_t& repeated) {
  if (!s.t.empty() && s.t.back() == t) {
    s.v.back() = v;
    ++repeated;
    return;
  }
  s.t.push_back(t);
  s.v.push_back(v);
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
    if (!row.has_position && !row.has_attitude && !row.has_commands) {
      ++counts.without_signal;
      continue;
    }
    if (out.states.empty()) out.states.push_back({row.t, true, false});  // the file is the flight, from its first signal
    last_t = row.t;
    if (row.has_position) append(out.position, row.t, row.position, counts.repeated);
    if (row.has_attitude) append(out.attitude, row.t, row.attitude, counts.repeated);
    if (row.has_commands) append(out.command, row.t, row.u, counts.repeated);
  }
  // The "topic" of each signal is its columns: the refusals and the report name them.
  out.position.source = {"columns x,y,z", "", ""};
  out.attitude.source = {reader.quaternionAttitude() ? "columns qw,qx,qy,qz" : "columns roll,pitch,yaw", "",
                         reader.quaternionAttitude() ? "quaternion → ZYX Euler" : ""};
  out.command.source = {"columns u1,u2,u3,u4", "", ""};
  out.command_kind = CommandKind::kThrustNewton;
  if (reader.numbering()) out.numbering = *reader.numbering();
  out.conventions.push_back("a merged telemetry CSV: " + plural(counts.rows, "row") + ", position in " +
                            std::to_string(out.position.t.size()) + ", attitude in " + std::to_string(out.attitude.t.size()) +
                            ", commands in " + std::to_string(out.command.t.size()) + "; the whole file is the flight");
  if (counts.without_signal > 0)
    out.conventions.push_back(plural(counts.without_signal, "row") + " with none of the three signals (other columns only) passed over");
  if (counts.partial > 0)
    out.conventions.push_back(plural(counts.partial, "signal") + " left out of a row for lacking some of its cells (first: " +
                              counts.first_problem + ")");
  if (counts.repeated > 0)
    out.conventions.push_back(plural(counts.repeated, "signal") + " given twice at one time: the later row kept");
  return counts;
}

}  // namespace quadfdi
