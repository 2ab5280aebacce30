// Telemetry CSV reading speed: a 10-minute 500 Hz flight (300 000 rows, the columns `quadfdi
// simulate` writes) from memory through TelemetryReader, every row parsed and checked. Reports
// rows/s and bytes/s; the lines are read with the reader's 1 MiB line bound.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "io/telemetry_reader.h"

using namespace quadfdi;

namespace {

const std::string& tenMinuteCsv() {
  static const std::string text = [] {
    std::string s = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4\n";
    char row[256];
    for (int k = 0; k < 300000; ++k) {
      const double t = 0.002 * k;
      std::snprintf(row, sizeof row, "%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f\n", t, std::sin(t), std::cos(t),
                    1.0 + 0.1 * std::sin(3 * t), 0.05 * std::sin(5 * t), 0.05 * std::cos(5 * t), 0.1 * t, 0.07 + 0.001 * std::sin(t),
                    0.07, 0.07, 0.07);
      s += row;
    }
    return s;
  }();
  return text;
}

void readTelemetryCsv(benchmark::State& state) {
  const std::string& text = tenMinuteCsv();
  long rows = 0;
  for (auto _ : state) {
    std::istringstream in(text);
    TelemetryReader reader(in, "bench.csv");
    TelemetrySample s;
    std::string problem;
    while (reader.next(s, problem) != SampleSource::Next::kEnd) ++rows;
  }
  state.counters["rows/s"] = benchmark::Counter(static_cast<double>(rows), benchmark::Counter::kIsRate);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(text.size()));
}
BENCHMARK(readTelemetryCsv)->Unit(benchmark::kMillisecond);

}  // namespace
