#include "roar/lockstep/tick_gathering.h"

#include <algorithm>

namespace roar::lockstep {

TickGathering::TickGathering(std::vector<std::string> cars, double wait)
    : cars_(std::move(cars)), wait_(wait), absent_(cars_.size(), 0), arrived_(cars_.size(), 0) {}

TickGathering::Tick TickGathering::take() {
  Tick tick{stamp_, {}};
  for (std::size_t i = 0; i < cars_.size(); ++i) {
    if (arrived_[i]) {
      tick.cars.push_back(cars_[i]);
    } else {
      absent_[i] = 1;
    }
    arrived_[i] = 0;
  }
  gathering_ = false;
  return tick;
}

std::vector<TickGathering::Tick> TickGathering::arrive(const std::string& car, double stamp, double wall) {
  const auto it = std::find(cars_.begin(), cars_.end(), car);
  if (it == cars_.end()) return {};
  const auto i = static_cast<std::size_t>(it - cars_.begin());
  std::vector<Tick> ticks;
  if (gathering_ && stamp < stamp_) return {{stamp, {car}}};
  // Its second message of the tick gathered (a repeat): the tick as it is, then this one afresh.
  if (gathering_ && (stamp > stamp_ || arrived_[i])) ticks.push_back(take());
  if (!gathering_) {
    gathering_ = true;
    stamp_ = stamp;
    first_wall_ = wall;
  }
  arrived_[i] = 1;
  absent_[i] = 0;
  bool complete = true;
  for (std::size_t k = 0; k < cars_.size(); ++k) complete = complete && (arrived_[k] || absent_[k]);
  if (complete) ticks.push_back(take());
  return ticks;
}

std::vector<TickGathering::Tick> TickGathering::expire(double wall) {
  if (!gathering_ || wall < first_wall_ + wait_) return {};
  return {take()};
}

}  // namespace roar::lockstep
