// The named scales (tiny, quick, default, paper) in one place: for each, the data side of
// Algorithm 1, the training schedule and the evaluation size. generate, train, evaluate and
// reproduce all read this table; an unknown name is refused, never taken for another.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace quadfdi {

// Algorithm 1's data per outer iteration. The paper's text says N₁ = 200 and a 1.5 M-window
// buffer; the authors' code flies 1 100 trajectories per iteration (N₁ = 100 × 11 Θ values),
// which `paper` follows.
struct DataScale {
  std::string name;                // recorded in model files as the training scale
  int initial_conditions = 0;      // N₁ per outer iteration [initial conditions]
  std::size_t buffer_windows = 0;  // N_buf, the FIFO buffer's capacity [windows]
};

// Algorithm 1's optimisation schedule.
struct TrainSchedule {
  int batch_size = 0;                  // windows per minibatch
  int passes = 0;                      // passes over the buffer per outer iteration
  int max_minibatches = 0;             // cap per outer iteration [minibatches], 0 = none
  int min_iterations = 0;              // N_m: no stop before this many outer iterations
  int max_iterations = 0;              // N_M: outer iterations at most
  int heldout_initial_conditions = 0;  // held-out set [initial conditions], flown at every Θ value
};

struct NamedScale {
  std::string name;            // tiny | quick | default | paper
  DataScale data;              // what one outer iteration generates and the buffer keeps
  TrainSchedule training;
  int test_flights_per_class;  // docs/decisions.md test sets [flights per fault class]; the protocol: 2 000
};

// Every named scale, smallest first.
const std::vector<NamedScale>& namedScales();
// Their names, in the same order (for choice lists and messages).
std::vector<std::string> scaleNames();
// The scale called `name`, or nullptr with `problem` (when given) set to
// "unknown scale 'x' (known: tiny, quick, default, paper)".
const NamedScale* findScale(const std::string& name, std::string* problem = nullptr);

}  // namespace quadfdi
