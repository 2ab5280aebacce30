// Reading flight telemetry (docs/conventions.md) for the detector: header names the columns (any order,
// extra columns ignored), one sample per row; cells separated by commas, or, where the header has
// none, by tabs, semicolons or runs of blanks (as the header is, every row is). A header name may
// carry its unit ("t [ms]", "roll (deg)"): read where it sets an option, checked everywhere else. Rows are read one at a time so a live pipe works.
// Attitude comes as ZYX Euler angles (roll, pitch, yaw) or, where those are absent, as a unit
// quaternion (qw, qx, qy, qz); body rates p, q, r (optional, read by models on scale-free-rates
// features) in rad/s or deg/s; position, attitude and rates in quadfdi's frames or in NED/FRD,
// which the reader turns into quadfdi's (core/frames.h).
#pragma once

#include <array>
#include <istream>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/frames.h"
#include "core/motor_numbering.h"
#include "core/sample_source.h"
#include "logs/quaternion_check.h"

namespace quadfdi {

// "NAME:LINE: problem" — bad input the reader cannot go past.
class TelemetryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a CSV's u1..u4 hold.
enum class CommandQuantity {
  kThrust,      // commanded thrust [N] (docs/conventions.md)
  kRotorSpeed,  // commanded rotor speed, any unit (rad/s, RPM, a fraction of the maximum): read as its square,
                // proportional to thrust for a fixed-pitch propeller (f = k_f·ω²) with k_f unknown
  kThrottle,    // the normalised motor command c ∈ [0, 1], what an ESC is asked for as a fraction of its range:
                // thrust from the vehicle's curve (CommandCurve)
  kPwm,         // the ESC's pulse width [µs]: c = (pwm − pwm_min) / (pwm_max − pwm_min), then the curve
};

// Motor command → thrust for kThrottle and kPwm, from a vehicle description's [thrust] table
// (docs/vehicles.md): f = max_thrust·((1 − k)·c + k·c²), thrustAtCommand (model/vehicle_params.h).
struct CommandCurve {
  double max_thrust = 0.0;    // [N] per motor at c = 1 (thrust.max)
  double model_factor = 0.0;  // [-] k in [0, 1] (thrust.model_factor; PX4's THR_MDL_FAC convention)
  // The pulse range: 1000–2000 µs is the common ESC calibration and both autopilots' default
  // (PX4 PWM_MAIN_MINn/MAXn, ArduPilot MOT_PWM_MIN/MAX taken from RC3 when 0).
  double pwm_min = 1000.0;  // [µs] the pulse at c = 0
  double pwm_max = 2000.0;  // [µs] the pulse at c = 1
};

// Seconds per unit of a time unit's name: s, ms, us (or µs), ns; 0 for any other name.
double secondsPerTimeUnit(const std::string& unit);

struct TelemetryReaderOptions {
  TelemetryFrame frame = TelemetryFrame::kZUp;            // of the position and attitude columns
  CommandQuantity commands = CommandQuantity::kThrust;  // of u1..u4
  CommandCurve curve;                                   // kThrottle and kPwm only
  // Header names of quadfdi's columns where the file names them otherwise, as {column, header
  // name}: a PlotJuggler export's "/mavros/local_position/pose/pose/position/x" read as x. A
  // header cell with quadfdi's own name is then not read for that column.
  std::vector<std::pair<std::string, std::string>> header_names;
  double time_unit = 1.0;  // [s] per unit of the t column: 1e-3 (ms), 1e-6 (µs), 1e-9 (ns, a ROS stamp)
  bool angles_in_degrees = false;  // roll, pitch, yaw in degrees (a quaternion has no unit)
  bool rates_in_degrees = false;   // p, q, r in degrees per second
  // false: p, q, r are extra columns, not read (for a model that does not need them, so that a
  // file's rate columns in another unit or with holes cost it nothing).
  bool read_rates = true;
  // The file's motor number m (its column u_m) of quadfdi's motor k + 1: a file written in an
  // autopilot's numbering (--csv-numbering vehicle) has the vehicle description's
  // autopilot_motor_of_quadfdi_motor here, and is read in quadfdi's order. A permutation of 1..4.
  std::array<int, kInputDim> file_motor{1, 2, 3, 4};
  // The axes quadfdi reads the airframe in (core/frames.h): a file in the airframe's own axes of a
  // plus or props-out frame (--csv-numbering vehicle) has the description's body_turn here, and its
  // attitude and body rates are read turned.
  BodyTurn body_turn;
  // How qw, qx, qy, qz are read (--csv-quaternion): the columns' order and the rotation's sense.
  QuaternionReading quaternion;
};

// One row of an export that merges signals sampled at different times (PlotJuggler, a ROS bag):
// each row holds some of the three signals, each converted as TelemetryReader::next converts a
// whole row (frames, quaternion, command quantity).
struct TelemetryRowParts {
  double t = 0.0;                     // [s]
  bool has_position = false;          // x, y, z all present
  bool has_attitude = false;          // roll, pitch, yaw (or qw..qz, non-zero) all present
  bool has_commands = false;          // u1..u4 all present
  std::array<bool, kInputDim> has_u{};  // each of u1..u4 present: a motor's command stands alone
  std::array<double, 3> position{};   // x, y, z [m], world, z up
  std::array<double, 3> attitude{};   // roll, pitch, yaw [rad], ZYX, body FLU
  std::array<double, kInputDim> u{};  // per motor, as TelemetrySample::u (those of has_u)
  bool has_rates = false;             // p, q, r all present (a header with them only)
  std::array<double, 3> rates{};      // p, q, r [rad/s], body FLU
  std::string dropped;  // "FILE:LINE: column 'y' is empty": position or attitude with some of its cells and not all, or
                        // a command cell NaN, infinite or absurd: left out
};

class TelemetryReader : public SampleSource {
 public:
  // Reads the header (blank lines and lines starting with '#' are skipped). Throws TelemetryError
  // for an empty input or a header without the required columns, std::invalid_argument for a
  // curve that maps no command to thrust (kThrottle, kPwm), a header name given for no column of
  // kColumns or twice, or a time unit that is not > 0.
  TelemetryReader(std::istream& in, std::string name, const TelemetryReaderOptions& options = {});

  using Row = SampleSource::Next;
  // kSample: `sample` holds the row; kSkipped: a NaN, infinite, empty or absurd (|v| > 1e9; t: over 1e13 is an error) cell,
  // `problem` says which, the row is dropped; kEnd.

  // Throws TelemetryError for a row that is not telemetry (wrong cell count, text in a number, an
  // angle or command out of range, a quaternion far from unit norm).
  Next next(TelemetrySample& sample, std::string& problem) override;
  // The next row of a merged export: kSample with the signals it holds (possibly none), kSkipped
  // when its t is empty or non-finite, kEnd. Throws as next() does.
  Next nextParts(TelemetryRowParts& parts, std::string& problem);
  std::string where() const override { return name_ + ":" + std::to_string(line_); }
  bool moreReady() const override;  // standard input: buffered or pollable data; files: always

  long line() const { return line_; }  // 1-based number of the last line read
  // The "# motor_numbering: NAME = A B C D" comment before the header (writeTelemetryCsvHeader),
  // if the file has one: the autopilot's numbers of quadfdi's motors 1..4.
  const std::optional<MotorNumbering>& numbering() const { return numbering_; }
  const std::string& name() const { return name_; }
  bool quaternionAttitude() const { return quaternion_; }  // read from qw, qx, qy, qz (no roll, pitch, yaw)
  bool carriesRates() const override { return rates_; }   // the header has p, q, r

  // t, x, y, z, roll, pitch, yaw, u1 … u4, then qw, qx, qy, qz (read instead of roll, pitch, yaw
  // when the header has none of those), then the optional body rates p, q, r.
  static constexpr int kColumnCount = 18;
  static const char* const kColumns[kColumnCount];

 private:
  bool readLine(std::string& text);
  void readNumberingComment(const std::string& comment);
  bool isRead(int column) const;  // index into kColumns: read with the header's attitude
  void readHeaderUnit(int column, const std::string& unit, bool& angle_unit_read);
  bool readCells(double (&values)[kColumnCount], bool (&present)[kColumnCount], std::string (&why)[kColumnCount]);
  std::string cellText(int column) const;  // of the row just read, cut at 40 characters
  bool attitudeOf(const double (&values)[kColumnCount], EulerZyx& attitude, std::string& problem) const;
  double commandOf(const double (&values)[kColumnCount], int column) const;  // column: kU1..kU1 + 3
  int commandColumn(std::size_t motor) const;  // index into kColumns of quadfdi motor + 1's command (options' file_motor)
  std::array<double, 3> positionOf(const double (&values)[kColumnCount]) const;
  std::array<double, 3> ratesOf(const double (&values)[kColumnCount]) const;  // [rad/s], body FLU
  EulerZyx inQuadfdisFrame(const EulerZyx& attitude) const;  // from the file's frame (options_.frame)
  const std::string& label(int column) const { return label_[static_cast<std::size_t>(column)]; }
  std::istream& in_;
  std::string name_;
  long line_ = 0;
  TelemetryReaderOptions options_;
  int cells_ = 0;                 // columns in the header
  char separator_ = ',';          // between cells, as the header has it (separatorOf)
  std::array<int, kColumnCount> column_{};  // cell index of each of kColumns; −1: absent
  std::array<std::string, kColumnCount> label_;  // how messages name each column: its name in the header
  bool quaternion_ = false;       // attitude from qw, qx, qy, qz
  bool rates_ = false;            // body rates from p, q, r
  bool rate_unit_read_ = false;   // a rate column's header named its unit
  std::vector<std::string> cells_buffer_;
  std::optional<MotorNumbering> numbering_;
  std::array<bool, kColumnCount> blank_{};  // of the row just read: which cells are empty (not NaN, not absurd)
};

}  // namespace quadfdi
