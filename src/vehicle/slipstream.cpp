#include "roar/vehicle/slipstream.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace roar::vehicle {

namespace {

void inRange(double value, SlipstreamRange range, const std::string& prefix, const char* field) {
  if (!(value >= range.low && value <= range.high)) {
    throw std::invalid_argument(prefix + field + " is " + std::to_string(value) + ": it must be in [" +
                                std::to_string(range.low) + ", " + std::to_string(range.high) + "]");
  }
}

}  // namespace

void validate(const SlipstreamOptions& o, const std::string& prefix) {
  inRange(o.max_reduction, kMaxReductionRange, prefix, "max_reduction");
  inRange(o.decay_length, kDecayLengthRange, prefix, "decay_length");
  inRange(o.spread_growth, kSpreadGrowthRange, prefix, "spread_growth");
  inRange(o.max_gap, kMaxGapRange, prefix, "max_gap");
  inRange(o.min_speed, kMinSpeedRange, prefix, "min_speed");
}

double slipstreamReduction(double gap, double offset, double speed, double width, const SlipstreamOptions& o) {
  if (!o.enabled || !(gap >= 0.0) || gap > o.max_gap || !(speed >= o.min_speed) || !std::isfinite(offset)) return 0.0;
  const double spread = 0.5 * width + o.spread_growth * gap;
  const double sideways = offset / spread;
  return o.max_reduction * std::exp(-gap / o.decay_length) * std::exp(-0.5 * sideways * sideways);
}

std::vector<double> dragShares(const std::vector<WakeCar>& cars, const SlipstreamOptions& options) {
  std::vector<double> share(cars.size(), 1.0);
  if (!options.enabled) return share;
  for (std::size_t i = 0; i < cars.size(); ++i) {
    double best = 0.0;
    for (std::size_t j = 0; j < cars.size(); ++j) {
      if (i == j) continue;
      const WakeCar& ahead = cars[j];
      const double speed = ahead.velocity.norm();
      if (!(speed >= options.min_speed)) continue;
      const Eigen::Vector2d heading = ahead.velocity / speed;
      const Eigen::Vector2d rel = cars[i].position - ahead.position;
      // Behind the car ahead along its path: tail to nose.
      const double gap = -rel.dot(heading) - 0.5 * (ahead.length + cars[i].length);
      const double offset = rel.x() * heading.y() - rel.y() * heading.x();
      best = std::max(best, slipstreamReduction(gap, offset, speed, ahead.width, options));
    }
    share[i] = 1.0 - best;
  }
  return share;
}

}  // namespace roar::vehicle
