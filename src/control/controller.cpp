#include "control/controller.h"

namespace quadfdi {

const char* toString(ControlStatus s) {
  switch (s) {
    case ControlStatus::kOk: return "ok";
    case ControlStatus::kSaturated: return "saturated";
    case ControlStatus::kFiltered: return "filtered";
    case ControlStatus::kQpInfeasible: return "qp-infeasible";
    case ControlStatus::kQpFailed: return "qp-failed";
  }
  return "?";
}

}  // namespace quadfdi
