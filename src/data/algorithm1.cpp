#include "data/algorithm1.h"

namespace quadfdi {

Algorithm1Data::Algorithm1Data(const Algorithm1DataConfig& config)
    : config_(config), engine_(config.rollout), buffer_(config.scale.buffer_windows, config.rollout.window) {}

std::shared_ptr<TrajectoryBatch> Algorithm1Data::generate(int iteration, const ProgressCallback& progress) const {
  const auto n1 = static_cast<std::uint64_t>(config_.scale.initial_conditions);
  auto batch = std::make_shared<TrajectoryBatch>();
  engine_.run(algorithm1Jobs(static_cast<std::uint64_t>(iteration) * n1, config_.scale.initial_conditions,
                             config_.thetas, config_.motors),
              config_.threads, *batch, progress);
  return batch;
}

void Algorithm1Data::nextIteration(const ProgressCallback& progress) {
  buffer_.add(generate(iteration_, progress));
  ++iteration_;
}

void Algorithm1Data::restoreTo(int iterations) {
  buffer_ = WindowBuffer(config_.scale.buffer_windows, config_.rollout.window);
  // Only the iterations whose windows can still be in the buffer need regenerating.
  const std::size_t per_iteration = static_cast<std::size_t>(config_.scale.initial_conditions) *
                                    config_.thetas.size() * config_.motors.size() *
                                    static_cast<std::size_t>(config_.rollout.window + 1);
  const int keep = per_iteration == 0 ? iterations
                                      : static_cast<int>(config_.scale.buffer_windows / per_iteration) + 2;
  iteration_ = std::max(0, iterations - keep);
  while (iteration_ < iterations) nextIteration();
}

}  // namespace quadfdi
