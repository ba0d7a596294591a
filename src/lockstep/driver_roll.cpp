#include "roar/lockstep/driver_roll.h"

namespace roar::lockstep {

void DriverRoll::add(const std::string& car) { drivers_[car] = Driver(); }

void DriverRoll::remove(const std::string& car) { drivers_.erase(car); }

bool DriverRoll::control(const std::string& car, double stamp) {
  auto it = drivers_.find(car);
  if (it == drivers_.end()) return false;
  Driver& d = it->second;
  d.seen = true;
  d.stamp = stamp;
  const bool back = d.lost;
  d.lost = false;
  return back;
}

bool DriverRoll::answered(double now) const {
  for (const auto& [car, d] : drivers_) {
    if (owes(car, d, now)) return false;
  }
  return true;
}

std::vector<std::string> DriverRoll::silent(double now) const {
  std::vector<std::string> out;
  for (const auto& [car, d] : drivers_) {
    if (owes(car, d, now)) out.push_back(car);
  }
  return out;
}

std::vector<std::string> DriverRoll::disconnected() const {
  std::vector<std::string> out;
  for (const auto& [car, d] : drivers_) {
    if (!d.lost && d.seen && !connected_(car)) out.push_back(car);
  }
  return out;
}

void DriverRoll::lose(const std::string& car) {
  auto it = drivers_.find(car);
  if (it != drivers_.end()) it->second.lost = true;
}

bool DriverRoll::lost(const std::string& car) const {
  auto it = drivers_.find(car);
  return it != drivers_.end() && it->second.lost;
}

bool DriverRoll::everyDriverLost() const {
  bool lost = false;
  for (const auto& [car, d] : drivers_) {
    if (connected_(car) && !d.lost) return false;
    lost = lost || d.lost;
  }
  return lost;
}

}  // namespace roar::lockstep
