#pragma once
// The slipstream (tow, draft): a car close behind another drives in its wake, where the air already moves
// with the car ahead, and meets less drag. One model of the wake serves the simulator (the drag it
// applies) and the planner (what a car in the tow can do), so both agree on what a tow is worth.
//
// The share of drag a car meets in the wake of a car ahead falls off with the gap between them and with
// the sideways offset from the car ahead's path: reduction = max_reduction * exp(-gap / decay_length) *
// exp(-0.5 (offset / spread)^2), spread = half the car's width + spread_growth * gap (the wake widens
// behind a car). Measured wind-tunnel and CFD figures for saloon and stock cars run from about 40 %
// less drag nose to tail to 10-20 % two or three car lengths back; the defaults follow them.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "roar/vehicle/car_size.h"

namespace roar::vehicle {

struct SlipstreamOptions {
  bool enabled = true;
  double max_reduction = 0.4;   // share of the drag taken away nose to tail
  double decay_length = 12.0;   // m of gap over which the reduction falls to 1/e
  double spread_growth = 0.05;  // m the wake's half-width grows per metre behind the car
  double max_gap = 40.0;        // m: no tow beyond this gap
  double min_speed = 10.0;      // m/s the car ahead must do to leave a wake worth having
};

// The range of each field that validate() holds the options to (and roar_sim reads its parameters within).
struct SlipstreamRange {
  double low, high;
};
inline constexpr SlipstreamRange kMaxReductionRange{0.0, 0.9};
inline constexpr SlipstreamRange kDecayLengthRange{0.1, 1000.0};
inline constexpr SlipstreamRange kSpreadGrowthRange{0.0, 10.0};
inline constexpr SlipstreamRange kMaxGapRange{0.0, 1000.0};
inline constexpr SlipstreamRange kMinSpeedRange{0.0, 1000.0};

// Throws std::invalid_argument naming the first field out of range (prefix: where the options came from).
void validate(const SlipstreamOptions& options, const std::string& prefix);

// The share of the drag taken away (0: free air) for a car `gap` metres (tail to nose) behind a car of
// width `width` doing `speed`, `offset` metres to the side of its path.
double slipstreamReduction(double gap, double offset, double speed, double width, const SlipstreamOptions& options);

// A car as the wake sees it: where it is and goes, in the plane.
struct WakeCar {
  Eigen::Vector2d position;           // m, the car's centre
  Eigen::Vector2d velocity;           // m/s
  double length = kDefaultCarLength;  // m, bumper to bumper
  double width = kDefaultCarWidth;    // m
};

// Each car's share of its free-air drag (1: free air) in the wakes of the others: the strongest tow
// counts (wakes do not add up).
std::vector<double> dragShares(const std::vector<WakeCar>& cars, const SlipstreamOptions& options);

}  // namespace roar::vehicle
