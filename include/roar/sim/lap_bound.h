#pragma once
// A lap-time bound from the car's own model in quasi-steady state, computed without the planner: at each
// point of a line the fastest the car can corner (each axle carrying its share of the cornering force,
// every wheel's friction from the tyre model at its load, the loads with the static split, downforce and
// the weight moved across and along the car), then the fastest it can reach that speed and leave it (full
// throttle in the strongest gear, or the brakes, each axle inside its friction circle after the cornering
// force, less drag and rolling resistance). Flat: a crest or a bank is not modelled. No car that follows
// the line laps faster than its bound, whatever drives it (lap_bound_test).
#include <vector>

#include "roar/vehicle/vehicle_params.h"

namespace roar::sim {

struct LapBound {
  double lap_time = 0.0;             // s round the line (closed) or from a standing start to its end (open)
  double top_speed = 0.0;            // m/s where full throttle meets drag and rolling resistance
  std::vector<double> speed;         // m/s at each point
  std::vector<double> corner_speed;  // m/s the point's curvature allows, steady state
};

// `curvature` (1/m) and `step` (m to the next point; for an open line the last is unused) per point of the
// line; `road_friction` the track's. Throws std::invalid_argument on an empty line, sizes that differ or a
// step that is not positive.
LapBound quasiSteadyStateLap(const std::vector<double>& curvature, const std::vector<double>& step, bool closed,
                             const vehicle::VehicleParams& car, double road_friction);

}  // namespace roar::sim
