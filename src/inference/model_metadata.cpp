#include "inference/model_metadata.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

namespace quadfdi {

const char* toString(Architecture a) {
  switch (a) {
    case Architecture::kLstm: return "lstm";
    case Architecture::kMlp: return "mlp";
    case Architecture::kTcn: return "tcn";
  }
  return "?";
}

bool parseArchitecture(const std::string& text, Architecture& a) {
  if (text == "lstm") { a = Architecture::kLstm; return true; }
  if (text == "mlp") { a = Architecture::kMlp; return true; }
  if (text == "tcn") { a = Architecture::kTcn; return true; }
  return false;
}

int TcnShape::receptiveField() const {
  long span = 0;
  for (int d : dilations) span += static_cast<long>(kernel - 1) * d;
  return static_cast<int>(std::min<long>(span + 1, std::numeric_limits<int>::max()));
}

std::string metadataToJson(const ModelMetadata& m) {
  nlohmann::json j = {{"architecture", toString(m.architecture)},
                      {"features", toString(m.features)},
                      {"output", m.output == OutputKind::kPositionEuler ? "position-euler" : "position-rates"},
                      {"symmetry", toString(m.symmetry)},
                      {"trained_motor", m.trained_motor},
                      {"window", m.window},
                      {"dt", m.dt},
                      {"hidden", m.hidden},
                      {"params", m.params},
                      {"controller", m.controller},
                      {"feature_mean", m.feature_mean},
                      {"feature_std", m.feature_std},
                      {"provenance",
                       {{"command", m.command},
                        {"scale", m.scale},
                        {"seed", m.seed},
                        {"iterations", m.iterations},
                        {"training_seconds", m.training_seconds},
                        {"final_loss", m.final_loss},
                        {"heldout_loss", m.heldout_loss},
                        {"heldout_accuracy", m.heldout_accuracy},
                        {"generator", m.generator}}}};
  if (!m.randomisation.empty()) j["randomisation"] = m.randomisation;
  if (!m.started_from.empty()) j["provenance"]["started_from"] = m.started_from;
  if (m.architecture == Architecture::kTcn)
    j["tcn"] = {{"channels", m.tcn.channels}, {"kernel", m.tcn.kernel}, {"dilations", m.tcn.dilations}};
  return j.dump();
}

ModelMetadata metadataFromJson(const std::string& text, const std::string& where) {
  auto fail = [&](const std::string& problem) -> ModelError { return ModelError(where + ": " + problem); };
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {  // parse_error, or out_of_range for a number like 1e400
    throw fail("metadata is not valid JSON (truncated or corrupt file?)");
  }
  // get<int> would cast a float or an out-of-range integer (undefined for 1e10): integers only.
  auto integer = [&](const nlohmann::json& v, const char* key) {
    constexpr std::int64_t kMin = std::numeric_limits<int>::min(), kMax = std::numeric_limits<int>::max();
    const bool fits = v.is_number_unsigned() ? v.get<std::uint64_t>() <= static_cast<std::uint64_t>(kMax)
                                             : v.is_number_integer() && v.get<std::int64_t>() >= kMin && v.get<std::int64_t>() <= kMax;
    if (!fits) throw fail(std::string("bad metadata: '") + key + "' must be an integer in the range of int");
    return static_cast<int>(v.get<std::int64_t>());
  };
  ModelMetadata m;
  try {
    if (!j.is_object()) throw fail("bad metadata: not a JSON object");
    if (!parseArchitecture(j.at("architecture").get<std::string>(), m.architecture)) throw fail("unknown architecture");
    if (!parseFeatureSet(j.at("features").get<std::string>(), m.features)) throw fail("unknown feature set");
    const std::string out = j.at("output").get<std::string>();
    if (out == "position-euler") m.output = OutputKind::kPositionEuler;
    else if (out == "position-rates") m.output = OutputKind::kPositionRates;
    else throw fail("unknown output kind '" + out + "'");
    if (!parseSymmetryMode(j.at("symmetry").get<std::string>(), m.symmetry)) throw fail("unknown symmetry mode");
    m.trained_motor = integer(j.at("trained_motor"), "trained_motor");
    m.window = integer(j.at("window"), "window");
    m.dt = j.at("dt").get<double>();
    m.hidden = integer(j.at("hidden"), "hidden");
    m.params = j.at("params").get<std::string>();
    m.controller = j.at("controller").get<std::string>();
    if (j.contains("randomisation")) m.randomisation = j.at("randomisation").get<std::string>();
    m.feature_mean = j.at("feature_mean").get<std::vector<float>>();
    m.feature_std = j.at("feature_std").get<std::vector<float>>();
    if (m.architecture == Architecture::kTcn) {
      const auto& t = j.at("tcn");
      m.tcn.channels = integer(t.at("channels"), "tcn.channels");
      m.tcn.kernel = integer(t.at("kernel"), "tcn.kernel");
      m.tcn.dilations.clear();
      if (!t.at("dilations").is_array()) throw fail("bad metadata: 'tcn.dilations' must be a list");
      for (const auto& d : t.at("dilations")) m.tcn.dilations.push_back(integer(d, "tcn.dilations"));
    }
    const auto& p = j.at("provenance");
    m.command = p.at("command").get<std::string>();
    m.scale = p.at("scale").get<std::string>();
    if (!p.at("seed").is_number_integer()) throw fail("bad metadata: 'seed' must be an integer");
    m.seed = p.at("seed").get<std::uint64_t>();
    m.iterations = integer(p.at("iterations"), "iterations");
    m.training_seconds = p.at("training_seconds").get<double>();
    m.final_loss = p.at("final_loss").get<double>();
    m.heldout_loss = p.at("heldout_loss").get<double>();
    m.heldout_accuracy = p.at("heldout_accuracy").get<double>();
    m.generator = p.at("generator").get<std::string>();
    if (p.contains("started_from")) m.started_from = p.at("started_from").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("bad metadata: ") + e.what());
  }
  const auto n = static_cast<std::size_t>(m.channels());
  if (m.window < 1 || m.window > 100000 || m.hidden < 1 || m.hidden > 4096 || !(m.dt > 0.0) || !std::isfinite(m.dt))
    throw fail("metadata out of range (window, hidden or dt)");
  if (m.trained_motor < 1 || m.trained_motor > 4) throw fail("trained_motor must be 1..4");
  if ((!m.feature_mean.empty() && m.feature_mean.size() != n) || (!m.feature_std.empty() && m.feature_std.size() != n))
    throw fail("normalisation statistics do not match the feature set");
  for (float s : m.feature_std)
    if (!(s > 0.0f) || !std::isfinite(s)) throw fail("normalisation scale must be finite and > 0");
  for (float v : m.feature_mean)
    if (!std::isfinite(v)) throw fail("normalisation mean must be finite");
  if (m.architecture == Architecture::kTcn) {
    if (m.tcn.channels < 1 || m.tcn.channels > 1024 || m.tcn.kernel < 1 || m.tcn.kernel > 64 ||
        m.tcn.dilations.empty() || m.tcn.dilations.size() > 32)
      throw fail("TCN shape out of range (channels 1..1024, kernel 1..64, 1..32 layers)");
    for (int d : m.tcn.dilations)
      if (d < 1 || d > 4096) throw fail("TCN dilation out of range (1..4096)");
    // The streaming form equals the windowed one only if the receptive field fits in the window
    // after the first sample (which has no predecessor for the difference features).
    if (m.tcn.receptiveField() > m.window - 1)
      throw fail("TCN receptive field (" + std::to_string(m.tcn.receptiveField()) + " samples) exceeds window − 1 (" +
                 std::to_string(m.window - 1) + ")");
  }
  return m;
}

}  // namespace quadfdi
