// Heading resets found with the gyro: see heading_resets.h.
#include "logs/heading_resets.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "core/frames.h"
#include "core/types.h"
#include "logs/reset_steps.h"

namespace quadfdi {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

// The gyro's rotation over [t0, t1] (body axes), as a unit quaternion: the rates interpolated
// linearly between their rows, held over each piece between two rows at its midpoint's value. False
// where the rows do not cover the interval or lie more than `max_gap` apart within it.
bool gyroRotation(const std::vector<double>& rt, const std::vector<std::array<double, 3>>& rv, double t0, double t1,
                  double max_gap, std::size_t& cursor, Quaternion& out) {
  if (rt.empty() || rt.front() > t0 || rt.back() < t1) return false;
  while (cursor + 1 < rt.size() && rt[cursor + 1] <= t0) ++cursor;
  out = Quaternion{};
  double a = t0;
  for (std::size_t i = cursor; a < t1; ++i) {
    if (i + 1 >= rt.size()) return false;
    const double b = std::min(t1, rt[i + 1]);
    if (rt[i + 1] - rt[i] > max_gap) return false;
    if (b > a) {
      const double mid = 0.5 * (a + b), s = (mid - rt[i]) / (rt[i + 1] - rt[i]);
      std::array<double, 3> angle;
      for (int c = 0; c < 3; ++c) angle[c] = (rv[i][c] + s * (rv[i + 1][c] - rv[i][c])) * (b - a);
      out = out * quaternionOfRotationVector(angle);  // a body-frame increment: right-multiplied
    }
    a = b;
  }
  return true;
}

// The yaw [rad] of a rotation: for the small residual between two attitudes, the part about the
// world's vertical.
double yawOf(const Quaternion& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

}  // namespace

HeadingResets takeOutHeadingResets(SignalSeries<3>& attitude, const SignalSeries<3>& rates,
                                   const HeadingResetOptions& o) {
  HeadingResets found;
  const std::size_t n = attitude.t.size();
  if (rates.t.size() < 2 || n < 2) return found;

  std::vector<double> rt;
  std::vector<std::array<double, 3>> rv;
  rt.reserve(rates.t.size());
  rv.reserve(rates.t.size());
  for (std::size_t i = 0; i < rates.t.size(); ++i)
    if (isUsableBodyRate(rates.v[i]) && std::isfinite(rates.t[i])) {
      rt.push_back(rates.t[i]);
      rv.push_back(rates.v[i]);
    }

  // Unexplained yaw of each step k (rows k − 1 → k), NaN where it cannot be compared.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> unexplained(n, nan);
  std::size_t cursor = 0;
  Quaternion previous = quaternionOfEuler({attitude.v[0][0], attitude.v[0][1], attitude.v[0][2]});
  for (std::size_t k = 1; k < n; ++k) {
    const Quaternion current = quaternionOfEuler({attitude.v[k][0], attitude.v[k][1], attitude.v[k][2]});
    const double t0 = attitude.t[k - 1], t1 = attitude.t[k];
    Quaternion turned;
    if (t1 > t0 && t1 - t0 <= o.max_interval && gyroRotation(rt, rv, t0, t1, o.max_interval, cursor, turned)) {
      // Rₖ·R̂ₖᵀ: the attitude's step less the gyro's, as a rotation in the world frame.
      const double yaw = yawOf(current * conjugate(previous * turned));
      if (std::isfinite(yaw)) {
        unexplained[k] = yaw;
        ++found.steps;
      }
    }
    previous = current;
  }
  if (found.steps == 0) return found;
  found.checked = true;

  const ResetSteps steps = findResetSteps(unexplained, {o.min_step, o.noise_multiple, o.neighbours});
  found.count = steps.count;
  found.largest = steps.largest;
  if (steps.count > 0) found.largest_t = attitude.t[steps.largest_row];
  found.largest_left = steps.largest_left;
  found.noise = steps.noise;
  found.threshold = steps.threshold;
  double shift = 0.0;  // [rad] sum of the resets so far
  found.resets.reserve(steps.count);
  for (std::size_t k = 1; k < n; ++k) {
    if (steps.step[k] != 0.0) found.resets.push_back({attitude.t[k], steps.step[k]});
    shift += steps.step[k];
    if (shift != 0.0) attitude.v[k][2] = wrapAngle(attitude.v[k][2] - shift);
  }
  return found;
}

std::string headingResetsLine(const HeadingResets& found, const SignalSeries<3>& rates) {
  return headingResetsLine(found, rates.source.topic.empty() ? "the body rates" : "the gyro (" + rates.source.topic + ")",
                           rates.empty() ? "the log has no body rates" : "the body rates do not cover the attitude's rows");
}

std::string headingResetsLine(const HeadingResets& found, const std::string& gyro, const std::string& why_unchecked) {
  if (!found.checked) return "heading: not checked for estimator resets the log does not record: " + why_unchecked;
  char buf[320];
  if (found.count == 0)
    std::snprintf(buf, sizeof buf,
                  "heading: each of %zu attitude steps checked against %s: no estimator reset the log does not record "
                  "(largest yaw step the gyro does not explain %.2g°, its noise σ %.2g°)",
                  found.steps, gyro.c_str(), found.largest_left * kRadToDeg, found.noise * kRadToDeg);
  else
    std::snprintf(buf, sizeof buf,
                  "heading: %zu yaw step%s that %s does not show — estimator resets the log does not record — taken "
                  "out (largest %.3g° at %.3f s; steps beyond %.2g° count), so the heading is continuous",
                  found.count, found.count == 1 ? "" : "s", gyro.c_str(), found.largest * kRadToDeg, found.largest_t,
                  found.threshold * kRadToDeg);
  return buf;
}

}  // namespace quadfdi
