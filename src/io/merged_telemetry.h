// A telemetry CSV that merges signals sampled at different times — a PlotJuggler or ROS bag
// export, a simulator that writes each topic when it arrives — read into the signals the log
// readers give (logs/flight_signals.h): each of position, attitude and commands at its own
// times, from the rows that hold it whole. The conventions layer (logs/telemetry_from_log.h)
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
  std::size_t partial = 0;        // signals left out of a row for holding some of their cells but not all
  std::size_t repeated = 0;       // a signal given twice at one time: the later row kept
  std::string first_problem;      // "FILE:LINE: …" of the first row or signal left out, for the warning
};

// Reads every remaining row of `reader` into `out` (position, attitude, command; commands as
// kThrustNewton, the numbering of the file's "# motor_numbering" comment or quadfdi's) and one
// "armed, not landed" event at the first row: the file is the flight, as a telemetry CSV always
// is. Throws TelemetryError "FILE:LINE: problem" for bad input and for a time that goes backwards.
MergedTelemetryCounts readMergedTelemetry(TelemetryReader& reader, FlightSignals& out);

}  // namespace quadfdi
