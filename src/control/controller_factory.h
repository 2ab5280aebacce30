// Builds a controller from its configuration (setup only: solves the Riccati equation).
#pragma once

#include <memory>
#include <string>

#include "control/cbf_qp.h"
#include "control/geometric.h"
#include "control/lqr.h"
#include "control/pid.h"

namespace quadfdi {

enum class ControllerKind { kLqr, kCbfQp, kPid, kGeometric };
const char* toString(ControllerKind k);
bool parseControllerKind(const std::string& text, ControllerKind& kind);  // "lqr" | "cbf" | "pid" | "geometric"

struct ControllerConfig {
  ControllerKind kind = ControllerKind::kLqr;
  LqrConfig lqr = LqrConfig::bryson();
  CbfConfig cbf;
  PidConfig pid;
  GeometricConfig geometric;
};

struct ControllerBuild {
  std::unique_ptr<Controller> controller;  // null on failure
  LqrDesign lqr;                           // the design behind it (LQR and CBF-QP only)
  std::string error;                       // empty on success
};

// `design_params`: the vehicle model the controller is designed for; dt [s].
ControllerBuild makeController(const VehicleParams& design_params, const ControllerConfig& config, double dt);

}  // namespace quadfdi
