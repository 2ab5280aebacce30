// Vehicle description files (docs/vehicles.md): a user's own symmetric quad — an X, a props-out X
// or a plus frame, the last two read as the X in turned body axes (core/quad_layout.h) — mass, inertia,
// the four rotors in the autopilot's motor numbering, thrust curve, yaw-moment coefficient,
// motor lag and sources — turned into VehicleParams plus the motor renumbering, or refused with
// one line "FILE:LINE: problem" when it breaks the symmetry the fault isolation relies on.
//
// Frame of the file: body FRD (x forward, y right, z down), as in the PX4 and ArduPilot airframe
// references; spins "cw"/"ccw" as seen from above. quadfdi's internal frame is FLU (y left), so
// y_quadfdi = −y_file; its motors are 1 front-right, 2 back-right, 3 back-left, 4 front-left with
// 1 and 3 spinning counter-clockwise seen from above (src/model/dynamics.h kYawSign).
#pragma once

#include <array>
#include <string>

#include "core/frames.h"
#include "io/file_bytes.h"
#include "model/vehicle_params.h"

namespace quadfdi {

struct RotorDescription {
  double x = 0.0;  // [m] forward of the centre of mass (FRD, as written in the file)
  double y = 0.0;  // [m] right of the centre of mass (FRD, as written in the file)
  bool ccw = false;  // [-] spins counter-clockwise seen from above
};

struct VehicleDescription {
  std::string name;
  std::string source;           // the file's `source` summary (citations)
  std::string motor_numbering;  // whose numbering the [motor.N] sections use, e.g. "PX4 quad X"
  std::array<RotorDescription, 4> rotors{};  // indexed by autopilot motor − 1, as written
  // quadfdi motor (1..4) of autopilot motor i + 1, and the inverse.
  std::array<int, 4> quadfdi_motor_of_autopilot_motor{};
  std::array<int, 4> autopilot_motor_of_quadfdi_motor{};
  // The axes quadfdi reads the airframe in: none for a standard X, 90° for a props-out X, ±45° for
  // a plus frame (core/quad_layout.h). `params` and quadfdi's motor numbers are in these axes.
  BodyTurn body_turn;
  VehicleParams params;  // rotor_x, rotor_y symmetrised (mean |x|, mean |y|), yaw_moment_coeff set
};

// Relative tolerance on |x|, |y| of the rotors and on the centre-of-mass offset (fraction of the
// mean |x| or |y|): 2 %, about the build tolerance of a hobby frame.
inline constexpr double kRotorPositionTolerance = 0.02;  // [-]

// Parses and checks a description; throws ConfigError("SOURCE:LINE: problem").
VehicleDescription vehicleDescriptionFromText(const std::string& text, const std::string& source);
// Reads `path` (a pipe only with PipeReading::kRead: a caller that reads it once in a run).
VehicleDescription loadVehicleDescription(const std::string& path, PipeReading pipes = PipeReading::kRefuse);
// The file form (round-trips through vehicleDescriptionFromText).
std::string vehicleDescriptionToText(const VehicleDescription& description);
// True when the text is a description (it has [motor.N] sections) rather than a parameter file.
bool looksLikeVehicleDescription(const std::string& text);

}  // namespace quadfdi
