#include "model/integrator.h"

namespace quadfdi {

const char* toString(StepStatus s) {
  switch (s) {
    case StepStatus::kOk: return "ok";
    case StepStatus::kNonFinite: return "non-finite state";
    case StepStatus::kAttitudeLimit: return "roll or pitch beyond the tilt bound";
    case StepStatus::kBelowGround: return "below ground (z < 0)";
  }
  return "?";
}

const char* toString(Integrator i) { return i == Integrator::kRk4 ? "rk4" : "euler"; }

}  // namespace quadfdi
