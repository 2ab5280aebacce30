// Batched, parallel generation of fault trajectories (docs/data.md, Algorithm 1's data side).
// Each trajectory is a pure function of (seed, scenario index, job), so the output is
// byte-identical whatever the thread count.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "control/controller_factory.h"
#include "data/randomisation.h"
#include "data/trajectory_batch.h"
#include "simulation/sampling.h"

namespace quadfdi {

struct RolloutConfig {
  VehicleParams plant = nominalParams();             // the vehicle flown
  VehicleParams controller_model = nominalParams();  // what the controller is designed on
  // The model behind the residual ỹ; docs/data.md: always the nominal parameters, which is what
  // makes model-based FDI fragile when the plant is perturbed.
  VehicleParams residual_model = nominalParams();
  ControllerConfig controller;
  SamplingRanges ranges;
  Integrator integrator = Integrator::kRk4;
  double dt = 0.002;        // [s] sample period (docs/model.md)
  int window = 100;         // T [samples]; trajectories hold 2T + 1 samples, fault at step T
  OutputKind output = OutputKind::kPositionEuler;
  // Random pre-roll: fly healthy for U{0 … preroll_max_steps} steps before sample 0, so that
  // windows also come from settled flight (docs/data.md). 0 = the paper's distribution.
  int preroll_max_steps = 0;
  std::uint64_t seed = 0;

  // Randomised flights (data/randomisation.h, docs/data.md#randomisation): when enabled, each
  // trajectory draws its vehicle, plant errors, estimator, controller and manoeuvre, and
  // plant / controller_model / residual_model / controller kind / preroll_max_steps above are unused.
  Randomisation randomisation;
  // Samples recorded after the fault step; 0 = T (the paper's 2T + 1 samples a trajectory).
  int post_fault_steps = 0;  // [steps]
  int samplesPerTrajectory() const { return window + (post_fault_steps > 0 ? post_fault_steps : window) + 1; }
  int faultStep() const { return window; }
};

// Empty when valid, else a one-line description of the first problem.
std::string validate(const RolloutConfig& config);

struct TrajectoryJob {
  std::uint64_t scenario_index = 0;  // RNG stream of the initial condition and goal
  int faulty_motor = 2;              // 1..4
  double theta = 1.0;                // effectiveness of that motor after the fault, [0, 1]
};

// Algorithm 1's jobs for one outer iteration: `initial_conditions` scenarios starting at
// `first_scenario`, each flown once per value in `thetas` on each motor in `motors`.
std::vector<TrajectoryJob> algorithm1Jobs(std::uint64_t first_scenario, int initial_conditions,
                                          const std::vector<double>& thetas, const std::vector<int>& motors);

// Called from worker threads with the number of trajectories finished so far.
using ProgressCallback = std::function<void(int done, int total)>;

class RolloutEngine {
 public:
  // setup: designs the controller once (throws nothing; check error()).
  explicit RolloutEngine(const RolloutConfig& config);
  const std::string& error() const { return error_; }
  const RolloutConfig& config() const { return config_; }

  // Fills `batch` (resized here) with one trajectory per job, using `threads` workers (0 = all
  // cores). Returns false if the engine is not set up, or if `stop` was raised before every job
  // ran (the workers finish their current chunk; the batch is then incomplete).
  bool run(const std::vector<TrajectoryJob>& jobs, int threads, TrajectoryBatch& batch,
           const ProgressCallback& progress = {}, const std::atomic<bool>* stop = nullptr) const;

  // One trajectory into slot `slot` of an already sized batch; `controller` is the calling
  // thread's own controller instance (controllers hold per-step state).
  void rolloutOne(const TrajectoryJob& job, Controller& controller, TrajectoryBatch& batch, int slot) const;
  // A randomised trajectory: its own plant, estimator and controller, built here from the draw.
  void rolloutRandomised(const TrajectoryJob& job, TrajectoryBatch& batch, int slot) const;
  std::unique_ptr<Controller> makeWorkerController() const;

  // Randomised flights: the draw of scenario `scenario_index` — the first of up to 8 draws that is
  // flyable (the drawn controller holds the drawn plant through a 1 s healthy probe without
  // crashing or sitting at a thrust limit; docs/data.md#flyability), else the 8th. `attempts`
  // receives how many draws were made.
  FlightDraw flightDraw(std::uint64_t scenario_index, int* attempts = nullptr) const;
  bool flyable(const FlightDraw& draw, std::uint64_t scenario_index) const;

 private:
  RolloutConfig config_;
  RigidBodyModel plant_model_;
  RigidBodyModel residual_model_;
  bool residual_is_plant_ = false;  // same parameters and no lag: prediction = plant step when healthy
  LqrDesign lqr_;
  // Randomised flights: every described vehicle (the library's, then the synthetic airframes) and
  // the LQR designs per (described vehicle, gain level), made in setup.
  std::vector<VehicleParams> described_;
  // Randomised flights: LQR designs per (described vehicle, gain level), made in setup.
  std::vector<std::vector<LqrDesign>> vehicle_lqr_;
  std::vector<double> lqr_gain_levels_;  // [-] gain scales the designs stand for
  std::string error_;

  std::unique_ptr<Controller> makeFlightController(const FlightDraw& draw) const;
};

}  // namespace quadfdi
