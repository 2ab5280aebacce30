#include "io/controller_config.h"

#include "io/key_value.h"

namespace quadfdi {
namespace {

template <typename Config>
struct IntKey {
  const char* name;
  int Config::*field;
};
template <typename Config>
struct NumberKey {
  const char* name;
  double Config::*field;
};

// One key of a section ("pid.", "geometric."): every field of its config struct is a key of the
// same name; each value is checked by the struct's own validate().
template <typename Config, std::size_t Ints, std::size_t Numbers>
void setSectionKey(const KeyValueDocument& doc, const KeyValueEntry& e, std::size_t prefix,
                   const IntKey<Config> (&ints)[Ints], const NumberKey<Config> (&numbers)[Numbers], Config& config) {
  const std::string name = e.key.substr(prefix);
  for (const IntKey<Config>& k : ints)
    if (name == k.name) {
      const long long v = doc.integer(e);
      if (v < 1 || v > 1000) doc.fail(e, "'" + e.key + "' must be an integer in 1 … 1000 (steps)");
      config.*k.field = static_cast<int>(v);
      return;
    }
  for (const NumberKey<Config>& k : numbers)
    if (name == k.name) {
      Config trial = config;
      trial.*k.field = doc.number(e);
      if (const std::string problem = validate(trial); !problem.empty()) doc.fail(e, problem);
      config = trial;
      return;
    }
  doc.fail(e, "unknown key '" + e.key + "'");
}

void setPidKey(const KeyValueDocument& doc, const KeyValueEntry& e, PidConfig& pid) {
  using P = PidConfig;
  static const IntKey<P> kInts[] = {{"position_divisor", &P::position_divisor},
                                    {"attitude_divisor", &P::attitude_divisor},
                                    {"rate_divisor", &P::rate_divisor}};
  static const NumberKey<P> kNumbers[] = {
      {"position_gain_xy", &P::position_gain_xy}, {"position_gain_z", &P::position_gain_z},
      {"velocity_gain_xy", &P::velocity_gain_xy}, {"velocity_integral_xy", &P::velocity_integral_xy},
      {"velocity_derivative_xy", &P::velocity_derivative_xy}, {"velocity_gain_z", &P::velocity_gain_z},
      {"velocity_integral_z", &P::velocity_integral_z}, {"velocity_derivative_z", &P::velocity_derivative_z},
      {"velocity_integral_limit", &P::velocity_integral_limit},
      {"velocity_derivative_cutoff", &P::velocity_derivative_cutoff}, {"max_tilt", &P::max_tilt},
      {"min_thrust_fraction", &P::min_thrust_fraction}, {"attitude_gain_rp", &P::attitude_gain_rp},
      {"attitude_gain_yaw", &P::attitude_gain_yaw}, {"yaw_weight", &P::yaw_weight},
      {"max_rate_rp", &P::max_rate_rp}, {"max_rate_yaw", &P::max_rate_yaw},
      {"rate_gain_rp", &P::rate_gain_rp}, {"rate_integral_rp", &P::rate_integral_rp},
      {"rate_derivative_rp", &P::rate_derivative_rp}, {"rate_gain_yaw", &P::rate_gain_yaw},
      {"rate_integral_yaw", &P::rate_integral_yaw}, {"rate_integral_limit", &P::rate_integral_limit}};
  setSectionKey(doc, e, 4, kInts, kNumbers, pid);
}

void setGeometricKey(const KeyValueDocument& doc, const KeyValueEntry& e, GeometricConfig& geometric) {
  using G = GeometricConfig;
  static const IntKey<G> kInts[] = {{"position_divisor", &G::position_divisor}};
  static const NumberKey<G> kNumbers[] = {
      {"position_frequency_xy", &G::position_frequency_xy}, {"position_damping_xy", &G::position_damping_xy},
      {"position_frequency_z", &G::position_frequency_z}, {"position_damping_z", &G::position_damping_z},
      {"position_integral", &G::position_integral}, {"position_integral_limit_xy", &G::position_integral_limit_xy},
      {"position_integral_limit_z", &G::position_integral_limit_z}, {"max_tilt", &G::max_tilt},
      {"min_thrust_fraction", &G::min_thrust_fraction}, {"attitude_frequency_rp", &G::attitude_frequency_rp},
      {"attitude_damping_rp", &G::attitude_damping_rp}, {"attitude_frequency_yaw", &G::attitude_frequency_yaw},
      {"attitude_damping_yaw", &G::attitude_damping_yaw}, {"attitude_integral_rp", &G::attitude_integral_rp},
      {"attitude_integral_yaw", &G::attitude_integral_yaw}, {"attitude_integral_limit", &G::attitude_integral_limit},
      {"attitude_integral_band", &G::attitude_integral_band}};
  setSectionKey(doc, e, 10, kInts, kNumbers, geometric);
}

}  // namespace

ControllerConfig controllerConfigFromText(const std::string& text, const std::string& source,
                                          const ControllerConfig& base) {
  const KeyValueDocument doc = parseKeyValue(text, source);
  ControllerConfig c = base;
  // A preset first, so that explicit weights below override it whatever the key order.
  if (const KeyValueEntry* e = doc.find("lqr.weights")) {
    const std::string preset = doc.string(*e);
    if (preset == "bryson") c.lqr = LqrConfig::bryson();
    else if (preset == "authors") c.lqr = LqrConfig::authors();
    else doc.fail(*e, "lqr.weights must be \"bryson\" or \"authors\", got '" + preset + "'");
  }
  auto positive = [&](const KeyValueEntry& e) {
    const double v = doc.number(e);
    if (!(v > 0.0)) doc.fail(e, "'" + e.key + "' must be > 0");
    return v;
  };
  for (const KeyValueEntry& e : doc.entries) {
    const std::string& k = e.key;
    if (k == "lqr.weights") continue;
    if (k == "controller") {
      const std::string kind = doc.string(e);
      if (!parseControllerKind(kind, c.kind))
        doc.fail(e, "controller must be \"lqr\", \"cbf\", \"pid\" or \"geometric\", got '" + kind + "'");
    } else if (k == "lqr.q_diag") {
      const auto q = doc.numberList(e);
      if (q.size() != kStateDim) doc.fail(e, "lqr.q_diag needs 12 values (state.h order), got " + std::to_string(q.size()));
      for (std::size_t i = 0; i < q.size(); ++i) {
        if (q[i] < 0.0) doc.fail(e, "lqr.q_diag values must be >= 0");
        c.lqr.q_diag(static_cast<int>(i)) = q[i];
      }
    } else if (k == "lqr.r_diag") {
      const auto r = doc.numberList(e);
      if (r.size() != kInputDim) doc.fail(e, "lqr.r_diag needs 4 values, got " + std::to_string(r.size()));
      for (std::size_t i = 0; i < r.size(); ++i) {
        if (!(r[i] > 0.0)) doc.fail(e, "lqr.r_diag values must be > 0");
        c.lqr.r_diag(static_cast<int>(i)) = r[i];
      }
    } else if (k == "lqr.discretization") {
      const std::string d = doc.string(e);
      if (d == "zoh") c.lqr.discretization = Discretization::kZeroOrderHold;
      else if (d == "euler") c.lqr.discretization = Discretization::kForwardEuler;
      else doc.fail(e, "lqr.discretization must be \"zoh\" or \"euler\", got '" + d + "'");
    } else if (k == "cbf.altitude_floor") {
      c.cbf.altitude_floor_enabled = doc.boolean(e);
    } else if (k == "cbf.min_altitude") {
      c.cbf.min_altitude = doc.number(e);
    } else if (k == "cbf.altitude_alpha1") {
      c.cbf.altitude_alpha1 = positive(e);
    } else if (k == "cbf.altitude_alpha2") {
      c.cbf.altitude_alpha2 = positive(e);
    } else if (k == "cbf.tilt_limit") {
      c.cbf.tilt_limit_enabled = doc.boolean(e);
    } else if (k == "cbf.max_tilt") {
      const double v = doc.number(e);
      if (!(v > 0.0 && v < 1.5)) doc.fail(e, "cbf.max_tilt must be in (0, 1.5) rad");
      c.cbf.max_tilt = v;
    } else if (k == "cbf.tilt_alpha1") {
      c.cbf.tilt_alpha1 = positive(e);
    } else if (k == "cbf.tilt_alpha2") {
      c.cbf.tilt_alpha2 = positive(e);
    } else if (k.rfind("pid.", 0) == 0) {
      setPidKey(doc, e, c.pid);
    } else if (k.rfind("geometric.", 0) == 0) {
      setGeometricKey(doc, e, c.geometric);
    } else {
      doc.fail(e, "unknown key '" + k + "'");
    }
  }
  return c;
}

ControllerConfig loadControllerConfig(const std::string& path, const ControllerConfig& base) {
  return controllerConfigFromText(readTextFile(path, "a controller file"), path, base);
}

}  // namespace quadfdi
