#include "evaluation/flight_streams.h"

#include <algorithm>
#include <stdexcept>
#include <thread>

#include "estimation/motor_estimator.h"

namespace quadfdi {

std::vector<FlightThetaStream> simulateThetaStreams(const TrainedModel& model, const RolloutConfig& rollout,
                                                    const std::vector<TrajectoryJob>& jobs, int threads, int chunk,
                                                    const std::atomic<bool>* stop, const CommandGateConfig& gate) {
  if (!StreamingMotorEstimator::canStream(model.metadata))
    throw std::invalid_argument("simulated Θ̂ streams need a streaming model (a TCN on streaming features)");
  const RolloutEngine engine(rollout);
  if (!engine.error().empty()) throw std::invalid_argument("rollout: " + engine.error());
  const int workers = std::max(1, threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency()));
  const int window = model.metadata.window;
  std::vector<FlightThetaStream> streams(jobs.size());
  TrajectoryBatch batch;
  for (std::size_t first = 0; first < jobs.size(); first += static_cast<std::size_t>(chunk)) {
    if (stop && stop->load()) break;
    const std::size_t last = std::min(jobs.size(), first + static_cast<std::size_t>(chunk));
    const std::vector<TrajectoryJob> part(jobs.begin() + static_cast<std::ptrdiff_t>(first), jobs.begin() + static_cast<std::ptrdiff_t>(last));
    engine.run(part, workers, batch, {}, stop);
    // One estimator per worker; each flight is streamed by exactly one worker.
    std::atomic<int> next{0};
    auto work = [&] {
      StreamingMotorEstimator estimator(model, model.metadata.symmetry);
      CommandGateConfig gate_config = gate;
      gate_config.hold = window;  // as the detector: an estimate reads the whole window
      CommandGate command_gate(gate_config);
      for (int t; (t = next.fetch_add(1)) < batch.count;) {
        FlightThetaStream& s = streams[first + static_cast<std::size_t>(t)];
        const TrajectoryJob& job = part[static_cast<std::size_t>(t)];
        const int length = batch.length[static_cast<std::size_t>(t)];
        s.theta.clear();
        s.theta.reserve(static_cast<std::size_t>(std::max(0, length - window + 1)));
        s.observable.clear();
        s.observable.reserve(s.theta.capacity());
        estimator.reset();
        command_gate.reset();
        for (int k = 0; k < length; ++k) {
          const std::size_t o = batch.sampleOffset(t, k);
          Output y;
          Input u;
          for (int i = 0; i < kOutputDim; ++i) y(i) = batch.outputs[o * kOutputDim + static_cast<std::size_t>(i)];
          for (int i = 0; i < kInputDim; ++i) u(i) = batch.inputs[o * kInputDim + static_cast<std::size_t>(i)];
          const Vec3 rates(batch.rates[o * kRateDim], batch.rates[o * kRateDim + 1], batch.rates[o * kRateDim + 2]);
          MotorTheta theta;
          const std::uint8_t observable = command_gate.step({u(0), u(1), u(2), u(3)});
          if (estimator.push(y, u, rates, theta)) {
            s.theta.push_back(theta);
            s.observable.push_back(observable);
          }
        }
        const bool healthy = job.theta >= 1.0;
        s.truth.motor = healthy ? 0 : job.faulty_motor;
        s.truth.theta = job.theta;
        // The fault scales the command from step F on, so sample F + 1 is the first it changes;
        // stream index i is flight sample i + T − 1.
        s.truth.fault_sample = healthy ? -1 : static_cast<long>(batch.fault_step[static_cast<std::size_t>(t)]) + 1 - (window - 1);
      }
    };
    std::vector<std::thread> pool;
    for (int w = 1; w < workers; ++w) pool.emplace_back(work);
    work();
    for (auto& th : pool) th.join();
  }
  return streams;
}

void dropLeadingSamples(FlightThetaStream& stream, long samples) {
  const std::size_t n = std::min(stream.theta.size(), static_cast<std::size_t>(std::max(0L, samples)));
  stream.theta.erase(stream.theta.begin(), stream.theta.begin() + static_cast<std::ptrdiff_t>(n));
  if (!stream.observable.empty())
    stream.observable.erase(stream.observable.begin(), stream.observable.begin() + static_cast<std::ptrdiff_t>(std::min(n, stream.observable.size())));
  if (stream.truth.fault_sample >= 0) stream.truth.fault_sample = std::max(0L, stream.truth.fault_sample - static_cast<long>(n));
}

}  // namespace quadfdi
