// Telemetry CSV (docs/conventions.md): header t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4; SI units, the
// conventions of model/state.h; u_i is the commanded thrust [N] (before the fault).
#pragma once

#include <ostream>

#include "core/motor_numbering.h"
#include "core/types.h"
#include "simulation/closed_loop.h"

namespace quadfdi {

struct TelemetryCsvOptions {
  double dt = 0.002;        // [s] sample period; t = k·dt
  bool full_state = false;  // append vx,vy,vz (body) [m/s], p,q,r [rad/s], f1..f4 applied thrust [N], status
  bool rates = false;       // append p,q,r [rad/s] alone (implied by full_state)
};

// Writes the header and one row per logged step. Numbers use the shortest text that
// reads back to the same double. p,q,r are the logged rates (FlightLog::rates, gyro noise and
// all, as the attitude columns carry the attitude noise), the true ones where none were logged.
void writeTelemetryCsv(std::ostream& out, const FlightLog& log, const TelemetryCsvOptions& options);

// The same columns one sample at a time (converted flight logs, `quadfdi import`): the header
// t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4, then one row per sample, numbers as above.
// With `numbering` other than quadfdi's own, a comment line before the header records the
// autopilot's number of each column's motor, "# motor_numbering: PX4 = 1 4 2 3" (u1..u4 stay in
// quadfdi's order), which `detect` reads back to name motors as the pilot's autopilot does.
// With `rates`, the body rates follow as columns p,q,r [rad/s] (a log that records them).
void writeTelemetryCsvHeader(std::ostream& out, const MotorNumbering& numbering = {}, bool rates = false);
void writeTelemetryCsvRow(std::ostream& out, const TelemetrySample& sample, bool rates = false);

}  // namespace quadfdi
