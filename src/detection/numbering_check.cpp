#include "detection/numbering_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace quadfdi {

namespace {

// The sign of quadfdi motor k's thrust in each body torque (docs/conventions.md, the mixer):
// roll, pitch, yaw rows; columns motors 1..4.
constexpr int kTorqueSign[3][kMotors] = {{-1, -1, 1, 1}, {-1, 1, 1, -1}, {-1, 1, -1, 1}};

// S[a][b]: the correlation pattern hypothesis h predicts between the acceleration about axis a and
// the torque pattern b computed as read (each entry −1, 0 or 1 for an X: the patterns are
// orthogonal).
std::array<std::array<double, 3>, 3> predictedPattern(const ColumnHypothesis& h) {
  std::array<std::array<double, 3>, 3> s{};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double dot = 0.0;
      for (int j = 0; j < kMotors; ++j) {
        const int truth = kTorqueSign[a][h.rotor_of_column[static_cast<std::size_t>(j)] - 1] * (a == 2 && h.spins_reversed ? -1 : 1);
        dot += truth * kTorqueSign[b][j];
      }
      s[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] = dot / kMotors;
    }
  return s;
}

double score(const std::array<std::array<double, 3>, 3>& pattern, const std::array<std::array<double, 3>, 3>& corr) {
  double sum = 0.0;
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < 3; ++b) sum += pattern[a][b] * corr[a][b];
  return sum;
}

// Every order of the columns (with the spins that fit it better) against a fit, and whether the
// best is shown: its roll and pitch fits clear of the floor and, to name another numbering, of
// what it leaves unexplained — a false "renumber your motors" costs a user more than a missed one,
// and most flights of the measurements that named a wrong one were such fits
// (docs/conventions.md#checking-the-motor-numbering).
struct Judgement {
  ColumnHypothesis best, second;
  double best_score = 0.0, second_score = -1e300, read_score = 0.0;
  bool shown = false;     // the best's roll and pitch fits ≥ min_correlation
  bool dominant = false;  // … and ≥ min_dominance × every fit it leaves unexplained in those rows
};

Judgement judge(const std::array<std::array<double, 3>, 3>& fit, const NumberingCheckConfig& config) {
  Judgement j;
  const ColumnHypothesis read;
  j.read_score = score(predictedPattern(read), fit);
  j.best = read;
  j.best_score = j.read_score;
  std::array<ColumnHypothesis, 24> orders{};
  std::array<double, 24> order_score{};
  std::array<int, kMotors> order{1, 2, 3, 4};
  std::size_t count = 0;
  do {
    for (const bool reversed : {false, true}) {
      ColumnHypothesis h;
      h.rotor_of_column = order;
      h.spins_reversed = reversed;
      const double s = score(predictedPattern(h), fit);
      if (!reversed || s > order_score[count]) {
        orders[count] = h;
        order_score[count] = s;
      }
    }
    if (order_score[count] > j.best_score) {
      j.best = orders[count];
      j.best_score = order_score[count];
    }
    ++count;
  } while (std::next_permutation(order.begin(), order.end()));
  for (std::size_t i = 0; i < orders.size(); ++i)  // the runner-up: the best other order
    if (orders[i].rotor_of_column != j.best.rotor_of_column && order_score[i] > j.second_score) {
      j.second = orders[i];
      j.second_score = order_score[i];
    }
  // The spins show only in the yaw row, the weakest: without a clear yaw fit the standard spins stand.
  if (j.best.spins_reversed) {
    const std::array<std::array<double, 3>, 3> reversed = predictedPattern(j.best);
    double yaw = 0.0;
    for (std::size_t b = 0; b < 3; ++b) yaw += reversed[2][b] * fit[2][b];
    if (yaw < config.min_correlation) {
      j.best.spins_reversed = false;
      j.best_score = score(predictedPattern(j.best), fit);
    }
  }
  const std::array<std::array<double, 3>, 3> pattern = predictedPattern(j.best);
  double explained = 1e300, unexplained = 0.0;
  for (std::size_t a = 0; a < 2; ++a)
    for (std::size_t b = 0; b < 3; ++b) {
      if (pattern[a][b] != 0.0)
        explained = std::min(explained, pattern[a][b] * fit[a][b]);
      else
        unexplained = std::max(unexplained, std::abs(fit[a][b]));
    }
  j.shown = explained >= config.min_correlation;
  j.dominant = j.shown && explained >= config.min_dominance * unexplained;
  return j;
}

struct NamedOrder {
  std::array<int, kMotors> rotor_of_column;
  const char* name;
};
// Orders autopilots write a quad X's outputs in, as quadfdi motors (1 FR, 2 BR, 3 BL, 4 FL).
// Sources: PX4's quad X airframe (1 FR, 2 BL, 3 FL, 4 BR; ArduPilot's FRAME_TYPE 1 the same),
// Betaflight's (1 BR, 2 FR, 3 BL, 4 FL; ArduPilot FRAME_TYPE 12), DJI's (1 FR, 2 FL, 3 BL, 4 BR;
// ArduPilot FRAME_TYPE 13): docs/conventions.md#motors-spin-directions-and-the-mixer.
constexpr NamedOrder kNamedOrders[] = {
    {{1, 2, 3, 4}, "quadfdi's (and the Crazyflie's) numbering"},
    {{1, 3, 4, 2}, "PX4's and ArduPilot's quad X order"},
    {{2, 1, 3, 4}, "Betaflight's order"},
    {{1, 4, 3, 2}, "DJI's order"},
};

}  // namespace

const char* toString(NumberingVerdict v) {
  switch (v) {
    case NumberingVerdict::kTooShort: return "too short";
    case NumberingVerdict::kConsistent: return "consistent";
    case NumberingVerdict::kInconclusive: return "inconclusive";
    case NumberingVerdict::kOtherNumbering: return "another numbering";
    case NumberingVerdict::kUpsideDown: return "upside down";
  }
  return "";
}

std::string ColumnHypothesis::describe() const {
  std::string s;
  for (const NamedOrder& o : kNamedOrders)
    if (o.rotor_of_column == rotor_of_column) s = o.name;
  std::string positions = "u1..u4 = ";
  for (int j = 0; j < kMotors; ++j)
    positions += std::string(j ? ", " : "") + motorPosition(rotor_of_column[static_cast<std::size_t>(j)]);
  s = s.empty() ? positions : s + " (" + positions + ")";
  if (spins_reversed) s += ", with every rotor spinning the other way (front-right clockwise)";
  return s;
}

std::string NumberingCheckResult::text() const {
  char buf[320];
  if (verdict == NumberingVerdict::kTooShort) {
    std::snprintf(buf, sizeof buf, "too short to check (%.1f s of flight)", seconds);
    return buf;
  }
  std::snprintf(buf, sizeof buf,
                "%s over %.1f s of flight (its angular acceleration, %s, fitted on the commands' torques as read: roll / pitch / yaw "
                "%.2f / %.2f / %.2f; its acceleration on its tilt %.2f)",
                toString(verdict), seconds, rates_used ? "from the body rates" : "from the attitude", fit[0][0], fit[1][1], fit[2][2],
                tilt_fit);
  std::string s = buf;
  if (verdict == NumberingVerdict::kUpsideDown) {
    s += ": it accelerates away from where it leans as read, and its pitch and yaw turn against their torques: its frames "
         "are upside down (a NED/FRD file read as z-up, or a z-up one read as NED)";
    if (best.isRead()) return s;
    std::snprintf(buf, sizeof buf, " (%.2f) fits better than the numbering read (%.2f)", best_score, read_score);
    return s + "; turned back, " + best.describe() + buf;
  }
  if (verdict != NumberingVerdict::kOtherNumbering) return s;
  std::snprintf(buf, sizeof buf, "%.2f", best_score);
  s += ": " + best.describe() + " (" + buf + ")";
  if (second_score > best_score - min_margin && !second.isRead()) {  // two orders fit alike: name both
    std::snprintf(buf, sizeof buf, "%.2f", second_score);
    s += " or " + second.describe() + " (" + buf + ")";
  }
  std::snprintf(buf, sizeof buf, "%.2f", read_score);
  s += std::string(" fits better than the numbering read (") + buf + ")";
  // The front–back mirror turns pitch and yaw the other way, as frames read upside down do; said
  // unless the tilt showed the frames the right way up.
  if (best.rotor_of_column == std::array<int, kMotors>{2, 1, 4, 3} && !best.spins_reversed && !upright_shown)
    s += ", or the file's frames are upside down (a NED/FRD file read as z-up), which looks the same in the rotation";
  return s;
}

NumberingCheck::NumberingCheck(const NumberingCheckConfig& config) : config_(config) {
  if (config_.window_nodes < 1 || 2 * config_.window_nodes + 1 > kHistory)
    throw std::invalid_argument("numbering check: window_nodes must be 1.." + std::to_string((kHistory - 1) / 2));
  if (!(config_.node_interval > 0.0)) throw std::invalid_argument("numbering check: node_interval must be > 0");
  if (!(config_.trend_seconds > 0.0)) throw std::invalid_argument("numbering check: trend_seconds must be > 0");
  if (!(config_.pending_seconds >= 0.0) || config_.pending_seconds / config_.node_interval > kPending - 1)
    throw std::invalid_argument("numbering check: pending_seconds must be 0.." + std::to_string((kPending - 1) * config_.node_interval) + " s");
}

void NumberingCheck::Sums::add(const Contribution& c) {
  n += 1.0;
  seconds += c.seconds;
  for (std::size_t i = 0; i < 3; ++i) {
    a[i] += c.acc[i];
    aa[i] += c.acc[i] * c.acc[i];
    tau[i] += c.tau[i];
    for (std::size_t b = 0; b < 3; ++b) {
      atau[i][b] += c.acc[i] * c.tau[b];
      tautau[i][b] += c.tau[i] * c.tau[b];
    }
  }
  for (std::size_t i = 0; i < 2; ++i) {
    n_lateral += 1.0;
    l += c.lateral[i];
    ll += c.lateral[i] * c.lateral[i];
    g += c.tilt[i];
    gg += c.tilt[i] * c.tilt[i];
    lg += c.lateral[i] * c.tilt[i];
  }
}

std::array<double, 3> NumberingCheck::HighPass::step(const std::array<double, 3>& x, double gain) {
  if (!set) {  // start from the first value: no step to take out
    mean[0] = x;
    mean[1] = {};
    set = true;
  }
  std::array<double, 3> y = x;
  for (std::array<double, 3>& m : mean)
    for (std::size_t b = 0; b < 3; ++b) {
      m[b] += gain * (y[b] - m[b]);
      y[b] -= m[b];
    }
  return y;
}

void NumberingCheck::alarm(bool active) {
  if (active && !held_) pending_begin_ = pending_end_;  // the flight before the alarm may already hold the fault
  held_ = active;
}

void NumberingCheck::setup(bool with_rates) {
  with_rates_ = with_rates;
  restart();
  have_last_ = false;
  held_ = false;
  pending_begin_ = pending_end_ = 0;
  sums_ = Sums{};
}

void NumberingCheck::restart() {
  node_count_ = 0;
  node_samples_ = 0;
  rate_sum_ = torque_sum_ = {};
  acc_trend_ = torque_trend_ = lateral_trend_ = tilt_trend_ = HighPass{};
}

void NumberingCheck::step(const TelemetrySample& sample) {
  const bool thrust = sample.u[0] + sample.u[1] + sample.u[2] + sample.u[3] > 0.0;
  if (!thrust || (have_last_ && !(sample.t - last_t_ <= config_.max_gap))) restart();
  have_last_ = true;
  last_t_ = sample.t;
  if (!thrust) return;
  if (node_samples_ == 0) node_start_ = sample.t;
  ++node_samples_;
  for (std::size_t b = 0; b < 3; ++b) {
    double tau = 0.0;
    for (std::size_t j = 0; j < kMotors; ++j) tau += kTorqueSign[b][j] * sample.u[j];
    torque_sum_[b] += tau;
    rate_sum_[b] += sample.rates[b];
  }
  open_.t = sample.t;
  open_.position = {sample.y[0], sample.y[1], sample.y[2]};
  open_.attitude = quaternionOfEuler({sample.y[3], sample.y[4], sample.y[5]});
  if (sample.t - node_start_ >= config_.node_interval - 1e-9) closeNode();
}

void NumberingCheck::closeNode() {
  const double k = 1.0 / node_samples_;
  for (std::size_t b = 0; b < 3; ++b) {
    open_.torque[b] = torque_sum_[b] * k;
    open_.rates[b] = rate_sum_[b] * k;
  }
  open_.tilt = thrustTilt(open_.attitude);
  node_samples_ = 0;
  rate_sum_ = torque_sum_ = {};
  // A turn between two nodes faster than any body rate is an estimator reset, not flight.
  if (node_count_ > 0) {
    const Node& prev = nodes_[static_cast<std::size_t>((node_count_ - 1) % kHistory)];
    const double dt = open_.t - prev.t;
    if (!(dt > 0.0) || rotationAngle(conjugate(prev.attitude) * open_.attitude) > kMaxBodyRate * dt) restart();
  }
  nodes_[static_cast<std::size_t>(node_count_ % kHistory)] = open_;
  ++node_count_;
  const int m = config_.window_nodes;
  if (node_count_ < 2 * m + 1) return;
  auto at = [&](int back) -> const Node& { return nodes_[static_cast<std::size_t>((node_count_ - 1 - back) % kHistory)]; };
  const Node& n0 = at(0);
  const Node& n1 = at(m);
  const Node& n2 = at(2 * m);
  // The angular acceleration over the last 2m nodes: the change between the mean body rates of the
  // two halves (from the gyro, or from the attitude's turn over each half, in the body axes).
  std::array<double, 3> w_new{}, w_old{};
  if (with_rates_) {
    for (int i = 0; i < m; ++i)
      for (std::size_t b = 0; b < 3; ++b) {
        w_new[b] += at(i).rates[b] / m;
        w_old[b] += at(m + i).rates[b] / m;
      }
  } else {
    const std::array<double, 3> turn_new = rotationVectorOfQuaternion(conjugate(n1.attitude) * n0.attitude);
    const std::array<double, 3> turn_old = rotationVectorOfQuaternion(conjugate(n2.attitude) * n1.attitude);
    for (std::size_t b = 0; b < 3; ++b) {
      w_new[b] = turn_new[b] / (n0.t - n1.t);
      w_old[b] = turn_old[b] / (n1.t - n2.t);
    }
  }
  const double span = 0.5 * (n0.t - n2.t);  // [s] between the halves' middles
  // The commands that drive it: their torque patterns weighted as the acceleration estimate weighs
  // the flight (the change of two m-node means of the rate is a triangle over the 2m nodes).
  std::array<double, 3> tau{}, acc{};
  std::array<double, 3> tilt{};
  double weights = 0.0;
  for (int i = 0; i < 2 * m; ++i) {
    const double w = std::min(i + 1, 2 * m - i);
    weights += w;
    for (std::size_t b = 0; b < 3; ++b) tau[b] += w * at(i).torque[b];
    for (std::size_t b = 0; b < 2; ++b) tilt[b] += w * at(i).tilt[b];
  }
  for (std::size_t b = 0; b < 3; ++b) {
    tau[b] /= weights;
    acc[b] = (w_new[b] - w_old[b]) / span;
  }
  // The frames the same way: a multirotor accelerates where its thrust leans (g·tilt holds its
  // height), read the right way up or not; a NED file read as z-up turns pitch and yaw the other
  // way, which a front–back mirrored order of the columns would also do, and this tells them apart.
  std::array<double, 3> lateral{};
  for (std::size_t b = 0; b < 2; ++b) {
    tilt[b] /= weights;
    lateral[b] = ((n0.position[b] - n1.position[b]) / (n0.t - n1.t) - (n1.position[b] - n2.position[b]) / (n1.t - n2.t)) / span;
  }
  // Both high-passed alike, from the same node on: what the commands hold for seconds (a centre of
  // mass off the middle, a slow manoeuvre's rolling and pitching a quarter period apart) turns
  // nothing the check can see in the acceleration, and would only weigh the fits down or across.
  const double node_dt = n0.t - at(1).t;  // [s]
  const double gain = std::min(1.0, node_dt / config_.trend_seconds);
  acc = acc_trend_.step(acc, gain);
  tau = torque_trend_.step(tau, gain);
  const double slow_gain = std::min(1.0, node_dt / config_.translation_trend_seconds);
  lateral = lateral_trend_.step(lateral, slow_gain);
  tilt = tilt_trend_.step(tilt, slow_gain);
  if (held_) return;
  Contribution& c = pending_[static_cast<std::size_t>(pending_end_++ % kPending)];
  c.t = n0.t;
  c.seconds = node_dt;
  c.acc = acc;
  c.tau = tau;
  c.lateral = {lateral[0], lateral[1]};
  c.tilt = {tilt[0], tilt[1]};
  // Flight older than pending_seconds can no longer be the run-up to an alarm: committed.
  while (pending_begin_ < pending_end_ &&
         (pending_end_ - pending_begin_ >= kPending || pending_[static_cast<std::size_t>(pending_begin_ % kPending)].t < c.t - config_.pending_seconds))
    sums_.add(pending_[static_cast<std::size_t>(pending_begin_++ % kPending)]);
}

NumberingCheckResult NumberingCheck::result() const {
  NumberingCheckResult r;
  r.rates_used = with_rates_;
  r.min_margin = config_.min_margin;
  Sums all = sums_;  // with the flight still pending: no alarm has come to take it back
  for (long i = pending_begin_; i < pending_end_; ++i) all.add(pending_[static_cast<std::size_t>(i % kPending)]);
  r.seconds = all.seconds;
  if (r.seconds < config_.min_seconds) return r;
  r.verdict = NumberingVerdict::kInconclusive;  // until the flight shows more
  // Standardised: the torque patterns' correlation matrix R and each acceleration's correlations
  // c_a with them; the regression's coefficients are R⁻¹ c_a.
  const double n = all.n;
  std::array<double, 3> sd_acc{}, sd_tau{};
  for (std::size_t b = 0; b < 3; ++b) {
    sd_acc[b] = std::sqrt(std::max(0.0, all.aa[b] / n - (all.a[b] / n) * (all.a[b] / n)));
    sd_tau[b] = std::sqrt(std::max(0.0, all.tautau[b][b] / n - (all.tau[b] / n) * (all.tau[b] / n)));
    if (!(sd_acc[b] > 0.0) || !(sd_tau[b] > 0.0)) return r;  // an axis without motion or torque: nothing to compare
  }
  Mat3 corr_tau{}, corr_acc{};
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < 3; ++b) {
      corr_tau[a][b] = (all.tautau[a][b] / n - (all.tau[a] / n) * (all.tau[b] / n)) / (sd_tau[a] * sd_tau[b]);
      corr_acc[a][b] = (all.atau[a][b] / n - (all.a[a] / n) * (all.tau[b] / n)) / (sd_acc[a] * sd_tau[b]);
    }
  const Mat3& m = corr_tau;
  const Mat3 cof = {{
      {m[1][1] * m[2][2] - m[1][2] * m[2][1], m[0][2] * m[2][1] - m[0][1] * m[2][2], m[0][1] * m[1][2] - m[0][2] * m[1][1]},
      {m[1][2] * m[2][0] - m[1][0] * m[2][2], m[0][0] * m[2][2] - m[0][2] * m[2][0], m[0][2] * m[1][0] - m[0][0] * m[1][2]},
      {m[1][0] * m[2][1] - m[1][1] * m[2][0], m[0][1] * m[2][0] - m[0][0] * m[2][1], m[0][0] * m[1][1] - m[0][1] * m[1][0]},
  }};
  r.torque_independence = m[0][0] * cof[0][0] + m[0][1] * cof[1][0] + m[0][2] * cof[2][0];
  if (!(r.torque_independence >= config_.min_independence)) return r;  // collinear: it parts nothing
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < 3; ++b)
      for (std::size_t k = 0; k < 3; ++k) r.fit[a][b] += cof[b][k] / r.torque_independence * corr_acc[a][k];
  // The frames: the vehicle accelerates toward where it leans.
  const double nl = all.n_lateral;
  const double sd_l = std::sqrt(std::max(0.0, all.ll / nl - (all.l / nl) * (all.l / nl)));
  const double sd_g = std::sqrt(std::max(0.0, all.gg / nl - (all.g / nl) * (all.g / nl)));
  if (sd_l > 0.0 && sd_g > 0.0) r.tilt_fit = (all.lg / nl - (all.l / nl) * (all.g / nl)) / (sd_l * sd_g);
  r.upright_shown = r.tilt_fit >= config_.min_correlation;
  // Read upside down (both frames turned 180° about x), the pitch and yaw accelerations come out
  // the other way — as they do with the columns in the front–back mirrored order. Upside down is
  // said where both agree: the vehicle accelerates away from where it leans, and turned back its
  // rotation fits the order read (the tilt alone dipped to −0.15 in 4 of 2 000 simulated flights
  // read the right way up, each losing a motor after 10 s; docs/conventions.md#checking-the-motor-numbering).
  // Both errors at once (a NED file in another autopilot's order) leave neither reading with the
  // order read: then the tilt decides, where turned back another order fits as clearly as an
  // upright file's must to be named (the rotation alone cannot tell them: the turned fit of an
  // order scores what the upright fit of its front–back mirror does).
  Mat3 turned = r.fit;
  for (std::size_t a = 1; a < 3; ++a)
    for (double& v : turned[a]) v = -v;
  const Judgement upright = judge(r.fit, config_), over = judge(turned, config_);
  const bool turned_names_another =
      !upright.best.isRead() && over.dominant && over.best_score - over.read_score >= config_.min_margin;
  const bool upside_down = r.tilt_fit <= -config_.min_correlation && (over.best.isRead() || turned_names_another);
  const Judgement& j = upside_down ? over : upright;
  r.read_score = j.read_score;
  r.best = j.best;
  r.best_score = j.best_score;
  r.second = j.second;
  r.second_score = j.second_score;
  if (!j.shown) return r;
  if (upside_down)
    r.verdict = NumberingVerdict::kUpsideDown;
  else if (r.best.isRead())
    r.verdict = NumberingVerdict::kConsistent;
  else if (j.dominant && r.best_score - r.read_score >= config_.min_margin)
    r.verdict = NumberingVerdict::kOtherNumbering;
  return r;
}

}  // namespace quadfdi
