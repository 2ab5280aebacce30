// One-off generator of the dataflash_fuzz seeds (fuzz/corpus/dataflash/): small logs written by
// tests/logs/dataflash_writer.h; with TEXT_DIR, the same logs as text (Mission Planner's .log) for
// dataflash_text_fuzz (fuzz/corpus/dataflash_text/). `fuzz_make_dataflash_seeds DIR [TEXT_DIR]`.
#include <array>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "logs/dataflash_writer.h"

using quadfdi::test::centi;
using quadfdi::test::DataflashWriter;

namespace {

void saveBytes(const std::string& path, const char* b, std::size_t n) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(b, 1, n, f) != n || std::fclose(f) != 0) std::perror(path.c_str());
}

std::string text_dir;  // empty: no text seeds

void save(const std::string& dir, const char* name, const std::vector<std::uint8_t>& b) {
  saveBytes(dir + "/" + name, reinterpret_cast<const char*>(b.data()), b.size());
}

// The binary seed, and its text form beside (NAME with .log for .bin).
void save(const std::string& dir, const char* name, const DataflashWriter& w) {
  save(dir, name, w.bytes);
  if (text_dir.empty()) return;
  std::string text_name = name;
  text_name.replace(text_name.rfind(".bin"), 4, ".log");
  saveBytes(text_dir + "/" + text_name, w.text.data(), w.text.size());
}

// frame_type: ArduPilot's FRAME_TYPE (1 X; 12 Betaflight order: the extractor maps motors by it).
// With `ekf_status`, XKF4 per core: SS without a position on the first row, an OFN/OFE reset
// shift changing half-way, the primary core (PI) switching from 0 to 1 half-way.
DataflashWriter copter(int rows, bool fmtu, int frame_type = 1, bool ekf_status = false) {
  DataflashWriter w;
  if (ekf_status) w.fmt(35, "XKF4", "QBcccccfffHBIHb", "TimeUS,C,SV,SP,SH,SM,SVT,errRP,OFN,OFE,FS,TS,SS,GPS,PI");
  w.fmt(30, "ATT", "QccccCCCCB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
  w.fmt(31, "XKF1", "QBccCfffffffccce", "TimeUS,C,Roll,Pitch,Yaw,VN,VE,VD,dPD,PN,PE,PD,GX,GY,GZ,OH");
  w.fmt(32, "RCOU", "QHHHHHHHHHHHHHH", "TimeUS,C1,C2,C3,C4,C5,C6,C7,C8,C9,C10,C11,C12,C13,C14");
  w.fmt(33, "EV", "QB", "TimeUS,Id");
  w.fmt(34, "ARM", "QBIBB", "TimeUS,ArmState,ArmChecks,Forced,Method");
  if (fmtu) {
    w.unit(0, '#', "instance");
    w.unit(0, 'd', "deg");
    w.mult(0, 'B', 0.01);
    w.mult(0, 'F', 1e-6);
    w.fmtu(0, 31, "s#ddhnnnnmmmkkkm", "F-BBB0000000BBBB");
    w.fmtu(0, 30, "sddddhhdh-", "FBBBBBBBB-");
  }
  w.parm(0, "MOT_THST_EXPO", 0.65);
  w.parm(0, "MOT_PWM_MIN", 1000);
  w.parm(0, "MOT_PWM_MAX", 2000);
  w.parm(0, "FRAME_TYPE", frame_type);
  w.msg(0, "ArduCopter V4.5.1 (abcdef12)");
  w.write(33, {100ull, 10});
  w.write(34, {100ull, 1, 0u, 0, 0});
  for (int k = 0; k < rows; ++k) {
    const unsigned long long t = 1000000ull + 2500ull * static_cast<unsigned long long>(k);
    w.write(30, {t, 0, centi(1.0 * k), 0, centi(-0.5 * k), 0, centi(10.0 * k), 0, 0, 3});
    for (unsigned core = 0; core < 2; ++core) {
      w.write(31, {t, core, 0, 0, 0, 0.0, 0.0, 0.0, 0.0, 0.1 * k, 0.2 * k, -1.0 - 0.1 * k, 0, 0, 0, 0});
      if (ekf_status) {
        const double shift = k >= rows / 2 ? 1.5 : 0.0;
        const unsigned ss = k == 0 ? 1u | 128u : 1u | 2u | 4u | 8u | 32u;
        w.write(35, {t, core, 0, 0, 0, 0, 0, 0.0, shift, -shift, 0u, 0u, ss, 0u, k >= rows / 2 ? 1 : 0});
      }
    }
    w.write(32, {t, 1500 + k, 1400, 1600 - k, 1450, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  }
  w.write(33, {9000000ull, 28});
  w.write(33, {9500000ull, 11});
  return w;
}

// A copter that turns at 40 °/s with RATE logged, whose ATT yaw steps by 5° at row 120 and whose
// XKF1 PD steps by 0.5 m at row 160 (resets ArduPilot does not log, which the extractor and the
// conventions layer find against the EKF's velocity and the gyro), and MOTB every 10 rows with the
// battery voltage ratio draining from 1 to 0.8 — one row's BatVolt in volts (12.6), read from LiftMax.
DataflashWriter copterWithResets(int rows) {
  DataflashWriter w;
  w.fmt(30, "ATT", "QccccCCCCB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
  w.fmt(31, "XKF1", "QBccCfffffffccce", "TimeUS,C,Roll,Pitch,Yaw,VN,VE,VD,dPD,PN,PE,PD,GX,GY,GZ,OH");
  w.fmt(32, "RCOU", "QHHHHHHHHHHHHHH", "TimeUS,C1,C2,C3,C4,C5,C6,C7,C8,C9,C10,C11,C12,C13,C14");
  w.fmt(33, "EV", "QB", "TimeUS,Id");
  w.fmt(36, "RATE", "Qffffffffffff", "TimeUS,RDes,R,ROut,PDes,P,POut,YDes,Y,YOut,ADes,A,AOut");
  w.fmt(37, "MOTB", "QffffB", "TimeUS,LiftMax,BatVolt,ThLimit,ThrAvMx,FailFlags");
  w.parm(0, "FRAME_TYPE", 1);
  w.write(33, {100ull, 10});
  w.write(33, {200ull, 28});
  for (int k = 0; k < rows; ++k) {
    const unsigned long long t = 1000000ull + 2500ull * static_cast<unsigned long long>(k);
    const double yaw = 0.1 * k + (k >= 120 ? 5.0 : 0.0);
    w.write(30, {t, 0, centi(0.5), 0, centi(-0.5), 0, static_cast<long long>(std::lround(yaw * 100.0)), 0, 0, 3});
    w.write(36, {t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 40.0, 0.0, 0.0, 0.0, 0.0});
    w.write(31, {t, 0u, 0, 0, 0, 1.0, 0.0, 0.0, 0.0, 0.0025 * k, 0.0, k >= 160 ? -1.5 : -1.0, 0, 0, 0, 0});
    if (k % 10 == 0) {
      const double v = 1.0 - 0.2 * k / rows, lift = 0.35 * v + 0.65 * v * v;  // MOT_THST_EXPO 0.65
      w.write(37, {t, lift, k == 50 ? 12.6 : v, 1.0, 0.5, 0u});
    }
    w.write(32, {t, 1500, 1500, 1500, 1500, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  }
  return w;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: %s DIR [TEXT_DIR]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  if (argc == 3) text_dir = argv[2];
  save(dir, "copter-fmtu.bin", copter(4, true));
  save(dir, "copter-plain.bin", copter(3, false));
  save(dir, "copter-bf-x.bin", copter(3, true, 12));
  save(dir, "copter-ekf-status.bin", copter(4, false, 1, true));
  {
    // Finding 13: an XKF4 whose SS is a float no uint32 holds (−5, 1e12, NaN).
    DataflashWriter w = copter(3, false);
    w.fmt(35, "XKF4", "QBfff", "TimeUS,C,OFN,OFE,SS");
    for (unsigned core = 0; core < 2; ++core) {
      w.write(35, {1000000ull, core, 0.0, 0.0, -5.0});
      w.write(35, {1002500ull, core, 0.0, 0.0, 1e12});
      w.write(35, {1005000ull, core, 1.0, 1.0, std::nan("")});
    }
    w.write(33, {9800000ull, 18});  // last byte 18: the fuzz target reads EKF core 18 % 3 = 0
    save(dir, "regress-ekf-status-out-of-range.bin", w);
  }
  save(dir, "all-chars.bin", quadfdi::test::everyFormatCharacterLog());
  {
    DataflashWriter w = copter(2, true);  // garbage, an undefined type, a truncated tail
    w.raw({0x00, 0xA3, 0x95, 0x11, 0x42, 0x42});
    w.write(32, {5000000ull, 1500, 1500, 1500, 1500, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
    w.bytes.resize(w.bytes.size() - 7);
    save(dir, "damaged.bin", w.bytes);
  }
  save(dir, "fmt-only.bin", DataflashWriter(false));
  save(dir, "copter-unlogged-resets.bin", copterWithResets(240));
  return 0;
}
