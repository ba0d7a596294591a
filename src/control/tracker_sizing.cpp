#include "roar/control/tracker_sizing.h"

#include <algorithm>
#include <cmath>

namespace roar::control {

TrackerOptions trackerFor(const vehicle::VehicleParams& vehicle, TrackerOptions base) {
  base.wheelbase = vehicle.wheelbase();
  base.max_steer_angle = vehicle.steering.max_angle;
  base.steering_curve = vehicle.steering.speed_curve;
  base.front_axle = vehicle.wheels[0].position.x();
  // The speed profile is read at least as far ahead as the pedals take to act (CARLA's Model 3: 0.28 s for
  // its torque, 0.26 s to build its brakes): read later, a car brakes late and runs wide.
  base.speed_preview = std::max(base.speed_preview, vehicle.pedalResponseTime());
  return base;
}

TrackerInput trackerInputOf(const vehicle::VehicleState& state) {
  const Eigen::Vector3d forward = state.pose.orientation * Eigen::Vector3d::UnitX();
  TrackerInput in;
  in.position = state.pose.position.head<2>();
  in.yaw = std::atan2(forward.y(), forward.x());
  in.speed = state.forward_speed;
  in.lateral_speed = state.body_linear_velocity.y();
  in.yaw_rate = state.body_angular_velocity.z();
  return in;
}

}  // namespace roar::control
