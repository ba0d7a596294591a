#pragma once
#include "roar/sensors/inertial.h"
#include "roar/sim/world.h"

namespace roar::sensors {

// The sensors' view of a simulated car's motion. The acceleration is the centre of mass's over the last
// physics substep; the difference to base_link's (a rotational term over half a metre) is neglected.
inline BodyMotion motionOf(const vehicle::VehicleState& state) {
  BodyMotion m;
  m.pose.linear() = state.pose.orientation.toRotationMatrix();
  m.pose.translation() = state.pose.position;
  m.linear_velocity = state.linear_velocity;
  m.angular_velocity = state.angular_velocity;
  m.linear_acceleration = m.pose.linear() * state.body_acceleration;
  return m;
}

inline Eigen::Isometry3d poseOf(const vehicle::VehicleState& state) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = state.pose.orientation.toRotationMatrix();
  t.translation() = state.pose.position;
  return t;
}

}  // namespace roar::sensors
