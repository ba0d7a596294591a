#pragma once
// Conversions between roar_ros / standard ROS messages and the ROS-free core types. Free functions,
// each tested by a round trip in test/unit/msg_conversion_test.cpp.
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <roar_ros/VehicleControl.h>
#include <roar_ros/VehicleStatus.h>
#include <ros/time.h>
#include <sensor_msgs/JointState.h>

#include "roar/track/pose.h"
#include "roar/track/track.h"
#include "roar/vehicle/vehicle_params.h"
#include "roar/vehicle/vehicle_state.h"

namespace roar::ros_bridge {

vehicle::VehicleControl fromMessage(const roar_ros::VehicleControl& msg);
roar_ros::VehicleControl toMessage(const vehicle::VehicleControl& control);

track::Pose fromMessage(const geometry_msgs::Pose& msg);
geometry_msgs::Pose toMessage(const track::Pose& pose);
// A place on the road (a spawn point, a respawn) as the pose on its surface.
geometry_msgs::Pose toMessage(const track::TrackPose& pose);

// Simulated seconds since the start <-> ROS time (the simulator's /clock starts at zero).
ros::Time toRosTime(double seconds);

// Pose of base_link in `map_frame`; twist in base_link (nav_msgs/Odometry convention).
nav_msgs::Odometry toOdometry(const vehicle::VehicleState& state, const ros::Time& stamp, const std::string& map_frame,
                              const std::string& base_frame);
// What odometry tells of a car's state: pose, body and map-frame velocities, speed (not its wheels,
// drivetrain or acceleration).
vehicle::VehicleState fromOdometry(const nav_msgs::Odometry& odom);
roar_ros::VehicleStatus toStatus(const vehicle::VehicleState& state, const ros::Time& stamp,
                                 const std::string& base_frame);
// The URDF's joints for robot_state_publisher: <wheel>_joint (rotation angle, rad; wheel_angles in the
// order of params.wheels) and steer_<front wheel>_joint (steering angle).
sensor_msgs::JointState toJointState(const vehicle::VehicleState& state, const vehicle::VehicleParams& params,
                                     const std::array<double, 4>& wheel_angles, const ros::Time& stamp);
geometry_msgs::TransformStamped toTransform(const track::Pose& pose, const ros::Time& stamp, const std::string& parent,
                                            const std::string& child);

// Yaw (rad) of a quaternion message, for planar drivers.
double yawOf(const geometry_msgs::Quaternion& q);

}  // namespace roar::ros_bridge
