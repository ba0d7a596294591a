#include "roar/planning/held_speed.h"

#include <algorithm>
#include <cmath>

namespace roar::planning {

namespace {
constexpr double kSteady = 0.5;     // m/s a held car's speed stays within over a run
constexpr double kBelowLine = 1.0;  // m/s below the line's speed it must be all along (room to go faster)
constexpr double kLineRise = 3.0;   // m/s the line's speed must rise over the run
constexpr double kRunTime = 2.0;    // s a run must last
constexpr double kFreed = 1.0;      // m/s above the held speed that shows the car is not held any more
}  // namespace

void HeldSpeed::observe(double speed, double line_speed, double time) {
  if (!std::isfinite(speed) || !std::isfinite(line_speed) || !std::isfinite(time)) return;
  if (held_ > 0.0 && speed > held_ + kFreed) held_ = 0.0;
  const bool steady = std::isfinite(run_start_) && std::abs(speed - run_speed_) <= kSteady && time >= run_start_;
  if (!steady || line_speed < speed + kBelowLine) {
    run_start_ = line_speed < speed + kBelowLine ? std::numeric_limits<double>::quiet_NaN() : time;
    run_speed_ = speed;
    line_start_ = line_max_ = line_speed;
    return;
  }
  line_max_ = std::max(line_max_, line_speed);
  if (time - run_start_ >= kRunTime && line_max_ - line_start_ >= kLineRise) held_ = std::max(held_, speed);
}

}  // namespace roar::planning
