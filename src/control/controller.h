// The interface every closed-loop controller implements.
#pragma once

#include <cstdint>

#include "control/reference.h"
#include "model/state.h"

namespace quadfdi {

// Per-step outcome of a controller (status enum, no exceptions in the loop).
enum class ControlStatus : std::uint8_t {
  kOk,            // command inside the motor bounds, no safety filter intervention needed
  kSaturated,     // command clipped (LQR) or desaturated (PID mixer) to the motor bounds
  kFiltered,      // CBF-QP solved and changed the command (a constraint was active)
  kQpInfeasible,  // CBF constraints + motor bounds infeasible: fell back to the clipped LQR command
  kQpFailed,      // solver failed (iteration limit, bad data): fell back to the clipped LQR command
};
const char* toString(ControlStatus s);

// Bits of ControlStep::active_constraints.
enum ConstraintBit : std::uint8_t {
  kAltitudeFloorActive = 1u << 0,
  kTiltLimitActive = 1u << 1,
  kMotorBoundActive = 1u << 2,
};

struct ControlStep {
  Input u_cmd = Input::Zero();      // [N] the command sent to the motors (what the detector sees)
  Input u_nominal = Input::Zero();  // [N] the LQR command (PID: the unconstrained allocation) before saturation and filtering
  ControlStatus status = ControlStatus::kOk;
  std::uint8_t active_constraints = 0;  // ConstraintBit mask
};

class Controller {
 public:
  virtual ~Controller() = default;
  // Target hover position [m], yaw 0: setReference(hoverReference(goal)).
  void setGoal(const Vec3& goal_position) { setReference(hoverReference(goal_position)); }
  // The reference position [m] now (the goal for a hover reference).
  const Vec3& goal() const { return reference().position; }
  // What to track from the next compute() on; may change every step (the simulator sets
  // referenceAt(spec, k·dt) before step k). setGoal or setReference before the first compute().
  virtual void setReference(const Reference& reference) = 0;
  virtual const Reference& reference() const = 0;
  // Forget the internal state (integrators, loop phases, held outputs) before a new flight.
  // Stateless controllers (LQR, CBF-QP) have nothing to forget.
  virtual void reset() {}
  // One control step from the measured state. Does not allocate.
  virtual void compute(const State& x, ControlStep& out) = 0;
};

}  // namespace quadfdi
