// The stage types every step of quadfdi's pipeline speaks (in the spirit of the Crazyflie
// firmware's stabilizer_types.h): log readers and the simulator produce TelemetrySample, the
// resampler puts it on the model's clock, the estimator turns windows of it into a MotorTheta,
// and the decision rules turn that into alarms. Plain data only: no Eigen, no allocation.
// Conventions (frames, units, motor numbering): docs/conventions.md.
#pragma once

#include <array>
#include <cmath>

namespace quadfdi {

inline constexpr int kMotors = 4;     // quad-X
inline constexpr int kInputDim = 4;   // per-motor thrusts f1..f4 [N], quadfdi (Crazyflie) numbering
inline constexpr int kOutputDim = 6;  // y = position (3) then attitude or rates (3), see OutputKind
// [rad/s] A logged body rate beyond this is no flight but a corrupt row or another unit (degrees per
// second read as radians per second, most often): flight controllers' MEMS gyros saturate at
// 2000 °/s (35 rad/s). The one bound of the CSV reader, the conventions layer and its reset check.
inline constexpr double kMaxBodyRate = 100.0;
// A logged row of body rates [rad/s] is flight where every component is finite and within kMaxBodyRate.
inline bool isUsableBodyRate(const std::array<double, 3>& w) {
  for (double c : w)
    if (!std::isfinite(c) || std::abs(c) > kMaxBodyRate) return false;
  return true;
}

// One measured sample of a flight: what a flight controller has, in quadfdi's conventions.
struct TelemetrySample {
  double t = 0.0;                     // [s]
  std::array<double, kOutputDim> y{};  // x, y, z [m] (world, z up), roll, pitch, yaw [rad] (ZYX, body FLU)
  std::array<double, kInputDim> u{};   // commanded thrust per motor [N], before any fault
  // Body rates p, q, r [rad/s] (body FLU), as the gyro's filtered output the flight controller
  // flies on; all zero from a source that carries none (SampleSource::carriesRates()).
  std::array<double, 3> rates{};
};

// Θ̂: estimated effectiveness per motor, 1 = healthy, 0 = no thrust; index k is motor k + 1.
using MotorTheta = std::array<float, kMotors>;

}  // namespace quadfdi

namespace quadfdi {

// The isolation rule everywhere (evaluation, detector, alarm filter): the motor with the lowest
// Θ̂, ties to the lowest motor number. Returns a 0-based index. Works on any 4-vector with [].
template <class Theta>
int weakestMotorIndex(const Theta& theta) {
  int best = 0;
  for (int k = 1; k < kMotors; ++k)
    if (theta[k] < theta[best]) best = k;
  return best;
}

}  // namespace quadfdi
