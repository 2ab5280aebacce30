#include "data/features.h"

#include <cmath>

#include "core/frames.h"

namespace quadfdi {

const char* toString(FeatureSet f) {
  switch (f) {
    case FeatureSet::kModelFree: return "model-free";
    case FeatureSet::kModelBased: return "model-based";
    case FeatureSet::kResidualOnly: return "residual";
    case FeatureSet::kModelFreeHeading: return "model-free-heading";
    case FeatureSet::kScaleFree: return "scale-free";
    case FeatureSet::kScaleFreeRates: return "scale-free-rates";
  }
  return "?";
}

bool parseFeatureSet(const std::string& text, FeatureSet& f) {
  if (text == "model-free") { f = FeatureSet::kModelFree; return true; }
  if (text == "model-based") { f = FeatureSet::kModelBased; return true; }
  if (text == "residual" || text == "residual-only") { f = FeatureSet::kResidualOnly; return true; }
  if (text == "model-free-heading") { f = FeatureSet::kModelFreeHeading; return true; }
  if (text == "scale-free") { f = FeatureSet::kScaleFree; return true; }
  if (text == "scale-free-rates") { f = FeatureSet::kScaleFreeRates; return true; }
  return false;
}

int featureChannels(FeatureSet f) {
  switch (f) {
    case FeatureSet::kModelFree: return kOutputDim + kInputDim;
    case FeatureSet::kModelBased: return 2 * kOutputDim + kInputDim;
    case FeatureSet::kResidualOnly: return kOutputDim;
    case FeatureSet::kModelFreeHeading: return kOutputDim + kInputDim;
    case FeatureSet::kScaleFree: return kOutputDim + kInputDim + 1;
    case FeatureSet::kScaleFreeRates: return kOutputDim + kInputDim + 1 + kRateDim;
  }
  return 0;
}

bool featuresReadRates(FeatureSet f) { return f == FeatureSet::kScaleFreeRates; }

bool featuresScaleFree(FeatureSet f) { return f == FeatureSet::kScaleFree || f == FeatureSet::kScaleFreeRates; }

void gatherWindowFeatures(const TrajectoryBatch& b, const WindowRef& w, int length, FeatureSet features,
                          OutputKind output, const SymmetryMap* map, float* out) {
  const std::size_t o = b.sampleOffset(w.trajectory, w.end_sample - length + 1);  // samples are contiguous
  gatherFeatures(&b.outputs[o * kOutputDim], &b.inputs[o * kInputDim],
                 b.residuals.empty() ? nullptr : &b.residuals[o * kOutputDim],
                 b.rates.empty() ? nullptr : &b.rates[o * kRateDim], length, features, output, map, out);
}

void headingFeatureRow(const Output& previous, const Output& current, const Input& u, float* out) {
  const double dx = current(0) - previous(0), dy = current(1) - previous(1);
  const double c = std::cos(current(5)), s = std::sin(current(5));
  const double dpsi = wrapAngle(current(5) - previous(5));  // the short way round
  out[0] = static_cast<float>(c * dx + s * dy);   // forward (heading frame)
  out[1] = static_cast<float>(-s * dx + c * dy);  // left
  out[2] = static_cast<float>(current(2) - previous(2));
  out[3] = static_cast<float>(current(3));
  out[4] = static_cast<float>(current(4));
  out[5] = static_cast<float>(dpsi);
  for (int i = 0; i < kInputDim; ++i) out[6 + i] = static_cast<float>(u(i));
}

bool isStreamingFeatureSet(FeatureSet f) {
  return f == FeatureSet::kModelFreeHeading || f == FeatureSet::kScaleFree || f == FeatureSet::kScaleFreeRates;
}

void streamingFeatureRow(FeatureSet f, const Output& previous_y, const Input& previous_u, const Output& y,
                         const Input& u, float* out) {
  if (f != FeatureSet::kScaleFree && f != FeatureSet::kScaleFreeRates) {
    headingFeatureRow(previous_y, y, u, out);
    return;
  }
  const Input no_commands = Input::Zero();
  headingFeatureRow(previous_y, y, no_commands, out);  // Δp, roll, pitch, Δψ; the commands follow
  const double collective = u.sum() / kInputDim, previous_collective = previous_u.sum() / kInputDim;
  // No thrust at all (motors idle, a log gap filled with zeros): no shares to speak of, so the
  // row says "evenly shared, unchanged" rather than dividing by zero. !(x > 0) also catches NaN.
  const bool defined = collective > 0.0 && std::isfinite(collective);
  for (int i = 0; i < kInputDim; ++i) out[6 + i] = static_cast<float>(defined ? u(i) / collective : 1.0);
  const bool change_defined = defined && previous_collective > 0.0 && std::isfinite(previous_collective);
  out[6 + kInputDim] = static_cast<float>(change_defined ? std::log(collective / previous_collective) : 0.0);
}

void rateChannels(const Vec3& rates, const SymmetryMap* map, float* out) {
  // ω → det(S)·S·ω for the exact group: the state map's rate block (docs/symmetry.md).
  const Vec3 w = map ? Vec3(map->state_map.block<kRateDim, kRateDim>(idx::kRate, idx::kRate) * rates) : rates;
  for (int i = 0; i < kRateDim; ++i) out[i] = static_cast<float>(w(i));
}

void gatherFeatures(const float* outputs, const float* inputs, const float* residuals, const float* rates, int length,
                    FeatureSet features, OutputKind output, const SymmetryMap* map, float* out) {
  if (isStreamingFeatureSet(features)) {
    const bool read_rates = featuresReadRates(features);
    const int rate_offset = featureChannels(features) - kRateDim;
    Output previous_y = Output::Zero();
    Input previous_u = Input::Zero();
    const int channels = featureChannels(features);
    for (int k = 0; k < length; ++k) {
      Output y;
      Input u;
      for (int c = 0; c < kOutputDim; ++c) y(c) = static_cast<double>(outputs[k * kOutputDim + c]);
      for (int c = 0; c < kInputDim; ++c) u(c) = static_cast<double>(inputs[k * kInputDim + c]);
      if (map) {
        y = map->applyToOutput(y, output);
        u = map->applyToInput(u);
      }
      // The first row has no predecessor: zero increments.
      if (k == 0) streamingFeatureRow(features, y, u, y, u, out);
      else streamingFeatureRow(features, previous_y, previous_u, y, u, out);
      if (read_rates)
        rateChannels(Vec3(static_cast<double>(rates[k * kRateDim]), static_cast<double>(rates[k * kRateDim + 1]),
                          static_cast<double>(rates[k * kRateDim + 2])),
                     map, out + rate_offset);
      previous_y = y;
      previous_u = u;
      out += channels;
    }
    return;
  }
  const bool use_y = features != FeatureSet::kResidualOnly;
  const bool use_res = features != FeatureSet::kModelFree;
  Output origin = Output::Zero();
  for (int k = 0; k < length; ++k) {
    Output y, r = Output::Zero();
    Input u;
    for (int c = 0; c < kOutputDim; ++c) {
      y(c) = outputs[k * kOutputDim + c];
      if (use_res) r(c) = residuals[k * kOutputDim + c];
    }
    for (int c = 0; c < kInputDim; ++c) u(c) = inputs[k * kInputDim + c];
    if (map) {
      y = map->applyToOutput(y, output);
      if (use_res) r = map->applyToOutput(r, output);
      u = map->applyToInput(u);
    }
    if (k == 0) origin.head<3>() = y.head<3>();
    y -= origin;  // positions relative to the window's first sample
    int c = 0;
    if (use_y) {
      for (int i = 0; i < kOutputDim; ++i) out[c++] = static_cast<float>(y(i));
      for (int i = 0; i < kInputDim; ++i) out[c++] = static_cast<float>(u(i));
    }
    if (use_res)
      for (int i = 0; i < kOutputDim; ++i) out[c++] = static_cast<float>(r(i));
    out += c;
  }
}

}  // namespace quadfdi
