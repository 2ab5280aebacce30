#include "estimation/motor_estimator.h"

#include <stdexcept>

#include "data/features.h"

namespace quadfdi {
namespace {

// The trained-motor rule, in one place: the maps send every motor to motor 2, so only a
// network trained on motor 2 reads them correctly.
std::array<SymmetryMap, kMotors> mapsToTrainedMotor(const ModelMetadata& m, SymmetryMode mode) {
  if (m.trained_motor != 2)
    throw std::invalid_argument("the model was trained on motor " + std::to_string(m.trained_motor) +
                                "; the symmetry maps send every motor to motor 2, so only motor-2 networks are supported");
  std::array<SymmetryMap, kMotors> maps{};
  for (int k = 1; k <= kMotors; ++k) maps[static_cast<std::size_t>(k - 1)] = mapMotorToMotor2(k, mode);
  return maps;
}

}  // namespace

MotorEstimator::MotorEstimator(const TrainedModel& model, SymmetryMode mode)
    : metadata_(model.metadata), maps_(mapsToTrainedMotor(model.metadata, mode)),
      per_window_(static_cast<std::size_t>(model.metadata.window) * static_cast<std::size_t>(model.metadata.channels())),
      engine_(std::make_unique<InferenceEngine>(model.weights)) {
  if (engine_->window() != metadata_.window || engine_->channels() != metadata_.channels())
    throw std::invalid_argument("the weights do not match the model's window and features");
  out_.assign(static_cast<std::size_t>(engine_->lanes()) * 4, 0.0f);
}

void MotorEstimator::gather(const float* outputs, const float* inputs, const float* residuals, const float* rates,
                            float* out) const {
  if (!rates && featuresReadRates(metadata_.features))
    throw std::invalid_argument("this model reads body rates (scale-free-rates features) and none were given");
  for (std::size_t k = 0; k < maps_.size(); ++k)
    gatherFeatures(outputs, inputs, residuals, rates, metadata_.window, metadata_.features, metadata_.output, &maps_[k],
                   out + k * per_window_);
}

void MotorEstimator::estimate(const float* features, int count, MotorTheta* theta, std::array<MotorTheta, kMotors>* raw) {
  const int trained = metadata_.trained_motor - 1;
  const int per_pass = std::max(1, engine_->lanes() / kMotors);  // windows whose four maps fill one pass
  for (int first = 0; first < count; first += per_pass) {
    const int n = std::min(per_pass, count - first);
    engine_->predict(features + static_cast<std::size_t>(first) * kMotors * per_window_, n * kMotors, out_.data());
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < kMotors; ++k) {
        const float* o = &out_[static_cast<std::size_t>(i * kMotors + k) * 4];
        theta[first + i][static_cast<std::size_t>(k)] = o[trained];
        if (raw) raw[first + i][static_cast<std::size_t>(k)] = {o[0], o[1], o[2], o[3]};
      }
  }
}

bool StreamingMotorEstimator::canStream(const ModelMetadata& m) {
  return m.architecture == Architecture::kTcn && isStreamingFeatureSet(m.features) &&
         m.output == OutputKind::kPositionEuler;
}

StreamingMotorEstimator::StreamingMotorEstimator(const TrainedModel& model, SymmetryMode mode)
    : metadata_(model.metadata),
      reads_rates_(featuresReadRates(model.metadata.features)),
      maps_(mapsToTrainedMotor(model.metadata, mode)) {
  if (!canStream(metadata_))
    throw std::invalid_argument(
        "only TCN networks on model-free-heading, scale-free or scale-free-rates features with Euler-angle outputs can "
        "stream");
  streamer_ = std::make_unique<TcnStreamer>(model.weights, kMotors);
  if (streamer_->receptiveField() > metadata_.window - 1)
    throw std::invalid_argument("the TCN's receptive field exceeds the window");
  reset();
}

void StreamingMotorEstimator::reset() {
  streamer_->reset();
  samples_ = 0;
}

bool StreamingMotorEstimator::push(const Output& y, const Input& u, MotorTheta& theta) {
  if (reads_rates_)
    throw std::logic_error("this model reads body rates (scale-free-rates features) and none were given");
  return push(y, u, Vec3::Zero(), theta);
}

bool StreamingMotorEstimator::push(const Output& y, const Input& u, const Vec3& rates, MotorTheta& theta) {
  const auto row = static_cast<std::size_t>(metadata_.channels());
  const auto rate_offset = row - kRateDim;
  for (std::size_t k = 0; k < maps_.size(); ++k) {
    const Output my = maps_[k].applyToOutput(y, OutputKind::kPositionEuler);
    const Input mu = maps_[k].applyToInput(u);
    // The first sample has no predecessor: zero increments, as in a window's first row.
    if (samples_ == 0) streamingFeatureRow(metadata_.features, my, mu, my, mu, rows_.data() + k * row);
    else streamingFeatureRow(metadata_.features, previous_[k], previous_u_[k], my, mu, rows_.data() + k * row);
    if (reads_rates_) rateChannels(rates, &maps_[k], rows_.data() + k * row + rate_offset);
    previous_[k] = my;
    previous_u_[k] = mu;
  }
  streamer_->step(rows_.data(), out_.data());
  ++samples_;
  if (samples_ < metadata_.window) return false;
  const auto trained = static_cast<std::size_t>(metadata_.trained_motor - 1);
  for (std::size_t k = 0; k < maps_.size(); ++k) theta[k] = out_[k * 4 + trained];
  return true;
}

}  // namespace quadfdi
