#pragma once
// The share of full steering lock a car has at a speed: CARLA's steering curve (its cars turn their
// wheels less at speed). Header-only and free of the simulator, so the simulator's dynamics and the
// stack's controller read the same curve.
#include <utility>
#include <vector>

namespace roar::vehicle {

// (speed m/s, share of the maximum steering angle) points with rising speeds; linear between them, the
// first and last share beyond them. No points: the full angle at every speed.
using SteeringCurve = std::vector<std::pair<double, double>>;

inline double steeringShare(const SteeringCurve& curve, double speed) {
  if (curve.empty()) return 1.0;
  if (speed <= curve.front().first) return curve.front().second;
  for (std::size_t i = 1; i < curve.size(); ++i) {
    if (speed <= curve[i].first) {
      const auto& [v0, s0] = curve[i - 1];
      const auto& [v1, s1] = curve[i];
      return s0 + (s1 - s0) * (speed - v0) / (v1 - v0);
    }
  }
  return curve.back().second;
}

}  // namespace roar::vehicle
