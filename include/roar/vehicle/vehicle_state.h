#pragma once
// A car's state as the simulator reports it and the stack reads it (from odometry on a real car): its pose
// and motion, drivetrain, steering and wheels.
#include <Eigen/Core>
#include <array>

#include "roar/track/pose.h"
#include "roar/vehicle/vehicle_control.h"

namespace roar::vehicle {

struct WheelState {
  double angular_velocity = 0.0;  // rad/s about the axle, positive rolling forward
  double steer_angle = 0.0;       // rad
  double load = 0.0;              // N
  double slip_ratio = 0.0;
  double slip_angle = 0.0;   // rad
  double compression = 0.0;  // m from static ride height, positive compressed
  bool in_contact = false;
  bool on_road = false;
};

struct VehicleState {
  track::Pose pose;                       // base_link in the map frame
  Eigen::Vector3d linear_velocity;        // m/s of base_link, map frame
  Eigen::Vector3d angular_velocity;       // rad/s, map frame
  Eigen::Vector3d body_linear_velocity;   // m/s, base_link frame
  Eigen::Vector3d body_angular_velocity;  // rad/s, base_link frame
  Eigen::Vector3d body_acceleration;      // m/s^2 of the centre of mass over the last physics substep,
                                          // base_link frame (gravity not included)
  double speed = 0.0;
  double forward_speed = 0.0;
  int gear = 0;
  double engine_rpm = 0.0;
  double steering_angle = 0.0;  // rad, mean of the front wheels
  std::array<WheelState, 4> wheels;
  bool on_track = false;    // every wheel on the road surface
  double drag_share = 1.0;  // of the free-air drag, this tick (below 1 in another car's slipstream)
  VehicleControl applied_control;
};

}  // namespace roar::vehicle
