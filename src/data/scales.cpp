#include "data/scales.h"

namespace quadfdi {

const std::vector<NamedScale>& namedScales() {
  // {name, {data name, N₁, N_buf}, {batch, passes, max minibatches, N_m, N_M, held-out N₁}, test flights}
  static const std::vector<NamedScale> scales = {
      // Tests: 44 trajectories an iteration, a few seconds end to end.
      {"tiny", {"tiny", 4, 20'000}, {256, 1, 8, 1, 2, 1}, 3},
      // Checks the chain end to end (reproduce --scale quick, ≈ 2 min an LSTM on 2 cores): the
      // default data scale (and its name in model files), five short iterations.
      {"quick", {"default", 40, 200'000}, {512, 1, 40, 5, 5, 5}, 25},
      // CPU: 440 trajectories an iteration, ≈ 15 min an LSTM on 2 cores.
      {"default", {"default", 40, 200'000}, {512, 1, 60, 10, 16, 20}, 200},
      // The paper's: the authors' 1 100 trajectories, the paper's N_buf, batch, passes and N_m; a GPU.
      {"paper", {"paper", 100, 1'500'000}, {50'000, 400, 0, 250, 500, 20}, 2000},
  };
  return scales;
}

std::vector<std::string> scaleNames() {
  std::vector<std::string> names;
  for (const NamedScale& s : namedScales()) names.push_back(s.name);
  return names;
}

const NamedScale* findScale(const std::string& name, std::string* problem) {
  for (const NamedScale& s : namedScales())
    if (s.name == name) return &s;
  if (problem) {
    std::string known;
    for (const NamedScale& s : namedScales()) known += (known.empty() ? "" : ", ") + s.name;
    *problem = "unknown scale '" + name + "' (known: " + known + ")";
  }
  return nullptr;
}

}  // namespace quadfdi
