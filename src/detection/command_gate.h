// Which motors' effectiveness the recent commands let the data show (docs/decisions.md
// "Unobservable motors"). Under the fault model f_k = Θ_k·u_k, a motor commanded far below the
// others — at its lower thrust limit in a hard recovery — changes the response by (1 − Θ_k)·u_k,
// next to nothing, so a network reading its window then cannot tell Θ_k, and in practice reads
// such a motor as failed. The sequential rule takes no evidence against a motor while it is not
// observable: its statistics may fall, not rise (SequentialRule::update). A failing motor is not
// hidden by this: the controller commands it up, not down.
//
// A motor is observable when its command has been at least `min_share` of the mean command at
// every sample of the last `hold` samples (the network's window: an estimate reads all of it).
//
// The failed level asks more (`failed_min_share`, docs/decisions.md "Failed evidence needs a raised
// command"): a motor that has lost most of its thrust tilts the vehicle toward itself and loses
// height and yaw moment, and every stabilising controller answers all three by commanding that
// motor up, so its command stands at or above the others' once the controller has seen the loss.
// Evidence at the failed level is taken only on samples where the motor's command is at least
// `failed_min_share` of the mean; a dip of Θ̂ on a motor the controller is commanding down (a hard
// manoeuvre, a recovery) then adds nothing to its failed statistic.
//
// The degraded share (`degraded_min_share`, docs/decisions.md "Degraded evidence needs a raised
// command") asks the same of all evidence, at a lower share: in steady flight a motor at
// effectiveness Θ is commanded 4 / (3Θ + 1) of the mean (1.08 at Θ = 0.9), so a motor commanded
// below that share now is, to that extent, not the one that lost thrust.
// Pure: no I/O, no allocation.
#pragma once

#include <array>
#include <cstdint>

#include "core/types.h"

namespace quadfdi {

// Bit k − 1 set: motor k observable. Bit kFailedWithheldShift + k − 1 set: motor k's command is below
// failed_min_share of the mean now, so it takes no evidence at the failed level (a mask without those
// bits, such as kAllMotorsObservable, withholds nothing).
inline constexpr std::uint8_t kAllMotorsObservable = 0x0F;
inline constexpr int kFailedWithheldShift = 4;

// Whether motor k (0-based) may gain evidence at the degraded level under `mask` (observable).
inline bool takesEvidence(std::uint8_t mask, int k) { return ((mask >> k) & 1u) != 0u; }

// Whether motor k (0-based) may gain evidence at the failed level under `mask` (observable, not withheld).
inline bool takesFailedEvidence(std::uint8_t mask, int k) {
  return takesEvidence(mask, k) && ((mask >> (kFailedWithheldShift + k)) & 1u) == 0u;
}

struct CommandGateConfig {
  double min_share = 0.3;  // [-] of the mean command (0: every motor always observable, no gating). Measured on the per-vehicle models' healthy calibration flights
                           //     (docs/decisions.md "Unobservable motors"): 0.1 left a racer's CBF-QP recovery at motors'
                           //     shares of 0.35–0.5 reading Θ̂ ≈ 0; 0.3 covers it, and no E7 fault's isolation changed
  int hold = 100;          // [samples] the network's window T (the detector and the streams set it from the model)
  double failed_min_share = 0.0;  // [-] of the mean command, at the current sample: below it a motor takes no evidence at
                                  //     the failed level (0: off, every calibration before 2026-12-04). Chosen per model by
                                  //     `calibrate --failed-min-share` (docs/decisions.md "Failed evidence needs a raised command")
  double degraded_min_share = 0.0;  // [-] of the mean command, at the current sample: below it a motor takes no evidence at
                                    //     either level (it is not observable then; 0: off, every calibration before
                                    //     2026-12-05). Chosen per model by `calibrate --degraded-min-share`
                                    //     (docs/decisions.md "Degraded evidence needs a raised command")
};

class CommandGate {
 public:
  explicit CommandGate(const CommandGateConfig& config = {}) : config_(config) { reset(); }
  // A new flight or a restart: every motor observable (nothing seen yet against it).
  void reset() { since_low_.fill(config_.hold); }
  // One model sample's commands [N]; returns the mask after it (observable bits, and the failed level's withheld bits).
  std::uint8_t step(const std::array<double, kMotors>& u) {
    const double mean = 0.25 * (u[0] + u[1] + u[2] + u[3]);
    std::uint8_t mask = 0;
    for (int k = 0; k < kMotors; ++k) {
      const double command = u[static_cast<std::size_t>(k)];
      if (config_.min_share > 0.0) {
        long& since = since_low_[static_cast<std::size_t>(k)];
        if (!(mean > 0.0) || command < config_.min_share * mean) since = 0;
        else if (since < config_.hold) ++since;
        if (since >= config_.hold) mask = static_cast<std::uint8_t>(mask | (1u << k));
      } else {
        mask = static_cast<std::uint8_t>(mask | (1u << k));  // observability gating off
      }
      // Evidence of any loss needs a motor commanded up to the degraded share now: a degraded motor is commanded
      // up by 1/Θ against the others in steady flight, so a dip of Θ̂ on one commanded below them is not its own.
      if (config_.degraded_min_share > 0.0 && (!(mean > 0.0) || command < config_.degraded_min_share * mean))
        mask = static_cast<std::uint8_t>(mask & ~(1u << k));
      if (config_.failed_min_share > 0.0 && (!(mean > 0.0) || command < config_.failed_min_share * mean))
        mask = static_cast<std::uint8_t>(mask | (1u << (kFailedWithheldShift + k)));
    }
    return mask;
  }
  const CommandGateConfig& config() const { return config_; }

 private:
  CommandGateConfig config_;
  std::array<long, kMotors> since_low_{};  // [samples] since the motor's share was last below min_share
};

}  // namespace quadfdi
