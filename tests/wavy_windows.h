// Network input windows that exercise every weight: a sine of the flat index, the same for every
// architecture's comparison against LibTorch.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "inference/model_metadata.h"

namespace quadfdi::test {

// `count` windows of m.window samples × m.channels() features, back to back.
inline std::vector<float> wavyWindows(const ModelMetadata& m, int count) {
  std::vector<float> w(static_cast<std::size_t>(count) * static_cast<std::size_t>(m.window * m.channels()));
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = static_cast<float>(std::sin(0.37 * static_cast<double>(i)));
  return w;
}

}  // namespace quadfdi::test
