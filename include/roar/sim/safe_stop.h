#pragma once
// What roar_sim drives a car with once its driver has fallen silent (control_timeout): it brakes steadily
// while steering along the road at its lateral place (kept inside the edges), then parks once stopped. A
// locked hand brake at speed, the old fail-safe, put cars into the barrier.
#include "roar/sim/world.h"
#include "roar/track/track.h"
#include "roar/vehicle/vehicle_control.h"
#include "roar/vehicle/vehicle_params.h"

namespace roar::sim {

struct SafeStopOptions {
  double brake = 0.3;           // pedal: about 4-5 m/s^2 on a sedan, well inside the grip of a corner
  double edge_clearance = 1.5;  // m kept between the car's centre line and a road edge
  double min_lookahead = 8.0;   // m
  double lookahead_time = 0.8;  // s of the car's speed
  double stopped_speed = 0.5;   // m/s below which the car is parked
};

vehicle::VehicleControl safeStopControl(const track::Track& track, const vehicle::VehicleState& state,
                                        const vehicle::VehicleParams& params, const SafeStopOptions& options = {});

}  // namespace roar::sim
