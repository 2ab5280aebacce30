#include "control/controller_factory.h"

#include <cmath>

namespace quadfdi {

const char* toString(ControllerKind k) {
  switch (k) {
    case ControllerKind::kLqr: return "lqr";
    case ControllerKind::kCbfQp: return "cbf";
    case ControllerKind::kPid: return "pid";
    case ControllerKind::kGeometric: return "geometric";
  }
  return "?";
}

bool parseControllerKind(const std::string& text, ControllerKind& kind) {
  if (text == "lqr") { kind = ControllerKind::kLqr; return true; }
  if (text == "cbf" || text == "cbf-qp") { kind = ControllerKind::kCbfQp; return true; }
  if (text == "pid") { kind = ControllerKind::kPid; return true; }
  if (text == "geometric") { kind = ControllerKind::kGeometric; return true; }
  return false;
}

ControllerBuild makeController(const VehicleParams& design_params, const ControllerConfig& config, double dt) {
  ControllerBuild build;
  if (const std::string problem = validate(design_params); !problem.empty()) {
    build.error = "controller design parameters: " + problem;
    return build;
  }
  if (config.kind == ControllerKind::kPid || config.kind == ControllerKind::kGeometric) {
    if (!(dt > 0.0) || !std::isfinite(dt)) {
      build.error = "time step must be finite and > 0";
      return build;
    }
    const bool pid = config.kind == ControllerKind::kPid;
    if (const std::string problem = pid ? validate(config.pid) : validate(config.geometric); !problem.empty()) {
      build.error = problem;
      return build;
    }
    if (pid)
      build.controller = std::make_unique<PidController>(design_params, config.pid, dt);
    else
      build.controller = std::make_unique<GeometricController>(design_params, config.geometric, dt);
    return build;
  }
  build.lqr = designLqr(design_params, config.lqr, dt);
  if (!build.lqr.ok()) {
    build.error = "LQR design failed: " + build.lqr.error;
    return build;
  }
  if (config.kind == ControllerKind::kLqr)
    build.controller = std::make_unique<LqrController>(design_params, build.lqr.gain);
  else
    build.controller = std::make_unique<CbfQpController>(design_params, build.lqr.gain, config.cbf);
  return build;
}

}  // namespace quadfdi
