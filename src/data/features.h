// Network inputs from windows (docs/networks.md): feature sets, the symmetry map applied to the
// window, and position made relative to the window's first sample so that the detector
// does not care where in the room the vehicle flies.
#pragma once

#include <string>

#include "data/trajectory_batch.h"
#include "symmetry/symmetry.h"

namespace quadfdi {

enum class FeatureSet {
  kModelFree,     // (y, u): 10 channels — the paper's contribution
  kModelBased,    // (y, u, ỹ): 16 channels
  kResidualOnly,  // ỹ: 6 channels
  kModelFreeHeading,  // (y, u) as local increments: 10 channels per sample, each a function of this
                      // sample and the one before only, so a network can run on a stream
                      // (docs/networks.md): velocity increment Δp in the heading frame Rz(−ψ)
                      // (3), roll, pitch (2), yaw increment Δψ wrapped to (−π, π] (1), u (4).
                      // Independent of position offset and of heading. Needs Euler-angle outputs.
  kScaleFree,  // model-free-heading with the commands made dimensionless, for vehicles of any
               // size: 11 channels — Δp, roll, pitch, Δψ as above (6), each motor's share of the
               // collective u_i / ū with ū = Σu/4 (4; ≈ 1 in hover for any vehicle), and
               // Δ ln ū, the collective's relative change since the previous sample (1). Also a
               // function of this sample and the one before only. Invariant to scaling every
               // command by one constant. ū ≤ 0 (no thrust): shares 1, Δ ln ū = 0.
  kScaleFreeRates,  // scale-free plus the measured body rates p, q, r [rad/s] (3): 14 channels. A
                    // gyro sees a lost motor's torque one integration sooner than the attitude
                    // does, with far less noise than a rate differenced from the attitude
                    // (docs/networks.md#body-rates). Rates are scale-free already.
};
const char* toString(FeatureSet f);
bool parseFeatureSet(const std::string& text, FeatureSet& f);  // model-free | model-based | residual | model-free-heading | scale-free | scale-free-rates
int featureChannels(FeatureSet f);
// Feature sets that read the measured body rates (TrajectoryBatch::rates) besides y and u.
bool featuresReadRates(FeatureSet f);
// Feature sets that read the commands only as shares of their mean (kScaleFree, kScaleFreeRates):
// a constant factor on every command, a thrust scale unknown, cannot change their output.
bool featuresScaleFree(FeatureSet f);

// Writes the window's features, [T][channels] row-major, into `out` (T·channels floats).
// Channel order: y (position relative to the window's first sample, then angles or rates),
// u, ỹ — each present only in the feature sets that use it; the body rates last. With `map`,
// every sample is first sent through the symmetry map (y, ỹ like outputs, u permuted, rates as
// the state's rate block maps them).
void gatherWindowFeatures(const TrajectoryBatch& batch, const WindowRef& window, int length, FeatureSet features,
                          OutputKind output, const SymmetryMap* map, float* out);

// The same from `length` consecutive samples held elsewhere (the online detector's history):
// outputs [length][kOutputDim], inputs [length][kInputDim], residuals likewise (may be null
// for model-free features).
// One kModelFreeHeading row from a (mapped) sample and its (mapped) predecessor.
void headingFeatureRow(const Output& previous, const Output& current, const Input& u, float* out);
// Feature sets whose row at a sample depends only on that sample and its predecessor: a causal
// network on them can run on a stream (kModelFreeHeading, kScaleFree, kScaleFreeRates).
bool isStreamingFeatureSet(FeatureSet f);
// One row of such a set from a (mapped) sample (y, u) and its (mapped) predecessor; the first
// sample of a stream or window passes itself as its predecessor (zero increments). For
// kScaleFreeRates it writes the scale-free channels; the rates follow from `rateChannels`.
void streamingFeatureRow(FeatureSet f, const Output& previous_y, const Input& previous_u, const Output& y,
                         const Input& u, float* out);
// The body-rate channels (3) of a sample, sent through `map` when there is one.
void rateChannels(const Vec3& rates, const SymmetryMap* map, float* out);

// `rates` ([length][kRateDim]) may be null unless featuresReadRates(features); `residuals` may be
// null for sets without residuals.
void gatherFeatures(const float* outputs, const float* inputs, const float* residuals, const float* rates, int length,
                    FeatureSet features, OutputKind output, const SymmetryMap* map, float* out);

}  // namespace quadfdi
