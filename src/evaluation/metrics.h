// FDI metrics (docs/decisions.md) over per-window outcomes of a test set.
#pragma once

#include <vector>

#include "evaluation/decision.h"

namespace quadfdi {

struct WindowOutcome {
  int trajectory = 0;     // test-set trajectory index
  int faulty_length = 0;  // L = k − F (0 = no faulty sample in the window)
  int true_motor = 0;     // 1..4, 0 for a healthy trajectory
  double true_theta = 1.0;  // Θ of the faulty motor
  Decision decision;
  Input theta_hat = Input::Ones();
};

struct AccuracyByLength {
  std::vector<double> accuracy;  // index L = 0 … max_length; NaN where no window has that L
  std::vector<int> windows;      // windows counted per L
};

// Faulty trajectories: the window with L faulty samples raises an alarm naming the true motor
// (for L = 0: raises no alarm). Healthy trajectories count at every L: no alarm is correct.
AccuracyByLength isolationAccuracy(const std::vector<WindowOutcome>& outcomes, int max_length, bool healthy);
// As isolation, and also |Θ̂_motor − Θ| ≤ tolerance (paper Fig. 5: 0.05).
AccuracyByLength identificationAccuracy(const std::vector<WindowOutcome>& outcomes, int max_length,
                                        double tolerance = 0.05);

struct DetectionDelay {
  double median = 0.0;  // [samples] first L whose window raises an alarm naming the right motor
  double p95 = 0.0;     // [samples]
  int detected = 0;     // faulty trajectories detected at all
  int faulty = 0;       // faulty trajectories
};
DetectionDelay detectionDelay(const std::vector<WindowOutcome>& outcomes);

// Fraction of windows without any faulty sample (healthy flights, or L = 0) that raise an alarm.
double falseAlarmRate(const std::vector<WindowOutcome>& outcomes);
// Mean |Θ̂_motor − Θ| of the true motor over windows with L ≥ 1.
double thetaMae(const std::vector<WindowOutcome>& outcomes);

}  // namespace quadfdi
