#include "roar/rl/action.h"

#include <algorithm>

namespace roar::rl {

Space actionSpace(const ActionOptions& options, int forward_gears) {
  std::vector<std::pair<std::string, Space>> entries = {
      {"throttle", Space::box(0.0, 1.0, {1})}, {"steer", Space::box(-1.0, 1.0, {1})},
      {"brake", Space::box(0.0, 1.0, {1})},    {"hand_brake", Space::box(0.0, 1.0, {1})},
      {"reverse", Space::multiBinary(1)},
  };
  if (options.manual_gears) entries.emplace_back("target_gear", Space::discrete(forward_gears, 1));
  return Space::dict(std::move(entries));
}

vehicle::VehicleControl toControl(const Space& space, const Value& action) {
  check(space, action, "action");
  vehicle::VehicleControl c;
  c.throttle = action.at("throttle").numbers[0];
  c.steer = action.at("steer").numbers[0];
  c.brake = action.at("brake").numbers[0];
  c.hand_brake = action.at("hand_brake").numbers[0] > 0.5;
  c.reverse = action.at("reverse").numbers[0] == 1.0;
  if (space.has("target_gear")) {
    c.manual_gear_shift = true;
    c.gear = c.reverse ? -1 : static_cast<int>(action.at("target_gear").numbers[0]);
  }
  return c;
}

Value toAction(const Space& space, const vehicle::VehicleControl& control) {
  Value a;
  a.at("throttle") = Value::of({std::clamp(control.throttle, 0.0, 1.0)});
  a.at("steer") = Value::of({std::clamp(control.steer, -1.0, 1.0)});
  a.at("brake") = Value::of({std::clamp(control.brake, 0.0, 1.0)});
  a.at("hand_brake") = Value::of({control.hand_brake ? 1.0 : 0.0});
  a.at("reverse") = Value::of({control.reverse ? 1.0 : 0.0});
  if (space.has("target_gear")) {
    const Space& gears = space.at("target_gear");
    a.at("target_gear") = Value::of(
        {static_cast<double>(std::clamp<std::int64_t>(control.gear, gears.start, gears.start + gears.n - 1))});
  }
  return a;
}

}  // namespace roar::rl
