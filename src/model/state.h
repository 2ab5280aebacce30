// The one place that defines how quadfdi stores a quadrotor state, an output
// and an input. Every other file indexes through these names.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include "core/types.h"

namespace quadfdi {

// 12-state rigid body, docs/model.md. World frame: z up. Body frame: x forward, y left, z up.
//   p  = (x, y, z)         world position            [m]
//   v  = (u, v, w)         body-frame velocity        [m/s]
//   η  = (φ, θ, ψ)         roll, pitch, yaw (ZYX)     [rad]
//   ω  = (p, q, r)         body rates                 [rad/s]
namespace idx {
inline constexpr int kPx = 0, kPy = 1, kPz = 2;
inline constexpr int kVx = 3, kVy = 4, kVz = 5;
inline constexpr int kRoll = 6, kPitch = 7, kYaw = 8;
inline constexpr int kP = 9, kQ = 10, kR = 11;
inline constexpr int kPos = 0, kVel = 3, kAtt = 6, kRate = 9;  // block starts
}  // namespace idx

inline constexpr int kStateDim = 12;
inline constexpr int kRateDim = 3;  // body rates p, q, r

using State = Eigen::Matrix<double, kStateDim, 1>;
using Input = Eigen::Matrix<double, kInputDim, 1>;
using Output = Eigen::Matrix<double, kOutputDim, 1>;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Which measured quantities form y. The paper's text uses Euler angles, the
// authors' final code body rates (docs/model.md); Euler angles are the default.
enum class OutputKind { kPositionEuler, kPositionRates };

inline Output outputOf(const State& x, OutputKind kind) {
  Output y;
  y.head<3>() = x.segment<3>(idx::kPos);
  y.tail<3>() = kind == OutputKind::kPositionEuler ? x.segment<3>(idx::kAtt)
                                                    : x.segment<3>(idx::kRate);
  return y;
}

}  // namespace quadfdi
