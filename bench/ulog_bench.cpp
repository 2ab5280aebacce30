// PX4 ULog parse speed: a 10-minute synthetic log with PX4's high-rate topics at full rate,
// written in memory with the test writer, then readUlog on one core. Reported as bytes/s
// (docs/logs/ulog.md records the figure).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "logs/px4_signals.h"
#include "logs/telemetry_from_log.h"
#include "logs/ulog.h"
#include "logs/ulog_writer.h"

namespace {

using quadfdi::testing::UlogPayload;
using quadfdi::testing::UlogWriter;

struct Topic {
  const char* format;
  std::uint16_t msg_id;
  int rate_hz;       // [Hz]
  int float_fields;  // floats after the timestamps (the rest of the message)
  int bool_fields;
};

// Field layouts like PX4's (a timestamp, a sample timestamp, floats, then flags).
const Topic kTopics[] = {
    {"vehicle_attitude:uint64_t timestamp;uint64_t timestamp_sample;float[4] q;float[4] delta_q_reset;"
     "uint8_t quat_reset_counter;uint8_t[7] _padding0;", 0, 250, 8, 1},
    {"vehicle_local_position:uint64_t timestamp;uint64_t timestamp_sample;float x;float y;float z;float vx;float vy;"
     "float vz;float ax;float ay;float az;float heading;float eph;float epv;float evh;float evv;float dist_bottom;"
     "float ref_alt;bool xy_valid;bool z_valid;bool v_xy_valid;bool v_z_valid;", 1, 100, 16, 4},
    {"actuator_motors:uint64_t timestamp;uint64_t timestamp_sample;float[12] control;", 2, 400, 12, 0},
    {"actuator_outputs:uint64_t timestamp;uint64_t timestamp_sample;float[16] output;", 3, 400, 16, 0},
    {"vehicle_angular_velocity:uint64_t timestamp;uint64_t timestamp_sample;float[3] xyz;float[3] xyz_derivative;", 4, 400, 6, 0},
    {"sensor_combined:uint64_t timestamp;uint64_t timestamp_sample;float[3] gyro_rad;float[3] accelerometer_m_s2;"
     "float[3] gyro_integral;float[2] misc;", 5, 250, 11, 0},
    {"vehicle_status:uint64_t timestamp;uint64_t timestamp_sample;float load;bool armed;", 6, 2, 1, 1},
};

std::vector<std::uint8_t> tenMinuteLog() {
  UlogWriter w(1, 0);
  w.reserve(std::size_t{80} << 20);
  w.flagBits();
  w.info("sys_name", "PX4");
  for (const Topic& t : kTopics) w.format(t.format);
  for (const Topic& t : kTopics) {
    std::string name(t.format);
    w.subscribe(0, t.msg_id, name.substr(0, name.find(':')));
  }
  const std::uint64_t duration_us = 600ull * 1000000ull;
  const std::uint64_t step_us = 500;  // 2 kHz scheduler tick: every rate above divides it
  for (std::uint64_t now = 0; now < duration_us; now += step_us) {
    for (const Topic& t : kTopics) {
      const std::uint64_t period = 1000000ull / static_cast<std::uint64_t>(t.rate_hz);
      if (now % period >= step_us) continue;
      UlogPayload p;
      p.put(now).put(now);
      for (int i = 0; i < t.float_fields; ++i) p.put(std::sin(static_cast<float>(now % 100000) * 1e-5f + static_cast<float>(i)));
      for (int i = 0; i < t.bool_fields; ++i) p.put(true);
      if (t.msg_id == 0) p.pad(7);
      w.data(t.msg_id, p);
    }
    if (now % 1000000 == 0) w.sync();
  }
  return w.bytes();
}

void BM_ReadUlog(benchmark::State& state) {
  static const std::vector<std::uint8_t> log = tenMinuteLog();
  std::size_t rows = 0;
  for (auto _ : state) {
    quadfdi::DecodedLog decoded;
    const quadfdi::LogIssue issue = quadfdi::readUlog(quadfdi::ByteSpan{log.data(), log.size()}, decoded);
    if (!issue.ok()) state.SkipWithError(issue.message.c_str());
    rows = 0;
    for (const auto& t : decoded.topics) rows += t.rows();
    benchmark::DoNotOptimize(decoded);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * log.size()));
  state.counters["log_MB"] = static_cast<double>(log.size()) / 1e6;
  state.counters["rows"] = static_cast<double>(rows);
}
BENCHMARK(BM_ReadUlog)->Unit(benchmark::kMillisecond)->UseRealTime();

// Read and convert, as `quadfdi import`/`detect` do: readUlog, the PX4 extractor, the
// conventions layer (rates, thrust scaling, phases) and every sample on the model's 500 Hz clock.
// The synthetic log has no land detector: phases come from the height rule, lowered so that the
// whole log counts as airborne (the work per sample is the same).
void BM_ReadAndConvertUlog(benchmark::State& state) {
  static const std::vector<std::uint8_t> log = tenMinuteLog();
  long samples = 0;
  for (auto _ : state) {
    quadfdi::DecodedLog decoded;
    quadfdi::LogIssue issue = quadfdi::readUlog(quadfdi::ByteSpan{log.data(), log.size()}, decoded);
    quadfdi::FlightSignals signals;
    if (issue.ok()) issue = quadfdi::extractPx4Signals(decoded, quadfdi::Px4SignalOptions{}, signals);
    if (!issue.ok()) {
      state.SkipWithError(issue.message.c_str());
      break;
    }
    quadfdi::ImportOptions options;
    options.max_thrust = 0.15;
    options.use_events = false;
    options.airborne_height = -1e9;
    options.airborne_thrust_fraction = -1e9;
    quadfdi::LogSampleSource source;
    const quadfdi::ImportRefusal refusal =
        quadfdi::buildLogSampleSource(std::move(signals), quadfdi::LogFormat::kUlog, options, source);
    if (refusal.refused()) {
      state.SkipWithError(refusal.message.c_str());
      break;
    }
    quadfdi::TelemetrySample sample;
    std::string problem;
    samples = 0;
    while (source.next(sample, problem) != quadfdi::SampleSource::Next::kEnd) ++samples;
    benchmark::DoNotOptimize(sample);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * log.size()));
  state.counters["log_MB"] = static_cast<double>(log.size()) / 1e6;
  state.counters["samples"] = static_cast<double>(samples);
}
BENCHMARK(BM_ReadAndConvertUlog)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
