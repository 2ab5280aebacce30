// The sequential decision rule (issue 14, docs/decisions.md "Severity and the sequential rule"):
// per motor, two one-sided CUSUMs (Page 1954) on Θ̂ — the accumulated deficit below the degraded
// level and below the failed level — raise `degraded` or `failed` naming one motor, with an
// estimate of that motor's Θ and an interval from a noise model of Θ̂ (per-sample σ, AR(1)
// autocorrelation φ at the model rate, and a systematic model error). Thresholds come from a
// target false-alarm rate per flight hour (detection/calibration.h).
//
// Pure: no I/O; the constructor allocates, update() does not.
#pragma once

#include <algorithm>
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "core/types.h"
#include "detection/command_gate.h"

namespace quadfdi {

enum class Severity { kHealthy, kDegraded, kFailed };
const char* toString(Severity s);  // healthy | degraded | failed

// What the rule reads as motor k's effectiveness (docs/decisions.md "Relative evidence").
enum class ThetaReference {
  kAbsolute,  // Θ̂_k as the network gives it: the rule of calibrations made before 2026-11-26 (a file without
              //     the key) and of the paper's reproduction
  kOthers,    // Θ̂_k over the median of the other three motors' Θ̂ (relativeToOthers)
};
const char* toString(ThetaReference r);  // absolute | others
// false for any other text; *out untouched then.
bool parseThetaReference(const std::string& text, ThetaReference* out);

// [-] Floor of the reference in relativeToOthers: a median below it means the network calls at
// least two motors weak at once, outside the single-fault model the isolation relies on; dividing
// by it would inflate Θ̂_k into false health.
inline constexpr float kMinOthersMedian = 0.5f;

// Θ̂_k / max(median of the other three Θ̂, kMinOthersMedian), each motor. Under the single-fault
// model at least two of any motor's three siblings are healthy, so their median is a healthy
// motor's Θ̂ in the same instant: a dip the network gives every motor at once (a hard manoeuvre, a
// plant error it reads as weak motors) cancels, and a fault stands out against it. Permuting the
// motors permutes the result.
MotorTheta relativeToOthers(const MotorTheta& theta);

// The motors the rule may take evidence against, from the CommandGate's mask `observable` and the
// rule's input. Read against its siblings (kOthers), a dip the network gives several motors at once
// cancels against the median of the other three, but only while they are observable. With just two
// motors observable (the other two hidden at their lower limit: a saturated torque demand, such as
// the CBF-QP's tilt limit reached in wind) a dip of both is read against the two hidden ones and
// stands: two motors weak at once (below kMinOthersMedian, as relativeToOthers reads "weak") is
// outside the single-fault model, so then neither gains evidence. Otherwise, and with kAbsolute,
// the mask is kept (docs/decisions.md "Two motors left to read").
std::uint8_t evidenceMask(std::uint8_t observable, const MotorTheta& rule_input, ThetaReference reference);

// The rule's input for a network output: `theta` itself (kAbsolute) or relativeToOthers(theta).
inline MotorTheta ruleInput(const MotorTheta& theta, ThetaReference r) {
  return r == ThetaReference::kOthers ? relativeToOthers(theta) : theta;
}

// No cap on a CUSUM's increment (the plain Page CUSUM).
inline constexpr double kNoIncrementCap = std::numeric_limits<double>::infinity();

// One range of the Θ estimate with its own spread (Mondrian split-conformal,
// detection/calibration.h fitBinnedEstimateSpread): the network's error is not the same size
// everywhere — near Θ = 0 its estimate is one-sided (Θ̂ ≥ 0, biased up) — so one spread pooled over
// Θ covers too little at low Θ and too much at high Θ (docs/decisions.md "The Θ estimate and its
// interval").
struct SpreadBin {
  double estimate_below = 1.0;  // [-] the range holds estimates below this and at or above the previous range's
                                //     bound; the last range also holds every estimate above (at least 1)
  double noise_scale = 1.0;     // [-] as ThetaNoiseModel::noise_scale, for this range
  double model_sigma = 0.0;     // [-] as ThetaNoiseModel::model_sigma, for this range
  long pairs = 0;               // [-] calibration pairs (estimate, Θ) it was fitted on
};
inline constexpr std::size_t kMaxSpreadBins = 16;  // [-] most ranges a noise model holds (a calibration file's bound)

// One node of a confidence belt (Neyman 1937): at true effectiveness `theta`, the flown-through
// estimate falls in [accept_lo, accept_hi] with the interval's probability. The interval for an
// estimate is then every Θ whose acceptance region holds it, so it holds the truth at its level
// for every Θ, not only on average over a range of the estimate (detection/calibration.h
// fitThetaBelt, docs/decisions.md "The confidence belt").
struct BeltNode {
  double theta = 0.0;      // [-] true effectiveness of the node
  double accept_lo = 0.0;  // [-] lowest estimate accepted at `theta`
  double accept_hi = 1.0;  // [-] highest estimate accepted at `theta`
  long pairs = 0;          // [-] calibration pairs (estimate, Θ) it was fitted on
};
inline constexpr int kBeltGrid = 1000;  // [-] the belt is inverted on Θ = 0, 1/kBeltGrid, …, 1
inline constexpr std::size_t kMaxBeltNodes = 64;  // [-] most nodes a noise model holds (a calibration file's bound)

// Θ̂ of one motor on healthy flights as a stationary AR(1) process, plus the systematic error of
// the network on faulty flights. Defaults: measured on the shipped TCN (models/tcn-model-free.qfdw)
// by `quadfdi calibrate --flights 40 --flight-seconds 90 --faulty-flights 100` (1.0 simulated
// flight hour, LQR, nominal Crazyflie; models/tcn-model-free.calibration.json, docs/decisions.md).
struct ThetaNoiseModel {
  double healthy_mean = 0.982;  // [-] mean Θ̂ on healthy flights
  double sigma = 0.039;         // [-] per-sample standard deviation of Θ̂ on healthy flights
  double phi = 0.84;            // [-] lag-1 autocorrelation of Θ̂ at the model rate (500 Hz)
  double model_sigma = 0.093;   // [-] standard deviation of (mean Θ̂ − Θ) on faulty flights, beyond the noise
  double noise_scale = 1.0;     // [-] the estimate's noise variance is this times the healthy AR(1) one; below 1
                                //     where healthy Θ̂ (manoeuvres included) is noisier than a flown-through faulty
                                //     estimate (fitted on coverage, detection/calibration.h fitEstimateSpread)
  std::vector<SpreadBin> spread_bins;  // per range of the estimate, ascending; when present they replace
                                       // noise_scale and model_sigma (the pooled fit) for the interval
  std::vector<BeltNode> belt;  // ascending in theta; when present the interval inverts it (the spread then only
                               // widens it for an estimate of fewer samples than the window)
};

struct SequentialConfig {
  double degraded_below = 0.8;      // [-] a motor below this effectiveness is `degraded`. Issue 14 suggests 0.9; the
                                    //     shipped TCN's healthy Θ̂ (σ ≈ 0.06) dips below 0.9 for 4 % of samples under
                                    //     estimator noise, which needs ~10× the evidence (h 136 vs 14) for 0.1 false
                                    //     alarms an hour (docs/decisions.md, "Levels")
  double failed_below = 0.3;        // [-] … below this, `failed` (issue 14)
  double degraded_threshold = 14.0; // [effectiveness·samples] CUSUM threshold h of the degraded level (shipped
                                    //     TCN calibration at 0.1 false alarms per flight hour, docs/decisions.md)
  double failed_threshold = 3.9;    // [effectiveness·samples] h of the failed level (same source)
  double degraded_cap = kNoIncrementCap;  // [effectiveness] most one sample adds to the degraded statistic: a deep,
                                          //     short dip of healthy Θ̂ (a hard manoeuvre) then weighs no more than a
                                          //     mild fault's sustained one (docs/decisions.md "Capped increments").
                                          //     A calibration sets it with its thresholds; none for these defaults
  double failed_cap = kNoIncrementCap;    // [effectiveness] the same for the failed statistic
  int clear_after = 100;            // [samples] Θ̂ of the flagged motor at or above the level this long
                                    //     clears (or de-escalates) it: 200 ms at 500 Hz, as the persistence filter
  int estimate_window = 50;         // [samples] Θ̂ estimate: mean of the last this many samples since the
                                    //     change point (100 ms at 500 Hz: long against φ, short against the fault)
  double interval_level = 0.9;      // [-] two-sided coverage of [theta_lo, theta_hi]
  double failed_min_share = 0.0;    // [-] the CommandGate share the failed evidence is gated at (CommandGateConfig::
                                    //     failed_min_share; 0: none). The rule reads it through the masks it is given;
                                    //     whoever computes them (the detector, the evaluation's streams) sets the gate from it
  double degraded_min_share = 0.0;  // [-] the CommandGate share all evidence is gated at (CommandGateConfig::degraded_min_share;
                                    //     0: none), read the same way
  ThetaReference reference = ThetaReference::kAbsolute;           // what the statistics and the recovery read (ruleInput)
  ThetaReference estimate_reference = ThetaReference::kAbsolute;  // what the estimate and its interval read: the network's
                                                                   //     own Θ̂ keeps the siblings' errors out of the estimate
                                                                   //     (docs/decisions.md "Relative evidence")
  ThetaNoiseModel noise;  // of the estimate_reference quantity: the interval is its only use here
};

// Sets on `gate` the command shares the rule's evidence is gated at: whoever computes the masks the
// rule reads (the detector, the evaluation's streams) gates as the calibration did.
inline void applyGateShares(const SequentialConfig& rule, CommandGateConfig& gate) {
  gate.failed_min_share = rule.failed_min_share;
  gate.degraded_min_share = rule.degraded_min_share;
}

// Empty when valid, else a one-line description of the first problem.
std::string validate(const SequentialConfig& config);

enum class SequentialStatus {
  kHealthy,    // no alarm, every statistic at zero
  kBuilding,   // no alarm, some motor's degraded statistic above zero (evidence building)
  kRaised,     // this update raised an alarm
  kActive,     // an alarm holds, severity unchanged
  kEscalated,  // degraded → failed on this update
  kRecovered,  // failed → degraded on this update
  kCleared,    // this update cleared the alarm
};

struct SequentialState {
  Severity severity = Severity::kHealthy;
  int motor = 0;              // 1..4 while not healthy, else 0
  double theta_est = 1.0;     // [-] Θ estimate of `motor` (mean Θ̂ since the change point, last estimate_window samples)
  double standard_error = 0.0;  // [-] of theta_est, noise and model error
  double theta_lo = 1.0, theta_hi = 1.0;  // [-] interval_level interval, clipped to [0, 1]
};

class SequentialRule {
 public:
  // setup: checks the config (std::invalid_argument with validate()'s text), allocates the
  // per-motor windows and the table of the windowed mean's variance.
  explicit SequentialRule(const SequentialConfig& config);

  // One Θ̂ (the network's output; the statistics take ruleInput of it by `reference`, the estimate by
  // `estimate_reference`) that stands for `samples` ≥ 1 model samples (the detector's stride holds an
  // estimate until the next evaluation). `gate_mask` is the CommandGate's: a motor whose bit is clear in
  // evidenceMask(gate_mask, ruleInput(theta, reference), reference) takes no evidence: its statistics may fall, not rise;
  // one whose failed-level bit is set (takesFailedEvidence false) takes none at the failed level. No allocation.
  SequentialStatus update(const MotorTheta& theta, int samples, std::uint8_t gate_mask = kAllMotorsObservable);
  const SequentialState& state() const { return state_; }
  bool active() const { return state_.severity != Severity::kHealthy; }
  // Gap or restart: every statistic, window and alarm back to the start.
  void reset();

  // Inspection (tests, calibration): the statistics of motor `k` (0-based).
  double degradedStatistic(int k) const { return degraded_[static_cast<std::size_t>(k)]; }
  double failedStatistic(int k) const { return failed_[static_cast<std::size_t>(k)]; }
  const SequentialConfig& config() const { return config_; }
  double z() const { return z_; }  // standard-normal quantile of the interval

 private:
  void estimate(int k);  // state_.theta_* for motor k

  SequentialConfig config_;
  double z_ = 1.6449;
  std::vector<SpreadBin> bins_;         // the noise model's ranges, or one range of its pooled spread
  std::vector<double> mean_variance_;  // [bin][n] noise variance of the mean of n consecutive samples, n = 0 … window
  std::array<double, kMotors> degraded_{}, failed_{};
  std::array<long, kMotors> since_change_{};  // samples since the degraded statistic left zero
  std::vector<float> window_;                 // [motor][estimate_window] ring buffers
  int window_at_ = 0;                          // next slot (shared: every motor gets every sample)
  long filled_ = 0;                            // samples pushed since reset
  long recovery_run_ = 0;                      // flagged motor at/above its level: consecutive samples
  SequentialState state_;
};

// One sample's increment of a CUSUM at `level` with an increment cap: min(level − Θ̂, cap)
// (a Huber-type robust CUSUM; the rule and its calibration share it).
inline double cusumIncrement(double level, double theta, double cap) { return std::min(level - theta, cap); }

// A belt's acceptance region at `theta` (linear between nodes; beyond the end nodes, the end
// node's region moved with theta). `belt` non-empty, ascending.
void beltAcceptance(const std::vector<BeltNode>& belt, double theta, double* lo, double* hi);
// The interval a belt gives an estimate: the least and greatest Θ on the grid 0, 1/kBeltGrid, …, 1
// whose acceptance region, widened by `widen` on each side, holds it; none: the Θ whose region is
// nearest, as a point. No allocation.
void invertBelt(const std::vector<BeltNode>& belt, double estimate, double widen, double* lo, double* hi);

// Standard-normal quantile Φ⁻¹(p), p in (0, 1) (bisection on erfc; to 1e-12).
double normalQuantile(double p);

// Variance of the mean of n consecutive samples of a stationary AR(1) with variance σ² and
// lag-1 correlation φ: σ²/n² [n(1+φ)/(1−φ) − 2φ(1−φⁿ)/(1−φ)²].
double ar1MeanVariance(double sigma, double phi, long n);

}  // namespace quadfdi
