// Resets a log does not record, found as steps of a signal that what should explain it does not
// show: an attitude row against the gyro (heading_resets.h), an EKF's position row against its own
// velocity (ArduPilot's height resets). No I/O.
//
// The part a row leaves unexplained is a filter lag, a bias, a time offset or an estimator's
// regular corrections where it changes smoothly from row to row, and a reset where one row stands
// out: so each row is measured against the median of its neighbours', and a step beyond both
// `min_step` and `noise_multiple` × the signal's own row-to-row noise is a reset.
#pragma once

#include <cstddef>
#include <vector>

namespace quadfdi {

struct ResetStepRule {
  double min_step = 0.0;         // [the signal's unit] the smallest step that counts
  // [-] a step must also stand this many times above the row-to-row noise (σ of the excesses over
  // the neighbours' median, from their median size: 1.4826·median |x| is σ for Gaussian x), so that
  // white noise is not read as resets.
  double noise_multiple = 10.0;
  int neighbours = 4;            // [rows] on each side whose median is the smooth part
};

struct ResetSteps {
  std::vector<double> step;      // per row: the reset found there [unit], 0 where none
  std::size_t compared = 0;      // rows with a finite unexplained part
  std::size_t count = 0;         // resets found
  double largest = 0.0;          // [unit] the largest |reset|
  std::size_t largest_row = 0;
  double largest_left = 0.0;     // [unit] the largest |excess| below the threshold
  double noise = 0.0;            // [unit] σ of the excesses
  double threshold = 0.0;        // [unit] max(min_step, noise_multiple·noise)
};

// `unexplained[k]`: what row k's change leaves unexplained (NaN where it could not be compared).
ResetSteps findResetSteps(const std::vector<double>& unexplained, const ResetStepRule& rule);

}  // namespace quadfdi
