#include "detection/detector.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>


namespace quadfdi {
namespace {
constexpr long kSpareSamples = 4096;  // history beyond T before it is compacted
constexpr int kMaxPoints = 8;         // evaluations per engine pass, at most
constexpr double kMaxBridged = 1e6;   // model samples one input sample may complete (max_gap / dt)
}

const char* toString(AlarmRule r) { return r == AlarmRule::kPersistence ? "persistence" : "sequential"; }

bool parseAlarmRule(const std::string& text, AlarmRule& r) {
  if (text == "sequential") r = AlarmRule::kSequential;
  else if (text == "persistence") r = AlarmRule::kPersistence;
  else return false;
  return true;
}

Detector::Detector(const DetectorConfig& config, const TrainedModel& model)
    : config_(config), window_(model.metadata.window), resampler_(config.resampler), alarm_(config.alarm) {
  const ModelMetadata& m = model.metadata;
  if (m.features == FeatureSet::kModelBased || m.features == FeatureSet::kResidualOnly || m.output != OutputKind::kPositionEuler)
    throw std::invalid_argument(std::string("the detector needs a model-free network on position and Euler angles; this one reads ") +
                                toString(m.features) + " features");
  if (StreamingMotorEstimator::canStream(m))
    streaming_ = std::make_unique<StreamingMotorEstimator>(model, config.symmetry);
  else
    windowed_ = std::make_unique<MotorEstimator>(model, config.symmetry);
  if (config.stride < 1) throw std::invalid_argument("detector: stride must be at least 1");
  if (!(config.resampler.dt > 0.0) || !(config.resampler.max_gap / config.resampler.dt <= kMaxBridged))
    throw std::invalid_argument("detector: max_gap / dt must be at most 1e6 model samples (a hole the resampler fills)");
  if (config.rule == AlarmRule::kSequential) sequential_ = std::make_unique<SequentialRule>(config.sequential);
  capacity_ = window_ + kSpareSamples;
  outputs_.assign(static_cast<std::size_t>(capacity_) * kOutputDim, 0.0f);
  inputs_.assign(static_cast<std::size_t>(capacity_) * kInputDim, 0.0f);
  reads_rates_ = featuresReadRates(m.features);
  if (reads_rates_) rates_.assign(static_cast<std::size_t>(capacity_) * kRateDim, 0.0f);
  times_.assign(static_cast<std::size_t>(capacity_), 0.0);
  observable_.assign(static_cast<std::size_t>(capacity_), kAllMotorsObservable);
  CommandGateConfig gate = config.command_gate;
  gate.hold = window_;  // an estimate reads the whole window
  applyGateShares(config.sequential, gate);  // the calibration's, as its excursions were gated
  gate_ = CommandGate(gate);
  if (windowed_) {
    features_.assign(static_cast<std::size_t>(kMaxPoints) * kMotors * windowed_->featuresPerWindow(), 0.0f);
    estimates_.assign(kMaxPoints, MotorTheta{});
  }
  restart();
}

void Detector::restart() {
  first_index_ = count_ = 0;
  next_due_ = window_ - 1;  // the first full window
  if (streaming_) streaming_->reset();
  dense_ = false;
  watch_left_ = config_.watch_samples;
  alarm_.reset();
  if (sequential_) sequential_->reset();
  gate_.reset();
  last_evaluation_ = -1;
  evaluations_.clear();
}

void Detector::appendModelSample(const TelemetrySample& s) {
  if (count_ - first_index_ == capacity_) {  // compact: keep what the next windows need
    // One input sample can complete more model samples than the spare room (a hole up to max_gap
    // filled at dt) while evaluations are due: make them now so that compaction frees their
    // samples. Same windows, same estimates: only the batching changes.
    if (std::min(next_due_, count_) - window_ + 1 <= first_index_) evaluateDue(false);
    const long keep_from = std::max(first_index_, std::min(next_due_, count_) - window_ + 1);
    const long n = count_ - keep_from, off = keep_from - first_index_;
    std::memmove(outputs_.data(), outputs_.data() + off * kOutputDim, sizeof(float) * static_cast<std::size_t>(n * kOutputDim));
    std::memmove(inputs_.data(), inputs_.data() + off * kInputDim, sizeof(float) * static_cast<std::size_t>(n * kInputDim));
    if (reads_rates_)
      std::memmove(rates_.data(), rates_.data() + off * kRateDim, sizeof(float) * static_cast<std::size_t>(n * kRateDim));
    std::memmove(times_.data(), times_.data() + off, sizeof(double) * static_cast<std::size_t>(n));
    std::memmove(observable_.data(), observable_.data() + off, static_cast<std::size_t>(n));
    first_index_ = keep_from;
  }
  const long at = count_ - first_index_;
  for (int i = 0; i < kOutputDim; ++i) outputs_[static_cast<std::size_t>(at * kOutputDim + i)] = static_cast<float>(s.y[static_cast<std::size_t>(i)]);
  for (int i = 0; i < kInputDim; ++i) inputs_[static_cast<std::size_t>(at * kInputDim + i)] = static_cast<float>(s.u[static_cast<std::size_t>(i)]);
  if (reads_rates_)
    for (int i = 0; i < kRateDim; ++i) rates_[static_cast<std::size_t>(at * kRateDim + i)] = static_cast<float>(s.rates[static_cast<std::size_t>(i)]);
  times_[static_cast<std::size_t>(at)] = s.t;
  observable_[static_cast<std::size_t>(at)] = sequential_ ? gate_.step(s.u) : kAllMotorsObservable;  // only that rule reads it
  ++count_;
  if (streaming_) {  // every sample is evaluated as it arrives
    Output y;
    Input u;
    for (int i = 0; i < kOutputDim; ++i) y(i) = s.y[static_cast<std::size_t>(i)];
    for (int i = 0; i < kInputDim; ++i) u(i) = s.u[static_cast<std::size_t>(i)];
    MotorTheta theta;
    const bool estimated = reads_rates_ ? streaming_->push(y, u, Vec3(s.rates[0], s.rates[1], s.rates[2]), theta)
                                        : streaming_->push(y, u, theta);
    if (estimated) apply(count_ - 1, theta);
  }
}

ResampleStatus Detector::push(const TelemetrySample& sample, bool look_ahead) {
  const ResampleStatus status = resampler_.push(
      sample, [&](const TelemetrySample& s) { appendModelSample(s); },
      [&] {  // a hole in the log: finish the stretch before it with what it has, then start again
        evaluateDue(false);
        resolve();
        pending_.clear();  // samples that never saw a full window get no output
        restart();
        ++summary_.restarts;
      });
  if (status == ResampleStatus::kNotIncreasing || status == ResampleStatus::kTooCoarse) return status;
  ++summary_.input_samples;
  pending_.push_back({sample.t, count_ - 1});
  evaluateDue(look_ahead);
  resolve();
  return status;
}

void Detector::finish() {
  evaluateDue(false);
  resolve();
  pending_.clear();
}

void Detector::evaluateDue(bool look_ahead) {
  if (streaming_) return;  // evaluated on arrival
  const std::size_t per = kMotors * windowed_->featuresPerWindow();
  const int points = std::min(kMaxPoints, std::max(1, windowed_->preferredBatch()));  // evaluations sharing one engine pass
  long due[kMaxPoints];
  while (next_due_ <= count_ - 1) {
    // The looks that follow if each changes nothing; a look whose result changes the plan ends the chain.
    const long step = dense_ ? 1 : config_.stride;
    int n = 0;
    for (long c = next_due_; n < points && c <= count_ - 1; c += step) due[n++] = c;
    if (n < points && look_ahead) break;  // file mode: wait for a full pass
    for (int i = 0; i < n; ++i) {
      const long first = due[i] - window_ + 1 - first_index_;
      windowed_->gather(&outputs_[static_cast<std::size_t>(first * kOutputDim)], &inputs_[static_cast<std::size_t>(first * kInputDim)],
                        nullptr, reads_rates_ ? &rates_[static_cast<std::size_t>(first * kRateDim)] : nullptr,
                        features_.data() + static_cast<std::size_t>(i) * per);
    }
    windowed_->estimate(features_.data(), n, estimates_.data());
    for (int i = 0; i < n && due[i] == next_due_; ++i) apply(due[i], estimates_[static_cast<std::size_t>(i)]);
  }
}

void Detector::apply(long index, const MotorTheta& theta) {
  Evaluation e;
  e.index = index;
  e.theta = theta;
  bool building = false;  // evidence building: decide at full rate
  const float lowest = *std::min_element(e.theta.begin(), e.theta.end());
  if (sequential_) {
    // The estimate stands for the model samples since the previous evaluation (the stride holds it).
    const long samples = last_evaluation_ < 0 ? 1 : index - last_evaluation_;
    const SequentialStatus status = sequential_->update(theta, static_cast<int>(std::min<long>(samples, 1L << 30)),
                                                         observable_[static_cast<std::size_t>(index - first_index_)]);
    const SequentialState& s = sequential_->state();
    e.active = s.severity != Severity::kHealthy;
    e.raised = status == SequentialStatus::kRaised;
    e.motor = s.motor;
    e.severity = s.severity;
    e.estimate = s.theta_est;
    e.lo = s.theta_lo;
    e.hi = s.theta_hi;
    building = status == SequentialStatus::kBuilding;
  } else {
    const AlarmState a = alarm_.update(e.theta, index);
    e.active = a.active;
    e.raised = a.raised;
    e.motor = a.motor;
    building = static_cast<double>(lowest) < config_.alarm.raise_below;
  }
  last_evaluation_ = index;
  ++summary_.evaluations;
  if (e.raised) {
    ++summary_.alarms_raised;
    if (summary_.alarms_raised == 1) {
      summary_.first_alarm_t = times_[static_cast<std::size_t>(index - first_index_)];
      summary_.first_alarm_motor = e.motor;
      summary_.first_alarm_theta = summary_.lowest_theta = e.theta[static_cast<std::size_t>(e.motor - 1)];
      tracking_first_alarm_ = true;
    }
  }
  if (tracking_first_alarm_) {
    if (e.active && e.motor == summary_.first_alarm_motor) {
      summary_.lowest_theta = std::min(summary_.lowest_theta, e.theta[static_cast<std::size_t>(e.motor - 1)]);
    } else {
      tracking_first_alarm_ = false;
    }
  }
  if (e.active) {
    dense_ = false;  // decided; tracked at the stride
  } else if (building) {
    dense_ = true;  // evidence is building: decide at full rate
  } else if (static_cast<double>(lowest) < config_.watch) {
    dense_ = watch_left_ > 0;
    if (watch_left_ > 0) --watch_left_;
  } else {
    dense_ = false;
    watch_left_ = config_.watch_samples;
  }
  next_due_ = index + (dense_ || streaming_ ? 1 : config_.stride);
  evaluations_.push_back(e);
}

void Detector::resolve() {
  while (!pending_.empty()) {
    const Pending& p = pending_.front();
    if (p.last_index < window_ - 1) {  // before the first full window: no output
      pending_.pop_front();
      continue;
    }
    if (p.last_index >= next_due_ || evaluations_.empty()) break;  // its evidence is not all in yet
    while (evaluations_.size() > 1 && evaluations_[1].index <= p.last_index) evaluations_.pop_front();
    const Evaluation& e = evaluations_.front();
    DetectorOutput out;
    out.t = p.t;
    out.theta = e.theta;
    out.alarm = e.active;
    out.motor = e.active ? e.motor : 0;
    out.severity = e.severity;
    out.theta_est = e.estimate;
    out.theta_lo = e.lo;
    out.theta_hi = e.hi;
    ready_.push_back(out);
    ++summary_.outputs;
    pending_.pop_front();
  }
}

bool Detector::pop(DetectorOutput& out) {
  if (ready_.empty()) return false;
  out = ready_.front();
  ready_.pop_front();
  return true;
}

}  // namespace quadfdi
