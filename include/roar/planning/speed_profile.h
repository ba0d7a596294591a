#pragma once
// Fastest speed along a path a car can hold: the cornering limit at every point, then a forward pass
// (acceleration limited by engine and by the grip the corner leaves) and a backward pass (braking limited
// by brakes and grip). On a closed circuit both passes start at the slowest corner, so the profile is
// consistent across the start/finish line.
#include <vector>

#include "roar/planning/vehicle_limits.h"

namespace roar::planning {

struct SpeedProfile {
  std::vector<double> speed;         // m/s at each point
  std::vector<double> acceleration;  // m/s^2 from each point to the next (the last of an open path: 0)
  std::vector<double> time;          // s from the first point
  double total_time = 0.0;           // s: round the loop when closed, to the last point when open
};

struct SpeedProfileOptions {
  double max_speed = 0.0;     // m/s; 0: the car's top speed
  double start_speed = -1.0;  // open paths: speed at the first point (negative: as fast as allowed)
  double end_speed = -1.0;    // open paths: speed at the last point (negative: as fast as allowed)
  // Per point, the sine of the road's slope from it to the next (positive uphill); empty: level. Gravity
  // along the road takes from the drive uphill and from the brakes downhill.
  std::vector<double> grade;
  // Per point, the road's curvature in the vertical plane (1/m, negative over a crest); empty: none. The
  // cornering speed falls where the car weighs less (VehicleLimits::corneringSpeed).
  std::vector<double> vertical_curvature;
};

// The hardest a car gains speed at speed v on curvature kappa: the engine or the grip the corner leaves
// the driven wheels, less drag and rolling resistance (none while the gearbox is `shifting`).
double accelerationAt(const VehicleLimits& limits, double v, double kappa, bool shifting = false);
// The hardest braking at speed v on curvature kappa: brakes or the grip the corner leaves, plus drag.
double decelerationAt(const VehicleLimits& limits, double v, double kappa);
// The same on a slope (`grade`: its sine, positive uphill): gravity along the road helps uphill, takes
// away downhill.
double decelerationAt(const VehicleLimits& limits, double v, double kappa, double grade);

// `step[i]` is the distance from point i to point i + 1 (on a closed path the last entry leads back to
// point 0; on an open path it is ignored). Throws std::invalid_argument naming the first bad entry.
SpeedProfile computeSpeedProfile(const std::vector<double>& step, const std::vector<double>& curvature,
                                 const VehicleLimits& limits, bool closed, const SpeedProfileOptions& options = {});

// Speeds planned for free air along an open path (`speed`, from computeSpeedProfile or a window of one),
// as a car meeting drag_share of its drag can drive them (in another car's slipstream): raised where the
// engine, not the grip, sets them; never lowered (the braking points stay the free-air ones).
std::vector<double> towedSpeeds(const std::vector<double>& step, const std::vector<double>& curvature,
                                const std::vector<double>& speed, const VehicleLimits& limits, double drag_share);

}  // namespace roar::planning
