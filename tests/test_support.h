// Small helpers shared by the tests.
#pragma once

#include <memory>

#include "control/controller_factory.h"
#include "simulation/closed_loop.h"
#include "simulation/sampling.h"

namespace quadfdi::test {

inline std::unique_ptr<Controller> makeOrDie(const VehicleParams& params, ControllerKind kind,
                                             const CbfConfig& cbf = {}, double dt = 0.002) {
  ControllerConfig cc;
  cc.kind = kind;
  cc.cbf = cbf;
  ControllerBuild build = makeController(params, cc, dt);
  if (!build.controller) throw std::runtime_error(build.error);
  return std::move(build.controller);
}

inline State hoverState(const Vec3& position) {
  State x = State::Zero();
  x.segment<3>(idx::kPos) = position;
  return x;
}

}  // namespace quadfdi::test
