// Is u1..u4 numbered the way it was read? A check of the motor columns against the flight itself.
//
// The detector names a motor by its column: telemetry whose columns follow another numbering (a
// simulator writing PX4's order as quadfdi's, a converter that swapped two outputs) gets every
// fault named on the wrong motor, and nothing in the file can say so — except the physics. Each
// motor's thrust turns the vehicle one way: with quadfdi's numbering the commanded torques are
// τx ∝ −u1 − u2 + u3 + u4, τy ∝ −u1 + u2 + u3 − u4, τz ∝ −u1 + u2 − u3 + u4 (docs/conventions.md),
// and the angular acceleration of the flight follows them, through the rotors' lag, whatever
// the controller. The check regresses the three components of the body's angular acceleration on
// the three torque patterns of the commands over the flight (both filtered alike and
// high-passed): right numbering, a positive diagonal; another numbering (or rotors spinning the
// other way) permutes and flips it in a way that names which. Closed-loop data can mislead such a
// fit (an oscillation whose roll and pitch run a quarter period apart, seen through the rotors'
// lag), so a numbering is named only where it explains the fit cleanly, and the verdict says
// "inconclusive" rather than guess: docs/conventions.md#checking-the-motor-numbering has what it
// measured.
//
// Streaming and allocation-free: `step` takes each sample as the detector reads it and keeps
// running sums; `result` can be asked at any time.
#pragma once

#include <array>
#include <string>

#include "core/frames.h"
#include "core/motor_numbering.h"
#include "core/types.h"

namespace quadfdi {

// The defaults were chosen on simulated randomised flights, each by what it did to the verdicts
// (docs/conventions.md#checking-the-motor-numbering: 80-ms halves against 20–120 ms, the 0.3-s
// trend against 0.05–1 s, the dominance 2 against 0–3); none is a property of a vehicle.
struct NumberingCheckConfig {
  double node_interval = 0.005;  // [s] samples are averaged into nodes this long (200 Hz: a 125 Hz log's rows are nodes of their own)
  int window_nodes = 16;         // [-] rates are taken over this many nodes (80 ms) and the acceleration as their change
  double trend_seconds = 0.3;    // [s] time constant of the two high-passes (slower content is left out: below ~0.5 Hz)
  double translation_trend_seconds = 2.0;  // [s] the same for the position's acceleration against the tilt
  double max_gap = 0.05;         // [s] a longer hole between samples (or an estimator reset) starts the differences again
  double min_seconds = 5.0;      // [s] of differenced flight before any verdict
  double min_correlation = 0.1;  // [-] the roll and pitch fits a numbering needs to count as shown by the flight
  double min_margin = 0.2;       // [-] how much better (summed fits) another numbering must fit to be named
  // … and how cleanly: each of its roll and pitch fits at least this many times every fit it
  // leaves unexplained in those rows (a flight whose fit no numbering explains names none).
  double min_dominance = 2.0;    // [-]
  double min_independence = 0.02;  // [-] torque patterns more collinear than this (det of their correlations) part no numbering
  // A lost motor breaks the torques the commands predict (its command rises, its thrust is gone) and
  // the vehicle spins up: flight from `pending_seconds` before an alarm until it clears is left out.
  double pending_seconds = 1.0;  // [s] ≥ the detector's delay for a complete failure (~0.1 s) with margin
};

enum class NumberingVerdict {
  kTooShort,        // less than min_seconds of usable flight
  kConsistent,      // the numbering read fits best: roll and pitch fits ≥ min_correlation
  kInconclusive,    // no numbering fits clearly (little manoeuvring, weak fits, or torques collinear)
  kOtherNumbering,  // another numbering (or the rotors' spin reversed) fits better by ≥ min_margin
  kUpsideDown,      // the vehicle accelerates against its tilt as read: its frames are upside down (NED read as z-up);
                    // `best` is the order that fits turned back (another than read where the file has both errors)
};

// "consistent", "inconclusive", "too short", "another numbering", "upside down" (detect --summary's words).
const char* toString(NumberingVerdict v);

// One way the columns can relate to the rotors: column j holds the rotor that quadfdi numbers
// `rotor_of_column[j]`, and the rotors spin as quadfdi's (`spins_reversed` false) or the other way.
struct ColumnHypothesis {
  std::array<int, kMotors> rotor_of_column{1, 2, 3, 4};  // [-] quadfdi motor 1..4
  bool spins_reversed = false;
  bool isRead() const { return rotor_of_column == std::array<int, kMotors>{1, 2, 3, 4} && !spins_reversed; }
  // "quadfdi's (and the Crazyflie's) numbering", "PX4's and ArduPilot's quad X order", … with the
  // positions ("u1..u4 = front-right, back-left, front-left, back-right").
  std::string describe() const;
};

struct NumberingCheckResult {
  NumberingVerdict verdict = NumberingVerdict::kTooShort;
  double seconds = 0.0;  // [s] of differenced flight the fits are over
  // fit[a][b]: the flight's angular acceleration about body axis a (roll, pitch, yaw)
  // regressed on the commands' three torque patterns as read, standardised (the correlation where
  // the patterns are uncorrelated; a manoeuvre that rolls and pitches together correlates every
  // pair, and the regression parts them): the diagonal is what the numbering read predicts.
  std::array<std::array<double, 3>, 3> fit{};
  double torque_independence = 0.0;  // [-] det of the torque patterns' correlation matrix: 1 independent, 0 collinear
  // [-] the position's horizontal acceleration against the tilt of the thrust (the body's z axis,
  // as read) that drives it (correlation, both filtered alike): positive where the frames are
  // read the right way up; 0 where the position does not move.
  double tilt_fit = 0.0;
  bool upright_shown = false;  // tilt_fit ≥ the config's min_correlation: the frames are read the right way up
  double read_score = 0.0;  // [-] the numbering read: fit's trace
  ColumnHypothesis best;    // the best-fitting hypothesis (the read one when consistent)
  double best_score = 0.0;  // [-] its summed signed fits
  ColumnHypothesis second;  // the best hypothesis with another order of the columns
  double second_score = 0.0;  // [-] its summed signed fits
  double min_margin = 0.2;  // [-] the config's: a runner-up within it of the best is named too
  bool rates_used = false;  // the acceleration came from the body rates (else from the attitude)
  std::string text() const;  // one line for the report: verdict, fits, and what fits better
};

class NumberingCheck {
 public:
  explicit NumberingCheck(const NumberingCheckConfig& config = {});
  // `with_rates`: the samples carry body rates (the gyro is less noisy than differenced attitude).
  void setup(bool with_rates);
  void step(const TelemetrySample& sample);
  // The detector's alarm state after the samples stepped so far: raising it drops the pending
  // flight and holds the check until it clears.
  void alarm(bool active);
  NumberingCheckResult result() const;

 private:
  using Mat3 = std::array<std::array<double, 3>, 3>;
  struct Node {
    double t = 0.0;                    // [s] time of the node's last sample
    Quaternion attitude;               // its last sample's attitude
    std::array<double, 3> rates{};     // [rad/s] mean body rates over the node
    std::array<double, 3> torque{};    // [N] mean of the three torque patterns of the commands
    std::array<double, 3> position{};  // [m] its last sample's position (world, as read)
    std::array<double, 2> tilt{};      // [-] the body z axis's horizontal part over its vertical one, world x and y
  };
  // One differenced node's contribution, held for pending_seconds before it joins the sums.
  struct Contribution {
    double t = 0.0, seconds = 0.0;             // [s] node time, and the flight it adds
    std::array<double, 3> acc{};    // [rad/s²] angular acceleration, body roll, pitch, yaw, high-passed
    std::array<double, 3> tau{};    // [N] the commands' torque patterns as read, filtered alike
    std::array<double, 2> lateral{};   // [m/s²] the position's horizontal acceleration, filtered
    std::array<double, 2> tilt{};      // [-] the tilt that drives it (g · tilt would hold the height), filtered alike
  };
  struct Sums {
    double n = 0.0, seconds = 0.0;
    std::array<double, 3> a{}, aa{}, tau{};
    Mat3 atau{}, tautau{};
    double n_lateral = 0.0, l = 0.0, ll = 0.0, g = 0.0, gg = 0.0, lg = 0.0;  // both horizontal axes pooled
    void add(const Contribution& c);
  };
  // Two first-order high-passes in series (exponential means taken out), one per channel.
  struct HighPass {
    std::array<std::array<double, 3>, 2> mean{};
    bool set = false;
    std::array<double, 3> step(const std::array<double, 3>& x, double gain);
  };
  static constexpr int kHistory = 64;   // [-] nodes kept: ≥ 2·window_nodes + 1 (checked)
  static constexpr int kPending = 512;  // [-] contributions held: ≥ pending_seconds / node_interval (checked)
  void closeNode();
  void restart();
  NumberingCheckConfig config_;
  bool with_rates_ = false;
  // The node being filled.
  double node_start_ = 0.0, last_t_ = 0.0;
  int node_samples_ = 0;
  bool have_last_ = false;
  Node open_;
  std::array<double, 3> rate_sum_{}, torque_sum_{};
  // Closed nodes since the last restart (a ring), and the high-passes of the accelerations and torques.
  std::array<Node, kHistory> nodes_{};
  int node_count_ = 0;
  HighPass acc_trend_, torque_trend_, lateral_trend_, tilt_trend_;
  // Contributions not yet committed (a ring: pending_begin_ … pending_end_), and the committed sums.
  std::array<Contribution, kPending> pending_{};
  long pending_begin_ = 0, pending_end_ = 0;
  bool held_ = false;  // an alarm is up
  Sums sums_;
};

}  // namespace quadfdi
