#include "evaluation/decision.h"

#include <algorithm>
#include <thread>

#include "estimation/motor_estimator.h"

namespace quadfdi {

Decision decide(const Input& theta_hat, double theta_tol) {
  Decision d;
  const int best = weakestMotorIndex(theta_hat);
  d.min_theta = theta_hat(best);
  d.alarm = d.min_theta < theta_tol;
  d.motor = d.alarm ? best + 1 : 0;
  return d;
}

Decision decidePaperRule(const std::array<Input, 4>& out, SymmetryMode mode, double theta_tol) {
  Decision d;
  int best_map = 0, best_output = 0;
  for (int n = 0; n < 4; ++n)
    for (int i = 0; i < kInputDim; ++i)
      if (out[static_cast<std::size_t>(n)](i) < out[static_cast<std::size_t>(best_map)](best_output)) {
        best_map = n;
        best_output = i;
      }
  d.min_theta = out[static_cast<std::size_t>(best_map)](best_output);
  d.alarm = d.min_theta < theta_tol;
  if (d.alarm) {
    // Output i of the mapped flight stands for the original motor g⁻¹(i).
    const SymmetryMap g = mapMotorToMotor2(best_map + 1, mode);
    d.motor = g.inverse().imageOfMotor(best_output + 1);
  }
  return d;
}

std::vector<Input> estimateAllMotors(const TrainedModel& model, SymmetryMode mode, const TrajectoryBatch& batch,
                                     const std::vector<WindowRef>& windows, std::vector<std::array<Input, 4>>* raw,
                                     int threads) {
  const ModelMetadata& m = model.metadata;
  std::vector<Input> theta(windows.size(), Input::Ones());
  if (raw) raw->assign(windows.size(), {});
  // Each worker owns an estimator and a contiguous share of the windows; the engine's results do
  // not depend on batching, so the output is the same for any number of workers.
  const std::size_t workers = std::max<std::size_t>(
      1, std::min<std::size_t>(windows.size() / 256 + 1,
                               threads > 0 ? static_cast<std::size_t>(threads) : std::thread::hardware_concurrency()));
  auto work = [&](std::size_t begin, std::size_t end) {
    MotorEstimator estimator(model, mode);
    constexpr std::size_t kChunk = 64;  // windows per call (×4 maps)
    const std::size_t per = estimator.featuresPerWindow();
    std::vector<float> features(kChunk * kMotors * per);
    std::vector<MotorTheta> est(kChunk);
    std::vector<std::array<MotorTheta, kMotors>> outs(kChunk);
    for (std::size_t first = begin; first < end; first += kChunk) {
      const std::size_t n = std::min(kChunk, end - first);
      for (std::size_t i = 0; i < n; ++i) {
        const WindowRef& w = windows[first + i];
        const std::size_t o = batch.sampleOffset(w.trajectory, w.end_sample - m.window + 1);  // samples are contiguous
        estimator.gather(&batch.outputs[o * kOutputDim], &batch.inputs[o * kInputDim],
                         batch.residuals.empty() ? nullptr : &batch.residuals[o * kOutputDim],
                         batch.rates.empty() ? nullptr : &batch.rates[o * kRateDim], &features[i * kMotors * per]);
      }
      estimator.estimate(features.data(), static_cast<int>(n), est.data(), raw ? outs.data() : nullptr);
      for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < kMotors; ++k) theta[first + i](k) = est[i][static_cast<std::size_t>(k)];
        if (raw)
          for (std::size_t k = 0; k < kMotors; ++k) {
            const MotorTheta& o = outs[i][k];
            (*raw)[first + i][k] = Input(o[0], o[1], o[2], o[3]);
          }
      }
    }
  };
  std::vector<std::thread> pool;
  const std::size_t share = (windows.size() + workers - 1) / workers;
  for (std::size_t w = 1; w < workers; ++w)
    pool.emplace_back(work, std::min(windows.size(), w * share), std::min(windows.size(), (w + 1) * share));
  work(0, std::min(windows.size(), share));
  for (std::thread& t : pool) t.join();
  return theta;
}

}  // namespace quadfdi
