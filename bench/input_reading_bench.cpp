// Input reading speed. readTelemetryCsv: a 10-minute 500 Hz flight (300 000 rows, the columns
// `quadfdi simulate` writes) from memory through TelemetryReader, every row parsed and checked,
// with the reader's 1 MiB line bound; rows/s and bytes/s. findCsvHeadingResets: detect's first
// reading of such a file with p,q,r, for its heading resets. readLogFile: a 256 MB file (a long
// flight log's size) read whole by readFileBounded, as detect and import read a log, from the
// page cache; bytes/s. checkCsvQuaternion: that first reading of a file with its attitude as a
// quaternion, which also checks the quaternion's reading.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/frames.h"
#include "io/file_bytes.h"
#include "io/telemetry_heading.h"
#include "io/telemetry_reader.h"

using namespace quadfdi;

namespace {

// With `rates`, the gyro columns p,q,r too (near the attitude's own rates).
const std::string& tenMinuteCsv(bool rates) {
  static const std::string texts[2] = {[] {
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
  }(), [] {
    std::string s = "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4,p,q,r\n";
    char row[320];
    for (int k = 0; k < 300000; ++k) {
      const double t = 0.002 * k;
      std::snprintf(row, sizeof row, "%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f\n", t, std::sin(t),
                    std::cos(t), 1.0 + 0.1 * std::sin(3 * t), 0.05 * std::sin(5 * t), 0.05 * std::cos(5 * t), 0.1 * t,
                    0.07 + 0.001 * std::sin(t), 0.07, 0.07, 0.07, 0.25 * std::cos(5 * t), -0.25 * std::sin(5 * t), 0.1);
      s += row;
    }
    return s;
  }()};
  return texts[rates ? 1 : 0];
}

// Arg: 1 with the gyro columns, read as a rates model reads them.
void readTelemetryCsv(benchmark::State& state) {
  const std::string& text = tenMinuteCsv(state.range(0) != 0);
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
BENCHMARK(readTelemetryCsv)->ArgNames({"rates"})->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// What `detect` adds for a CSV file with p,q,r: the first, whole reading that finds its heading
// resets (io/telemetry_heading.h) — every row parsed again, then the check.
void findCsvHeadingResets(benchmark::State& state) {
  const std::string& text = tenMinuteCsv(true);
  for (auto _ : state) {
    std::istringstream in(text);
    benchmark::DoNotOptimize(checkTelemetryFile(in, "bench.csv", {}).heading.steps);
  }
  state.counters["rows/s"] = benchmark::Counter(300000.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(findCsvHeadingResets)->Unit(benchmark::kMillisecond);

// The same file with its attitude as qw,qx,qy,qz: detect's first reading then also checks the
// quaternion's reading against the flight (logs/quaternion_check.h: four readings' tilt and, with
// p,q,r, their turns), before the rates and the heading.
void checkCsvQuaternion(benchmark::State& state) {
  static const std::string text = [] {
    std::string s = "t,x,y,z,qw,qx,qy,qz,u1,u2,u3,u4,p,q,r\n";
    char row[360];
    for (int k = 0; k < 300000; ++k) {
      const double t = 0.002 * k;
      const Quaternion q = quaternionOfEuler({0.05 * std::sin(5 * t), 0.05 * std::cos(5 * t), 0.1 * t});
      std::snprintf(row, sizeof row, "%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f\n", t, std::sin(t),
                    std::cos(t), 1.0 + 0.1 * std::sin(3 * t), q.w, q.x, q.y, q.z, 0.07 + 0.001 * std::sin(t), 0.07, 0.07, 0.07,
                    0.25 * std::cos(5 * t), -0.25 * std::sin(5 * t), 0.1);
      s += row;
    }
    return s;
  }();
  for (auto _ : state) {
    std::istringstream in(text);
    benchmark::DoNotOptimize(checkTelemetryFile(in, "bench.csv", {}).quaternion.seconds);
  }
  state.counters["rows/s"] = benchmark::Counter(300000.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(checkCsvQuaternion)->Unit(benchmark::kMillisecond);

void readLogFile(benchmark::State& state) {
  const std::string path = (std::filesystem::temp_directory_path() / ("quadfdi_bench_log_" + std::to_string(::getpid()) + ".bin")).string();
  constexpr std::size_t kBytes = std::size_t{256} << 20;
  {
    std::ofstream out(path, std::ios::binary);
    const std::string block(std::size_t{1} << 20, '\x5a');
    for (std::size_t written = 0; written < kBytes; written += block.size()) out << block;
  }
  for (auto _ : state) benchmark::DoNotOptimize(readFileBounded(path, kMaxLogFileBytes, "a flight log", PipeReading::kRead).size());
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(kBytes));
  std::remove(path.c_str());
}
BENCHMARK(readLogFile)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
