#include "io/params_file.h"

#include <sstream>
#include <utility>
#include <vector>

#include "io/key_value.h"
#include "io/vehicle_file.h"

namespace quadfdi {
namespace {

// Field name ↔ member. One table, used for reading and writing.
const std::vector<std::pair<const char*, double VehicleParams::*>>& fields() {
  static const std::vector<std::pair<const char*, double VehicleParams::*>> table = {
      {"mass", &VehicleParams::mass},
      {"inertia_xx", &VehicleParams::inertia_xx},
      {"inertia_yy", &VehicleParams::inertia_yy},
      {"inertia_zz", &VehicleParams::inertia_zz},
      {"thrust_coeff", &VehicleParams::thrust_coeff},
      {"drag_coeff", &VehicleParams::drag_coeff},
      {"arm_length", &VehicleParams::arm_length},
      {"rotor_x", &VehicleParams::rotor_x},
      {"rotor_y", &VehicleParams::rotor_y},
      {"yaw_moment_coeff", &VehicleParams::yaw_moment_coeff},
      {"gravity", &VehicleParams::gravity},
      {"min_thrust", &VehicleParams::min_thrust},
      {"max_thrust", &VehicleParams::max_thrust},
      {"thrust_model_factor", &VehicleParams::thrust_model_factor},
      {"motor_time_constant", &VehicleParams::motor_time_constant},
      {"linear_drag", &VehicleParams::linear_drag},
      {"rotational_drag", &VehicleParams::rotational_drag},
  };
  return table;
}

}  // namespace

VehicleParams vehicleParamsFromText(const std::string& text, const std::string& source) {
  const KeyValueDocument doc = parseKeyValue(text, source);
  VehicleParams params;
  if (const KeyValueEntry* base = doc.find("base")) {
    const std::string name = doc.string(*base);
    if (!isNamedParamSet(name))
      doc.fail(*base, "unknown base parameter set '" + name + "' (nominal, perturbed, perturbed-strong)");
    params = namedParams(name);
  }
  for (const auto& entry : doc.entries) {
    if (entry.key == "base") continue;
    bool known = false;
    for (const auto& [name, member] : fields()) {
      if (entry.key == name) {
        params.*member = doc.number(entry);
        known = true;
        break;
      }
    }
    if (!known) {
      std::string list;
      for (const auto& f : fields()) list += std::string(list.empty() ? "" : ", ") + f.first;
      doc.fail(entry, "unknown parameter '" + entry.key + "' (known: base, " + list + ")");
    }
  }
  if (const std::string problem = validate(params); !problem.empty())
    throw ConfigError(source + ": invalid vehicle: " + problem);
  return params;
}

VehicleParams loadVehicleParams(const std::string& spec) {
  if (isNamedParamSet(spec)) return namedParams(spec);
  const std::string text = readTextFile(spec, "a vehicle parameter file");
  if (looksLikeVehicleDescription(text)) return vehicleDescriptionFromText(text, spec).params;
  return vehicleParamsFromText(text, spec);
}

std::string vehicleParamsToText(const VehicleParams& params) {
  std::ostringstream out;
  out.precision(17);
  for (const auto& [name, member] : fields()) out << name << " = " << params.*member << "\n";
  return out.str();
}

}  // namespace quadfdi
