#include "detection/sequential.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace quadfdi {

const char* toString(Severity s) {
  switch (s) {
    case Severity::kDegraded: return "degraded";
    case Severity::kFailed: return "failed";
    case Severity::kHealthy: break;
  }
  return "healthy";
}

const char* toString(ThetaReference r) { return r == ThetaReference::kOthers ? "others" : "absolute"; }

bool parseThetaReference(const std::string& text, ThetaReference* out) {
  if (text == "absolute") *out = ThetaReference::kAbsolute;
  else if (text == "others") *out = ThetaReference::kOthers;
  else return false;
  return true;
}

MotorTheta relativeToOthers(const MotorTheta& theta) {
  MotorTheta r;
  for (int k = 0; k < kMotors; ++k) {
    std::array<float, kMotors - 1> others;
    for (int j = 0, n = 0; j < kMotors; ++j)
      if (j != k) others[static_cast<std::size_t>(n++)] = theta[static_cast<std::size_t>(j)];
    std::sort(others.begin(), others.end());
    r[static_cast<std::size_t>(k)] = theta[static_cast<std::size_t>(k)] / std::max(kMinOthersMedian, others[1]);
  }
  return r;
}

void beltAcceptance(const std::vector<BeltNode>& belt, double theta, double* lo, double* hi) {
  const BeltNode* below = &belt.front();
  const BeltNode* above = &belt.back();
  if (theta <= below->theta) above = below;
  else if (theta >= above->theta) below = above;
  else {
    const auto it = std::upper_bound(belt.begin(), belt.end(), theta, [](double t, const BeltNode& n) { return t < n.theta; });
    above = &*it;
    below = &*(it - 1);
  }
  if (below == above) {  // outside the nodes: the end node's region moved with Θ
    *lo = below->accept_lo + (theta - below->theta);
    *hi = below->accept_hi + (theta - below->theta);
    return;
  }
  const double f = (theta - below->theta) / (above->theta - below->theta);
  *lo = below->accept_lo + f * (above->accept_lo - below->accept_lo);
  *hi = below->accept_hi + f * (above->accept_hi - below->accept_hi);
}

void invertBelt(const std::vector<BeltNode>& belt, double estimate, double widen, double* lo, double* hi) {
  double first = 2.0, last = -1.0, nearest = 0.0, nearest_gap = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kBeltGrid; ++i) {
    const double theta = static_cast<double>(i) / kBeltGrid;
    double a_lo, a_hi;
    beltAcceptance(belt, theta, &a_lo, &a_hi);
    const double gap = std::max({0.0, a_lo - widen - estimate, estimate - a_hi - widen});
    if (gap == 0.0) {
      first = std::min(first, theta);
      last = std::max(last, theta);
    } else if (gap < nearest_gap) {
      nearest_gap = gap;
      nearest = theta;
    }
  }
  if (last < first) first = last = nearest;
  *lo = first;
  *hi = last;
}

double normalQuantile(double p) {
  // Φ(x) = erfc(−x/√2)/2 is increasing: bisect on [−40, 40].
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 1e-13; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

double ar1MeanVariance(double sigma, double phi, long n) {
  if (n <= 0) return 0.0;
  const double dn = static_cast<double>(n);
  if (phi == 0.0) return sigma * sigma / dn;
  const double sum = dn * (1.0 + phi) / (1.0 - phi) - 2.0 * phi * (1.0 - std::pow(phi, dn)) / ((1.0 - phi) * (1.0 - phi));
  return sigma * sigma * sum / (dn * dn);
}

std::string validate(const SequentialConfig& c) {
  if (!(c.failed_below > 0.0 && c.failed_below < c.degraded_below && c.degraded_below <= 1.0))
    return "levels must satisfy 0 < failed_below < degraded_below <= 1";
  if (!(c.degraded_threshold > 0.0) || !(c.failed_threshold > 0.0)) return "CUSUM thresholds must be positive";
  if (!(c.degraded_cap > 0.0) || !(c.failed_cap > 0.0)) return "CUSUM increment caps must be positive (infinite: none)";
  if (c.clear_after < 1) return "clear_after must be at least 1 sample";
  if (c.estimate_window < 1 || c.estimate_window > 100000) return "estimate_window must be 1 … 100000 samples";
  if (!(c.interval_level > 0.0 && c.interval_level < 1.0)) return "interval_level must lie in (0, 1)";
  const ThetaNoiseModel& n = c.noise;
  if (!(n.sigma >= 0.0) || !(n.model_sigma >= 0.0) || !std::isfinite(n.sigma) || !std::isfinite(n.model_sigma))
    return "noise sigmas must be finite and non-negative";
  if (!(n.noise_scale > 0.0) || !std::isfinite(n.noise_scale)) return "noise noise_scale must be finite and positive";
  if (n.spread_bins.size() > kMaxSpreadBins) return "noise spread_bins: at most " + std::to_string(kMaxSpreadBins) + " ranges";
  for (std::size_t b = 0; b < n.spread_bins.size(); ++b) {
    const SpreadBin& bin = n.spread_bins[b];
    const std::string at = "noise spread_bins[" + std::to_string(b) + "]: ";
    if (!(bin.noise_scale > 0.0) || !std::isfinite(bin.noise_scale)) return at + "noise_scale must be finite and positive";
    if (!(bin.model_sigma >= 0.0) || !std::isfinite(bin.model_sigma)) return at + "model_sigma must be finite and non-negative";
    if (!std::isfinite(bin.estimate_below) || (b > 0 && !(bin.estimate_below > n.spread_bins[b - 1].estimate_below)))
      return at + "estimate_below must be finite and ascending";
  }
  if (!n.spread_bins.empty() && !(n.spread_bins.back().estimate_below >= 1.0)) return "noise spread_bins: the last range must reach 1";
  if (n.belt.size() > kMaxBeltNodes) return "noise belt: at most " + std::to_string(kMaxBeltNodes) + " nodes";
  for (std::size_t b = 0; b < n.belt.size(); ++b) {
    const BeltNode& node = n.belt[b];
    const std::string at = "noise belt[" + std::to_string(b) + "]: ";
    if (!std::isfinite(node.theta) || node.theta < 0.0 || node.theta > 1.0 || (b > 0 && !(node.theta > n.belt[b - 1].theta)))
      return at + "theta must lie in [0, 1] and ascend";
    if (!std::isfinite(node.accept_lo) || !std::isfinite(node.accept_hi) || !(node.accept_lo <= node.accept_hi))
      return at + "accept_lo and accept_hi must be finite with accept_lo <= accept_hi";
  }
  if (!(n.phi >= 0.0 && n.phi < 1.0)) return "noise phi must lie in [0, 1)";
  if (!std::isfinite(n.healthy_mean)) return "noise healthy_mean must be finite";
  return {};
}

SequentialRule::SequentialRule(const SequentialConfig& config) : config_(config) {
  if (std::string p = validate(config); !p.empty()) throw std::invalid_argument("sequential rule: " + p);
  z_ = normalQuantile(0.5 + 0.5 * config.interval_level);
  bins_ = config.noise.spread_bins;
  if (bins_.empty()) bins_.push_back({1.0, config.noise.noise_scale, config.noise.model_sigma, 0});
  const std::size_t per_bin = static_cast<std::size_t>(config.estimate_window) + 1;
  mean_variance_.resize(bins_.size() * per_bin);
  for (std::size_t b = 0; b < bins_.size(); ++b)
    for (int n = 0; n <= config.estimate_window; ++n)
      mean_variance_[b * per_bin + static_cast<std::size_t>(n)] = bins_[b].noise_scale * ar1MeanVariance(config.noise.sigma, config.noise.phi, n);
  window_.assign(static_cast<std::size_t>(kMotors) * static_cast<std::size_t>(config.estimate_window), 1.0f);
  reset();
}

void SequentialRule::reset() {
  degraded_.fill(0.0);
  failed_.fill(0.0);
  since_change_.fill(0);
  std::fill(window_.begin(), window_.end(), 1.0f);
  window_at_ = 0;
  filled_ = 0;
  recovery_run_ = 0;
  state_ = SequentialState{};
}

std::uint8_t evidenceMask(std::uint8_t observable, const MotorTheta& rule_input, ThetaReference reference) {
  if (reference != ThetaReference::kOthers) return observable;
  int seen = 0;
  bool a_seen_motor_reads_strong = false;
  for (int k = 0; k < kMotors; ++k) {
    if (!takesEvidence(observable, k)) continue;
    ++seen;
    a_seen_motor_reads_strong = a_seen_motor_reads_strong || !(rule_input[static_cast<std::size_t>(k)] < kMinOthersMedian);
  }
  return seen == 2 && !a_seen_motor_reads_strong ? std::uint8_t{0} : observable;
}

SequentialStatus SequentialRule::update(const MotorTheta& network_theta, int samples, std::uint8_t gate_mask) {
  const MotorTheta theta = ruleInput(network_theta, config_.reference);
  const std::uint8_t observable = evidenceMask(gate_mask, theta, config_.reference);
  const MotorTheta estimated = config_.estimate_reference == config_.reference ? theta : ruleInput(network_theta, config_.estimate_reference);
  const long n = std::max(1, samples);
  const double dn = static_cast<double>(n);
  const int w = config_.estimate_window;
  // The held estimate enters the windows once per sample it stands for (at most a full window).
  const long pushes = std::min<long>(n, w);
  for (int k = 0; k < kMotors; ++k) {
    const double x = static_cast<double>(theta[static_cast<std::size_t>(k)]);
    // Page's CUSUM with the reference at the level: it grows exactly while Θ̂ is below the level,
    // by at most the cap per sample. A held x adds the same increment n times, and max(0, ·) of a
    // constant-sign sum is the same whether applied once or per sample.
    // An unobservable motor (CommandGate) gains no evidence; what it has may still decay.
    // At the failed level a motor the controller is not commanding up gains none either (CommandGate).
    const double gain_limit = takesEvidence(observable, k) ? kNoIncrementCap : 0.0;
    const double failed_gain_limit = takesFailedEvidence(observable, k) ? kNoIncrementCap : 0.0;
    const double before = degraded_[static_cast<std::size_t>(k)];
    degraded_[static_cast<std::size_t>(k)] =
        std::max(0.0, before + dn * std::min(gain_limit, cusumIncrement(config_.degraded_below, x, config_.degraded_cap)));
    failed_[static_cast<std::size_t>(k)] = std::max(
        0.0, failed_[static_cast<std::size_t>(k)] + dn * std::min(failed_gain_limit, cusumIncrement(config_.failed_below, x, config_.failed_cap)));
    long& since = since_change_[static_cast<std::size_t>(k)];
    if (degraded_[static_cast<std::size_t>(k)] <= 0.0) since = 0;
    else since = (before <= 0.0) ? n : since + n;
    float* ring = &window_[static_cast<std::size_t>(k) * static_cast<std::size_t>(w)];
    for (long i = 0, at = window_at_; i < pushes; ++i, at = (at + 1 == w) ? 0 : at + 1) ring[at] = estimated[static_cast<std::size_t>(k)];
  }
  window_at_ = static_cast<int>((window_at_ + pushes) % w);
  filled_ += n;

  SequentialStatus status = SequentialStatus::kActive;
  if (state_.severity == Severity::kHealthy) {
    // Raise on the motor with the largest degraded statistic among those past a threshold (ties:
    // the lowest motor); failed if its failed statistic is past its own threshold.
    int best = -1;
    for (int k = 0; k < kMotors; ++k) {
      const std::size_t i = static_cast<std::size_t>(k);
      if (degraded_[i] < config_.degraded_threshold && failed_[i] < config_.failed_threshold) continue;
      if (best < 0 || degraded_[i] > degraded_[static_cast<std::size_t>(best)]) best = k;
    }
    if (best < 0) {
      bool building = false;
      for (double s : degraded_) building = building || s > 0.0;
      return building ? SequentialStatus::kBuilding : SequentialStatus::kHealthy;
    }
    state_.motor = best + 1;
    state_.severity = failed_[static_cast<std::size_t>(best)] >= config_.failed_threshold ? Severity::kFailed : Severity::kDegraded;
    recovery_run_ = 0;
    status = SequentialStatus::kRaised;
  } else {
    const std::size_t m = static_cast<std::size_t>(state_.motor - 1);
    const double x = static_cast<double>(theta[m]);
    if (state_.severity == Severity::kDegraded && failed_[m] >= config_.failed_threshold) {
      state_.severity = Severity::kFailed;
      recovery_run_ = 0;
      status = SequentialStatus::kEscalated;
    } else {
      // Hysteresis: the CUSUM raises on an accumulated deficit; recovery needs Θ̂ at or above the
      // level for clear_after samples without a break.
      const double level = state_.severity == Severity::kFailed ? config_.failed_below : config_.degraded_below;
      recovery_run_ = x >= level ? recovery_run_ + n : 0;
      if (recovery_run_ >= config_.clear_after) {
        recovery_run_ = 0;
        if (state_.severity == Severity::kFailed) {
          state_.severity = Severity::kDegraded;
          failed_[m] = 0.0;
          status = SequentialStatus::kRecovered;
        } else {
          degraded_[m] = failed_[m] = 0.0;
          since_change_[m] = 0;
          state_ = SequentialState{};
          return SequentialStatus::kCleared;
        }
      }
    }
  }
  estimate(state_.motor - 1);
  return status;
}

void SequentialRule::estimate(int k) {
  const int w = config_.estimate_window;
  // Samples since the change point the CUSUM found, at most the window (and at least one).
  const long n = std::max<long>(1, std::min<long>({since_change_[static_cast<std::size_t>(k)], w, filled_}));
  const float* ring = &window_[static_cast<std::size_t>(k) * static_cast<std::size_t>(w)];
  double sum = 0.0;
  int at = window_at_;
  for (long i = 0; i < n; ++i) {
    at = (at == 0) ? w - 1 : at - 1;
    sum += static_cast<double>(ring[at]);
  }
  state_.theta_est = sum / static_cast<double>(n);
  std::size_t b = 0;  // the estimate's range (the last takes everything above)
  while (b + 1 < bins_.size() && state_.theta_est >= bins_[b].estimate_below) ++b;
  const double variance = mean_variance_[b * (static_cast<std::size_t>(w) + 1) + static_cast<std::size_t>(n)];
  state_.standard_error = std::sqrt(variance + bins_[b].model_sigma * bins_[b].model_sigma);
  const std::vector<BeltNode>& belt = config_.noise.belt;
  if (belt.empty()) {
    state_.theta_lo = std::clamp(state_.theta_est - z_ * state_.standard_error, 0.0, 1.0);
    state_.theta_hi = std::clamp(state_.theta_est + z_ * state_.standard_error, 0.0, 1.0);
    return;
  }
  // The belt is fitted on full windows: a mean of fewer samples has more noise, which widens
  // every acceptance region by z times the extra standard deviation.
  const double full = mean_variance_[b * (static_cast<std::size_t>(w) + 1) + static_cast<std::size_t>(w)];
  const double widen = z_ * std::sqrt(std::max(0.0, variance - full));
  invertBelt(belt, state_.theta_est, widen, &state_.theta_lo, &state_.theta_hi);
}

}  // namespace quadfdi
