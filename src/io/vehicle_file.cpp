#include "io/vehicle_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "core/motor_numbering.h"
#include "core/quad_layout.h"
#include "io/key_value.h"

namespace quadfdi {
namespace {

std::string percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f %%", 100.0 * fraction);
  return buf;
}

std::string metres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g m", v);
  return buf;
}

// Top-level numeric fields: key, unit (for messages), required.
struct NumberField {
  const char* key;
  const char* unit;
  bool required;
};
const NumberField kNumberFields[] = {
    {"mass", "kg", true},
    {"inertia_xx", "kg·m²", true},
    {"inertia_yy", "kg·m²", true},
    {"inertia_zz", "kg·m²", true},
    {"inertia_xy", "kg·m²", false},
    {"inertia_xz", "kg·m²", false},
    {"inertia_yz", "kg·m²", false},
    {"yaw_moment_coeff", "m", true},
    {"motor_time_constant", "s", true},
    {"gravity", "m/s²", false},
    {"linear_drag", "N·s/m", false},
    {"rotational_drag", "N·m·s/rad", false},
    {"thrust.max", "N per motor", true},
    {"thrust.min", "N per motor", true},
    {"thrust.model_factor", "-", true},
};
const char* const kStringFields[] = {"name", "source", "motor_numbering", "frame"};

class Reader {
 public:
  Reader(const std::string& text, const std::string& source)
      : doc_(parseKeyValue(text, source)), source_(source), last_line_(std::max(1, lineCount(text))) {}

  const KeyValueDocument& doc() const { return doc_; }

  // The line a message about a missing key points at: the first key of its section, else the end.
  int lineFor(const std::string& key) const {
    const auto dot = key.rfind('.');
    if (dot != std::string::npos) {
      const std::string section = key.substr(0, dot + 1);
      for (const auto& e : doc_.entries)
        if (e.key.compare(0, section.size(), section) == 0) return e.line;
    }
    return last_line_;
  }
  [[noreturn]] void failAt(int line, const std::string& problem) const {
    throw ConfigError(source_ + ":" + std::to_string(line) + ": " + problem);
  }
  const KeyValueEntry& require(const std::string& key, const std::string& what) const {
    const KeyValueEntry* e = doc_.find(key);
    if (!e) failAt(lineFor(key), "missing '" + key + "' (" + what + ")");
    return *e;
  }

 private:
  static int lineCount(const std::string& text) {
    return static_cast<int>(std::count(text.begin(), text.end(), '\n')) + (text.empty() || text.back() == '\n' ? 0 : 1);
  }
  KeyValueDocument doc_;
  std::string source_;
  int last_line_;
};

void rejectUnknownKeys(const KeyValueDocument& doc) {
  std::set<std::string> known(std::begin(kStringFields), std::end(kStringFields));
  for (const NumberField& f : kNumberFields) known.insert(f.key);
  for (int m = 1; m <= 4; ++m)
    for (const char* k : {"x", "y", "spin"}) known.insert("motor." + std::to_string(m) + "." + k);
  for (const auto& e : doc.entries) {
    if (known.count(e.key)) continue;
    if (e.key.rfind("motor.", 0) == 0)
      doc.fail(e, "unknown motor key '" + e.key + "' (a quad X has [motor.1] … [motor.4], each with x, y, spin)");
    std::string list;
    for (const char* s : kStringFields) list += std::string(list.empty() ? "" : ", ") + s;
    for (const NumberField& f : kNumberFields) list += std::string(", ") + f.key;
    doc.fail(e, "unknown key '" + e.key + "' (known: " + list + ", motor.N.x/y/spin)");
  }
}

std::string formatNumber(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}

}  // namespace

bool looksLikeVehicleDescription(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const auto b = line.find_first_not_of(" \t");
    if (b != std::string::npos && line.compare(b, 7, "[motor.") == 0) return true;
  }
  return false;
}

VehicleDescription vehicleDescriptionFromText(const std::string& text, const std::string& source) {
  const Reader r(text, source);
  const KeyValueDocument& doc = r.doc();
  rejectUnknownKeys(doc);

  VehicleDescription d;
  d.name = doc.string(r.require("name", "the vehicle's name"));
  d.source = doc.string(r.require("source", "where the numbers come from"));
  d.motor_numbering = doc.string(r.require("motor_numbering", "whose motor numbers [motor.N] uses, e.g. \"PX4 quad X\""));
  const KeyValueEntry& frame = r.require("frame", "\"frd\": x forward, y right, z down");
  if (doc.string(frame) != "frd")
    doc.fail(frame, "frame must be \"frd\" (x forward, y right, z down, as in the PX4/ArduPilot airframe references), got \"" +
                        doc.string(frame) + "\"");

  auto number = [&](const NumberField& f, double fallback) {
    const KeyValueEntry* e = doc.find(f.key);
    if (!e) {
      if (f.required) r.require(f.key, std::string("[") + f.unit + "]");
      return fallback;
    }
    return doc.number(*e);
  };
  auto field = [&](const char* key) -> const NumberField& {
    for (const NumberField& f : kNumberFields)
      if (std::string(f.key) == key) return f;
    throw std::logic_error(key);
  };
  VehicleParams& p = d.params;
  p.mass = number(field("mass"), 0.0);
  p.inertia_xx = number(field("inertia_xx"), 0.0);
  p.inertia_yy = number(field("inertia_yy"), 0.0);
  p.inertia_zz = number(field("inertia_zz"), 0.0);
  for (const char* product : {"inertia_xy", "inertia_xz", "inertia_yz"})
    if (const KeyValueEntry* e = doc.find(product); e && doc.number(*e) != 0.0)
      doc.fail(*e, std::string("non-zero product of inertia ") + product +
                       ": quadfdi's model and its symmetry maps need the principal axes along the body axes (a "
                       "diagonal inertia); give the diagonal in principal axes");
  p.yaw_moment_coeff = number(field("yaw_moment_coeff"), 0.0);
  p.motor_time_constant = number(field("motor_time_constant"), 0.0);
  p.gravity = number(field("gravity"), 9.81);  // [m/s²] standard gravity to three digits
  p.linear_drag = number(field("linear_drag"), 0.0);
  p.rotational_drag = number(field("rotational_drag"), 0.0);
  p.max_thrust = number(field("thrust.max"), 0.0);
  p.min_thrust = number(field("thrust.min"), 0.0);
  p.thrust_model_factor = number(field("thrust.model_factor"), 0.0);

  // --- Rotors, in the autopilot's numbering. ---
  std::array<int, 4> line_of{};
  for (int m = 1; m <= 4; ++m) {
    const std::string sec = "motor." + std::to_string(m) + ".";
    RotorDescription& rotor = d.rotors[static_cast<std::size_t>(m - 1)];
    const KeyValueEntry& ex = r.require(sec + "x", "[m] forward of the centre of mass");
    const KeyValueEntry& ey = r.require(sec + "y", "[m] right of the centre of mass");
    const KeyValueEntry& es = r.require(sec + "spin", "\"cw\" or \"ccw\" seen from above");
    rotor.x = doc.number(ex);
    rotor.y = doc.number(ey);
    std::string spin = doc.string(es);
    std::transform(spin.begin(), spin.end(), spin.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (spin != "cw" && spin != "ccw") doc.fail(es, "'" + es.key + "' must be \"cw\" or \"ccw\" (seen from above), got \"" + spin + "\"");
    rotor.ccw = spin == "ccw";
    line_of[static_cast<std::size_t>(m - 1)] = ex.line;
  }
  // An X, a plus or a props-out frame, read as the standard X in turned axes (core/quad_layout.h).
  std::array<RotorPlacement, 4> placements{};
  for (std::size_t i = 0; i < 4; ++i) placements[i] = {d.rotors[i].x, d.rotors[i].y, d.rotors[i].ccw ? 1 : -1};
  const QuadLayout layout = quadLayout(placements);
  const auto lineOf = [&](int motor) { return line_of[static_cast<std::size_t>(motor - 1)]; };
  const auto named = [&](int motor) {
    const int q = layout.quadfdi_motor_of[static_cast<std::size_t>(motor - 1)];
    return "motor " + std::to_string(motor) + (q > 0 ? std::string(" (") + motorPosition(q, layout.turn) + ")" : std::string());
  };
  switch (layout.status) {
    case QuadLayoutStatus::kOk: break;
    case QuadLayoutStatus::kRotorAtCentre:
      r.failAt(lineOf(layout.motor), "motor " + std::to_string(layout.motor) + " is at the centre (x = y = 0): every rotor needs an arm");
      break;
    case QuadLayoutStatus::kMixedAxes:
      r.failAt(lineOf(layout.motor), "motor " + std::to_string(layout.motor) + " lies on a body axis and motor " +
                                         std::to_string(layout.other) +
                                         " does not: quadfdi reads a quad X (every rotor at (±a, ±b) with a, b > 0) or a "
                                         "plus frame (every rotor on an axis)");
      break;
    case QuadLayoutStatus::kDuplicateQuadrant: {
      const RotorPlacement& o = layout.turned[static_cast<std::size_t>(layout.other - 1)];
      r.failAt(lineOf(layout.other), "motors " + std::to_string(layout.motor) + " and " + std::to_string(layout.other) + " are both " +
                                         motorPosition(quadfdiMotorAtFrd(o.x_forward, o.y_right), layout.turn) +
                                         " (duplicate motor position): a quad has exactly one rotor in each quadrant" +
                                         (layout.plus ? " (a plus frame: one on each arm)" : ""));
    }
    case QuadLayoutStatus::kWrongSpinPattern:
    case QuadLayoutStatus::kSpinsUnknown:  // not reached: a description gives every spin
      if (placements[static_cast<std::size_t>(layout.motor - 1)].spin != placements[static_cast<std::size_t>(layout.other - 1)].spin)
        r.failAt(lineOf(layout.other), "wrong spin pattern: motors " + std::to_string(layout.motor) + " and " + std::to_string(layout.other) +
                                           " are opposite each other and must spin the same way, or hovering needs a yaw moment");
      r.failAt(lineOf(layout.other), "wrong spin pattern: motors " + std::to_string(layout.motor) + " and " + std::to_string(layout.other) +
                                         " are neighbours and spin the same way: a quad needs two rotors spinning each way, "
                                         "opposite rotors alike, to make a yaw moment");
  }
  d.body_turn = layout.turn;
  d.quadfdi_motor_of_autopilot_motor = layout.quadfdi_motor_of;
  d.autopilot_motor_of_quadfdi_motor = layout.rotor_of_quadfdi_motor;
  const std::string axes = layout.turn.none() ? "" : " (in the axes turned " + std::to_string(45 * layout.turn.eighths) + "°)";

  // Centre of mass at the centre of the rotors; rotors at (±a, ±b): checked in the axes the model reads.
  double mean_x = 0.0, mean_y = 0.0, a = 0.0, b = 0.0;
  for (const RotorPlacement& rotor : layout.turned) {
    mean_x += rotor.x_forward / 4.0;
    mean_y += rotor.y_right / 4.0;
    a += std::abs(rotor.x_forward) / 4.0;
    b += std::abs(rotor.y_right) / 4.0;
  }
  if (std::abs(mean_x) > kRotorPositionTolerance * a || std::abs(mean_y) > kRotorPositionTolerance * b)
    r.failAt(line_of[0], "centre of mass offset: the mean rotor position is (" + metres(mean_x) + ", " + metres(mean_y) +
                             ")" + axes + " from the centre of mass (more than " + percent(kRotorPositionTolerance) +
                             " of the arm); the isolation's symmetry needs the centre of mass at the centre of the rotors "
                             "(measure rotor positions from the centre of mass)");
  for (int m = 1; m <= 4; ++m) {
    const RotorPlacement& rotor = layout.turned[static_cast<std::size_t>(m - 1)];
    const double ex = std::abs(std::abs(rotor.x_forward) - a) / a, ey = std::abs(std::abs(rotor.y_right) - b) / b;
    if (ex > kRotorPositionTolerance || ey > kRotorPositionTolerance)
      r.failAt(lineOf(m), "asymmetric rotor positions: " + named(m) + " at |x| = " + metres(std::abs(rotor.x_forward)) +
                              ", |y| = " + metres(std::abs(rotor.y_right)) + axes + " differs from the mean (" + metres(a) + ", " +
                              metres(b) + ") by " + percent(std::max(ex, ey)) + " (> " + percent(kRotorPositionTolerance) +
                              "); the isolation needs every rotor at (±a, ±b)" +
                              (layout.plus ? ", for a plus frame every arm of one length" : "") +
                              " — symmetrise the positions if the difference is a measurement artefact");
  }
  // The inertia in the turned axes: a quarter turn swaps the roll and pitch axes; an eighth turn
  // (a plus frame) keeps it diagonal only when the two are equal.
  if (layout.turn.swapsXY()) std::swap(p.inertia_xx, p.inertia_yy);
  if (layout.plus) {
    const double mean = 0.5 * (p.inertia_xx + p.inertia_yy), diff = std::abs(p.inertia_xx - p.inertia_yy);
    if (diff > kRotorPositionTolerance * mean)
      r.failAt(doc.find("inertia_xx") ? doc.find("inertia_xx")->line : lineOf(1),
               "a plus frame with inertia_xx and inertia_yy " + percent(diff / mean) + " apart (> " + percent(kRotorPositionTolerance) +
                   "): read as an X in axes turned 45°, the difference would be a product of inertia, which quadfdi's "
                   "model and symmetry maps do not have");
    p.inertia_xx = p.inertia_yy = mean;
  }

  p.rotor_x = a;
  p.rotor_y = b;
  p.arm_length = std::hypot(a, b);  // informative (centre to rotor); the levers are rotor_x, rotor_y
  if (const std::string problem = validate(p); !problem.empty())
    throw ConfigError(source + ": invalid vehicle: " + problem);
  return d;
}

VehicleDescription loadVehicleDescription(const std::string& path, PipeReading pipes) {
  return vehicleDescriptionFromText(readTextFile(path, "a vehicle file", pipes), path);
}

std::string vehicleDescriptionToText(const VehicleDescription& d) {
  const VehicleParams& p = d.params;
  std::ostringstream out;
  out << "name = \"" << d.name << "\"\n";
  out << "source = \"" << d.source << "\"\n";
  out << "motor_numbering = \"" << d.motor_numbering << "\"\n";
  out << "frame = \"frd\"\n";
  out << "mass = " << formatNumber(p.mass) << "  # [kg]\n";
  // The airframe's own axes, as the rotors are written (params hold the turned axes' inertia).
  const bool swapped = d.body_turn.swapsXY();
  out << "inertia_xx = " << formatNumber(swapped ? p.inertia_yy : p.inertia_xx) << "  # [kg·m²]\n";
  out << "inertia_yy = " << formatNumber(swapped ? p.inertia_xx : p.inertia_yy) << "  # [kg·m²]\n";
  out << "inertia_zz = " << formatNumber(p.inertia_zz) << "  # [kg·m²]\n";
  out << "yaw_moment_coeff = " << formatNumber(p.yaw_moment_coeff) << "  # [m]\n";
  out << "motor_time_constant = " << formatNumber(p.motor_time_constant) << "  # [s]\n";
  out << "gravity = " << formatNumber(p.gravity) << "  # [m/s²]\n";
  out << "linear_drag = " << formatNumber(p.linear_drag) << "  # [N·s/m]\n";
  out << "rotational_drag = " << formatNumber(p.rotational_drag) << "  # [N·m·s/rad]\n";
  out << "\n[thrust]\n";
  out << "max = " << formatNumber(p.max_thrust) << "  # [N] per motor\n";
  out << "min = " << formatNumber(p.min_thrust) << "  # [N] per motor\n";
  out << "model_factor = " << formatNumber(p.thrust_model_factor) << "  # [-]\n";
  for (int m = 1; m <= 4; ++m) {
    const RotorDescription& rotor = d.rotors[static_cast<std::size_t>(m - 1)];
    out << "\n[motor." << m << "]\n";
    out << "x = " << formatNumber(rotor.x) << "  # [m] forward\n";
    out << "y = " << formatNumber(rotor.y) << "  # [m] right\n";
    out << "spin = \"" << (rotor.ccw ? "ccw" : "cw") << "\"\n";
  }
  return out.str();
}

}  // namespace quadfdi
