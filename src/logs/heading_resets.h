// Estimator heading resets that a log does not record, found with the gyro (no I/O).
//
// An estimator that re-aligns its heading moves the attitude it reports by a step about the
// vertical within one row: ArduPilot's EKF3 after the first climb (its in-flight yaw alignment)
// or on a compass switch or a GSF yaw reset, none of which ArduPilot logs with its shift; any
// estimator behind a CSV export. The vehicle did not turn, so the gyro does not show the step,
// but the detector would read it as a violent yaw (measured on a PX4 log with the shift left in:
// a 2.9° step put the lowest Θ̂ at 0.27 for a window; docs/logs/ulog.md). PX4 logs its
// resets and its extractor takes them out; this check is what every log gets, before the
// conventions layer puts it on the model's clock.
//
// Each attitude row is compared with the one before it turned by the gyro over the same interval
// (the body rates integrated, R̂ₖ = Rₖ₋₁·exp([ω]×·Δt)). The rotation about the world's vertical
// that the gyro does not explain is a row's unexplained yaw; a row that stands out of its
// neighbours' by more than `min_step` and the attitude's own noise (logs/reset_steps.h) is a reset,
// taken out of that row's yaw and every later one (a rotation about the world's
// vertical leaves roll and pitch as they are). Docs: docs/logs/README.md "Heading resets".
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "logs/flight_signals.h"

namespace quadfdi {

struct HeadingResetOptions {
  // [rad] 0.1°: the smallest step taken out. On the real PX4 logs the gyro explains each row of
  // the estimator's attitude to within 0.007° beyond its neighbours (noise σ ≤ 0.0012°), so PX4's
  // own recorded 0.23° heading reset stands out when its record is ignored (test
  // HeadingResets.RealPx4ResetIsFoundWithoutItsRecord); smaller steps move Θ̂ by less than its noise.
  double min_step = 0.1 * 3.14159265358979323846 / 180.0;
  // [-] and a step must stand this many times above the attitude's own row-to-row noise (σ of the
  // steps beyond their neighbours', from their median size), so that a simulator's white attitude
  // noise is not read as resets.
  double noise_multiple = 10.0;
  double max_interval = 0.05;  // [s] attitude rows, or gyro rows, further apart are not compared (a hole)
  int neighbours = 4;          // [rows] on each side whose median unexplained yaw is the smooth part
};

// One reset taken out: the estimator's heading moved by `shift` at `t`.
struct HeadingShift {
  double t = 0.0;      // [s] the first row whose yaw it moved (it stays in every later one)
  double shift = 0.0;  // [rad] taken out of that row's yaw and every later one's
};

struct HeadingResets {
  bool checked = false;          // the body rates covered the attitude rows (false: no rates in the log)
  std::size_t steps = 0;         // attitude steps compared with the gyro
  std::size_t count = 0;         // resets taken out
  double largest = 0.0;          // [rad] the largest |shift| taken out
  double largest_t = 0.0;        // [s] when
  double largest_left = 0.0;     // [rad] the largest |unexplained step| left in (below the threshold)
  double noise = 0.0;            // [rad] σ of the unexplained steps beyond their neighbours'
  double threshold = 0.0;        // [rad] max(min_step, noise_multiple·noise): larger steps were resets
  std::vector<HeadingShift> resets;  // the `count` resets taken out, in time order
};

// Takes the resets out of `attitude`'s yaw (both series in the same body axes: body rates FLU
// about the body of the attitude's ZYX angles). Rates of non-finite value or beyond 100 rad/s are
// not read.
HeadingResets takeOutHeadingResets(SignalSeries<3>& attitude, const SignalSeries<3>& rates,
                                   const HeadingResetOptions& options = {});

// One line for the import report's conventions: what was found, or why nothing was checked.
std::string headingResetsLine(const HeadingResets& found, const SignalSeries<3>& rates);
// The same, naming the rates `gyro` ("the gyro (RATE)") and giving `why_unchecked` where nothing was checked.
std::string headingResetsLine(const HeadingResets& found, const std::string& gyro, const std::string& why_unchecked);

}  // namespace quadfdi
