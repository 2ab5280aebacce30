// Do the body rates agree with the attitude's own turn? (no I/O)
//
// A telemetry file's p,q,r in another frame (FRD rates beside z-up attitude), another unit
// (degrees per second read as radians: a hover's ±20 °/s stays under any plausibility bound) or
// with two axes swapped read as a consistent file; a model on body rates then gets them wrong and
// the heading check compares against the wrong turn. The attitude itself says how the body turned:
// over windows of ≥ 20 ms the rotation between the window's ends, as a body-frame rotation vector
// over the window's length, is the mean body rate; correlated axis by axis with the gyro's mean over
// the same rows, each of the 48 signed orders of the gyro's columns scores the correlations it
// predicts: the identity where the two agree, and the best order names what the columns hold
// instead; the ratio of their spreads shows a unit 57.3 times off. Docs: docs/conventions.md#body-rates.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "logs/flight_signals.h"

namespace quadfdi {

struct RateAgreementOptions {
  double min_window = 0.02;        // [s] the attitude's turn is taken over at least this (its noise ÷ the window)
  double max_window = 0.1;         // [s] longer (a hole in the rows) is not compared; logs of 20–50 Hz attitude fit
  std::size_t min_windows = 100;   // [-] fewer compare nothing (2 s of flight)
  double min_rate_spread = 0.002;  // [rad/s] the gyro's spread (all axes) below which nothing is compared (a hover on the
                                   // real PX4 logs moves 0.006–0.008: the explained share, not this, decides)
  // An axis of the best order tells only where its correlation stands this many standard errors
  // (1/√windows) above none, and above min_correlation; two axes must tell. Another order is named
  // where its summed correlations beat the columns as read by two such thresholds.
  double significance = 5.0;       // [-] standard errors
  double min_correlation = 0.1;    // [-]
};

enum class RateAgreementVerdict {
  kNotChecked,  // no rates, too few windows, or an axis that does not turn
  kAgrees,      // the fit is the identity
  kDiffers,     // another order or sign of the columns fits clearly better, or a unit 57.3 times off
  kUnclear,     // fewer than two axes correlate clearly with a column, or no order clearly better than as read
};

struct RateAgreement {
  RateAgreementVerdict verdict = RateAgreementVerdict::kNotChecked;
  std::size_t windows = 0;               // attitude windows compared
  RateAgreementOptions options;          // what it was checked with (its text says so)
  std::array<int, 3> axis{0, 1, 2};      // the gyro column (0 p, 1 q, 2 r) each body axis's rate fits best …
  std::array<int, 3> sign{1, 1, 1};      // … with this sign
  double scale = 1.0;                    // … times this (the median of axis_scale over the axes that tell)
  double score = 0.0;                    // [-] the order's summed correlations (3 at most)
  double score_as_read = 0.0;            // [-] those of p, q, r as read
  std::array<double, 3> axis_correlation{};  // each body axis's rate with its column (as chosen, signed)
  std::array<double, 3> as_read{};           // … with p, q, r as read
  std::array<double, 3> axis_scale{};        // the spread of each body axis's rate over its column's (as chosen)
  std::array<bool, 3> axis_told{};           // its correlation passed the threshold: the axis turned enough to decide
  double threshold = 0.0;                    // [-] that threshold
  bool in_order = false;                     // ≥ 2 axes told, each by its own column with its own sign (any unit)
  bool unit_untold = false;                  // the scale's bracket (noise shrinks one bound, swells the other) spans units
  std::string text() const;              // one line for a report ("body rates: …")
};

// `attitude` (ZYX, body FLU, z up) and `rates` (body FLU) as read, on any rows; rates are taken
// at the attitude's rows by linear interpolation.
RateAgreement checkRateAgreement(const SignalSeries<3>& attitude, const SignalSeries<3>& rates, const RateAgreementOptions& options = {});

}  // namespace quadfdi
