// Steps that stand out of their neighbours: see reset_steps.h.
#include "logs/reset_steps.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace quadfdi {

ResetSteps findResetSteps(const std::vector<double>& unexplained, const ResetStepRule& rule) {
  const std::size_t n = unexplained.size();
  ResetSteps found;
  found.step.assign(n, 0.0);
  std::vector<double> beyond(n, std::numeric_limits<double>::quiet_NaN()), around, sizes;
  const std::size_t w = static_cast<std::size_t>(std::max(1, rule.neighbours));
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(unexplained[k])) continue;
    around.clear();
    for (std::size_t j = k > w ? k - w : 0; j <= std::min(n - 1, k + w); ++j)
      if (j != k && std::isfinite(unexplained[j])) around.push_back(unexplained[j]);
    double smooth = 0.0;
    if (around.size() >= 2) {
      std::nth_element(around.begin(), around.begin() + static_cast<std::ptrdiff_t>(around.size() / 2), around.end());
      smooth = around[around.size() / 2];
    }
    beyond[k] = unexplained[k] - smooth;
    sizes.push_back(std::abs(beyond[k]));
  }
  found.compared = sizes.size();
  if (sizes.empty()) return found;
  std::nth_element(sizes.begin(), sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2), sizes.end());
  found.noise = 1.4826 * sizes[sizes.size() / 2];
  found.threshold = std::max(rule.min_step, rule.noise_multiple * found.noise);
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(beyond[k])) continue;
    const double size = std::abs(beyond[k]);
    if (size > found.threshold) {
      found.step[k] = beyond[k];
      ++found.count;
      if (size > found.largest) {
        found.largest = size;
        found.largest_row = k;
      }
    } else {
      found.largest_left = std::max(found.largest_left, size);
    }
  }
  return found;
}

}  // namespace quadfdi
