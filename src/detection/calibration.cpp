#include "detection/calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace quadfdi {
namespace {
constexpr double kSecondsPerHour = 3600.0;

// log P(Poisson(λ) ≤ k), summed in log space.
double poissonLogCdf(long k, double lambda) {
  if (lambda <= 0.0) return 0.0;
  double log_term = -lambda, acc = log_term;  // i = 0
  for (long i = 1; i <= k; ++i) {
    log_term += std::log(lambda) - std::log(static_cast<double>(i));
    const double hi = std::max(acc, log_term), lo = std::min(acc, log_term);
    acc = hi + std::log1p(std::exp(lo - hi));
  }
  return acc;
}

void fillAchieved(LevelCalibration& c, double flight_hours) {
  c.alarms_at_threshold = static_cast<long>(std::count_if(c.tail_maxima.begin(), c.tail_maxima.end(),
                                                          [&](double m) { return m >= c.threshold; }));
  c.rate_at_threshold = flight_hours > 0.0 ? static_cast<double>(c.alarms_at_threshold) / flight_hours : 0.0;
  c.rate_upper_bound = flight_hours > 0.0 ? poissonUpperBound(c.alarms_at_threshold) / flight_hours : 0.0;
}
}  // namespace

long fewestSamplesToAlarm(const LevelCalibration& l) {
  const double most_per_sample = std::min(l.level, l.increment_cap);
  // The relative slack keeps an exact multiple (3.0 / 0.15 = 19.999…96 or 20.000…04) at its count.
  return static_cast<long>(std::ceil(l.threshold / most_per_sample * (1.0 - 1e-12)));
}

double poissonUpperBound(long count, double confidence) {
  // λ with P(X ≤ count | λ) = 1 − confidence; the CDF falls as λ grows.
  const double target = std::log(1.0 - confidence);
  double lo = 0.0, hi = 10.0 + 3.0 * static_cast<double>(count);
  while (poissonLogCdf(count, hi) > target) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (poissonLogCdf(count, mid) > target) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

ThetaNoiseModel fitNoiseModel(const std::vector<std::vector<MotorTheta>>& streams, long skip, ThetaReference of) {
  double n = 0.0, sum = 0.0;
  for (const auto& s : streams)
    for (std::size_t i = static_cast<std::size_t>(std::max(0L, skip)); i < s.size(); ++i)
      for (float x : ruleInput(s[i], of)) sum += static_cast<double>(x), n += 1.0;
  ThetaNoiseModel m;
  if (n < 2.0) return m;
  const double mean = sum / n;
  double var = 0.0, cov = 0.0, pairs = 0.0;
  for (const auto& s : streams) {
    MotorTheta previous{};
    for (std::size_t i = static_cast<std::size_t>(std::max(0L, skip)); i < s.size(); ++i) {
      const MotorTheta x = ruleInput(s[i], of);
      for (int k = 0; k < kMotors; ++k) {
        const double d = static_cast<double>(x[static_cast<std::size_t>(k)]) - mean;
        var += d * d;
        if (i > static_cast<std::size_t>(std::max(0L, skip))) {
          cov += d * (static_cast<double>(previous[static_cast<std::size_t>(k)]) - mean);
          pairs += 1.0;
        }
      }
      previous = x;
    }
  }
  m.healthy_mean = mean;
  m.sigma = std::sqrt(var / (n - 1.0));
  m.phi = (var > 0.0 && pairs > 0.0) ? std::clamp((cov / pairs) / (var / n), 0.0, 0.999) : 0.0;
  return m;
}

SequentialConfig sequentialConfig(const LevelCalibration& degraded, const LevelCalibration& failed, const ThetaNoiseModel& noise,
                                  ThetaReference reference) {
  SequentialConfig c;
  c.reference = reference;
  c.estimate_reference = reference;
  c.degraded_below = degraded.level;
  c.failed_below = failed.level;
  c.degraded_threshold = degraded.threshold;
  c.failed_threshold = failed.threshold;
  c.degraded_cap = degraded.increment_cap;
  c.failed_cap = failed.increment_cap;
  c.failed_min_share = failed.min_command_share;
  c.degraded_min_share = degraded.min_command_share;
  c.noise = noise;
  return c;
}

SequentialConfig sequentialConfig(const DecisionCalibration& c) {
  SequentialConfig config = sequentialConfig(c.degraded, c.failed, c.noise, c.reference);
  config.estimate_reference = c.estimate_reference;
  config.noise = estimateNoise(c);
  return config;
}

namespace {
// Walks every motor's CUSUM of every stream and hands each finished excursion to `found`.
template <typename Found>
void walkExcursions(const std::vector<std::vector<MotorTheta>>& streams, double level, long skip, double cap,
                    const std::vector<std::vector<std::uint8_t>>* observable, EvidenceLevel of, Found&& found) {
  for (std::size_t f = 0; f < streams.size(); ++f)
    for (int k = 0; k < kMotors; ++k) {
      const std::vector<MotorTheta>& s = streams[f];
      const std::vector<std::uint8_t>* mask = observable && f < observable->size() && !(*observable)[f].empty() ? &(*observable)[f] : nullptr;
      double S = 0.0;
      Excursion e;
      e.stream = f;
      e.motor = k;
      for (std::size_t i = static_cast<std::size_t>(std::max(0L, skip)); i < s.size(); ++i) {
        double increment = cusumIncrement(level, static_cast<double>(s[i][static_cast<std::size_t>(k)]), cap);
        const bool gains = !mask || (of == EvidenceLevel::kFailed ? takesFailedEvidence((*mask)[i], k) : takesEvidence((*mask)[i], k));
        if (!gains) increment = std::min(increment, 0.0);  // as SequentialRule::update
        S = std::max(0.0, S + increment);
        if (S > 0.0) {
          if (e.peak == 0.0) e.start = static_cast<long>(i);
          e.peak = std::max(e.peak, S);
        } else if (e.peak > 0.0) {
          e.length = static_cast<long>(i) - e.start;
          found(e);
          e.peak = 0.0;
        }
      }
      if (e.peak > 0.0) {  // an excursion cut by the end of the flight
        e.length = static_cast<long>(s.size()) - e.start;
        found(e);
      }
    }
}
}  // namespace

std::vector<double> excursionMaxima(const std::vector<std::vector<MotorTheta>>& streams, double level, long skip, double cap,
                                    const std::vector<std::vector<std::uint8_t>>* observable, EvidenceLevel of) {
  std::vector<double> maxima;
  walkExcursions(streams, level, skip, cap, observable, of, [&](const Excursion& e) { maxima.push_back(e.peak); });
  return maxima;
}

std::vector<Excursion> largestExcursions(const std::vector<std::vector<MotorTheta>>& streams, double level, std::size_t count, long skip,
                                         double cap, const std::vector<std::vector<std::uint8_t>>* observable, EvidenceLevel of) {
  std::vector<Excursion> largest;  // kept sorted, largest first, at most `count`
  if (count == 0) return largest;
  walkExcursions(streams, level, skip, cap, observable, of, [&](const Excursion& e) {
    if (largest.size() == count && e.peak <= largest.back().peak) return;
    const auto at = std::find_if(largest.begin(), largest.end(), [&](const Excursion& x) { return e.peak > x.peak; });
    largest.insert(at, e);
    if (largest.size() > count) largest.pop_back();
  });
  return largest;
}

double siegmundThreshold(const ThetaNoiseModel& noise, double level, double rate_per_hour, double dt) {
  // Standardised by the long-run standard deviation σ_LR = σ √((1+φ)/(1−φ)): increments with
  // drift −Δ, Δ = (μ₀ − level)/σ_LR; ARL(b) ≈ (e^{2Δ(b+1.166)} − 1 − 2Δ(b+1.166)) / (2Δ²)
  // (Siegmund 1985, eq. 2.57), in samples; b = h/σ_LR.
  const double sigma_lr = std::max(1e-9, noise.sigma * std::sqrt((1.0 + noise.phi) / (1.0 - noise.phi)));
  const double delta = (noise.healthy_mean - level) / sigma_lr;
  const double arl_needed = static_cast<double>(kMotors) * kSecondsPerHour / (rate_per_hour * dt);  // per motor
  auto arl = [&](double b) {
    const double x = 2.0 * delta * (b + 1.166);
    if (std::abs(delta) < 1e-9) return (b + 1.166) * (b + 1.166);
    return (std::exp(std::min(x, 700.0)) - 1.0 - x) / (2.0 * delta * delta);
  };
  double lo = 0.0, hi = 1.0;
  while (arl(hi) < arl_needed && hi < 1e12) hi *= 2.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (arl(mid) < arl_needed ? lo : hi) = mid;
  }
  return std::max(kMinThreshold, hi * sigma_lr);
}

void retarget(LevelCalibration& c, double flight_hours, double rate_per_hour, const ThetaNoiseModel& noise, double dt) {
  // The stored fit (calibrateLevel's): N_u, the maxima at or above u.
  const auto fitted = static_cast<std::size_t>(
      std::count_if(c.tail_maxima.begin(), c.tail_maxima.end(), [&](double m) { return m >= c.tail_start; }));
  if (fitted >= static_cast<std::size_t>(kMinTail) && flight_hours > 0.0 && c.tail_scale > 0.0) {
    c.method = "tail";
    const double h = c.tail_start + c.tail_scale * std::log(static_cast<double>(fitted) / (flight_hours * rate_per_hour));
    c.threshold = std::max({kMinThreshold, c.tail_start, h});  // below u the fit says nothing: stay conservative
    // No more alarms in the data itself than the target expects of it (⌊target · T⌋; none below
    // one): h above the next largest excursion. A fit on the bulk of the tail extrapolated the few
    // largest excursions (another cause) too lightly — measured on the 1.5 kg quad's model before
    // kTailSpan: 5 alarms in its 5 calibration hours; and with the fit near the target, six of nine
    // 0.03-an-hour calibrations held more alarms in their own data than expected and measured 2–6
    // times the target on fresh flights. (A generalised Pareto fit by probability-weighted moments
    // was tried instead and dropped: on the general model's two-cluster tail it gave ξ = 0.57 and
    // h = 962 against a largest excursion of 29.)
    const double expected = std::floor(flight_hours * rate_per_hour);
    if (expected < static_cast<double>(c.tail_maxima.size()))
      c.threshold = std::max(c.threshold, std::nextafter(c.tail_maxima[static_cast<std::size_t>(expected)], std::numeric_limits<double>::infinity()));
  } else {
    c.method = "siegmund";
    c.threshold = siegmundThreshold(noise, c.level, rate_per_hour, dt);
  }
  fillAchieved(c, flight_hours);
}

LevelCalibration calibrateLevel(std::vector<double> maxima, double level, double flight_hours, double rate_per_hour,
                                const ThetaNoiseModel& noise, double dt, double cap) {
  LevelCalibration c;
  c.level = level;
  c.increment_cap = cap;
  c.excursions = static_cast<long>(maxima.size());
  std::sort(maxima.begin(), maxima.end(), std::greater<double>());
  const std::size_t k = std::clamp<std::size_t>(maxima.size() / 5, std::min<std::size_t>(maxima.size(), kMinTail), kMaxTail);
  c.tail_maxima.assign(maxima.begin(), maxima.begin() + static_cast<long>(k));
  // The exponential is fitted on the maxima at most kTailSpan times as frequent as the target (at
  // least kMinTail of them): u, the smallest of them, and β, their mean excess. A real model's
  // maxima are a mixture (estimator noise in the bulk, a manoeuvre's transient in the few
  // largest); a fit near the target describes the cause that sets it. The fit is kept: retarget
  // re-solves h on it for another rate, so h falls as the rate rises.
  if (k >= static_cast<std::size_t>(kMinTail) && flight_hours > 0.0) {
    const double wanted = std::min(std::ceil(kTailSpan * rate_per_hour * flight_hours), 1e9);
    const std::size_t fitted = std::clamp<std::size_t>(static_cast<std::size_t>(wanted), kMinTail, k);
    c.tail_start = c.tail_maxima[fitted - 1];
    double excess = 0.0;
    for (std::size_t i = 0; i < fitted; ++i) excess += c.tail_maxima[i] - c.tail_start;
    c.tail_scale = excess / static_cast<double>(fitted - 1);
  }
  retarget(c, flight_hours, rate_per_hour, noise, dt);
  return c;
}

EstimateSpread fitEstimateSpread(const std::vector<double>& estimates, const std::vector<double>& truths,
                                 const std::vector<double>& noise_variances, double coverage) {
  if (estimates.empty()) return {ThetaNoiseModel{}.noise_scale, ThetaNoiseModel{}.model_sigma};
  const double z = normalQuantile(0.5 + 0.5 * coverage);
  const double rank = std::ceil(static_cast<double>(estimates.size() + 1) * coverage);
  const std::size_t at = std::min(estimates.size(), static_cast<std::size_t>(std::max(1.0, rank))) - 1;
  auto quantile = [&](std::vector<double> needs) {
    std::nth_element(needs.begin(), needs.begin() + static_cast<long>(at), needs.end());
    return needs[at];
  };
  std::vector<double> scale(estimates.size()), additive(estimates.size());
  for (std::size_t i = 0; i < estimates.size(); ++i) {
    const double e = std::abs(estimates[i] - truths[i]) / z;
    scale[i] = noise_variances[i] > 0.0 ? e / std::sqrt(noise_variances[i]) : (e > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
    additive[i] = std::sqrt(std::max(0.0, e * e - noise_variances[i]));
  }
  const double q = quantile(scale);
  if (q <= 1.0) return {std::max(q * q, kMinNoiseScale), 0.0};
  return {1.0, quantile(additive)};
}

std::vector<SpreadBin> fitBinnedEstimateSpread(const std::vector<double>& estimates, const std::vector<double>& truths,
                                               const std::vector<double>& noise_variances, double coverage, const std::vector<double>& edges) {
  // Ranges [bounds[b − 1], bounds[b]), the last open above; merged until each has enough pairs.
  std::vector<double> bounds = edges;
  bounds.push_back(std::numeric_limits<double>::infinity());
  auto pairsIn = [&](std::size_t b) {
    const double lo = b == 0 ? -std::numeric_limits<double>::infinity() : bounds[b - 1];
    return static_cast<long>(std::count_if(estimates.begin(), estimates.end(), [&](double e) { return e >= lo && e < bounds[b]; }));
  };
  for (std::size_t b = 0; bounds.size() > 1 && b < bounds.size();) {
    if (pairsIn(b) >= kMinSpreadPairs) {
      ++b;
      continue;
    }
    // Too few: drop the bound above (join the next range) or, for the last range, the one below.
    bounds.erase(bounds.begin() + static_cast<long>(b + 1 < bounds.size() ? b : b - 1));
    if (b == bounds.size()) --b;
  }
  std::vector<SpreadBin> bins;
  for (std::size_t b = 0; b < bounds.size(); ++b) {
    const double lo = b == 0 ? -std::numeric_limits<double>::infinity() : bounds[b - 1];
    std::vector<double> est, truth, var;
    for (std::size_t i = 0; i < estimates.size(); ++i)
      if (estimates[i] >= lo && estimates[i] < bounds[b]) {
        est.push_back(estimates[i]);
        truth.push_back(truths[i]);
        var.push_back(noise_variances[i]);
      }
    const EstimateSpread s = fitEstimateSpread(est, truth, var, coverage);
    bins.push_back({b + 1 == bounds.size() ? 1.0 : bounds[b], s.noise_scale, s.model_sigma, static_cast<long>(est.size())});
  }
  return bins;
}

std::vector<BeltNode> fitThetaBelt(const std::vector<double>& estimates, const std::vector<double>& truths, double coverage,
                                   const std::vector<double>& nodes, double half_width) {
  std::vector<BeltNode> belt;
  const double alpha = 1.0 - coverage;
  std::vector<double> moved;
  for (double g : nodes) {
    moved.clear();
    // At the boundary the estimate is clipped, not shifted, as Θ moves: Θ = 0.04 errs downward where
    // Θ = 0 cannot, so the node takes complete failures only (measured: truths up to 0.02 with them
    // put the racer's Θ = 0 at 97 % for a nominal 90 %).
    const bool boundary = g <= 0.0;
    for (std::size_t i = 0; i < estimates.size() && i < truths.size(); ++i)
      if (boundary ? truths[i] <= kBeltBoundaryWidth : std::abs(truths[i] - g) <= half_width)
        moved.push_back(boundary ? estimates[i] : g + estimates[i] - truths[i]);
    if (moved.size() < static_cast<std::size_t>(kMinSpreadPairs)) continue;
    std::sort(moved.begin(), moved.end());
    const double n = static_cast<double>(moved.size());
    auto rank = [&](double r) { return moved[static_cast<std::size_t>(std::clamp(r, 1.0, n)) - 1]; };  // 1-based
    BeltNode node;
    node.theta = g;
    node.pairs = static_cast<long>(moved.size());
    if (boundary) {
      node.accept_lo = std::min(0.0, moved.front());
      node.accept_hi = rank(std::ceil((n + 1.0) * coverage));
    } else {
      node.accept_lo = rank(std::floor((n + 1.0) * alpha / 2.0));
      node.accept_hi = rank(std::ceil((n + 1.0) * (1.0 - alpha / 2.0)));
    }
    belt.push_back(node);
  }
  return belt;
}

DecisionCalibration defaultCalibration(double degraded_below, double failed_below, double target_rate, double dt) {
  DecisionCalibration c;
  c.target_rate = target_rate;
  c.dt = dt;
  c.source = "defaults (docs/decisions.md): noise model of the shipped TCN, thresholds by Siegmund's approximation";
  c.degraded = calibrateLevel({}, degraded_below, 0.0, target_rate / 2.0, c.noise, dt);
  c.failed = calibrateLevel({}, failed_below, 0.0, target_rate / 2.0, c.noise, dt);
  return c;
}

std::string calibrationModelProblem(const DecisionCalibration& c, std::uint32_t model_crc32) {
  if (!c.model_crc32 || model_crc32 == 0 || *c.model_crc32 == model_crc32) return "";
  return "made for another model (weights file CRC-32 " + crc32Hex(*c.model_crc32) + ", this model's " + crc32Hex(model_crc32) +
         "): recalibrate with quadfdi calibrate --model MODEL, or give the calibration made for this model";
}

std::string crc32Hex(std::uint32_t crc) {
  char text[11];
  std::snprintf(text, sizeof text, "0x%08x", crc);
  return text;
}

}  // namespace quadfdi
