// Thresholds of the sequential rule from a target false-alarm rate per flight hour (issue 14,
// docs/decisions.md "Calibration"). Input: Θ̂ streams of healthy flights at the model rate, one
// MotorTheta per model sample. Output: a plain DecisionCalibration (noise model, thresholds, the
// tail data they came from, the achieved rate and its Poisson upper bound); io/calibration_file
// reads and writes it as JSON.
//
// Method: peaks over threshold of the CUSUM's excursions. On healthy data each motor's CUSUM is a
// reflected random walk with negative drift; its excursions above zero are independent (renewal)
// and their maxima have an exponential tail (Cramér–Lundberg: P(max > h) ∝ exp(−θ*h)), so the
// rate of excursions whose maximum exceeds h — the false alarms a threshold h gives — is
// λ(h) = (N_u / T) · exp(−(h − u) / β), fitted on the N_u largest maxima (u: the smallest of them,
// β: their mean excess, the exponential's maximum-likelihood scale), those at most kTailSpan times
// as frequent as the target. h solves λ(h) = target.
// h is also kept above the (⌊target · T⌋ + 1)-th largest excursion of the calibration data, so the
// data itself holds no more alarms than the target expects of it (none when target · T < 1): the
// exponential fitted near the target was lighter than the flights' own tail, and six of nine
// calibrations at 0.03 an hour measured 2–6 times that on fresh flights (models/README.md,
// "2026-11-26, later").
// With too few excursions (a level far below healthy Θ̂, such as `failed`) it falls back to
// Siegmund's approximation of the CUSUM's average run length for the AR(1) noise model, whose
// long-run variance σ²(1+φ)/(1−φ) accounts for the autocorrelation of Θ̂.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "detection/sequential.h"

namespace quadfdi {

struct LevelCalibration {
  double level = 0.9;               // [-] the CUSUM's reference (degraded_below or failed_below)
  double increment_cap = kNoIncrementCap;  // [effectiveness] the CUSUM's cap per sample (SequentialConfig::degraded_cap)
  double min_command_share = 0.0;   // [-] the CommandGate's failed_min_share (failed level) or degraded_min_share (degraded) the excursions were taken
                                    //     under, which the detector must gate with (0: none; absent from older files)
  double threshold = 3.0;           // [effectiveness·samples] h for the target rate
  std::string method = "siegmund";  // "tail" (fitted on excursions) | "siegmund" (noise model)
  long excursions = 0;              // [-] CUSUM excursions above zero in the data, all motors
  std::vector<double> tail_maxima;  // [effectiveness·samples] the largest excursion maxima, descending
  double tail_start = 0.0;          // [effectiveness·samples] u: the smallest maximum of the tail
  double tail_scale = 0.0;          // [effectiveness·samples] β: mean excess over u
  long alarms_at_threshold = 0;     // [-] excursions reaching h in the data (false alarms it would raise)
  double rate_at_threshold = 0.0;   // [1/flight hour] that count / flight hours
  double rate_upper_bound = 0.0;    // [1/flight hour] one-sided 95 % Poisson (Garwood) bound on it
};

struct DecisionCalibration {
  ThetaNoiseModel noise;     // of the `reference` quantity: the thresholds' fallback (Siegmund) and, when the estimate
                             // reads the same quantity, the interval
  double target_rate = 0.1;  // [false alarms / flight hour] of the whole vehicle, split evenly over the two levels
  double dt = 0.002;         // [s] model sample period of the data
  long flights = 0;          // [-] healthy flights
  double flight_hours = 0.0; // [h] healthy flight time, per vehicle (not per motor)
  long faulty_flights = 0;   // [-] faulty flights used for noise.model_sigma (0: default kept)
  ThetaReference reference = ThetaReference::kAbsolute;  // the quantity calibrated (SequentialConfig::reference)
  ThetaReference estimate_reference = ThetaReference::kAbsolute;  // what the estimate reads (SequentialConfig::estimate_reference)
  ThetaNoiseModel estimate_noise;  // of the estimate_reference quantity, for the interval; used only where it differs
                                   // from `reference`
  LevelCalibration degraded, failed;
  std::string source;        // provenance: command, model, simulation settings
  // The CRC-32 of the weights file calibrated (TrainedModel::file_crc32): thresholds fitted on one
  // network's Θ̂ mean nothing for another's, so a model with another CRC is refused
  // (calibrationModelProblem). Absent (nullopt) in files written before 2026-11-27: not checked.
  std::optional<std::uint32_t> model_crc32;
};

// "" when `c` may run with a model whose weights file has CRC `model_crc32`; else why not, naming
// both CRCs (hex). A calibration without a recorded CRC, or a model not read from a file (0), passes.
std::string calibrationModelProblem(const DecisionCalibration& c, std::uint32_t model_crc32);
std::string crc32Hex(std::uint32_t crc);  // "0x" and eight lower-case hex digits, as calibration files write it

// The rule for two calibrated levels and a noise model of the `reference` quantity: their levels,
// thresholds and caps; the estimate reads the same quantity; every other setting (clear_after,
// estimate_window, interval_level) at its default.
SequentialConfig sequentialConfig(const LevelCalibration& degraded, const LevelCalibration& failed, const ThetaNoiseModel& noise,
                                  ThetaReference reference);

// Whether the estimate reads another quantity than the statistics, so that its interval has a
// noise model of its own (estimate_noise).
inline bool ownEstimateNoise(const DecisionCalibration& c) { return c.estimate_reference != c.reference; }
// The noise model of what the estimate reads: estimate_noise where it is its own, else noise.
inline const ThetaNoiseModel& estimateNoise(const DecisionCalibration& c) { return ownEstimateNoise(c) ? c.estimate_noise : c.noise; }
inline ThetaNoiseModel& estimateNoise(DecisionCalibration& c) { return ownEstimateNoise(c) ? c.estimate_noise : c.noise; }

// The rule a calibration describes: sequentialConfig of its levels, its estimate's reference and
// the noise model of that quantity.
SequentialConfig sequentialConfig(const DecisionCalibration& c);

// The default calibration (no data): the default noise model (of absolute Θ̂), thresholds by
// Siegmund, no caps.
DecisionCalibration defaultCalibration(double degraded_below, double failed_below, double target_rate, double dt);

// Pooled over motors and flights (each stream's first `skip` samples dropped): mean, standard
// deviation and lag-1 autocorrelation of ruleInput(Θ̂, of). model_sigma is left at the default.
ThetaNoiseModel fitNoiseModel(const std::vector<std::vector<MotorTheta>>& streams, long skip = 0,
                              ThetaReference of = ThetaReference::kAbsolute);

// Which of the rule's two statistics an excursion is of: the masks withhold more at the failed level
// (CommandGate's failed_min_share).
enum class EvidenceLevel { kDegraded, kFailed };

// Every excursion maximum of the CUSUM S_k = max(0, S_{k−1} + min(level − Θ̂_k, cap)) of every
// motor of every stream (unsorted). With `observable` (per stream, per sample, CommandGate masks;
// an empty stream entry: all observable), a motor's statistic gains nothing while it is hidden (at
// the failed level: or withheld), as in the rule.
std::vector<double> excursionMaxima(const std::vector<std::vector<MotorTheta>>& streams, double level, long skip = 0,
                                    double cap = kNoIncrementCap,
                                    const std::vector<std::vector<std::uint8_t>>* observable = nullptr,
                                    EvidenceLevel of = EvidenceLevel::kDegraded);

// One excursion of one motor's CUSUM in one stream: which flight and when, for a calibration to say
// which flights set its threshold (a few long healthy dips can decide h alone).
struct Excursion {
  std::size_t stream = 0;  // [-] index into the streams
  int motor = 0;           // [-] 0-based
  double peak = 0.0;       // [effectiveness·samples] the excursion's maximum
  long start = 0;          // [samples] stream index of its first positive sample
  long length = 0;         // [samples] from its start to where it returned to zero (or the stream ended)
};

// The `count` largest excursions of excursionMaxima's walk (same arguments), largest first.
std::vector<Excursion> largestExcursions(const std::vector<std::vector<MotorTheta>>& streams, double level, std::size_t count,
                                         long skip = 0, double cap = kNoIncrementCap,
                                         const std::vector<std::vector<std::uint8_t>>* observable = nullptr,
                                         EvidenceLevel of = EvidenceLevel::kDegraded);

// Siegmund's ARL approximation for the AR(1) noise model: the CUSUM threshold h at `level` for
// `rate_per_hour` false alarms per flight hour over kMotors motors at period dt. At least h_min.
double siegmundThreshold(const ThetaNoiseModel& noise, double level, double rate_per_hour, double dt);

// Fits a level from its excursion maxima (of the CUSUM with increment cap `cap`) over
// `flight_hours` (per vehicle) for `rate_per_hour`; falls back to Siegmund with fewer than
// kMinTail maxima (Siegmund's Gaussian increments ignore the cap: conservative, since a cap only
// removes evidence).
LevelCalibration calibrateLevel(std::vector<double> maxima, double level, double flight_hours, double rate_per_hour,
                                const ThetaNoiseModel& noise, double dt, double cap = kNoIncrementCap);
// Re-solves an existing level's threshold for another target rate from its stored tail.
void retarget(LevelCalibration& c, double flight_hours, double rate_per_hour, const ThetaNoiseModel& noise, double dt);

// The estimate's spread beyond the healthy noise model: noise_scale and model_sigma of
// ThetaNoiseModel, so that the interval theta_est ± z·√(noise_scale·noise variance + model_sigma²)
struct EstimateSpread {
  double noise_scale = 1.0;  // [-]
  double model_sigma = 0.0;  // [-]
};

// …holds Θ in `coverage` (two-sided, z = Φ⁻¹(½ + ½ coverage)) of the pairs of faulty flights:
// `estimates` and `truths` are pairs (theta_est, Θ) taken once the fault has been flown through,
// `noise_variances` the healthy noise model's variance of each estimate. Split-conformal: each pair
// needs a scale r = |theta_est − Θ| / (z·√variance) of its noise; with q the ⌈(n + 1)·coverage⌉-th
// smallest need, q ≤ 1 gives noise_scale q² and model_sigma 0, else noise_scale 1 and model_sigma
// the same rank of the additive needs √(max(0, (theta_est − Θ)²/z² − variance)). Fitted on
// coverage rather than on the RMS error: the errors are heavy-tailed and healthy Θ̂ is noisier than
// a flown-through estimate, and the RMS fit's intervals held Θ 97–100 % of the time for a nominal
// 90 % in the per-vehicle models' trained conditions (docs/decisions.md "The Θ estimate and its
// interval"). No pairs: the default noise model's spread.
EstimateSpread fitEstimateSpread(const std::vector<double>& estimates, const std::vector<double>& truths,
                                 const std::vector<double>& noise_variances, double coverage);

// [-] Bounds of the estimate's ranges that `calibrate` fits apart (fitBinnedEstimateSpread): the
// per-vehicle models' pooled fits held Θ in 17–63 % of flown-through estimates at Θ 0–0.1 and
// 97–100 % at Θ 0.7–0.8 for a nominal 90 % (docs/results/vehicles until the evening of 2026-11-25); finer near 0,
// where the estimate is one-sided.
inline const std::vector<double> kSpreadBinEdges{0.05, 0.15, 0.3, 0.5, 0.7};
inline constexpr long kMinSpreadPairs = 60;  // [-] fewest pairs a range is fitted on (≈ 10 faulty flights of 6 windows)

// Mondrian split-conformal (Vovk et al. 2005, "Algorithmic Learning in a Random World", §4.5): the
// pairs are split by their estimate at `edges` (ascending, inside (0, 1)) and each range is fitted
// as fitEstimateSpread on its own pairs, so the interval holds Θ at its coverage within every range
// of the estimate, not only on average. A range with fewer than kMinSpreadPairs pairs joins the
// next (the last joins the one before); no pairs at all: one range of the default spread.
std::vector<SpreadBin> fitBinnedEstimateSpread(const std::vector<double>& estimates, const std::vector<double>& truths,
                                               const std::vector<double>& noise_variances, double coverage,
                                               const std::vector<double>& edges = kSpreadBinEdges);

// [-] The belt's nodes that `calibrate --interval belt` fits (its faulty flights draw Θ uniformly
// from [0, 0.9]), and the half-width of the truths each node pools.
inline const std::vector<double> kBeltNodes{0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
inline constexpr double kBeltHalfWidth = 0.05;
inline constexpr double kBeltBoundaryWidth = 1e-9;  // [-] the node at Θ = 0 takes the complete failures only, unshifted

// A confidence belt (Neyman 1937) at `coverage`: per node g, the pairs whose truth lies within
// `half_width` of g, each moved to g (g + estimate − Θ), give the acceptance region — their
// central `coverage` range (split-conformal ranks ⌊(n + 1)α/2⌋ and ⌈(n + 1)(1 − α/2)⌉), except at
// g = 0, the physical boundary, where the estimate can only err upward: there every estimate up to
// the ⌈(n + 1)·coverage⌉-th smallest is accepted. Inverting it (SequentialRule) gives an interval
// that holds Θ at `coverage` for each Θ, where a spread per range of the estimate holds it only on
// average over the Θ that produce that range (docs/decisions.md "The confidence belt"). A node
// with fewer than kMinSpreadPairs pairs is left out.
std::vector<BeltNode> fitThetaBelt(const std::vector<double>& estimates, const std::vector<double>& truths, double coverage,
                                   const std::vector<double>& nodes = kBeltNodes, double half_width = kBeltHalfWidth);

// The fewest samples in which a CUSUM at this level can reach its threshold, however clear the
// fault: Θ̂ ≥ 0, so a sample adds at most min(level, cap), and S ≥ h needs ⌈h / min(level, cap)⌉
// of them (docs/decisions.md "Why the 1.5 kg quad is late"). `l.threshold` > 0, `l.level` > 0.
long fewestSamplesToAlarm(const LevelCalibration& l);

// One-sided upper confidence bound of a Poisson mean after `count` events (Garwood 1936:
// ½ χ²_{2(count+1)}(confidence)), by bisection on the Poisson distribution function.
double poissonUpperBound(long count, double confidence = 0.95);

inline constexpr int kMinTail = 10;        // [-] fewest excursion maxima for a tail fit
inline constexpr int kMaxTail = 200;       // [-] most maxima kept in the tail
// [-] The fit's tail: the maxima at most this many times as frequent as the target rate, so h lies
// at most ln 20 ≈ 3 scales beyond u. The per-vehicle models' maxima are a mixture — estimator noise
// in the bulk, the few largest from manoeuvre transients (docs/decisions.md "Calibration") — and a
// fit on the top kMaxTail (the bulk) put the racer's degraded h at 4.0 for 0.05 alarms an hour where
// its own 5 calibration hours held four maxima above 4.8.
inline constexpr double kTailSpan = 20.0;
// [effectiveness] The degraded level's increment cap that `calibrate` uses by default: swept over
// 0.1 … 0.3 and none at level 0.8 on the three per-vehicle models' calibration flights (5 h each)
// and held-out E7-style flights, 0.1 isolated the most partial faults at +300 ms on every vehicle
// with no false alarm in 10 test hours each (docs/decisions.md "Capped increments").
inline constexpr double kDefaultDegradedCap = 0.1;
inline constexpr double kMinNoiseScale = 1e-4;  // [-] floor of EstimateSpread::noise_scale: an interval never shrinks to a point
inline constexpr double kMinThreshold = 1.0;  // [effectiveness·samples] floor on h: at least 10 samples 0.1 below the level

}  // namespace quadfdi
