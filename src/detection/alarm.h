// Alarm persistence (issue 6): the raw rule min_k Θ̂_k < Θ_tol (docs/decisions.md) flips on a single
// noisy window. The filter raises an alarm only after `raise_after` consecutive evaluations put
// the same motor below `raise_below`, and clears it only after every motor has stayed above
// `clear_above` for `clear_after` samples (hysteresis).
#pragma once

#include <array>

#include "core/types.h"

namespace quadfdi {

struct AlarmConfig {
  double raise_below = 0.5;  // [-] Θ̂ of the weakest motor below this is evidence of a fault
                             //     (the paper's Θ_tol is 0.2 for complete faults; 0.5 also catches
                             //     a motor down to half its thrust)
  double clear_above = 0.8;  // [-] every Θ̂ above this is evidence of health
  int raise_after = 5;       // [evaluations] consecutive evidence, same motor (the detector evaluates
                             //     every sample while evidence builds: 10 ms at 500 Hz)
  int clear_after = 100;     // [samples] healthy evidence held this long (200 ms at 500 Hz)
};

struct AlarmState {
  bool active = false;
  int motor = 0;          // 1..4 while active
  bool raised = false;    // this evaluation raised it
  bool cleared = false;   // this evaluation cleared it
};

class AlarmFilter {
 public:
  explicit AlarmFilter(const AlarmConfig& config) : config_(config) {}
  // One evaluation's four estimates (motor 1..4) at model sample `index`. Ties in the minimum go
  // to the lower motor.
  AlarmState update(const std::array<float, 4>& theta, long index);
  const AlarmState& state() const { return state_; }
  void reset() { state_ = {}; faulty_run_ = 0; candidate_ = 0; healthy_since_ = -1; }

 private:
  AlarmConfig config_;
  AlarmState state_;
  int candidate_ = 0, faulty_run_ = 0;
  long healthy_since_ = -1;  // first sample of the current healthy run while active, −1 if none
};

}  // namespace quadfdi
