// controller: drives one car round the track's centre line (pure pursuit + speed profile).
// Answers every odometry message with a control stamped with the odometry's time, which is what the
// simulator's lockstep mode waits for.
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <roar_ros/VehicleControl.h>

#include "roar/control/centreline_follower.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/param_reading.h"
#include "roar/sim/vehicle_config.h"
#include "roar/track/map_folder.h"

using namespace roar;

namespace {

struct ControllerOptions {
  std::string vehicle;
  std::string map_folder;
  control::FollowerOptions follower;
};

ControllerOptions readParameters(const ros::NodeHandle& nh) {
  using namespace ros_bridge;
  ControllerOptions o;
  const std::string pkg = packagePath();
  o.vehicle = readString(nh, "vehicle", "ego");
  try {
    o.map_folder = track::resolveMapFolder(readString(nh, "map", "roar_ring"), readString(nh, "maps_dir", pkg + "/maps"));
  } catch (const track::MapError& e) {
    throw ParamError("parameter " + nh.resolveName("map") + ": " + e.what());
  }
  // The car's geometry comes from the same vehicle files the simulator reads.
  const auto car = sim::loadVehicleModel(readString(nh, "model", "sedan"), readString(nh, "urdf_dir", pkg + "/urdf"),
                                         readString(nh, "vehicle_config_dir", pkg + "/config/vehicles"));
  auto& f = o.follower;
  f.wheelbase = car.wheelbase();
  f.max_steer_angle = car.steering.max_angle;
  f.lookahead_min = readDouble(nh, "lookahead_min", f.lookahead_min, 0.5, 100);
  f.lookahead_time = readDouble(nh, "lookahead_time", f.lookahead_time, 0.0, 5);
  f.yaw_rate_gain = readDouble(nh, "yaw_rate_gain", f.yaw_rate_gain, 0.0, 2);
  f.lateral_accel = readDouble(nh, "lateral_accel", f.lateral_accel, 0.5, 50);
  f.braking_decel = readDouble(nh, "braking_decel", f.braking_decel, 0.5, 50);
  f.max_speed = readDouble(nh, "max_speed", f.max_speed, 0.5, 150);
  f.speed_gain = readDouble(nh, "speed_gain", f.speed_gain, 0.01, 10);
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "controller");
  ros::NodeHandle nh, private_nh("~");
  try {
    const ControllerOptions options = readParameters(private_nh);
    const track::Track track = track::loadMapFolder(options.map_folder);
    control::CentrelineFollower follower(track, options.follower);
    ros::Publisher pub = nh.advertise<roar_ros::VehicleControl>(options.vehicle + "/control", 10);
    ros::Subscriber sub = nh.subscribe<nav_msgs::Odometry>(
        options.vehicle + "/odom", 10,
        [&](const nav_msgs::Odometry::ConstPtr& odom) {
          control::FollowerInput in;
          in.position = Eigen::Vector2d(odom->pose.pose.position.x, odom->pose.pose.position.y);
          in.yaw = ros_bridge::yawOf(odom->pose.pose.orientation);
          in.speed = odom->twist.twist.linear.x;
          in.yaw_rate = odom->twist.twist.angular.z;
          roar_ros::VehicleControl msg = ros_bridge::toMessage(follower.update(in));
          msg.header.stamp = odom->header.stamp;
          pub.publish(msg);
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
    ROS_INFO("controller: driving '%s' round '%s'", options.vehicle.c_str(), track.info().name.c_str());
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("controller: %s", e.what());
    return 1;
  }
  return 0;
}
