#pragma once
#include <limits>

namespace roar::planning {

// Tells a car held to a speed (a pace car, a car driven at a set speed) from one driven at a share of the
// line's: its speed stays put while the line's speed where it is rises under it (a car at a share of the
// line gains speed with it; one at its top speed sees the line's fall at the end of a straight, not rise). Fed every
// located position; a car seen faster than the speed it was held to is no longer held (it was held up behind another
// car, not by its driver).
class HeldSpeed {
 public:
  // speed: the car's, line_speed: the racing line's where it is, time: s.
  void observe(double speed, double line_speed, double time);
  double speed() const { return held_; }  // 0: not held

 private:
  double held_ = 0.0;
  double run_start_ = std::numeric_limits<double>::quiet_NaN();  // s the present steady run began
  double run_speed_ = 0.0;
  double line_start_ = 0.0, line_max_ = 0.0;  // the line's speeds over the run: where it began, the highest
};

}  // namespace roar::planning
