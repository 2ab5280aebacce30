#include "io/randomisation_file.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>

#include "io/key_value.h"
#include "io/params_file.h"

namespace quadfdi {
namespace {

// Every interval key of the file and where it lands.
std::vector<std::pair<std::string, Interval*>> intervalFields(Randomisation& r) {
  return {{"parameters.mass", &r.parameters.mass},
          {"parameters.inertia", &r.parameters.inertia},
          {"parameters.thrust", &r.parameters.thrust},
          {"parameters.yaw_moment", &r.parameters.yaw_moment},
          {"parameters.motor_time_constant", &r.parameters.motor_time_constant},
          {"sensors.position_std", &r.sensors.position_std},
          {"sensors.velocity_std", &r.sensors.velocity_std},
          {"sensors.attitude_std", &r.sensors.attitude_std},
          {"sensors.rate_std", &r.sensors.rate_std},
          {"sensors.attitude_filter_tau", &r.sensors.attitude_filter_tau},
          {"sensors.rate_filter_tau", &r.sensors.rate_filter_tau},
          {"sensors.estimate_error_tau", &r.sensors.estimate_error_tau},
          {"manoeuvres.speed", &r.manoeuvres.speed},
          {"manoeuvres.size", &r.manoeuvres.size},
          {"manoeuvres.yaw_sweep_amplitude", &r.manoeuvres.yaw_sweep_amplitude},
          {"manoeuvres.yaw_sweep_period", &r.manoeuvres.yaw_sweep_period},
          {"controllers.gain_scale", &r.controllers.gain_scale},
          {"preroll_seconds", &r.preroll_seconds},
          {"wind.rotor_drag", &r.wind.rotor_drag},
          {"wind.mean_speed", &r.wind.mean_speed},
          {"wind.turbulence_std", &r.wind.turbulence_std},
          {"wind.turbulence_tau", &r.wind.turbulence_tau},
          {"wind.gust_rate", &r.wind.gust_rate},
          {"wind.gust_peak", &r.wind.gust_peak},
          {"wind.gust_duration", &r.wind.gust_duration},
          {"airframes.mass", &r.airframes.mass},
          {"airframes.size_factor", &r.airframes.size_factor},
          {"airframes.aspect", &r.airframes.aspect},
          {"airframes.inertia_factor", &r.airframes.inertia_factor},
          {"airframes.yaw_inertia_ratio", &r.airframes.yaw_inertia_ratio},
          {"airframes.hover_fraction", &r.airframes.hover_fraction},
          {"airframes.idle_fraction", &r.airframes.idle_fraction},
          {"airframes.yaw_moment_coeff", &r.airframes.yaw_moment_coeff},
          {"airframes.motor_time_constant", &r.airframes.motor_time_constant}};
}

bool isAirframeKey(const std::string& key) { return key.rfind("airframes.", 0) == 0; }
bool isHeadingKey(const std::string& key) {
  return key.rfind("manoeuvres.facing_velocity", 0) == 0 || key.rfind("manoeuvres.yaw_sweep", 0) == 0;
}

std::vector<std::pair<std::string, double*>> numberFields(Randomisation& r) {
  return {{"manoeuvres.hover", &r.manoeuvres.hover},
          {"manoeuvres.point_to_point", &r.manoeuvres.point_to_point},
          {"manoeuvres.circle", &r.manoeuvres.circle},
          {"manoeuvres.figure_eight", &r.manoeuvres.figure_eight},
          {"manoeuvres.max_lateral_accel", &r.manoeuvres.max_lateral_accel},
          {"manoeuvres.facing_velocity", &r.manoeuvres.facing_velocity},
          {"manoeuvres.facing_velocity_yaw_rate_max", &r.manoeuvres.facing_velocity_yaw_rate_max},
          {"manoeuvres.yaw_sweep", &r.manoeuvres.yaw_sweep},
          {"controllers.lqr", &r.controllers.lqr},
          {"controllers.pid", &r.controllers.pid},
          {"controllers.cbf", &r.controllers.cbf},
          {"controllers.geometric", &r.controllers.geometric},
          {"airframes.share", &r.airframes.share}};
}

std::string vehicleName(const std::string& spec) { return std::filesystem::path(spec).stem().string(); }

// [-] Most files one `base` chain may read: a chain this long is a cycle (a → b → a) or a mistake.
constexpr int kMaxBaseDepth = 8;

Randomisation parseRandomisation(const std::string& text, const std::string& source, int depth,
                                  const VehicleNameResolver& resolve);

// `base = "FILE"` (the file's first key): the randomisation this file starts from. Relative paths
// are relative to the file's folder, so a recipe beside the file it extends names it alone.
Randomisation loadBase(const KeyValueDocument& doc, const KeyValueEntry& e, int depth, const VehicleNameResolver& resolve) {
  if (depth >= kMaxBaseDepth)
    doc.fail(e, "base: more than " + std::to_string(kMaxBaseDepth) + " files deep (does a base name this file again?)");
  std::filesystem::path path = doc.string(e);
  if (path.empty()) doc.fail(e, "base must name a randomisation file");
  if (path.is_relative()) path = std::filesystem::path(doc.source).parent_path() / path;
  try {  // readTextFile refuses a folder, a device and a file past the configs' size bound
    return parseRandomisation(readTextFile(path.string(), "a randomisation file"), path.string(), depth + 1, resolve);
  } catch (const std::exception& ex) {
    doc.fail(e, std::string("base: ") + ex.what());
  }
}

Randomisation parseRandomisation(const std::string& text, const std::string& source, int depth,
                                  const VehicleNameResolver& resolve) {
  const KeyValueDocument doc = parseKeyValue(text, source);
  Randomisation r;
  if (!doc.entries.empty() && doc.entries.front().key == "base") r = loadBase(doc, doc.entries.front(), depth, resolve);
  const auto intervals = intervalFields(r);
  const auto numbers = numberFields(r);
  for (const KeyValueEntry& e : doc.entries) {
    if (e.key == "base") {
      if (&e != &doc.entries.front()) doc.fail(e, "base must be the file's first key (before every section)");
      continue;
    }
    bool known = false;
    for (const auto& [key, field] : intervals)
      if (e.key == key) {
        const std::vector<double> v = doc.numberList(e);
        if (v.size() != 2) doc.fail(e, "'" + key + "' needs [lo, hi]");
        if (!(v[0] >= 0.0 && v[1] >= v[0])) doc.fail(e, "'" + key + "' needs 0 <= lo <= hi");
        *field = {v[0], v[1]};
        known = true;
      }
    for (const auto& [key, field] : numbers)
      if (e.key == key) {
        *field = doc.number(e);
        known = true;
      }
    if (e.key == "airframes.count" || e.key == "airframes.seed") {
      const long long v = doc.integer(e);
      if (v < 0 || v > (e.key == "airframes.count" ? 1000 : (1LL << 53)))
        doc.fail(e, e.key + (e.key == "airframes.count" ? " must be in 0 … 1000" : " must be in 0 … 2^53"));
      if (e.key == "airframes.count") r.airframes.count = static_cast<int>(v);
      else r.airframes.seed = static_cast<std::uint64_t>(v);
      known = true;
    }
    if (e.key == "sensors.delay_steps_max") {
      const long long v = doc.integer(e);
      if (v < 0 || v > 1000) doc.fail(e, "sensors.delay_steps_max must be in 0 … 1000");
      r.sensors.delay_steps_max = static_cast<int>(v);
      known = true;
    }
    if (e.key == "vehicles") {
      // This file's vehicles replace its base's, never add to them (a key appears once a file).
      r.vehicles.clear();
      r.vehicle_names.clear();
      // A list of quoted paths: the key-value reader's lists hold numbers, so split here.
      std::string list = e.value;
      if (list.size() < 2 || list.front() != '[' || list.back() != ']') doc.fail(e, "vehicles must be a list of \"paths\"");
      list = list.substr(1, list.size() - 2);
      std::size_t at = 0;
      while (true) {
        const std::size_t open = list.find('"', at);
        if (open == std::string::npos) break;
        const std::size_t close = list.find('"', open + 1);
        if (close == std::string::npos) doc.fail(e, "unterminated string in vehicles");
        std::string spec = list.substr(open + 1, close - open - 1);
        // The error_code overloads: a name the file system rejects (too long, …) is "not found"
        // here and gets its one-line message from the loader below, never an exception.
        std::error_code ignored;
        if (!isNamedParamSet(spec) && !std::filesystem::exists(spec, ignored)) {
          const std::filesystem::path near = std::filesystem::path(source).parent_path() / spec;
          if (std::filesystem::exists(near, ignored)) spec = near.string();
          else if (resolve)
            if (std::string named = resolve(spec); !named.empty()) spec = std::move(named);
        }
        try {
          r.vehicles.push_back(loadVehicleParams(spec));
        } catch (const std::exception& ex) {
          doc.fail(e, std::string("vehicle: ") + ex.what());
        }
        r.vehicle_names.push_back(vehicleName(spec));
        at = close + 1;
      }
      if (r.vehicles.empty()) doc.fail(e, "vehicles must name at least one vehicle");
      known = true;
    }
    if (!known) doc.fail(e, "unknown key '" + e.key + "'");
  }
  // Without vehicles a randomisation is off (Randomisation::enabled): refuse it rather than
  // train silently on the fixed plant.
  if (r.vehicles.empty()) throw ConfigError(source + ": no 'vehicles = [\"FILE\", …]': a randomisation needs at least one vehicle");
  if (const std::string problem = validate(r); !problem.empty()) throw ConfigError(source + ": " + problem);
  return r;
}

}  // namespace

Randomisation randomisationFromText(const std::string& text, const std::string& source, const VehicleNameResolver& resolve) {
  return parseRandomisation(text, source, 0, resolve);
}

Randomisation loadRandomisation(const std::string& path) { return randomisationFromText(readTextFile(path, "a randomisation file"), path); }

void flyOnlyVehicles(Randomisation& r, const std::vector<std::string>& vehicle_files) {
  r.vehicles.clear();
  r.vehicle_names.clear();
  for (const std::string& v : vehicle_files) {
    r.vehicles.push_back(loadVehicleParams(v));
    r.vehicle_names.push_back(vehicleName(v));
  }
  r.airframes.count = 0;
}

std::string randomisationToText(const Randomisation& r) {
  Randomisation copy = r;
  std::string out = "vehicles = [";
  for (std::size_t i = 0; i < r.vehicle_names.size(); ++i) out += (i ? ", \"" : "\"") + r.vehicle_names[i] + "\"";
  out += "]\n";
  char buf[160];
  // Without synthetic airframes or heading motion their keys are left out, and so is a yaw-rate
  // limit of 0 (none): the text of every earlier model is unchanged.
  const bool airframes = r.airframes.enabled(), heading = r.manoeuvres.headingEnabled();
  const auto leftOut = [&](const std::string& key) {
    return (isAirframeKey(key) && !airframes) || (isHeadingKey(key) && !heading) ||
           (key == "manoeuvres.facing_velocity_yaw_rate_max" && !(r.manoeuvres.facing_velocity_yaw_rate_max > 0.0));
  };
  for (const auto& [key, field] : numberFields(copy)) {
    if (leftOut(key)) continue;
    std::snprintf(buf, sizeof buf, "%s = %.17g\n", key.c_str(), *field);
    out += buf;
  }
  for (const auto& [key, field] : intervalFields(copy)) {
    if (leftOut(key)) continue;
    std::snprintf(buf, sizeof buf, "%s = [%.17g, %.17g]\n", key.c_str(), field->lo, field->hi);
    out += buf;
  }
  if (airframes) {
    std::snprintf(buf, sizeof buf, "airframes.count = %d\nairframes.seed = %llu\n", r.airframes.count,
                  static_cast<unsigned long long>(r.airframes.seed));
    out += buf;
  }
  std::snprintf(buf, sizeof buf, "sensors.delay_steps_max = %d\n", r.sensors.delay_steps_max);
  return out + buf;
}

}  // namespace quadfdi
