// DataFlash reading speed: a 10-minute synthetic ArduPilot log in memory (ATT and RCOU at
// 400 Hz, XKF1 of two EKF cores at 400 Hz each: the loop rate, as with LOG_BITMASK's
// ATTITUDE_FAST and RCOUT bits; plus FMTU/UNIT/MULT and a few PARM), timed through
// readDataflash and through readDataflash + extractArdupilotSignals; and the same log as text
// (Mission Planner's .log, as the test writer prints it) through readDataflashText. Reports bytes/s
// of the form read.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <vector>

#include "logs/ardupilot_signals.h"
#include "logs/dataflash.h"
#include "logs/dataflash_text.h"
#include "logs/dataflash_writer.h"

using namespace quadfdi;
using quadfdi::test::centi;
using quadfdi::test::DataflashWriter;

namespace {

const DataflashWriter& tenMinuteWriter() {
  static const DataflashWriter writer = [] {
    DataflashWriter w;
    w.fmt(30, "ATT", "QccccCCCCB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
    w.fmt(31, "XKF1", "QBccCfffffffccce", "TimeUS,C,Roll,Pitch,Yaw,VN,VE,VD,dPD,PN,PE,PD,GX,GY,GZ,OH");
    w.fmt(32, "RCOU", "QHHHHHHHHHHHHHH", "TimeUS,C1,C2,C3,C4,C5,C6,C7,C8,C9,C10,C11,C12,C13,C14");
    w.unit(0, '#', "instance");
    w.unit(0, 'd', "deg");
    w.unit(0, 'm', "m");
    w.unit(0, 's', "s");
    w.mult(0, 'B', 0.01);
    w.mult(0, 'F', 1e-6);
    w.mult(0, '0', 1.0);
    w.fmtu(0, 30, "sddddhhdh-", "FBBBBBBBB-");
    w.fmtu(0, 31, "s#ddhnnnnmmmkkkm", "F-BBB0000000BBBB");
    w.parm(0, "MOT_THST_EXPO", 0.65);
    w.parm(0, "MOT_SPIN_MIN", 0.15);
    constexpr int kSeconds = 600;
    constexpr int kRate = 400;  // [Hz]
    for (int k = 0; k < kSeconds * kRate; ++k) {
      const unsigned long long t = 1000000ull + 2500ull * static_cast<unsigned long long>(k);
      const double s = 0.0025 * k;
      w.write(30, {t, centi(1.0), centi(0.9), centi(-2.0), centi(-2.1), centi(90.0), centi(90.5), 1, 2, 3});
      for (unsigned core = 0; core < 2; ++core)
        w.write(31, {t + core, core, centi(0.9), centi(-2.1), centi(90.5), 0.5, 0.1, -0.2, -0.2, 0.5 * s, 0.1 * s, -10.0,
                     1, 2, 3, 0});
      w.write(32, {t, 1500 + k % 50, 1510, 1490, 1505, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
    }
    return w;
  }();
  return writer;
}

const std::vector<std::uint8_t>& tenMinuteLog() { return tenMinuteWriter().bytes; }

void BM_ReadDataflash(benchmark::State& state) {
  const std::vector<std::uint8_t>& bytes = tenMinuteLog();
  for (auto _ : state) {
    DecodedLog log;
    const LogIssue issue = readDataflash(ByteSpan{bytes.data(), bytes.size()}, log);
    if (!issue.ok()) state.SkipWithError(issue.message.c_str());
    benchmark::DoNotOptimize(log.topics.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes.size()));
  state.counters["log_MB"] = static_cast<double>(bytes.size()) / 1e6;
}
BENCHMARK(BM_ReadDataflash)->Unit(benchmark::kMillisecond);

void BM_ReadAndExtractArdupilot(benchmark::State& state) {
  const std::vector<std::uint8_t>& bytes = tenMinuteLog();
  for (auto _ : state) {
    DecodedLog log;
    FlightSignals signals;
    if (!readDataflash(ByteSpan{bytes.data(), bytes.size()}, log).ok()) state.SkipWithError("read");
    if (!extractArdupilotSignals(log, ArdupilotSignalOptions{}, signals).ok()) state.SkipWithError("extract");
    benchmark::DoNotOptimize(signals.command.v.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes.size()));
}
BENCHMARK(BM_ReadAndExtractArdupilot)->Unit(benchmark::kMillisecond);

void BM_ReadDataflashText(benchmark::State& state) {
  const std::string& text = tenMinuteWriter().text;
  for (auto _ : state) {
    DecodedLog log;
    const LogIssue issue = readDataflashText(ByteSpan{reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}, log);
    if (!issue.ok()) state.SkipWithError(issue.message.c_str());
    benchmark::DoNotOptimize(log.topics.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(text.size()));
  state.counters["log_MB"] = static_cast<double>(text.size()) / 1e6;
}
BENCHMARK(BM_ReadDataflashText)->Unit(benchmark::kMillisecond);

}  // namespace
