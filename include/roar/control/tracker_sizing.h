#pragma once
// The tracker sized to the car it drives, and what it reads of the car's state: one answer for the
// controller node, the in-process harness, the benchmarks and the binding.
#include "roar/control/trajectory_tracker.h"
#include "roar/vehicle/vehicle_params.h"
#include "roar/vehicle/vehicle_state.h"

namespace roar::control {

// The tracker options the vehicle implies: its wheelbase and maximum steering angle over `base`.
TrackerOptions trackerFor(const vehicle::VehicleParams& vehicle, TrackerOptions base = {});

// What the tracker needs of a car's state: base_link's position, heading, forward speed, yaw rate.
TrackerInput trackerInputOf(const vehicle::VehicleState& state);

}  // namespace roar::control
