// One-off generator of fuzz/corpus/ulog/ (small ULogs written with the test writer):
//   fuzz_make_ulog_seeds OUT_DIR
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "logs/ulog_writer.h"

using quadfdi::testing::UlogPayload;
using quadfdi::testing::UlogWriter;

namespace {

void save(const std::string& dir, const std::string& name, const std::vector<std::uint8_t>& b) {
  std::FILE* f = std::fopen((dir + "/" + name).c_str(), "wb");
  if (!f || std::fwrite(b.data(), 1, b.size(), f) != b.size() || std::fclose(f) != 0) std::perror(name.c_str());
}

// The PX4 topics the extractor reads, a few rows of each.
// With `geometry`, the control allocation's rotor table (PX4 ≥ 1.13), numbered clockwise from the
// front right rather than PX4's quad-X order, so the extractor maps the motors by it.
// With `resets`, the EKF2 validity flags and reset counters with their shifts (PX4 ≥ 1.10).
// With `battery`, MC_BAT_SCALE_EN 1 and battery_status rows (a scale rising from 1, one NaN, one
// disconnected) by which the extractor divides the commands.
UlogWriter px4Flight(bool motors, int rows, bool geometry = false, bool resets = false, bool battery = false) {
  UlogWriter w(1, 5000);
  w.flagBits();
  w.info("sys_name", "PX4");
  if (geometry) {
    w.paramInt("CA_AIRFRAME", 0);
    w.paramInt("CA_ROTOR_COUNT", 4);
    const float rotors[4][3] = {{0.1f, 0.1f, 0.05f}, {-0.1f, 0.1f, -0.05f}, {-0.1f, -0.1f, 0.05f}, {0.1f, -0.1f, -0.05f}};
    for (int i = 0; i < 4; ++i) {
      const std::string r = "CA_ROTOR" + std::to_string(i) + "_";
      w.paramFloat(r + "PX", rotors[i][0]).paramFloat(r + "PY", rotors[i][1]).paramFloat(r + "KM", rotors[i][2]);
    }
  }
  w.paramFloat("THR_MDL_FAC", 0.3f);
  w.paramInt("PWM_MAIN_MIN", 1000);
  w.paramInt("PWM_MAIN_MAX", 2000);
  if (battery) w.paramInt("MC_BAT_SCALE_EN", 1);
  quadfdi::testing::formatPx4Estimates(w, resets);
  w.format("actuator_motors:uint64_t timestamp;float[4] control;");
  w.format("actuator_outputs:uint64_t timestamp;uint32_t noutputs;float[4] output;");
  w.format("vehicle_status:uint64_t timestamp;uint8_t arming_state;");
  w.format("vehicle_land_detected:uint64_t timestamp;bool maybe_landed;bool landed;");
  w.subscribe(0, 0, "vehicle_local_position");
  w.subscribe(0, 1, "vehicle_attitude");
  w.subscribe(0, 2, motors ? "actuator_motors" : "actuator_outputs");
  w.subscribe(0, 3, "vehicle_status");
  w.subscribe(0, 4, "vehicle_land_detected");
  if (battery) {
    w.format("battery_status:uint64_t timestamp;float scale;bool connected;");
    w.subscribe(0, 5, "battery_status");
  }
  for (int i = 0; i < rows; ++i) {
    const std::uint64_t t = 1000000 + static_cast<std::uint64_t>(i) * 4000;
    const float a = 0.1f * static_cast<float>(i);
    if (resets) {
      // Counters: one step at row 2, two at row 4 (a break), a wrap 255 → 0 for the attitude;
      // row 1 flagged invalid; a non-finite shift at row 5.
      const std::uint8_t xy_counter = static_cast<std::uint8_t>(i < 2 ? 7 : i < 4 ? 8 : 10);
      const float shift = i == 5 ? NAN : 0.5f;
      w.data(0, UlogPayload().put(t).put(a).put(-a).put(-1.0f).put(shift).put(-shift).put(0.2f).put(i != 1).put(true)
                    .put(xy_counter).put<std::uint8_t>(static_cast<std::uint8_t>(i >= 5)));
      w.data(1, UlogPayload().put(t).put(std::cos(a)).put(0.0f).put(std::sin(a)).put(0.0f)
                    .put(std::cos(0.1f)).put(0.0f).put(0.0f).put(std::sin(0.1f))
                    .put<std::uint8_t>(static_cast<std::uint8_t>(i < 3 ? 255 : 0)));
    } else {
      w.data(0, UlogPayload().put(t).put(a).put(-a).put(-1.0f).put(true).pad(3));
      w.data(1, UlogPayload().put(t).put(std::cos(a)).put(0.0f).put(std::sin(a)).put(0.0f));
    }
    if (motors)
      w.data(2, UlogPayload().put(t).put(0.5f).put(0.6f).put(NAN).put(-0.1f));
    else
      w.data(2, UlogPayload().put(t).put<std::uint32_t>(4).put(1500.0f).put(900.0f).put(2100.0f).put(1200.0f));
    if (i % 2 == 0) w.data(3, UlogPayload().put(t).put<std::uint8_t>(static_cast<std::uint8_t>(1 + i % 3)));
    if (i % 3 == 0) w.data(4, UlogPayload().put(t).put(i % 2 == 0).put(i % 4 == 0));
    if (battery && i % 2 == 0) w.data(5, UlogPayload().put(t).put(i == 2 ? NAN : 1.0f + 0.05f * static_cast<float>(i)).put(i != 4));
  }
  return w;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  save(dir, "px4-actuator-motors.ulg", px4Flight(true, 6).bytes());
  save(dir, "px4-actuator-outputs.ulg", px4Flight(false, 6).bytes());
  save(dir, "px4-rotor-geometry.ulg", px4Flight(true, 6, true).bytes());
  save(dir, "px4-estimator-resets.ulg", px4Flight(true, 6, false, true).bytes());
  save(dir, "px4-battery-scaling.ulg", px4Flight(true, 8, false, false, true).bytes());
  {
    std::vector<std::uint8_t> b = px4Flight(true, 4).bytes();
    b.resize(b.size() - 7);
    save(dir, "truncated-last-message.ulg", b);
  }
  {
    UlogWriter w(2);
    w.flagBits(1, 0);
    w.format("pair:int8_t a;uint16_t b;");
    w.format("inner:pair[2] p;double d;");
    w.format("all:uint64_t timestamp;int8_t i8;uint8_t u8;int16_t i16;uint16_t u16;int32_t i32;uint32_t u32;"
             "int64_t i64;uint64_t u64;float f;double d;bool b;char[4] s;inner[2] nest;uint8_t[5] _padding0;");
    w.subscribe(0, 0, "all");
    w.subscribe(1, 1, "all");
    UlogPayload p;
    p.put<std::uint64_t>(10).put<std::int8_t>(-1).put<std::uint8_t>(2).put<std::int16_t>(-3).put<std::uint16_t>(4);
    p.put<std::int32_t>(-5).put<std::uint32_t>(6).put<std::int64_t>(-7).put<std::uint64_t>(8).put(9.5f).put(10.5);
    p.put(true).put('a').put('b').put('c').put('d');
    for (int i = 0; i < 2; ++i) p.put<std::int8_t>(1).put<std::uint16_t>(2).put<std::int8_t>(3).put<std::uint16_t>(4).put(5.0);
    w.data(0, p);
    w.data(1, p);
    save(dir, "nested-all-types.ulg", w.bytes());
  }
  {
    UlogWriter w(1);
    w.flagBits(1);
    w.format("t:uint64_t timestamp;float v;");
    w.info("ver_hw", "SITL");
    w.infoUInt32("ver_sw_release", 0x010e00ffu);
    w.multiInfo("perf", "part one ", false);
    w.multiInfo("perf", "part two", true);
    w.defaultParamFloat(3, "MPC_XY_P", 0.95f);
    w.subscribe(0, 0, "t");
    w.logging('6', 100, "hello");
    w.taggedLogging('3', 7, 200, "tagged");
    w.data(0, UlogPayload().put<std::uint64_t>(300).put(1.0f));
    w.dropout(50);
    w.paramInt("SDLOG_PROFILE", 3);
    w.message('Z', std::string("unknown type"));
    w.sync();
    w.unsubscribe(0);
    w.subscribe(0, 1, "t");
    w.data(1, UlogPayload().put<std::uint64_t>(400).put(2.0f));
    save(dir, "messages-params-info.ulg", w.bytes());
  }
  {
    UlogWriter w;
    w.format("t:uint64_t timestamp;float v;");
    w.subscribe(0, 0, "t");
    w.data(0, UlogPayload().put<std::uint64_t>(1).put(1.0f));
    w.data(9, UlogPayload().put<std::uint64_t>(2).put(2.0f));
    w.sync();
    w.data(0, UlogPayload().put<std::uint64_t>(3).put(3.0f));
    save(dir, "resync-after-unknown-msg-id.ulg", w.bytes());
  }
  {
    UlogWriter w(2);
    w.flagBits(0, 1, 0);
    w.format("t:uint64_t timestamp;float v;");
    w.subscribe(0, 0, "t");
    w.data(0, UlogPayload().put<std::uint64_t>(1).put(1.0f));
    std::vector<std::uint8_t> b = w.bytes();
    b.resize(b.size() - 3);
    const std::uint64_t at = b.size();
    for (int i = 0; i < 8; ++i) b[16 + 3 + 16 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(at >> (8 * i));
    UlogWriter tail;
    tail.data(0, UlogPayload().put<std::uint64_t>(2).put(2.0f));
    b.insert(b.end(), tail.bytes().begin() + 16, tail.bytes().end());
    save(dir, "appended-data.ulg", b);
  }
  {
    UlogWriter w;
    w.format("t:uint64_t timestamp;float v;");
    w.format("broken:uint64_t timestamp;float[x] v;");
    save(dir, "corrupt-format.ulg", w.bytes());
  }
  return 0;
}
