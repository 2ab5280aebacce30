#include "io/telemetry_csv.h"

#include <array>
#include <charconv>

namespace quadfdi {
namespace {

void put(std::ostream& out, double v) {
  std::array<char, 32> buf;
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  out.write(buf.data(), res.ptr - buf.data());
}

}  // namespace

void writeTelemetryCsvHeader(std::ostream& out, const MotorNumbering& numbering, bool rates) {
  if (!numbering.isQuadfdis()) {
    out << "# motor_numbering: " << numbering.name << " =";
    for (int m : numbering.autopilot_motor) out << ' ' << m;
    // A plus or props-out frame: the rows are in its turned axes; where each motor sits follows from the turn.
    if (!numbering.body_turn.none()) out << " turned " << 45 * numbering.body_turn.eighths;
    out << '\n';
  }
  out << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4" << (rates ? ",p,q,r\n" : "\n");
}

void writeTelemetryCsvRow(std::ostream& out, const TelemetrySample& s, bool rates) {
  put(out, s.t);
  for (double v : s.y) { out << ','; put(out, v); }
  for (double v : s.u) { out << ','; put(out, v); }
  if (rates)
    for (double v : s.rates) { out << ','; put(out, v); }
  out << '\n';
}

void writeTelemetryCsv(std::ostream& out, const FlightLog& log, const TelemetryCsvOptions& options) {
  out << "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4";
  if (options.full_state) out << ",vx,vy,vz,p,q,r,f1,f2,f3,f4,status";
  else if (options.rates) out << ",p,q,r";
  out << '\n';
  const bool logged_rates = log.rates.size() == log.states.size();
  for (int k = 0; k < log.size(); ++k) {
    const auto ku = static_cast<std::size_t>(k);
    const Vec3 rates = logged_rates ? log.rates[ku] : Vec3(log.states[ku].segment<3>(idx::kRate));
    put(out, k * options.dt);
    const Output& y = log.outputs[ku];
    for (int i = 0; i < kOutputDim; ++i) { out << ','; put(out, y(i)); }
    const Input& u = log.controls[ku].u_cmd;
    for (int i = 0; i < kInputDim; ++i) { out << ','; put(out, u(i)); }
    if (options.full_state) {
      const State& x = log.states[ku];
      for (int i = idx::kVel; i < idx::kVel + 3; ++i) { out << ','; put(out, x(i)); }
      for (int i = 0; i < 3; ++i) { out << ','; put(out, rates(i)); }
      const Input& f = log.applied[ku];
      for (int i = 0; i < kInputDim; ++i) { out << ','; put(out, f(i)); }
      out << ',' << toString(log.controls[ku].status);
    } else if (options.rates) {
      for (int i = 0; i < 3; ++i) { out << ','; put(out, rates(i)); }
    }
    out << '\n';
  }
}

}  // namespace quadfdi
