// The online detector (issue 6): telemetry samples in, one decision per input sample out.
//
// Cost. Θ̂ for four motors needs four LSTM passes over a T-sample window; with the shipped
// network (H = 128, T = 100) that is ≈ 27 M multiply-adds per sample, too much for 10× real time
// at 500 Hz on one core. So the detector evaluates every `stride` samples, and every sample only
// while an alarm is being decided: while the weakest Θ̂ is below the alarm's `raise_below`, and
// for up to `watch_samples` evaluations after it first dips below `watch`. A fault's Θ̂ falls
// through `watch` before it reaches the alarm threshold, so the alarm is decided at full rate; the
// stride delays only the first look, by at most stride − 1 samples. Once raised, the alarm is
// tracked (and cleared) at the stride.
//
// Streaming networks (a TCN on model-free-heading features) need none of this: every model
// sample is evaluated as it arrives, at a cost independent of T (docs/decisions.md).
//
// Determinism. Which samples are evaluated depends only on earlier estimates, and the inference
// engine gives a window the same bits in any batch, so reading a file (with look-ahead) and
// streaming (without) give identical output.
#pragma once

#include <array>
#include <deque>
#include <string>
#include <vector>

#include <memory>

#include "detection/alarm.h"
#include "detection/resampler.h"
#include "detection/sequential.h"
#include "estimation/motor_estimator.h"

namespace quadfdi {

// Which rule turns Θ̂ into alarms (docs/decisions.md).
enum class AlarmRule {
  kSequential,   // per-motor CUSUMs, severity levels, thresholds from a false-alarm rate (issue 14)
  kPersistence,  // the AlarmFilter: raise_after evaluations below raise_below (issue 6; the reproduction, goldens)
};
const char* toString(AlarmRule r);
bool parseAlarmRule(const std::string& text, AlarmRule& r);  // sequential | persistence

struct DetectorConfig {
  SymmetryMode symmetry = SymmetryMode::kExactGroup;  // maps for the other motors (normally the model's own)
  int stride = 4;          // [samples] windowed networks: evaluation period while healthy (extra first-look
                           //     delay ≤ stride − 1); streaming networks evaluate every sample
  double watch = 0.9;      // [-] below this min Θ̂, evaluate every sample …
  int watch_samples = 16;  // [evaluations] … for at most this many, unless Θ̂ < raise_below
  ResamplerConfig resampler;
  AlarmRule rule = AlarmRule::kSequential;
  AlarmConfig alarm;            // kPersistence
  SequentialConfig sequential;  // kSequential
  CommandGateConfig command_gate;  // kSequential: motors the commands hide take no evidence (hold: set to the model's T)
};

struct DetectorOutput {
  double t = 0.0;                        // [s] of the input sample
  MotorTheta theta{1, 1, 1, 1};          // Θ̂ per motor from the latest evaluation at or before t
  bool alarm = false;                    // sequential: severity is degraded or failed; persistence: the filter's alarm
  int motor = 0;                         // 1..4 while alarm, else 0
  // Sequential rule only (persistence: kHealthy and 1, its defaults):
  Severity severity = Severity::kHealthy;
  double theta_est = 1.0;                // [-] Θ estimate of `motor` while alarm
  double theta_lo = 1.0, theta_hi = 1.0; // [-] its interval (SequentialConfig::interval_level)
};

struct DetectorSummary {
  long input_samples = 0, outputs = 0, evaluations = 0, restarts = 0;
  long alarms_raised = 0;
  double first_alarm_t = 0.0;  // [s] valid when alarms_raised > 0
  int first_alarm_motor = 0;
  float first_alarm_theta = 1.0f;  // Θ̂ of that motor when raised
  float lowest_theta = 1.0f;       // lowest Θ̂ of that motor while the first alarm was up
  // The sequential rule's severities and estimates per alarm are in the outputs (DetectorOutput);
  // the CLI's alarm episodes (cli/detection_summary.h) collect them.
};

class Detector {
 public:
  // setup: builds the estimator (streaming when the model can), allocates the history and the
  // feature buffers. Throws std::invalid_argument for a model the detector cannot use.
  Detector(const DetectorConfig& config, const TrainedModel& model);
  bool streaming() const { return streaming_ != nullptr; }
  const char* kernel() const { return streaming_ ? streaming_->kernel() : windowed_->kernel(); }
  // The model reads body rates (scale-free-rates features): every sample pushed must carry them.
  bool readsRates() const { return reads_rates_; }

  // Feeds one input sample. kNotIncreasing and kTooCoarse refuse it (the caller reports and stops);
  // kRestarted (a gap) and kJumped (an estimator reset) emptied the history. Evaluates what is
  // due; with `look_ahead`, waits for the next due sample so that two evaluations share one pass
  // (file mode).
  ResampleStatus push(const TelemetrySample& sample, bool look_ahead);
  void finish();  // end of input: evaluate everything still due
  const EstimateJump& lastJump() const { return resampler_.lastJump(); }  // after kJumped

  bool pop(DetectorOutput& out);  // next ready output, in input order
  const DetectorSummary& summary() const { return summary_; }

 private:
  struct Evaluation {
    long index;  // model sample it was made at
    MotorTheta theta;
    bool active = false, raised = false;
    int motor = 0;
    Severity severity = Severity::kHealthy;
    double estimate = 1.0, lo = 1.0, hi = 1.0;
  };
  void appendModelSample(const TelemetrySample& s);
  void evaluateDue(bool look_ahead);
  void apply(long index, const MotorTheta& theta);  // one evaluation
  void resolve();                                  // pending input samples → ready outputs
  void restart();

  DetectorConfig config_;
  int window_ = 0;  // T [samples]
  std::unique_ptr<MotorEstimator> windowed_;             // one of the two
  std::unique_ptr<StreamingMotorEstimator> streaming_;
  Resampler resampler_;
  AlarmFilter alarm_;
  std::unique_ptr<SequentialRule> sequential_;  // with AlarmRule::kSequential
  long last_evaluation_ = -1;                   // model sample of the previous evaluation since the restart
  // History of model-rate samples since the last restart, contiguous: [capacity][6], [capacity][4]
  // and, for a model that reads them, the body rates [capacity][3].
  std::vector<float> outputs_, inputs_, rates_;
  bool reads_rates_ = false;
  std::vector<double> times_;
  std::vector<std::uint8_t> observable_;  // [capacity] the command gate's mask after each sample
  CommandGate gate_;
  long capacity_ = 0, first_index_ = 0, count_ = 0;  // indices count model samples since the restart
  long next_due_ = 0;
  bool dense_ = false;  // evaluating every sample
  int watch_left_ = 0;  // dense evaluations left in the watch band
  std::vector<float> features_;
  std::vector<MotorTheta> estimates_;
  struct Pending {
    double t;
    long last_index;  // model samples up to here are its evidence
  };
  std::deque<Pending> pending_;
  std::deque<Evaluation> evaluations_;
  std::deque<DetectorOutput> ready_;
  DetectorSummary summary_;
  bool tracking_first_alarm_ = false;
};

}  // namespace quadfdi
