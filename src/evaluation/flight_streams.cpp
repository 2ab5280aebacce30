#include "evaluation/flight_streams.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "detection/resampler.h"
#include "estimation/motor_estimator.h"

namespace quadfdi {

std::vector<FlightThetaStream> simulateThetaStreams(const TrainedModel& model, const RolloutConfig& rollout,
                                                    const std::vector<TrajectoryJob>& jobs, const ThetaStreamOptions& options) {
  const double log_period = options.log_period;
  const std::atomic<bool>* stop = options.stop;
  if (!StreamingMotorEstimator::canStream(model.metadata))
    throw std::invalid_argument("simulated Θ̂ streams need a streaming model (a TCN on streaming features)");
  if (!(log_period >= 0.0) || !std::isfinite(log_period))
    throw std::invalid_argument("simulated Θ̂ streams: the log period must be finite and ≥ 0 s");
  if (options.chunk < 1) throw std::invalid_argument("simulated Θ̂ streams: at least one flight per chunk");
  const double dt = rollout.dt;
  // The resampler as detect's, its limits opened to the period asked for: this measures the
  // period's cost, not whether detect's default accepts it.
  ResamplerConfig resampling;
  resampling.dt = dt;
  resampling.max_input_period = std::max(resampling.max_input_period, log_period + dt);
  resampling.max_gap = std::max(resampling.max_gap, 2.0 * (log_period + dt));
  const RolloutEngine engine(rollout);
  if (!engine.error().empty()) throw std::invalid_argument("rollout: " + engine.error());
  const int workers = std::max(1, options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency()));
  const int window = model.metadata.window;
  std::vector<FlightThetaStream> streams(jobs.size());
  TrajectoryBatch batch;
  for (std::size_t first = 0; first < jobs.size(); first += static_cast<std::size_t>(options.chunk)) {
    if (stop && stop->load()) break;
    const std::size_t last = std::min(jobs.size(), first + static_cast<std::size_t>(options.chunk));
    const std::vector<TrajectoryJob> part(jobs.begin() + static_cast<std::ptrdiff_t>(first), jobs.begin() + static_cast<std::ptrdiff_t>(last));
    engine.run(part, workers, batch, {}, stop);
    // One estimator per worker; each flight is streamed by exactly one worker.
    std::atomic<int> next{0};
    auto work = [&] {
      StreamingMotorEstimator estimator(model, model.metadata.symmetry);
      CommandGateConfig gate_config = options.gate;
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
        auto estimate = [&](const TelemetrySample& sample) {
          Output y;
          Input u;
          for (int i = 0; i < kOutputDim; ++i) y(i) = sample.y[static_cast<std::size_t>(i)];
          for (int i = 0; i < kInputDim; ++i) u(i) = sample.u[static_cast<std::size_t>(i)];
          MotorTheta theta;
          const std::uint8_t observable = command_gate.step(sample.u);
          if (estimator.push(y, u, Vec3(sample.rates[0], sample.rates[1], sample.rates[2]), theta)) {
            s.theta.push_back(theta);
            s.observable.push_back(observable);
          }
        };
        Resampler resampler(resampling);
        long logged = 0;  // samples logged so far; the next one is the first at or after logged × log_period
        for (int k = 0; k < length; ++k) {
          const double time = dt * k;
          if (log_period > 0.0 && time < static_cast<double>(logged) * log_period - 1e-6 * dt) continue;
          const std::size_t o = batch.sampleOffset(t, k);
          TelemetrySample sample;
          sample.t = time;
          for (int i = 0; i < kOutputDim; ++i) sample.y[static_cast<std::size_t>(i)] = batch.outputs[o * kOutputDim + static_cast<std::size_t>(i)];
          for (int i = 0; i < kInputDim; ++i) sample.u[static_cast<std::size_t>(i)] = batch.inputs[o * kInputDim + static_cast<std::size_t>(i)];
          for (int i = 0; i < kRateDim; ++i) sample.rates[static_cast<std::size_t>(i)] = batch.rates[o * kRateDim + static_cast<std::size_t>(i)];
          if (log_period <= 0.0) {
            estimate(sample);
            continue;
          }
          ++logged;
          // A restart (an estimator-reset step) would start the grid, and the stream's index, again:
          // the stream ends there, as a crash ends it.
          if (resampler.push(sample, estimate) != ResampleStatus::kOk) break;
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
