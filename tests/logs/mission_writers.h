// A simulated mission (sim_flights.h) written as each autopilot would log it, in its own frames,
// motor numbering, units and rates, with a slow position topic (header only):
//  * PX4 ULog: vehicle_attitude q (FRD → NED) at 250 Hz, vehicle_local_position NED at 50 Hz,
//    actuator_motors.control (thrust fractions of max_thrust, PX4 quad-X order) at 500 Hz,
//    vehicle_status (arming) and vehicle_land_detected (take-off/touchdown seen 0.3 s late).
//  * ArduPilot DataFlash: ATT Roll/Pitch/Yaw [cdeg, NED/FRD, yaw 0..360] at 400 Hz (interpolated
//    from the 500 Hz flight), RCOU PWM [µs] at 400 Hz (held) through MOT_* of the log with
//    ArduPilot's motor order, XKF1 PN/PE/PD at 25 Hz, EV ARMED/NOT_LANDED/LAND_COMPLETE/DISARMED.
//  * Crazyflie micro-SD: fixedFrequency at 500 Hz with stateEstimate.roll/pitch/yaw [deg, pitch
//    negated] and motor.m1..m4 [0..65535] through the firmware's duty → thrust map; position
//    stateEstimate.x/y/z in a separate event at 50 Hz; no armed/landed states. Or the compact
//    stateEstimateZ.quat (compressed quaternion) and stateEstimateZ.x/y/z [mm] in their place.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/frames.h"
#include "logs/ardupilot_signals.h"
#include "logs/crazyflie_signals.h"
#include "logs/crazyflie_usd_writer.h"
#include "logs/dataflash_writer.h"
#include "logs/sim_flights.h"
#include "logs/ulog_writer.h"

namespace quadfdi::test {

inline constexpr double kMissionPi = 3.14159265358979323846;
inline constexpr double kMissionMaxThrust = 0.15;  // [N] the simulated Crazyflie's motor maximum (nominalParams)

inline std::uint64_t micros(double t) { return static_cast<std::uint64_t>(std::llround(t * 1e6)); }

// The mission's outputs and body rates linearly interpolated at t (angles the short way), commands held.
inline TelemetrySample missionAt(const Mission& m, double t) {
  const auto k = static_cast<std::size_t>(std::floor(t / m.dt + 1e-9));
  const std::size_t a = std::min(k, m.samples.size() - 1), b = std::min(a + 1, m.samples.size() - 1);
  const double w = b == a ? 0.0 : (t - m.samples[a].t) / (m.samples[b].t - m.samples[a].t);
  TelemetrySample s = m.samples[a];
  s.t = t;
  for (std::size_t i = 0; i < 6; ++i) {
    double d = m.samples[b].y[i] - m.samples[a].y[i];
    if (i >= 3) d = std::remainder(d, 2.0 * kMissionPi);
    s.y[i] = m.samples[a].y[i] + w * d;
  }
  for (std::size_t i = 0; i < 3; ++i) s.rates[i] = m.samples[a].rates[i] + w * (m.samples[b].rates[i] - m.samples[a].rates[i]);
  return s;
}

// ---------- PX4 ----------
// quadfdi (roll, pitch, yaw) = PX4 (φ, −θ, −ψ); q = Rz(ψ)·Ry(θ)·Rx(φ) FRD → NED.
inline Quaternion px4QuatFromQuadfdi(double roll, double pitch, double yaw) {
  const double phi = roll, theta = -pitch, psi = -yaw;
  const Quaternion qz{std::cos(psi / 2), 0, 0, std::sin(psi / 2)};
  const Quaternion qy{std::cos(theta / 2), 0, std::sin(theta / 2), 0};
  const Quaternion qx{std::cos(phi / 2), std::sin(phi / 2), 0, 0};
  return qz * qy * qx;
}

struct Px4LogOptions {
  int attitude_every = 2;   // [samples] 250 Hz
  int position_every = 10;  // [samples] 50 Hz
  int motors_every = 1;     // [samples] 500 Hz
  bool with_states = true;
  // An EKF2 reset in flight (GPS regained, a heading source switched): from reset_at on the
  // logged position is shifted by reset_shift and the attitude turned by reset_yaw about down.
  // With log_reset_shifts the shifts are logged with their counters, as PX4 logs them
  // (delta_xy, delta_z, delta_q_reset); without, only the jump (fields of PX4 < 1.10 layout).
  double reset_at = -1.0;                                // [s] no reset when < 0
  std::array<double, 3> reset_shift = {3.0, -2.0, 0.5};  // [m] NED
  double reset_yaw = 0.35;                               // [rad] about NED down
  bool log_reset_shifts = true;
  bool with_rates = false;  // vehicle_angular_velocity.xyz [rad/s, FRD] with the attitude
};

inline std::vector<std::uint8_t> writePx4Mission(const Mission& m, const Px4LogOptions& o = {}) {
  testing::UlogWriter w;
  const bool resets = o.reset_at >= 0.0 && o.log_reset_shifts;
  testing::formatPx4Estimates(w, resets);
  const Quaternion yaw_reset{std::cos(o.reset_yaw / 2), 0, 0, std::sin(o.reset_yaw / 2)};
  w.format("actuator_motors:uint64_t timestamp;uint64_t timestamp_sample;uint16_t reversible_flags;float[12] control;");
  w.format("vehicle_status:uint64_t timestamp;uint8_t arming_state;");
  w.format("vehicle_land_detected:uint64_t timestamp;bool maybe_landed;bool landed;");
  w.subscribe(0, 0, "vehicle_local_position");
  w.subscribe(0, 1, "vehicle_attitude");
  w.subscribe(0, 2, "actuator_motors");
  w.subscribe(0, 4, "vehicle_status");
  w.subscribe(0, 5, "vehicle_land_detected");
  if (o.with_rates) {
    w.format("vehicle_angular_velocity:uint64_t timestamp;uint64_t timestamp_sample;float[3] xyz;");
    w.subscribe(0, 6, "vehicle_angular_velocity");
  }
  const std::array<int, 4> px4_index = {0, 3, 1, 2};  // PX4 motor (0-based) of quadfdi motor k
  bool armed = false, landed = true, status_written = false;
  const double takeoff_seen = m.takeoff_at + 0.3, landing_seen = m.landed_at + 0.3;
  for (std::size_t i = 0; i < m.samples.size(); ++i) {
    const TelemetrySample& s = m.samples[i];
    const std::uint64_t t = micros(s.t);
    if (o.with_states) {
      const bool now_armed = s.t >= m.armed_at && !(m.landed_at >= 0 && s.t >= landing_seen + 0.5);
      if (!status_written || now_armed != armed) {
        w.data(4, testing::UlogPayload().put(t).put<std::uint8_t>(now_armed ? 2 : 1));
        armed = now_armed;
      }
      const bool now_landed = s.t < takeoff_seen || (m.landed_at >= 0 && s.t >= landing_seen);
      if (!status_written || now_landed != landed) {
        w.data(5, testing::UlogPayload().put(t).put(now_landed).put(now_landed));
        landed = now_landed;
      }
      status_written = true;
    }
    const bool reset = o.reset_at >= 0.0 && s.t >= o.reset_at;
    if (i % static_cast<std::size_t>(o.position_every) == 0) {
      std::array<double, 3> ned = {s.y[0], -s.y[1], -s.y[2]};
      for (std::size_t k = 0; k < 3; ++k) ned[k] += reset ? o.reset_shift[k] : 0.0;
      testing::UlogPayload p;
      p.put(t).put(static_cast<float>(ned[0])).put(static_cast<float>(ned[1])).put(static_cast<float>(ned[2]));
      if (resets) {
        const auto counter = static_cast<std::uint8_t>(reset ? 1 : 0);
        p.put(static_cast<float>(o.reset_shift[0])).put(static_cast<float>(o.reset_shift[1])).put(static_cast<float>(o.reset_shift[2]));
        p.put(true).put(true).put(counter).put(counter);
      } else {
        p.put(true);
      }
      w.data(0, p);
    }
    if (i % static_cast<std::size_t>(o.attitude_every) == 0) {
      Quaternion q = px4QuatFromQuadfdi(s.y[3], s.y[4], s.y[5]);
      if (reset) q = yaw_reset * q;
      testing::UlogPayload p;
      p.put(t).put(static_cast<float>(q.w)).put(static_cast<float>(q.x)).put(static_cast<float>(q.y)).put(static_cast<float>(q.z));
      if (resets) {
        for (double v : {yaw_reset.w, yaw_reset.x, yaw_reset.y, yaw_reset.z}) p.put(static_cast<float>(v));
        p.put(static_cast<std::uint8_t>(reset ? 1 : 0));
      }
      w.data(1, p);
      if (o.with_rates)  // FLU → FRD: (p, −q, −r)
        w.data(6, testing::UlogPayload().put(t).put(t).put(static_cast<float>(s.rates[0])).put(static_cast<float>(-s.rates[1])).put(
                      static_cast<float>(-s.rates[2])));
    }
    if (i % static_cast<std::size_t>(o.motors_every) == 0) {
      std::array<float, 12> control;
      control.fill(NAN);
      for (std::size_t k = 0; k < 4; ++k)
        control[static_cast<std::size_t>(px4_index[k])] = s.t >= m.armed_at ? static_cast<float>(s.u[k] / kMissionMaxThrust) : NAN;
      testing::UlogPayload p;
      p.put(t).put(t).put<std::uint16_t>(0);
      for (float c : control) p.put(c);
      w.data(2, p);
    }
  }
  return w.bytes();
}

// ---------- ArduPilot ----------
inline constexpr std::uint8_t kApAtt = 30, kApXkf1 = 31, kApRcou = 32, kApEv = 33, kApRate = 34, kApImu = 35, kApMotb = 36;

// The body rates an ArduPilot log holds: none; RATE R, P, Y [deg/s, FRD] with ATT, as
// AC_AttitudeControl::Write_Rate logs them; or no RATE but IMU GyrX, GyrY, GyrZ [rad/s, FRD] of two
// IMUs (instance field I), the second's off by 5 rad/s so that reading it shows.
enum class ApRates { kNone, kRate, kImu };
// The writer holds the log as binary (`bytes`, the .BIN) and as text (`text`, Mission Planner's .log).
// `frame_type`: FRAME_TYPE 1 (X), 3 (H: the X's positions, every spin reversed) or 0 (PLUS). The
// mission flew the standard X; an H is that X seen from axes turned −90°, a PLUS from axes turned
// +45° (docs/vehicles.md), so its ATT and RATE are written in those axes and its outputs in its
// own numbering (AP_MotorsMatrix::setup_quad_matrix, worked out by hand for the test).
struct ApFrame {
  int frame_type;
  int eighths;                // the turn the reader must find
  std::array<int, 4> motor;   // ArduPilot motor at quadfdi motor 1..4 of the turned axes
};
inline constexpr ApFrame kApX{1, 0, {1, 4, 2, 3}};
inline constexpr ApFrame kApH{3, 2, {3, 1, 4, 2}};
inline constexpr ApFrame kApPlus{0, -1, {1, 4, 2, 3}};
// EKF resets ArduPilot does not log with their shift: a heading reset (EKF3's in-flight yaw
// alignment, a compass switch), after which ATT's Yaw is `heading_degrees` more (clockwise), and a
// height reset (EKF3 ResetHeight, a change of height source), after which XKF1's PD is
// `height_metres` less (the vehicle higher), and a horizontal one as a log without XKF4's OFN, OFE
// would hold it. Neither the gyro nor the EKF's velocity shows them.
struct ApResets {
  double heading_at = -1.0;      // [s] (< 0: none)
  double heading_degrees = 0.0;  // [deg] added to ATT.Yaw
  double height_at = -1.0;       // [s] (< 0: none)
  double height_metres = 0.0;    // [m] taken from XKF1.PD
  double north_at = -1.0;        // [s] (< 0: none) a horizontal reset, in a log without XKF4 OFN, OFE
  double north_metres = 0.0;     // [m] added to XKF1.PN
};
// A battery draining while ArduPilot compensates for it (MOT_BAT_VOLT_MAX set): its voltage ratio v
// falls linearly from `from` to `to` over the log, every throttle is divided by it
// (ArdupilotThrustMap::pwmFor), and MOTB logs it at 10 Hz where `logged` (LOG_BITMASK bit 17).
struct ApBattery {
  double from = 1.0;    // [-] v at t = 0
  double to = 1.0;      // [-] v at the log's end
  bool logged = true;   // MOTB written (only when v moves)
};
inline DataflashWriter ardupilotMissionLog(const Mission& m, double loop_hz = 400.0, double ekf_hz = 25.0,
                                           ApRates rates = ApRates::kNone, const ApFrame& frame = kApX,
                                           const ApResets& reset = {}, const ApBattery& battery = {}) {
  DataflashWriter w;
  w.fmt(kApAtt, "ATT", "QccccCCCCB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
  w.fmt(kApXkf1, "XKF1", "QBccCfffffffccce", "TimeUS,C,Roll,Pitch,Yaw,VN,VE,VD,dPD,PN,PE,PD,GX,GY,GZ,OH");
  w.fmt(kApRcou, "RCOU", "QHHHHHHHHHHHHHH", "TimeUS,C1,C2,C3,C4,C5,C6,C7,C8,C9,C10,C11,C12,C13,C14");
  w.fmt(kApEv, "EV", "QB", "TimeUS,Id");
  if (rates == ApRates::kRate) w.fmt(kApRate, "RATE", "Qffffffffffff", "TimeUS,RDes,R,ROut,PDes,P,POut,YDes,Y,YOut,ADes,A,AOut");
  if (rates == ApRates::kImu)
    w.fmt(kApImu, "IMU", "QBffffffIIfBBHH", "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz");
  const bool motb = battery.logged && (battery.from != 1.0 || battery.to != 1.0);
  if (motb) w.fmt(kApMotb, "MOTB", "QffffB", "TimeUS,LiftMax,BatVolt,ThLimit,ThrAvMx,FailFlags");
  w.unit(0, '#', "instance");
  w.fmtu(0, kApXkf1, "s#ddhnnnnmmmkkkm", "F-BBB0000000BBBB");
  ArdupilotThrustMap map;  // MOT_PWM_MIN/MAX 1000/2000, SPIN 0.15/0.95, EXPO 0.65
  w.parm(0, "FRAME_CLASS", 1);
  w.parm(0, "FRAME_TYPE", frame.frame_type);
  w.parm(0, "MOT_PWM_MIN", map.pwm_min);
  w.parm(0, "MOT_PWM_MAX", map.pwm_max);
  w.parm(0, "MOT_SPIN_MIN", map.spin_min);
  w.parm(0, "MOT_SPIN_MAX", map.spin_max);
  w.parm(0, "MOT_THST_EXPO", map.expo);
  // The X: quadfdi 1 FR, 2 BR, 3 BL, 4 FL = ArduPilot motors 1, 4, 2, 3 → AP motor n on output n.
  const std::array<int, 4> ap_motor = frame.motor;
  const BodyTurn own_axes{-frame.eighths};  // from the mission's X axes to the airframe's
  const double end = m.samples.back().t;
  const double loop = 1.0 / loop_hz, ekf = 1.0 / ekf_hz;
  std::vector<std::pair<double, int>> events = {{m.armed_at, 10}, {m.takeoff_at + 0.3, 28}};
  if (m.landed_at >= 0) {
    events.push_back({m.landed_at + 0.3, 18});
    events.push_back({m.landed_at + 0.8, 11});
  }
  std::size_t next_event = 0;
  long e = 0;
  for (long n = 0;; ++n) {
    const double t = static_cast<double>(n) * loop;
    if (t > end + 1e-9) break;
    while (next_event < events.size() && events[next_event].first <= t) {
      w.write(kApEv, {micros(events[next_event].first), events[next_event].second});
      ++next_event;
    }
    TelemetrySample s = missionAt(m, t);
    const EulerZyx own = attitudeOfTurnedAxes({s.y[3], s.y[4], s.y[5]}, own_axes);
    s.y[3] = own.roll;
    s.y[4] = own.pitch;
    s.y[5] = own.yaw;
    s.rates = bodyVectorInTurnedAxes(s.rates, own_axes);
    double yaw_deg = -s.y[5] * 180.0 / kMissionPi + (reset.heading_at >= 0.0 && t >= reset.heading_at ? reset.heading_degrees : 0.0);
    yaw_deg = std::fmod(std::fmod(yaw_deg, 360.0) + 360.0, 360.0);
    w.write(kApAtt, {micros(t), 0, centi(s.y[3] * 180.0 / kMissionPi), 0, centi(-s.y[4] * 180.0 / kMissionPi), 0,
                     static_cast<long long>(std::llround(yaw_deg * 100.0)) % 36000, 0, 0, 3});
    if (rates == ApRates::kRate) {
      const double deg = 180.0 / kMissionPi;
      w.write(kApRate, {micros(t), 0.0, s.rates[0] * deg, 0.0, 0.0, -s.rates[1] * deg, 0.0, 0.0, -s.rates[2] * deg, 0.0, 0.0, 0.0, 0.0});
    }
    if (rates == ApRates::kImu)
      for (int instance = 0; instance < 2; ++instance) {
        const double off = 5.0 * instance;
        w.write(kApImu, {micros(t), instance, s.rates[0] + off, -s.rates[1] + off, -s.rates[2] + off, 0.0, 0.0, -9.81, 0, 0, 25.0,
                         1, 1, 400, 400});
      }
    // The battery's ratio, held over each MOTB interval (0.1 s) as ArduPilot's 0.5 Hz filter nearly holds it.
    const long motb_every = std::max(1L, std::lround(loop_hz / 10.0));
    const double ratio = battery.from + (battery.to - battery.from) * (static_cast<double>(n - n % motb_every) * loop) / end;
    if (motb && n % motb_every == 0)
      w.write(kApMotb, {micros(t), ratio * (1.0 - map.expo) + map.expo * ratio * ratio, ratio, 1.0, 0.5, 0u});
    std::array<int, 14> pwm{};
    for (std::size_t k = 0; k < 4; ++k)
      pwm[static_cast<std::size_t>(ap_motor[k] - 1)] =
          static_cast<int>(std::lround(s.t >= m.armed_at ? map.pwmFor(s.u[k] / kMissionMaxThrust, ratio) : map.pwm_min));
    w.write(kApRcou, {micros(t), pwm[0], pwm[1], pwm[2], pwm[3], 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
    while (static_cast<double>(e) * ekf <= t + 1e-9) {
      const double te = static_cast<double>(e) * ekf;
      const TelemetrySample p = missionAt(m, te);
      // The EKF's velocity: the flight's own, by central differences over ±1 ms (one-sided at the ends).
      const double h = 0.001, before = std::max(0.0, te - h), after = std::min(end, te + h);
      const TelemetrySample p0 = missionAt(m, before), p1 = missionAt(m, after);
      std::array<double, 3> v{};
      for (std::size_t i = 0; i < 3; ++i) v[i] = after > before ? (p1.y[i] - p0.y[i]) / (after - before) : 0.0;
      const double up = reset.height_at >= 0.0 && te >= reset.height_at ? reset.height_metres : 0.0;
      const double north = reset.north_at >= 0.0 && te >= reset.north_at ? reset.north_metres : 0.0;
      w.write(kApXkf1, {micros(te), 0u, 0, 0, 0, v[0], -v[1], -v[2], 0.0, p.y[0] + north, -p.y[1], -p.y[2] - up, 0, 0, 0, 0});
      ++e;
    }
  }
  return w;
}

inline std::vector<std::uint8_t> writeArdupilotMission(const Mission& m, double loop_hz = 400.0, double ekf_hz = 25.0,
                                                      ApRates rates = ApRates::kNone, const ApFrame& frame = kApX,
                                                      const ApResets& reset = {}, const ApBattery& battery = {}) {
  return ardupilotMissionLog(m, loop_hz, ekf_hz, rates, frame, reset, battery).bytes;
}

// ---------- Crazyflie ----------
// `compressed`: the firmware's compact group instead, stateEstimateZ.quat (the attitude in 32 bits)
// and stateEstimateZ.x/y/z (int16 millimetres), as a bandwidth-minded config.txt logs them.
// `rates`: gyro.x/y/z [deg/s, body FLU] in the fixed-frequency event.
inline std::vector<std::uint8_t> writeCrazyflieMission(const Mission& m, int position_every = 10,
                                                       bool compressed = false, bool rates = false) {
  UsdEventType fixed;
  if (compressed)
    fixed.variables = {{"stateEstimateZ.quat", 'I'}};
  else
    fixed.variables = {{"stateEstimate.roll", 'f'}, {"stateEstimate.pitch", 'f'}, {"stateEstimate.yaw", 'f'}};
  for (const char* motor : {"motor.m1", "motor.m2", "motor.m3", "motor.m4"}) fixed.variables.push_back({motor, 'I'});
  if (rates)
    for (const char* gyro : {"gyro.x", "gyro.y", "gyro.z"}) fixed.variables.push_back({gyro, 'f'});
  UsdEventType pos;
  pos.id = 1;
  pos.name = "estPosition";
  if (compressed)
    pos.variables = {{"stateEstimateZ.x", 'h'}, {"stateEstimateZ.y", 'h'}, {"stateEstimateZ.z", 'h'}};
  else
    pos.variables = {{"stateEstimate.x", 'f'}, {"stateEstimate.y", 'f'}, {"stateEstimate.z", 'f'}};
  UsdWriter w(2, {fixed, pos});
  const CrazyflieSignalOptions cf;  // the firmware's quadratic duty map
  for (std::size_t i = 0; i < m.samples.size(); ++i) {
    const TelemetrySample& s = m.samples[i];
    std::vector<double> row;
    if (compressed)
      row = {static_cast<double>(usdCompressQuaternion(usdQuaternionOfEuler(s.y[3], s.y[4], s.y[5])))};
    else
      row = {s.y[3] * 180.0 / kMissionPi, -s.y[4] * 180.0 / kMissionPi, s.y[5] * 180.0 / kMissionPi};
    for (std::size_t k = 0; k < 4; ++k) {
      const double f = std::max(s.u[k], 0.0);
      const double r = (-cf.duty_b + std::sqrt(cf.duty_b * cf.duty_b + 4.0 * cf.duty_a * f)) / (2.0 * cf.duty_a);
      row.push_back(std::round(std::clamp(r, 0.0, 1.0) * cf.command_full_scale));
    }
    if (rates)
      for (double rate : s.rates) row.push_back(rate * 180.0 / kMissionPi);
    w.record(0, micros(s.t), row);
    if (i % static_cast<std::size_t>(position_every) != 0) continue;
    if (compressed)
      w.record(1, micros(s.t) + 1, {std::round(s.y[0] * 1e3), std::round(s.y[1] * 1e3), std::round(s.y[2] * 1e3)});
    else
      w.record(1, micros(s.t) + 1, {s.y[0], s.y[1], s.y[2]});
  }
  return w.closed();
}

}  // namespace quadfdi::test
