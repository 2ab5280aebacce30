// Initial conditions and goals (docs/control.md): the "safe set" the authors sample from.
#pragma once

#include "model/state.h"
#include "simulation/rng.h"

namespace quadfdi {

struct Interval {
  double lo;  // inclusive
  double hi;  // exclusive
};

struct SamplingRanges {
  // Goal position, uniform in a box [m].
  Interval goal_x{-1.0, 1.0};
  Interval goal_y{-1.0, 1.0};
  Interval goal_z{0.75, 1.5};
  double position_offset = 1.0;  // [m] initial position within ±offset of the goal, per axis
  double min_altitude = 0.5;     // [m] initial z ≥ this (the safe set)
  double body_velocity = 0.5;    // [m/s] each body velocity component in ±this
  double roll_pitch = 0.3;       // [rad] roll and pitch in ±this
  double yaw = 0.5;              // [rad] yaw in ±this
  double body_rate = 1.0;        // [rad/s] each body rate in ±this
};

struct Scenario {
  State initial_state = State::Zero();
  Vec3 goal = Vec3::Zero();
};

// Empty when valid, else a one-line description (negative range, lo > hi, …).
std::string validate(const SamplingRanges& ranges);

// Draws one scenario. The altitude is drawn from the part of [goal_z − offset, goal_z + offset]
// above min_altitude, so z ≥ min_altitude without piling mass at the floor.
Scenario sampleScenario(const SamplingRanges& ranges, Rng& rng);

}  // namespace quadfdi
