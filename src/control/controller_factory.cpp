#include "control/controller_factory.h"

namespace quadfdi {

const char* toString(ControllerKind k) { return k == ControllerKind::kLqr ? "lqr" : "cbf"; }

bool parseControllerKind(const std::string& text, ControllerKind& kind) {
  if (text == "lqr") { kind = ControllerKind::kLqr; return true; }
  if (text == "cbf" || text == "cbf-qp") { kind = ControllerKind::kCbfQp; return true; }
  return false;
}

ControllerBuild makeController(const VehicleParams& design_params, const ControllerConfig& config, double dt) {
  ControllerBuild build;
  if (const std::string problem = validate(design_params); !problem.empty()) {
    build.error = "controller design parameters: " + problem;
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
