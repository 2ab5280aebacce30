// Is a telemetry file's attitude quaternion read as its writer meant it? (no I/O)
//
// A quaternion's four columns carry two conventions no header states: the order of its
// components (Hamilton scalar first, w x y z, as quadfdi reads it, or scalar last, x y z w, as
// Eigen's coeffs(), ROS messages and SciPy's as_quat() hold them) and the rotation it stands for
// (body → world, as PX4, ArduPilot and the Crazyflie log it, or world → body, its inverse, as some
// estimators and JPL-convention filters keep it). Either mistake reads as a unit quaternion of a
// plausible attitude, and the detector then reads a flight that did not happen. The flight tells
// them apart: a multirotor accelerates where its thrust leans (its body z axis; g·tilt holds its
// height), and its gyro measures the attitude's own turn. Each of the four readings of the
// columns is scored by how the position's horizontal acceleration follows its tilt (either way up:
// a frame read upside down is the motor-numbering check's to name) and, where the file has
// p,q,r, by whether the rates follow its turn in their own order (logs/rate_agreement.h).
// Docs: docs/conventions.md#attitude-as-a-quaternion.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "core/frames.h"
#include "logs/flight_signals.h"
#include "logs/rate_agreement.h"

namespace quadfdi {

// How four columns (qw, qx, qy, qz as the header names them) are read as the attitude.
struct QuaternionReading {
  bool scalar_last = false;    // the columns hold x, y, z, w (else w, x, y, z)
  bool world_to_body = false;  // the quaternion rotates world → body (else body → world)
  bool operator==(const QuaternionReading& o) const { return scalar_last == o.scalar_last && world_to_body == o.world_to_body; }
  bool operator!=(const QuaternionReading& o) const { return !(*this == o); }
  std::string name() const;     // "w,x,y,z body → world"
  std::string options() const;  // the detect options that read it ("--csv-quaternion xyzw-world-to-body")
};
// The four, in the order QuaternionCheck's arrays hold them.
inline constexpr std::array<QuaternionReading, 4> kQuaternionReadings{{{false, false}, {false, true}, {true, false}, {true, true}}};
std::size_t indexOf(const QuaternionReading& reading);

// The body → world rotation four columns (c0..c3 in the header's qw, qx, qy, qz places) stand for
// when read as `reading` (not normalised), and back: columnsOfQuaternion(quaternionOfColumns(c, r), r) == c.
Quaternion quaternionOfColumns(const std::array<double, 4>& c, const QuaternionReading& reading);
std::array<double, 4> columnsOfQuaternion(const Quaternion& q, const QuaternionReading& reading);

struct QuaternionCheckOptions {
  double node_interval = 0.02;      // [s] the flight is taken on this grid (position linear, attitude the nearest row)
  double max_gap = 0.1;             // [s] rows further apart break the grid (a hole); the filters start again after it
  // [s] the position's second difference over ± this (its noise ÷ span²): on randomised flights
  // (estimator noise on the position) the right reading's tilt fit rose from 0.02–0.07 over ±0.1 s
  // to a median of 0.60 over ±0.5 s; longer spans gained little and let wrong readings fit more
  // often (docs/conventions.md#attitude-as-a-quaternion).
  double acceleration_span = 0.5;
  double trend_seconds = 2.0;       // [s] acceleration and tilt are high-passed alike: wind and a centre of mass off the
                                    // middle lean the vehicle for seconds without accelerating it (the numbering check's 2 s)
  double min_seconds = 5.0;         // [s] of grid after the filters' start-up; less checks nothing
  double min_fit = 0.3;             // [-] a reading's tilt fit shows it where |fit| ≥ this
  // [m/s²] and only where each axis's acceleration per unit of tilt lies within these: g without
  // drag; on 2 000 randomised flights read right (both axes fitting ≥ 0.5) its median was 6.9, 1 %
  // below 1.9 and 1 % above 12.5 (drag, and noise in the tilt, shrink it).
  double min_slope = 2.0;
  double max_slope = 15.0;
  // Another reading is named from the tilt alone where it fits this much better than the one read,
  // and the one read agrees where every other fits this much worse. Two things keep readings close:
  // at a steady heading ψ the inverse quaternion's tilt fits |cos ψ| as well as the right one (its
  // tilt is the body's, not the world's), and on noisy flights a wrong reading's axis can follow by
  // chance: with 0.3, 1 of 2 000 randomised flights read right was named another reading; with 0.5
  // and the slope band, none (docs/conventions.md#attitude-as-a-quaternion).
  double min_margin = 0.5;          // [-]
};

enum class QuaternionVerdict {
  kNotChecked,    // no quaternion columns, or too little flight on the grid
  kAgrees,        // the reading used fits: its rates in order, or (without) its tilt, every other reading's clearly worse
  kOtherReading,  // another reading fits clearly better: named
  kUnclear,       // none fits clearly, or another fits alike (the inverse at a steady heading near north, without rates)
};

const char* toString(QuaternionVerdict v);  // "agrees", "another reading", "unclear", "not checked" (the summary's)

struct QuaternionCheck {
  QuaternionVerdict verdict = QuaternionVerdict::kNotChecked;
  QuaternionReading read;              // the reading used
  QuaternionReading best;              // the one that fits best (= read unless kOtherReading)
  double seconds = 0.0;                // [s] of grid compared (tilt)
  double min_seconds = 0.0;            // [s] the options' least (its text says so)
  // [-] correlation of the horizontal acceleration with the tilt, per reading (kQuaternionReadings);
  // negative where the frames are read upside down (the numbering check names that), so |fit| decides.
  std::array<double, 4> tilt_fit{};
  std::array<std::array<double, 2>, 4> axis_slope{};  // [m/s²] the acceleration per unit of tilt per world axis: g, read right
  std::array<std::array<double, 2>, 4> axis_fit{};  // [-] the correlation per world axis (x, y); tilt_fit is the smaller, alike in sign
  bool rates_compared = false;         // the file's p,q,r were compared with each reading's turn
  std::array<bool, 4> rates_in_order{};        // each reading's turn follows p,q,r in their own order and sign (≥ 2 axes)
  std::array<double, 4> rate_score{};          // [-] its summed per-axis correlations with p,q,r as read (3 at most)
  // kOtherReading from the tilt alone: the best reading's inverse fits nearly as well (a steady
  // heading), so its order is told and not its sense.
  bool sense_untold = false;
  std::array<bool, 4> alike{};         // kUnclear: another reading whose tilt fits as well (within the margin) as the one read
  std::string text() const;            // one line for a report ("attitude quaternion: …")
};

// `position` (world, z up) and `attitude` (ZYX, body FLU) as the reader read them from the file's
// columns with `read`, in its `ned` frame and body `turn` (telemetry_reader.h); `rates` (body FLU,
// as read) empty where the file has none. Rows at any times; rates are taken at the attitude's rows.
QuaternionCheck checkQuaternionReading(const SignalSeries<3>& position, const SignalSeries<3>& attitude, const SignalSeries<3>& rates,
                                       const QuaternionReading& read, bool ned, BodyTurn turn,
                                       const QuaternionCheckOptions& options = {});

}  // namespace quadfdi
