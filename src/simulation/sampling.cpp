#include "simulation/sampling.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace quadfdi {

std::string validate(const SamplingRanges& r) {
  auto interval = [](const Interval& i, const char* name) -> std::string {
    if (!std::isfinite(i.lo) || !std::isfinite(i.hi) || i.lo > i.hi)
      return std::string(name) + " must be a finite interval with lo <= hi";
    return {};
  };
  for (const auto& msg : {interval(r.goal_x, "goal_x"), interval(r.goal_y, "goal_y"),
                          interval(r.goal_z, "goal_z")})
    if (!msg.empty()) return msg;
  const double spreads[] = {r.position_offset, r.body_velocity, r.roll_pitch, r.yaw, r.body_rate};
  const char* names[] = {"position_offset", "body_velocity", "roll_pitch", "yaw", "body_rate"};
  for (int i = 0; i < 5; ++i)
    if (!(std::isfinite(spreads[i]) && spreads[i] >= 0.0)) return std::string(names[i]) + " must be finite and >= 0";
  if (!(r.roll_pitch < 1.5)) return "roll_pitch must be below 1.5 rad (the crash bound)";
  if (!std::isfinite(r.min_altitude)) return "min_altitude must be finite";
  if (r.goal_z.hi + r.position_offset < r.min_altitude)
    return "no initial altitude satisfies z >= min_altitude with these goal_z and position_offset";
  return {};
}

Scenario sampleScenario(const SamplingRanges& r, Rng& rng) {
  Scenario s;
  s.goal = Vec3(rng.uniform(r.goal_x.lo, r.goal_x.hi), rng.uniform(r.goal_y.lo, r.goal_y.hi),
                rng.uniform(r.goal_z.lo, r.goal_z.hi));
  State& x = s.initial_state;
  x(idx::kPx) = s.goal.x() + rng.uniform(-r.position_offset, r.position_offset);
  x(idx::kPy) = s.goal.y() + rng.uniform(-r.position_offset, r.position_offset);
  const double z_lo = std::max(r.min_altitude, s.goal.z() - r.position_offset);
  const double z_hi = std::max(z_lo, s.goal.z() + r.position_offset);
  x(idx::kPz) = rng.uniform(z_lo, z_hi);
  for (int i = 0; i < 3; ++i) x(idx::kVel + i) = rng.uniform(-r.body_velocity, r.body_velocity);
  x(idx::kRoll) = rng.uniform(-r.roll_pitch, r.roll_pitch);
  x(idx::kPitch) = rng.uniform(-r.roll_pitch, r.roll_pitch);
  x(idx::kYaw) = rng.uniform(-r.yaw, r.yaw);
  for (int i = 0; i < 3; ++i) x(idx::kRate + i) = rng.uniform(-r.body_rate, r.body_rate);
  return s;
}

}  // namespace quadfdi
