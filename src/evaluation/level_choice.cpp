#include "evaluation/level_choice.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace quadfdi {
namespace {

// Index of the candidate no later one is `better` than (the first among equals); −1 for none.
template <class Candidate, class Better>
int bestIndex(const std::vector<Candidate>& candidates, Better better) {
  int chosen = -1;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (chosen < 0 || better(candidates[i], candidates[static_cast<std::size_t>(chosen)])) chosen = static_cast<int>(i);
  return chosen;
}

// The faulty flights whose true Θ is below `bound`: the faults a choice is scored on.
std::vector<FlightThetaStream> faultsBelow(const std::vector<FlightThetaStream>& faulty, double bound) {
  std::vector<FlightThetaStream> below;
  for (const FlightThetaStream& f : faulty)
    if (f.truth.motor > 0 && f.truth.fault_sample >= 0 && f.truth.theta < bound) below.push_back(f);
  return below;
}

}  // namespace

LevelChoice chooseDegradedLevel(const std::vector<std::vector<MotorTheta>>& healthy, const std::vector<FlightThetaStream>& faulty,
                                const LevelChoiceConfig& config, const std::vector<std::vector<std::uint8_t>>* healthy_observable) {
  if (config.candidates.empty()) throw std::invalid_argument("no degraded level to choose from");
  for (double level : config.candidates)
    if (!(level > config.failed.level && level <= 1.0))
      throw std::invalid_argument("degraded level " + std::to_string(level) + " is not in (failed level, 1]");
  const double highest = *std::max_element(config.candidates.begin(), config.candidates.end());
  const std::vector<FlightThetaStream> scored = faultsBelow(faulty, highest);  // the faults every candidate is asked to report

  LevelChoice choice;
  for (double level : config.candidates) {
    LevelCandidate c;
    c.degraded = calibrateLevel(excursionMaxima(healthy, level, 0, config.cap, healthy_observable), level, config.flight_hours, config.rate_per_hour,
                                config.noise, config.dt, config.cap);
    SequentialEvaluationConfig e;
    e.rule = sequentialConfig(c.degraded, config.failed, config.noise, config.reference);
    e.dt = config.dt;
    e.isolation_late = config.delay_budget;
    const SequentialEvaluation r = evaluateSequential(scored, e);
    c.faults = r.isolation_flights;
    c.isolated = r.named_late;
    choice.candidates.push_back(c);
  }
  choice.chosen = bestIndex(choice.candidates, [](const LevelCandidate& c, const LevelCandidate& best) {
    return c.isolated > best.isolated || (c.isolated == best.isolated && c.degraded.level > best.degraded.level);
  });
  return choice;
}

FailedCapChoice chooseFailedCap(const std::vector<std::vector<MotorTheta>>& healthy, const std::vector<FlightThetaStream>& faulty,
                                const FailedCapChoiceConfig& config, const std::vector<std::vector<std::uint8_t>>* healthy_observable) {
  if (config.caps.empty()) throw std::invalid_argument("no failed cap to choose from");
  for (double cap : config.caps)
    if (!(cap > 0.0)) throw std::invalid_argument("failed cap " + std::to_string(cap) + " is not above 0");
  if (!(config.level > 0.0 && config.level < 1.0))
    throw std::invalid_argument("failed level " + std::to_string(config.level) + " is not in (0, 1)");
  const std::vector<FlightThetaStream> scored = faultsBelow(faulty, config.level);  // the faults a failed decision is owed for

  const LevelChoiceConfig& d = config.degraded;
  FailedCapChoice choice;
  for (double cap : config.caps) {
    FailedCapCandidate c;
    c.failed = calibrateLevel(excursionMaxima(healthy, config.level, 0, cap, healthy_observable, EvidenceLevel::kFailed), config.level, d.flight_hours,
                              d.rate_per_hour, d.noise, d.dt, cap);
    LevelChoiceConfig under = d;
    under.failed = c.failed;
    c.degraded = chooseDegradedLevel(healthy, faulty, under, healthy_observable);
    SequentialEvaluationConfig e;
    e.rule = sequentialConfig(c.degraded.candidates[static_cast<std::size_t>(c.degraded.chosen)].degraded, c.failed, d.noise, d.reference);
    e.dt = d.dt;
    e.isolation_early = config.delay_budget;
    const SequentialEvaluation r = evaluateSequential(scored, e);
    c.faults = r.recorded_early;
    c.named = r.named_early;
    choice.candidates.push_back(c);
  }
  choice.chosen = bestIndex(choice.candidates, [](const FailedCapCandidate& c, const FailedCapCandidate& best) {
    return c.named > best.named || (c.named == best.named && c.failed.increment_cap < best.failed.increment_cap);
  });
  return choice;
}

}  // namespace quadfdi
