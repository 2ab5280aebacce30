#include "evaluation/level_choice.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace quadfdi {

LevelChoice chooseDegradedLevel(const std::vector<std::vector<MotorTheta>>& healthy, const std::vector<FlightThetaStream>& faulty,
                                const LevelChoiceConfig& config, const std::vector<std::vector<std::uint8_t>>* healthy_observable) {
  if (config.candidates.empty()) throw std::invalid_argument("no degraded level to choose from");
  for (double level : config.candidates)
    if (!(level > config.failed.level && level <= 1.0))
      throw std::invalid_argument("degraded level " + std::to_string(level) + " is not in (failed level, 1]");
  const double highest = *std::max_element(config.candidates.begin(), config.candidates.end());
  std::vector<FlightThetaStream> scored;  // the faults every candidate is asked to report
  for (const FlightThetaStream& f : faulty)
    if (f.truth.motor > 0 && f.truth.fault_sample >= 0 && f.truth.theta < highest) scored.push_back(f);

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
  for (std::size_t i = 0; i < choice.candidates.size(); ++i) {
    if (choice.chosen < 0) {
      choice.chosen = static_cast<int>(i);
      continue;
    }
    const LevelCandidate& best = choice.candidates[static_cast<std::size_t>(choice.chosen)];
    const LevelCandidate& c = choice.candidates[i];
    if (c.isolated > best.isolated || (c.isolated == best.isolated && c.degraded.level > best.degraded.level))
      choice.chosen = static_cast<int>(i);
  }
  return choice;
}

}  // namespace quadfdi
