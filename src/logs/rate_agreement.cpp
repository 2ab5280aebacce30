// Body rates against the attitude's own turn: see rate_agreement.h.
#include "logs/rate_agreement.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/frames.h"
#include "core/types.h"

namespace quadfdi {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;  // [rad]
constexpr const char* kAxisNames[3] = {"roll", "pitch", "yaw"};

// The rates linearly interpolated at t (false outside them or across a row gap over `max_gap`).
class RateLookup {
 public:
  RateLookup(const SignalSeries<3>& r, double max_gap) : r_(r), max_gap_(max_gap) {}
  bool at(double t, std::array<double, 3>& out) {
    const std::vector<double>& ts = r_.t;
    if (ts.empty() || t < ts.front() || t > ts.back()) return false;
    if (cursor_ > 0 && ts[cursor_] > t) cursor_ = 0;  // not in time order: search again
    while (cursor_ + 1 < ts.size() && ts[cursor_ + 1] <= t) ++cursor_;
    if (ts[cursor_] == t) {
      out = r_.v[cursor_];
    } else {
      if (cursor_ + 1 >= ts.size() || ts[cursor_ + 1] - ts[cursor_] > max_gap_) return false;
      const double s = (t - ts[cursor_]) / (ts[cursor_ + 1] - ts[cursor_]);
      for (std::size_t c = 0; c < 3; ++c) out[c] = r_.v[cursor_][c] + s * (r_.v[cursor_ + 1][c] - r_.v[cursor_][c]);
    }
    return isUsableBodyRate(out);
  }

 private:
  const SignalSeries<3>& r_;
  double max_gap_;
  std::size_t cursor_ = 0;
};

}  // namespace

RateAgreement checkRateAgreement(const SignalSeries<3>& attitude, const SignalSeries<3>& rates, const RateAgreementOptions& o) {
  RateAgreement out;
  out.options = o;
  if (attitude.t.size() < 2 || rates.t.size() < 2) return out;
  RateLookup lookup(rates, o.max_window);
  std::vector<std::array<double, 3>> turn_rate, gyro;  // per window: the attitude's mean body rate, the gyro's
  std::size_t start = 0;
  const std::size_t n = attitude.t.size();
  while (start + 1 < n) {
    // The window: rows start..end, at least min_window long, no row gap over max_window.
    std::size_t end = start + 1;
    const double shortest = o.min_window - 1e-9;  // rows exactly min_window apart make a window despite their times' rounding
    while (end < n && attitude.t[end] - attitude.t[start] < shortest && attitude.t[end] - attitude.t[end - 1] <= o.max_window) ++end;
    if (end >= n) break;
    const double span = attitude.t[end] - attitude.t[start];
    if (!(span >= shortest && span <= o.max_window) || attitude.t[end] - attitude.t[end - 1] > o.max_window) {
      start = end;
      continue;
    }
    // The gyro's mean over the window (trapezoid over the attitude's rows).
    std::array<double, 3> g{}, w0{}, w1{};
    bool covered = lookup.at(attitude.t[start], w0);
    for (std::size_t k = start + 1; covered && k <= end; ++k) {
      covered = lookup.at(attitude.t[k], w1);
      const double dt = attitude.t[k] - attitude.t[k - 1];
      for (std::size_t c = 0; c < 3; ++c) g[c] += 0.5 * (w0[c] + w1[c]) * dt / span;
      w0 = w1;
    }
    const auto& p = attitude.v[start];
    const auto& q = attitude.v[end];
    const Quaternion turn = conjugate(quaternionOfEuler({p[0], p[1], p[2]})) * quaternionOfEuler({q[0], q[1], q[2]});
    const std::array<double, 3> angle = rotationVectorOfQuaternion(turn);  // body axes of the window's start
    start = end;
    bool finite = covered;
    for (std::size_t c = 0; c < 3; ++c) finite = finite && std::isfinite(angle[c]);
    if (!finite) continue;
    turn_rate.push_back({angle[0] / span, angle[1] / span, angle[2] / span});
    gyro.push_back(g);
  }
  out.windows = turn_rate.size();
  if (out.windows < o.min_windows) return out;
  // Enough rotation to compare at all: the gyro's spread summed over its axes.
  std::array<double, 3> mean_g{}, mean_w{};
  const double count = static_cast<double>(out.windows);
  for (std::size_t k = 0; k < out.windows; ++k)
    for (std::size_t c = 0; c < 3; ++c) {
      mean_g[c] += gyro[k][c] / count;
      mean_w[c] += turn_rate[k][c] / count;
    }
  std::array<double, 3> var_g{}, var_w{};
  std::array<std::array<double, 3>, 3> cov{};  // cov[i][j]: attitude rate i with gyro column j
  for (std::size_t k = 0; k < out.windows; ++k)
    for (std::size_t i = 0; i < 3; ++i) {
      const double wi = turn_rate[k][i] - mean_w[i], gi = gyro[k][i] - mean_g[i];
      var_g[i] += gi * gi / count;
      var_w[i] += wi * wi / count;
      for (std::size_t j = 0; j < 3; ++j) cov[i][j] += wi * (gyro[k][j] - mean_g[j]) / count;
    }
  if (!(std::sqrt(var_g[0] + var_g[1] + var_g[2]) >= o.min_rate_spread)) return out;
  for (std::size_t c = 0; c < 3; ++c)
    if (!(var_g[c] > 0.0) || !(var_w[c] > 0.0)) return out;
  // Correlations are per axis and scale-free: an axis that hardly turns still shows its sign,
  // where a fit of all three together is the most-turning axis's. Each signed order of the columns
  // scores the correlations it predicts; the best is what the columns hold.
  std::array<std::array<double, 3>, 3> corr{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) corr[i][j] = cov[i][j] / std::sqrt(var_w[i] * var_g[j]);
  std::array<int, 3> perm{0, 1, 2};
  out.score = -1e300;
  do {
    for (int signs = 0; signs < 8; ++signs) {
      std::array<int, 3> sign{};
      double score = 0.0;
      for (std::size_t i = 0; i < 3; ++i) {
        sign[i] = (signs >> i) & 1 ? -1 : 1;
        score += sign[i] * corr[i][static_cast<std::size_t>(perm[i])];
      }
      if (score > out.score) {
        out.score = score;
        out.axis = perm;
        out.sign = sign;
      }
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  out.score_as_read = corr[0][0] + corr[1][1] + corr[2][2];
  for (std::size_t i = 0; i < 3; ++i) out.as_read[i] = corr[i][i];
  // The chosen order's per-axis correlation and scale. Noise in the gyro shrinks the slope of the
  // turn's rate on its column, noise in the attitude's turn swells the inverse slope; the true
  // scale lies between (their geometric mean, the ratio of the spreads, is reported).
  std::array<double, 3> low{}, high{};
  for (std::size_t i = 0; i < 3; ++i) {
    const std::size_t j = static_cast<std::size_t>(out.axis[i]);
    out.axis_correlation[i] = out.sign[i] * corr[i][j];
    out.axis_scale[i] = std::sqrt(var_w[i] / var_g[j]);
    const double c = std::abs(cov[i][j]);
    low[i] = c / var_g[j];
    high[i] = c > 0.0 ? var_w[i] / c : 1e300;
  }
  // An axis that hardly turns against the attitude's noise (a steady heading's yaw) tells nothing;
  // the others decide, two at least.
  out.threshold = std::max(o.min_correlation, o.significance / std::sqrt(count));
  int told = 0;
  bool identity_where_told = true;
  for (std::size_t i = 0; i < 3; ++i) {
    out.axis_told[i] = out.axis_correlation[i] >= out.threshold;
    if (!out.axis_told[i]) continue;
    ++told;
    identity_where_told = identity_where_told && out.axis[i] == static_cast<int>(i) && out.sign[i] == 1;
  }
  out.in_order = told >= 2 && identity_where_told;
  // The scale: the median over the axes that tell. Noise moves it a few-fold at most (the
  // attitude's on quiet axes); a unit other than read moves it 57.3-fold, so nearer 1° than 1 (in
  // ratio) is degrees per second read as radians, and the other way round.
  std::vector<double> scales, lows, highs;
  for (std::size_t i = 0; i < 3; ++i)
    if (out.axis_told[i]) {
      scales.push_back(out.axis_scale[i]);
      lows.push_back(low[i]);
      highs.push_back(high[i]);
    }
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 1.0 : v.size() % 2 ? v[v.size() / 2] : std::sqrt(v[v.size() / 2 - 1] * v[v.size() / 2]);
  };
  out.scale = median(scales);
  // The unit: another one where the whole bracket lies past the geometric middle between 1 and
  // 57.3, this one where it lies within both middles; else the flight turned too little to tell.
  const double middle = std::sqrt(1.0 / kDegree);
  const double low_scale = median(lows), high_scale = median(highs);
  const bool other_unit = high_scale < 1.0 / middle || low_scale > middle;
  const bool this_unit = low_scale >= 1.0 / middle && high_scale <= middle;
  out.unit_untold = !other_unit && !this_unit;
  if (told < 2)
    out.verdict = RateAgreementVerdict::kUnclear;
  else if (identity_where_told)
    out.verdict = other_unit ? RateAgreementVerdict::kDiffers : this_unit ? RateAgreementVerdict::kAgrees : RateAgreementVerdict::kUnclear;
  else
    out.verdict = out.score - out.score_as_read >= 2.0 * out.threshold ? RateAgreementVerdict::kDiffers : RateAgreementVerdict::kUnclear;
  return out;
}

std::string RateAgreement::text() const {
  char head[200];
  std::snprintf(head, sizeof head, " over %zu windows of ≥ %.0f ms (correlation per axis %.2f / %.2f / %.2f, as read %.2f / %.2f / %.2f; scale %.3g)",
                windows, options.min_window * 1e3, axis_correlation[0], axis_correlation[1], axis_correlation[2], as_read[0], as_read[1], as_read[2], scale);
  switch (verdict) {
    case RateAgreementVerdict::kNotChecked:
    {
      char why[160];
      std::snprintf(why, sizeof why, "under %zu windows of rows ≤ %.0f ms apart (%.3g s), or too little rotation", options.min_windows,
                    options.max_window * 1e3, static_cast<double>(options.min_windows) * options.min_window);
      return "body rates: not compared with the attitude's turn (" + std::string(why) + ")";
    }
    case RateAgreementVerdict::kAgrees: {
      std::string quiet;
      for (std::size_t i = 0; i < 3; ++i)
        if (!axis_told[i]) quiet += std::string(quiet.empty() ? "" : " and ") + kAxisNames[i];
      return "body rates: p,q,r agree with the attitude's own turn" + std::string(head) +
             (quiet.empty() ? "" : "; " + quiet + " turned too little to tell");
    }
    case RateAgreementVerdict::kUnclear:
      if (unit_untold)
        return "body rates: p,q,r follow the attitude's turn in order and sign" + std::string(head) +
               ", but it turned too little against the sensors' noise to tell their unit";
      return "body rates: no order, sign and scale of p,q,r fits the attitude's turn clearly" + std::string(head) +
             ": too little rotation against the sensors' noise, rates lagging far behind the attitude, or rates of something else";
    case RateAgreementVerdict::kDiffers: break;
  }
  static const char* const kNames[3] = {"p", "q", "r"};
  std::string as;
  for (std::size_t i = 0; i < 3; ++i) as += std::string(i ? ", " : "") + (sign[i] < 0 ? "−" : "") + kNames[axis[i]];
  // The order and signs on the axes that tell (an axis that hardly turns may show any).
  bool identity = true, frd = true;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!axis_told[i]) continue;
    identity = identity && axis[i] == static_cast<int>(i) && sign[i] == 1;
    frd = frd && axis[i] == static_cast<int>(i) && sign[i] == (i == 0 ? 1 : -1);
  }
  char scale_text[48] = "";
  if (identity) std::snprintf(scale_text, sizeof scale_text, " × %.3g", scale);
  std::string s = "body rates: the attitude turns as (" + as + ")" + scale_text + " would, not as p,q,r read" + head;
  // Rates in °/s read as rad/s are 57.3 times the turn: the scale is then near 1°, and the other way round near 1/1°.
  if (identity && scale < 1.0)
    s += ": p,q,r look like degrees per second read as radians (--csv-rate-unit deg/s, or 'p [deg/s]' in the header)";
  else if (identity)
    s += ": p,q,r look like radians per second read as degrees (drop --csv-rate-unit deg/s or the header's deg/s)";
  else if (frd)
    s += ": FRD rates (PX4, ArduPilot, Gazebo) beside attitude in quadfdi's frames? Give both in NED/FRD with --csv-frame ned, "
         "or q and r with their signs turned";
  else
    s += ": the columns hold other axes or signs than p, q, r in quadfdi's body frame (x forward, y left, z up)";
  return s;
}

}  // namespace quadfdi
