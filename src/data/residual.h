// Model-based residual (seed §III-B, docs/data.md): ỹ(k) = y(k) − ȳ(k), where ȳ(k) is the output of
// the nominal fault-free model advanced one step from the true x(k−1) under the commanded u(k−1).
#pragma once

#include "model/integrator.h"

namespace quadfdi {

inline Output oneStepResidual(const RigidBodyModel& nominal, Integrator integrator, double dt, const State& x_prev,
                              const Input& u_prev, const State& x_now, OutputKind output) {
  PlantState predicted;
  predicted.x = x_prev;
  stepPlant(nominal, integrator, dt, 0.0, u_prev, predicted);
  return outputOf(x_now, output) - outputOf(predicted.x, output);
}

}  // namespace quadfdi
