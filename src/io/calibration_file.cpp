#include "io/calibration_file.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "io/key_value.h"

namespace quadfdi {
namespace {

nlohmann::json levelToJson(const LevelCalibration& c) {
  nlohmann::json j = {{"level", c.level},
          {"threshold", c.threshold},
          {"method", c.method},
          {"excursions", c.excursions},
          {"tail_maxima", c.tail_maxima},
          {"tail_start", c.tail_start},
          {"tail_scale", c.tail_scale},
          {"alarms_at_threshold", c.alarms_at_threshold},
          {"rate_at_threshold", c.rate_at_threshold},
          {"rate_upper_bound", c.rate_upper_bound}};
  if (std::isfinite(c.increment_cap)) j["increment_cap"] = c.increment_cap;  // absent: no cap (files before the cap)
  if (c.min_command_share > 0.0) j["min_command_share"] = c.min_command_share;  // absent: no gate (files before 2026-12-04)
  return j;
}

// A count: get<long> would convert a float or an out-of-range number (undefined behaviour for
// 6.7e60, found by the fuzz target), so only JSON integers ≥ 0 are accepted.
long count(const nlohmann::json& v, const char* key) {
  const bool ok = v.is_number_unsigned() ? v.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<long>::max())
                                         : v.is_number_integer() && v.get<std::int64_t>() >= 0;
  if (!ok) throw nlohmann::json::type_error::create(302, std::string("'") + key + "' must be a whole number >= 0", &v);
  return static_cast<long>(v.get<std::int64_t>());
}

LevelCalibration levelFromJson(const nlohmann::json& j) {
  LevelCalibration c;
  c.level = j.at("level").get<double>();
  c.threshold = j.at("threshold").get<double>();
  c.method = j.at("method").get<std::string>();
  c.excursions = count(j.at("excursions"), "excursions");
  c.tail_maxima = j.at("tail_maxima").get<std::vector<double>>();
  c.tail_start = j.at("tail_start").get<double>();
  c.tail_scale = j.at("tail_scale").get<double>();
  c.alarms_at_threshold = count(j.at("alarms_at_threshold"), "alarms_at_threshold");
  c.rate_at_threshold = j.at("rate_at_threshold").get<double>();
  c.rate_upper_bound = j.at("rate_upper_bound").get<double>();
  if (j.contains("increment_cap")) c.increment_cap = j.at("increment_cap").get<double>();
  if (j.contains("min_command_share")) c.min_command_share = j.at("min_command_share").get<double>();
  return c;
}

nlohmann::json noiseToJson(const ThetaNoiseModel& m) {
  nlohmann::json noise = {
      {"healthy_mean", m.healthy_mean}, {"sigma", m.sigma}, {"phi", m.phi}, {"model_sigma", m.model_sigma}, {"noise_scale", m.noise_scale}};
  if (!m.spread_bins.empty()) {
    noise["spread_bins"] = nlohmann::json::array();
    for (const SpreadBin& b : m.spread_bins)
      noise["spread_bins"].push_back(
          {{"estimate_below", b.estimate_below}, {"noise_scale", b.noise_scale}, {"model_sigma", b.model_sigma}, {"pairs", b.pairs}});
  }
  if (!m.belt.empty()) {
    noise["belt"] = nlohmann::json::array();
    for (const BeltNode& b : m.belt)
      noise["belt"].push_back({{"theta", b.theta}, {"accept_lo", b.accept_lo}, {"accept_hi", b.accept_hi}, {"pairs", b.pairs}});
  }
  return noise;
}

ThetaNoiseModel noiseFromJson(const nlohmann::json& n, const std::string& where, const char* key) {
  ThetaNoiseModel m;
  m.healthy_mean = n.at("healthy_mean").get<double>();
  m.sigma = n.at("sigma").get<double>();
  m.phi = n.at("phi").get<double>();
  m.model_sigma = n.at("model_sigma").get<double>();
  m.noise_scale = n.value("noise_scale", 1.0);  // absent in calibrations before 2026-11-25
  if (n.contains("spread_bins")) {                // absent before the evening of 2026-11-25: the pooled spread
    const auto& bins = n.at("spread_bins");  // their count and values: validate()
    if (!bins.is_array()) throw ConfigError(where + ": bad calibration: " + key + " spread_bins must be an array of ranges");
    for (const auto& b : bins)
      m.spread_bins.push_back({b.at("estimate_below").get<double>(), b.at("noise_scale").get<double>(), b.at("model_sigma").get<double>(),
                               count(b.at("pairs"), "pairs")});
  }
  if (n.contains("belt")) {  // absent before 2026-11-27, and where the calibration fitted none: the spread's interval
    const auto& belt = n.at("belt");  // its count and values: validate()
    if (!belt.is_array()) throw ConfigError(where + ": bad calibration: " + key + " belt must be an array of nodes");
    for (const auto& b : belt)
      m.belt.push_back({b.at("theta").get<double>(), b.at("accept_lo").get<double>(), b.at("accept_hi").get<double>(), count(b.at("pairs"), "pairs")});
  }
  return m;
}

}  // namespace

std::string calibrationToJson(const DecisionCalibration& c) {
  nlohmann::json j = {
      {"format", "quadfdi-decision-calibration-1"},
      {"noise", noiseToJson(c.noise)},
      {"target_rate_per_hour", c.target_rate},
      {"dt", c.dt},
      {"flights", c.flights},
      {"flight_hours", c.flight_hours},
      {"faulty_flights", c.faulty_flights},
      {"reference", toString(c.reference)},
      {"estimate_reference", toString(c.estimate_reference)},
      {"degraded", levelToJson(c.degraded)},
      {"failed", levelToJson(c.failed)},
      {"source", c.source}};
  if (ownEstimateNoise(c)) j["estimate_noise"] = noiseToJson(c.estimate_noise);
  if (c.model_crc32) j["model_crc32"] = crc32Hex(*c.model_crc32);
  return j.dump(2) + "\n";
}

DecisionCalibration calibrationFromJson(const std::string& text, const std::string& where) {
  auto fail = [&](const std::string& problem) { return ConfigError(where + ": " + problem); };
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    throw fail("not valid JSON");
  }
  DecisionCalibration c;
  try {
    if (!j.is_object() || !j.contains("format") || j.at("format") != "quadfdi-decision-calibration-1")
      throw fail("not a quadfdi decision calibration (format quadfdi-decision-calibration-1)");
    c.noise = noiseFromJson(j.at("noise"), where, "noise");
    c.target_rate = j.at("target_rate_per_hour").get<double>();
    c.dt = j.at("dt").get<double>();
    c.flights = count(j.at("flights"), "flights");
    c.flight_hours = j.at("flight_hours").get<double>();
    c.faulty_flights = count(j.at("faulty_flights"), "faulty_flights");
    if (j.contains("reference") && !parseThetaReference(j.at("reference").get<std::string>(), &c.reference))  // absent before 2026-11-26
      throw fail("bad calibration: reference must be \"absolute\" or \"others\"");
    c.estimate_reference = c.reference;  // absent before 2026-11-26, afternoon: the estimate read what the rule read
    if (j.contains("estimate_reference") && !parseThetaReference(j.at("estimate_reference").get<std::string>(), &c.estimate_reference))
      throw fail("bad calibration: estimate_reference must be \"absolute\" or \"others\"");
    if (ownEstimateNoise(c)) {
      if (!j.contains("estimate_noise")) throw fail("bad calibration: estimate_reference differs from reference but there is no estimate_noise");
      c.estimate_noise = noiseFromJson(j.at("estimate_noise"), where, "estimate_noise");
    }
    c.degraded = levelFromJson(j.at("degraded"));
    c.failed = levelFromJson(j.at("failed"));
    c.source = j.at("source").get<std::string>();
    if (j.contains("model_crc32")) {  // absent before 2026-11-27
      const std::string hex = j.at("model_crc32").get<std::string>();
      if (hex.size() != 10 || hex.compare(0, 2, "0x") != 0 || hex.find_first_not_of("0123456789abcdef", 2) != std::string::npos)
        throw fail("bad calibration: model_crc32 must be \"0x\" and eight lower-case hex digits, not \"" + hex + "\"");
      c.model_crc32 = static_cast<std::uint32_t>(std::stoul(hex.substr(2), nullptr, 16));
    }
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("bad calibration: ") + e.what());
  }
  if (std::string p = validate(sequentialConfig(c.degraded, c.failed, c.noise, c.reference)); !p.empty()) throw fail("bad calibration: " + p);
  if (ownEstimateNoise(c))  // the same config as above otherwise; only its noise model differs
    if (std::string p = validate(sequentialConfig(c)); !p.empty()) throw fail("bad calibration: estimate_" + p);
  if (!(c.target_rate > 0.0) || !(c.dt > 0.0) || !(c.flight_hours >= 0.0)) throw fail("bad calibration: target_rate, dt or flight_hours out of range");
  // 4: the most a share of the mean can be (the other three motors at zero).
  for (const LevelCalibration* l : {&c.degraded, &c.failed})
    if (!(l->min_command_share >= 0.0 && l->min_command_share <= 4.0))
      throw fail(std::string("bad calibration: ") + (l == &c.failed ? "failed" : "degraded") + " min_command_share must lie in [0, 4]");
  return c;
}

DecisionCalibration readCalibrationFile(const std::string& path) {
  return calibrationFromJson(readTextFile(path, "a calibration file"), path);
}

void writeCalibrationFile(const std::string& path, const DecisionCalibration& c) {
  AtomicFileWriter out(path);
  out.stream() << calibrationToJson(c);
  out.commit();
}

}  // namespace quadfdi
