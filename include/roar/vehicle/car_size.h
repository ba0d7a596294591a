#pragma once
// A car's size where its model is not given (the sedan's body, about a Model 3's): what the planner, the
// race rules and the slipstream take for every car unless told its model's box.

namespace roar::vehicle {

inline constexpr double kDefaultCarLength = 4.7;  // m, bumper to bumper
inline constexpr double kDefaultCarWidth = 1.85;  // m

}  // namespace roar::vehicle
