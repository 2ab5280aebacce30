// A telemetry CSV that merges signals sampled at different times — a PlotJuggler or ROS bag
// export, a simulator that writes each topic when it arrives — read into the signals the log
// readers give (logs/flight_signals.h): each of position, attitude and commands at its own
// times, from the rows that hold it whole (each motor's command from the rows that give it, when
// the motors come on rows of their own: one topic per motor). The conventions layer (logs/telemetry_from_log.h)
// then puts them on the model's clock as it does a flight log's: attitude and position
// interpolated, commands held, holes not bridged, rates checked.
#pragma once

#include <cstddef>
#include <string>

#include "io/telemetry_reader.h"
#include "logs/flight_signals.h"

namespace quadfdi {

struct MergedTelemetryCounts {
  std::size_t rows = 0;           // data rows read
  std::size_t without_time = 0;   // skipped: t empty or non-finite
  std::size_t without_signal = 0; // rows holding none of the three signals (another topic's columns only)
  std::size_t partial = 0;        // rows leaving out position or attitude for holding some of its cells but not all,
                                  // or a motor's command for a NaN, infinite or absurd cell
  std::size_t split_commands = 0; // rows giving some of u1..u4 and not all: the motors at times of their own
  std::size_t repeated = 0;       // a signal given twice at one time: the later row kept
  std::string first_problem;      // "FILE:LINE: …" of the first row or signal left out, for the warning
};

// Reads every remaining row of `reader` into `out` (position, attitude, command; commands as
// kThrustNewton, the numbering of the file's "# motor_numbering" comment or quadfdi's) and one
// "armed, not landed" event at the first row: the file is the flight, as a telemetry CSV always
// is. The motors' commands may come on rows of their own (u1 on one row, u2 on another, at the
// same or other times): each is then read alone and held to the others' times
// (FlightSignals::command_times_per_motor). Throws TelemetryError "FILE:LINE: problem" for bad
// input and for a time that goes backwards.
MergedTelemetryCounts readMergedTelemetry(TelemetryReader& reader, FlightSignals& out);

}  // namespace quadfdi
