#include "detection/alarm.h"

namespace quadfdi {

AlarmState AlarmFilter::update(const std::array<float, 4>& theta, long index) {
  const int weakest = weakestMotorIndex(theta);
  const double lowest = static_cast<double>(theta[static_cast<std::size_t>(weakest)]);
  state_.raised = state_.cleared = false;
  if (!state_.active) {
    if (lowest < config_.raise_below) {
      faulty_run_ = (weakest + 1 == candidate_) ? faulty_run_ + 1 : 1;
      candidate_ = weakest + 1;
    } else {
      faulty_run_ = 0;
      candidate_ = 0;
    }
    if (faulty_run_ >= config_.raise_after) {
      state_.active = state_.raised = true;
      state_.motor = candidate_;
      healthy_since_ = -1;
    }
  } else {
    if (lowest > config_.clear_above) {
      if (healthy_since_ < 0) healthy_since_ = index;
    } else {
      healthy_since_ = -1;
    }
    if (healthy_since_ >= 0 && index - healthy_since_ + 1 >= config_.clear_after) {
      state_.active = false;
      state_.cleared = true;
      state_.motor = 0;
      faulty_run_ = 0;
      candidate_ = 0;
    }
  }
  return state_;
}

}  // namespace quadfdi
