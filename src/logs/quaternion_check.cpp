// The attitude quaternion's reading checked against the flight: see quaternion_check.h.
#include "logs/quaternion_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace quadfdi {

std::string QuaternionReading::name() const {
  return std::string(scalar_last ? "x,y,z,w" : "w,x,y,z") + (world_to_body ? " world → body" : " body → world");
}

std::string QuaternionReading::options() const {
  if (!scalar_last && !world_to_body) return "--csv-quaternion wxyz (the default)";
  return std::string("--csv-quaternion ") + (scalar_last ? "xyzw" : "wxyz") + (world_to_body ? "-world-to-body" : "");
}

const char* toString(QuaternionVerdict v) {
  switch (v) {
    case QuaternionVerdict::kNotChecked: return "not checked";
    case QuaternionVerdict::kAgrees: return "agrees";
    case QuaternionVerdict::kOtherReading: return "another reading";
    case QuaternionVerdict::kUnclear: return "unclear";
  }
  return "";
}

std::size_t indexOf(const QuaternionReading& reading) { return (reading.scalar_last ? 2 : 0) + (reading.world_to_body ? 1 : 0); }

Quaternion quaternionOfColumns(const std::array<double, 4>& c, const QuaternionReading& reading) {
  const Quaternion q = reading.scalar_last ? Quaternion{c[3], c[0], c[1], c[2]} : Quaternion{c[0], c[1], c[2], c[3]};
  return reading.world_to_body ? conjugate(q) : q;
}

std::array<double, 4> columnsOfQuaternion(const Quaternion& body_to_world, const QuaternionReading& reading) {
  const Quaternion q = reading.world_to_body ? conjugate(body_to_world) : body_to_world;
  if (reading.scalar_last) return {q.x, q.y, q.z, q.w};
  return {q.w, q.x, q.y, q.z};
}

namespace {

// First-order high-pass, started at its first input.
struct HighPass {
  std::array<double, 2> low{};
  bool started = false;
  std::array<double, 2> step(const std::array<double, 2>& x, double gain) {
    if (!started) {
      low = x;
      started = true;
    }
    for (std::size_t i = 0; i < 2; ++i) low[i] += gain * (x[i] - low[i]);
    return {x[0] - low[0], x[1] - low[1]};
  }
};

// |fit| with two decimals, as the texts print every fit.
std::string fitText(double fit) {
  char text[16];
  std::snprintf(text, sizeof text, "%.2f", std::abs(fit));
  return text;
}

struct Correlation {
  double n = 0.0, a = 0.0, g = 0.0, aa = 0.0, gg = 0.0, ag = 0.0;
  void add(double x, double y) {
    n += 1.0;
    a += x;
    g += y;
    aa += x * x;
    gg += y * y;
    ag += x * y;
  }
  double value() const {
    if (n < 2.0) return 0.0;
    const double sa = aa / n - (a / n) * (a / n), sg = gg / n - (g / n) * (g / n);
    return sa > 0.0 && sg > 0.0 ? (ag / n - (a / n) * (g / n)) / std::sqrt(sa * sg) : 0.0;
  }
  // The least-squares slope of the first on the second.
  double slope() const {
    if (n < 2.0) return 0.0;
    const double sg = gg / n - (g / n) * (g / n);
    return sg > 0.0 ? (ag / n - (a / n) * (g / n)) / sg : 0.0;
  }
};

}  // namespace

QuaternionCheck checkQuaternionReading(const SignalSeries<3>& position, const SignalSeries<3>& attitude, const SignalSeries<3>& rates,
                                       const QuaternionReading& read, bool ned, BodyTurn turn, const QuaternionCheckOptions& o) {
  QuaternionCheck out;
  out.read = out.best = read;
  out.min_seconds = o.min_seconds;
  if (attitude.t.size() < 2 || position.t.size() < 2) return out;
  // Each attitude row back to the columns it was read from: the body turn and the frame undone,
  // then the reading. The body turn does not move the body z axis and turns the gyro with the body,
  // so both are compared in the file's own body axes.
  const BodyTurn back{-turn.eighths};
  const Quaternion unturn = quaternionOfRotationVector({0.0, 0.0, -turn.radians()});
  std::vector<std::array<double, 4>> columns(attitude.t.size());
  for (std::size_t i = 0; i < attitude.t.size(); ++i) {
    const auto& e = attitude.v[i];
    Quaternion q = quaternionOfEuler({e[0], e[1], e[2]}) * unturn;
    if (ned) q = turnedAboutX(q);
    columns[i] = columnsOfQuaternion(q, read);
  }
  // Each reading's body → world quaternion in quadfdi's frame (the file's body axes), per row.
  auto readAs = [&](const std::array<double, 4>& c, const QuaternionReading& r) {
    Quaternion q = quaternionOfColumns(c, r);
    const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    q = {q.w / norm, q.x / norm, q.y / norm, q.z / norm};
    return ned ? turnedAboutX(q) : q;
  };

  // The tilt: the flight on a grid, in pieces without holes.
  const double dt = o.node_interval;
  const int m = std::max(1, static_cast<int>(std::lround(o.acceleration_span / dt)));
  const double gain = std::min(1.0, dt / o.trend_seconds);
  const std::size_t warm_up = static_cast<std::size_t>(std::ceil(o.trend_seconds / dt));
  std::array<std::array<Correlation, 2>, 4> fits;  // per reading, per horizontal axis
  std::size_t counted = 0;
  std::vector<std::array<double, 2>> piece_position;                        // x, y per node of the piece
  std::vector<std::array<std::array<double, 2>, 4>> piece_tilt;             // per node, per reading
  auto closePiece = [&]() {
    const std::size_t nodes = piece_position.size();
    if (nodes > static_cast<std::size_t>(2 * m)) {
      std::array<HighPass, 4> tilt_trend;
      HighPass lateral_trend;
      const double span2 = (m * dt) * (m * dt);
      for (std::size_t j = static_cast<std::size_t>(m); j + static_cast<std::size_t>(m) < nodes; ++j) {
        // The second difference over ±m nodes is the acceleration weighted by a triangle; the tilt alike.
        std::array<double, 2> lateral{};
        for (std::size_t b = 0; b < 2; ++b)
          lateral[b] = (piece_position[j + m][b] - 2.0 * piece_position[j][b] + piece_position[j - m][b]) / span2;
        lateral = lateral_trend.step(lateral, gain);
        const bool counts = j - static_cast<std::size_t>(m) >= warm_up;
        for (std::size_t k = 0; k < 4; ++k) {
          std::array<double, 2> tilt{};
          double weights = 0.0;
          for (int i = -m + 1; i < m; ++i) {
            const double w = m - std::abs(i);
            weights += w;
            for (std::size_t b = 0; b < 2; ++b) tilt[b] += w * piece_tilt[static_cast<std::size_t>(static_cast<int>(j) + i)][k][b];
          }
          for (double& v : tilt) v /= weights;
          tilt = tilt_trend[k].step(tilt, gain);
          if (counts)
            for (std::size_t b = 0; b < 2; ++b) fits[k][b].add(lateral[b], tilt[b]);
        }
        if (counts) ++counted;
      }
    }
    piece_position.clear();
    piece_tilt.clear();
  };
  std::size_t pi = 0, ai = 0;  // rows at or before the node
  const double t_begin = std::max(position.t.front(), attitude.t.front());
  const double t_end = std::min(position.t.back(), attitude.t.back());
  for (double node = 0.0;; node += 1.0) {
    const double t = t_begin + node * dt;
    if (!(t <= t_end)) break;
    while (pi + 1 < position.t.size() && position.t[pi + 1] <= t) ++pi;
    while (ai + 1 < attitude.t.size() && attitude.t[ai + 1] <= t) ++ai;
    const bool position_whole = pi + 1 < position.t.size() ? position.t[pi + 1] - position.t[pi] <= o.max_gap : position.t[pi] == t;
    const bool attitude_whole = ai + 1 < attitude.t.size() ? attitude.t[ai + 1] - attitude.t[ai] <= o.max_gap : attitude.t[ai] == t;
    if (!position_whole || !attitude_whole) {
      // A hole: the piece ends, and the grid goes on from the rows after it (a file's clock may
      // jump by hours, which a node at a time would walk for ever).
      closePiece();
      double resume = t;
      if (!position_whole && pi + 1 < position.t.size()) resume = std::max(resume, position.t[pi + 1]);
      if (!attitude_whole && ai + 1 < attitude.t.size()) resume = std::max(resume, attitude.t[ai + 1]);
      node = std::max(node, std::ceil((resume - t_begin) / dt) - 1.0);
      continue;
    }
    std::array<double, 2> p{};
    bool finite = true;
    {
      const double s = pi + 1 < position.t.size() ? (t - position.t[pi]) / (position.t[pi + 1] - position.t[pi]) : 0.0;
      for (std::size_t b = 0; b < 2; ++b) {
        const double next = pi + 1 < position.t.size() ? position.v[pi + 1][b] : position.v[pi][b];
        p[b] = position.v[pi][b] + s * (next - position.v[pi][b]);
        finite = finite && std::isfinite(p[b]);
      }
    }
    if (!finite) {
      closePiece();
      continue;
    }
    const std::size_t nearest = ai + 1 < attitude.t.size() && attitude.t[ai + 1] - t < t - attitude.t[ai] ? ai + 1 : ai;
    std::array<std::array<double, 2>, 4> tilt{};
    for (std::size_t k = 0; k < 4; ++k) tilt[k] = thrustTilt(readAs(columns[nearest], kQuaternionReadings[k]));
    piece_position.push_back(p);
    piece_tilt.push_back(tilt);
  }
  closePiece();
  out.seconds = static_cast<double>(counted) * dt;
  // Each horizontal axis's acceleration on its own tilt; a reading fits as well as its worse axis
  // (a scalar-last reading near north keeps x's tilt and puts the yaw into y's), the two alike in sign.
  for (std::size_t k = 0; k < 4; ++k) {
    const double fx = fits[k][0].value(), fy = fits[k][1].value();
    out.axis_fit[k] = {fx, fy};
    out.axis_slope[k] = {fits[k][0].slope(), fits[k][1].slope()};
    // A multirotor accelerates g per unit of tilt, less with drag: a slope far from it is a chance
    // likeness (a yaw that follows the path, read as tilt by a scalar-last reading), not the thrust.
    bool physical = true;
    for (double slope : out.axis_slope[k]) physical = physical && std::abs(slope) >= o.min_slope && std::abs(slope) <= o.max_slope;
    out.tilt_fit[k] = fx * fy > 0.0 && physical ? std::copysign(std::min(std::abs(fx), std::abs(fy)), fx) : 0.0;
  }

  // The rates: each reading's turn against p,q,r in the file's body axes.
  if (!rates.empty()) {
    SignalSeries<3> body_rates = rates, turned = attitude;
    for (auto& w : body_rates.v) w = bodyVectorInTurnedAxes(w, back);
    for (std::size_t k = 0; k < 4; ++k) {
      for (std::size_t i = 0; i < attitude.t.size(); ++i) {
        const Quaternion q = readAs(columns[i], kQuaternionReadings[k]);
        const EulerZyx e = eulerZyxFromUnitQuaternion(q.w, q.x, q.y, q.z);
        turned.v[i] = {e.roll, e.pitch, e.yaw};
      }
      const RateAgreement a = checkRateAgreement(turned, body_rates);
      if (a.verdict == RateAgreementVerdict::kNotChecked) break;  // alike for every reading: too little rotation or rows
      out.rates_compared = true;
      out.rates_in_order[k] = a.in_order;
      out.rate_score[k] = a.score_as_read;
    }
  }

  if (out.seconds < o.min_seconds && !out.rates_compared) return out;
  const std::size_t r = indexOf(read);
  auto fit = [&](std::size_t k) { return std::abs(out.tilt_fit[k]); };
  auto name = [&](std::size_t k) {
    out.best = kQuaternionReadings[k];
    out.verdict = k == r ? QuaternionVerdict::kAgrees : QuaternionVerdict::kOtherReading;
    return out;
  };
  const bool tilt_told = out.seconds >= o.min_seconds;
  // The gyro first: it measures the turn itself, and a reading whose turn it follows in order is the
  // one (p,q,r in another frame or order follow none in order: the tilt decides then).
  // Two readings in order (the inverse at a steady heading near south, its yaw too still to tell)
  // leave it to the tilt.
  if (out.rates_compared) {
    std::size_t only = 4, count = 0;
    for (std::size_t k = 0; k < 4; ++k)
      if (out.rates_in_order[k]) {
        only = k;
        ++count;
      }
    if (count == 1 && (only == r || !tilt_told || fit(only) >= fit(r) - o.min_margin)) return name(only);
  }
  if (!tilt_told) {
    out.verdict = QuaternionVerdict::kUnclear;
    return out;
  }
  std::size_t best = r;
  for (std::size_t k = 0; k < 4; ++k)
    if (fit(k) > fit(best)) best = k;
  // Named where it beats every other reading by the margin; its own inverse, only where that is
  // left open (its sense untold), nothing else may come close.
  const std::size_t best_inverse = indexOf({kQuaternionReadings[best].scalar_last, !kQuaternionReadings[best].world_to_body});
  bool clear = best != r && fit(best) >= o.min_fit;
  for (std::size_t k = 0; k < 4; ++k)
    if (k != best && k != best_inverse) clear = clear && fit(best) - fit(k) >= o.min_margin;
  if (clear && best_inverse != r) {
    out.sense_untold = fit(best_inverse) > fit(best) - o.min_margin;
    return name(best);
  }
  if (clear && fit(best) - fit(r) >= o.min_margin) return name(best);
  // The reading used agrees where it fits and every other fits clearly worse; one that fits alike
  // (the inverse at a steady heading near north or south) leaves it open.
  bool alone = fit(r) >= o.min_fit;
  for (std::size_t k = 0; k < 4; ++k)
    if (k != r && fit(k) > fit(r) - o.min_margin) {
      alone = false;
      out.alike[k] = fit(k) >= o.min_fit;
    }
  if (alone) return name(r);
  out.verdict = QuaternionVerdict::kUnclear;
  return out;
}

std::string QuaternionCheck::text() const {
  char fits[400];
  std::snprintf(fits, sizeof fits, "its horizontal acceleration on the tilt over %.1f s: %.2f read %s", seconds,
                std::abs(tilt_fit[indexOf(read)]), read.name().c_str());
  std::string line = fits;
  if (best != read) {
    std::snprintf(fits, sizeof fits, ", %.2f read %s", std::abs(tilt_fit[indexOf(best)]), best.name().c_str());
    line += fits;
  }
  if (rates_compared) {
    std::snprintf(fits, sizeof fits, "; p,q,r follow its turn %s%s (correlations summed %.2f%s)",
                  rates_in_order[indexOf(read)] ? "in order read " : "not in order read ", read.name().c_str(),
                  rate_score[indexOf(read)], best != read && rates_in_order[indexOf(best)] ? (", in order read " + best.name()).c_str() : "");
    line += fits;
  }
  switch (verdict) {
    case QuaternionVerdict::kNotChecked:
    {
      std::snprintf(fits, sizeof fits, "attitude quaternion: not checked (under %.3g s of flight without holes, and no body rates to compare)",
                    min_seconds);
      return fits;
    }
    case QuaternionVerdict::kAgrees:
      return "attitude quaternion: read as " + read.name() + " it fits the flight (" + line + ")";
    case QuaternionVerdict::kOtherReading: {
      if (!sense_untold)
        return "attitude quaternion: the columns qw,qx,qy,qz fit the flight read as " + best.name() + ", not as " + read.name() + " (" +
               line + "): read them with " + best.options();
      const QuaternionReading other{best.scalar_last, !best.world_to_body};
      return "attitude quaternion: the columns qw,qx,qy,qz fit the flight read as " + std::string(best.scalar_last ? "x,y,z,w" : "w,x,y,z") +
             ", not as " + read.name() + " (" + line + "; " + other.name() + " " +
             fitText(tilt_fit[indexOf(other)]) +
             ": at a steady heading the tilt does not tell a rotation from its inverse): read them with " + best.options() + " or " +
             other.options() + " (p,q,r columns would tell which)";
    }
    case QuaternionVerdict::kUnclear:
      break;
  }
  std::string alike_names;
  for (std::size_t k = 0; k < 4; ++k)
    if (alike[k]) {
      std::snprintf(fits, sizeof fits, "%s%s (%.2f)", alike_names.empty() ? "" : ", ", kQuaternionReadings[k].name().c_str(),
                    std::abs(tilt_fit[k]));
      alike_names += fits;
    }
  const QuaternionReading inverse{read.scalar_last, !read.world_to_body};
  return "attitude quaternion: the flight does not tell how it is read (" + line + ")" +
         (alike_names.empty() ? std::string()
                              : "; read as " + alike_names + " the tilt fits nearly as well" +
                                    (alike[indexOf(inverse)] ? " (the inverse's tilt is the body's, which a steady heading near north or "
                                                               "south cannot tell from the world's)"
                                                             : "") +
                                    (rates_compared ? "" : ": p,q,r columns would tell"));
}

}  // namespace quadfdi
