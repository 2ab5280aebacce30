#include "io/controller_config.h"

#include "io/key_value.h"

namespace quadfdi {
namespace {

// One [pid] key; every PidConfig field is a key of the same name.
void setPidKey(const KeyValueDocument& doc, const KeyValueEntry& e, PidConfig& pid) {
  const std::string name = e.key.substr(4);
  struct IntKey { const char* name; int PidConfig::*field; };
  struct NumberKey { const char* name; double PidConfig::*field; };
  static const IntKey kInts[] = {{"position_divisor", &PidConfig::position_divisor},
                                 {"attitude_divisor", &PidConfig::attitude_divisor},
                                 {"rate_divisor", &PidConfig::rate_divisor}};
  static const NumberKey kNumbers[] = {
      {"position_gain_xy", &PidConfig::position_gain_xy}, {"position_gain_z", &PidConfig::position_gain_z},
      {"velocity_gain_xy", &PidConfig::velocity_gain_xy}, {"velocity_integral_xy", &PidConfig::velocity_integral_xy},
      {"velocity_derivative_xy", &PidConfig::velocity_derivative_xy}, {"velocity_gain_z", &PidConfig::velocity_gain_z},
      {"velocity_integral_z", &PidConfig::velocity_integral_z}, {"velocity_derivative_z", &PidConfig::velocity_derivative_z},
      {"velocity_integral_limit", &PidConfig::velocity_integral_limit},
      {"velocity_derivative_cutoff", &PidConfig::velocity_derivative_cutoff}, {"max_tilt", &PidConfig::max_tilt},
      {"min_thrust_fraction", &PidConfig::min_thrust_fraction}, {"attitude_gain_rp", &PidConfig::attitude_gain_rp},
      {"attitude_gain_yaw", &PidConfig::attitude_gain_yaw}, {"yaw_weight", &PidConfig::yaw_weight},
      {"max_rate_rp", &PidConfig::max_rate_rp}, {"max_rate_yaw", &PidConfig::max_rate_yaw},
      {"rate_gain_rp", &PidConfig::rate_gain_rp}, {"rate_integral_rp", &PidConfig::rate_integral_rp},
      {"rate_derivative_rp", &PidConfig::rate_derivative_rp}, {"rate_gain_yaw", &PidConfig::rate_gain_yaw},
      {"rate_integral_yaw", &PidConfig::rate_integral_yaw}, {"rate_integral_limit", &PidConfig::rate_integral_limit}};
  for (const IntKey& k : kInts)
    if (name == k.name) {
      const long long v = doc.integer(e);
      if (v < 1 || v > 1000) doc.fail(e, "'" + e.key + "' must be an integer in 1 … 1000 (steps)");
      pid.*k.field = static_cast<int>(v);
      return;
    }
  for (const NumberKey& k : kNumbers)
    if (name == k.name) {
      PidConfig trial = pid;
      trial.*k.field = doc.number(e);
      if (const std::string problem = validate(trial); !problem.empty()) doc.fail(e, problem);
      pid = trial;
      return;
    }
  doc.fail(e, "unknown key '" + e.key + "'");
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
        doc.fail(e, "controller must be \"lqr\", \"cbf\" or \"pid\", got '" + kind + "'");
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
    } else {
      doc.fail(e, "unknown key '" + k + "'");
    }
  }
  return c;
}

ControllerConfig loadControllerConfig(const std::string& path, const ControllerConfig& base) {
  return controllerConfigFromText(readTextFile(path), path, base);
}

}  // namespace quadfdi
