#include "evaluation/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace quadfdi {
namespace {

AccuracyByLength accuracy(const std::vector<WindowOutcome>& outcomes, int max_length, bool healthy,
                          double tolerance) {
  std::vector<int> hits(static_cast<std::size_t>(max_length + 1), 0);
  AccuracyByLength r;
  r.windows.assign(static_cast<std::size_t>(max_length + 1), 0);
  for (const WindowOutcome& o : outcomes) {
    if ((o.true_motor == 0) != healthy) continue;
    if (o.faulty_length < 0 || o.faulty_length > max_length) continue;
    const auto l = static_cast<std::size_t>(o.faulty_length);
    bool correct;
    if (healthy || o.faulty_length == 0) {
      correct = !o.decision.alarm;
    } else {
      correct = o.decision.alarm && o.decision.motor == o.true_motor;
      if (correct && tolerance >= 0.0) correct = std::abs(o.theta_hat(o.true_motor - 1) - o.true_theta) <= tolerance;
    }
    ++r.windows[l];
    hits[l] += correct;
  }
  r.accuracy.resize(hits.size());
  for (std::size_t l = 0; l < hits.size(); ++l)
    r.accuracy[l] = r.windows[l] > 0 ? static_cast<double>(hits[l]) / r.windows[l] : std::numeric_limits<double>::quiet_NaN();
  return r;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  // Nearest-rank definition: the smallest value with at least p of the data at or below it.
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

}  // namespace

AccuracyByLength isolationAccuracy(const std::vector<WindowOutcome>& outcomes, int max_length, bool healthy) {
  return accuracy(outcomes, max_length, healthy, -1.0);
}

AccuracyByLength identificationAccuracy(const std::vector<WindowOutcome>& outcomes, int max_length, double tolerance) {
  return accuracy(outcomes, max_length, false, tolerance);
}

DetectionDelay detectionDelay(const std::vector<WindowOutcome>& outcomes) {
  std::map<int, int> first;  // trajectory → first correct L (−1: none yet)
  for (const WindowOutcome& o : outcomes) {
    if (o.true_motor == 0) continue;
    auto it = first.emplace(o.trajectory, -1).first;
    if (o.faulty_length >= 1 && o.decision.alarm && o.decision.motor == o.true_motor &&
        (it->second < 0 || o.faulty_length < it->second))
      it->second = o.faulty_length;
  }
  DetectionDelay d;
  std::vector<double> delays;
  for (const auto& [trajectory, l] : first) {
    ++d.faulty;
    if (l >= 0) delays.push_back(l);
  }
  d.detected = static_cast<int>(delays.size());
  d.median = percentile(delays, 0.5);
  d.p95 = percentile(delays, 0.95);
  return d;
}

double falseAlarmRate(const std::vector<WindowOutcome>& outcomes) {
  int n = 0, alarms = 0;
  for (const WindowOutcome& o : outcomes)
    if (o.true_motor == 0 || o.faulty_length == 0) {
      ++n;
      alarms += o.decision.alarm;
    }
  return n > 0 ? static_cast<double>(alarms) / n : 0.0;
}

double thetaMae(const std::vector<WindowOutcome>& outcomes) {
  double sum = 0.0;
  int n = 0;
  for (const WindowOutcome& o : outcomes)
    if (o.true_motor != 0 && o.faulty_length >= 1) {
      sum += std::abs(o.theta_hat(o.true_motor - 1) - o.true_theta);
      ++n;
    }
  return n > 0 ? sum / n : 0.0;
}

}  // namespace quadfdi
