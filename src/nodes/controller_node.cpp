// controller: drives one car along the planner's trajectory (<vehicle>/local_trajectory). Answers every
// odometry message with a control stamped with the odometry's time, which is what the simulator's lockstep
// mode waits for. Until the first trajectory arrives it does not answer, so a lockstep simulator waits for
// the stack to be ready (an async one holds the car with its control timeout). When odometry stops coming
// for odom_timeout seconds of wall time it brakes the car to a stop and says so. Gains and limits are
// dynamic_reconfigure parameters (cfg/Controller.cfg), tunable while it drives.
#include <dynamic_reconfigure/server.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <roar_ros/ControllerConfig.h>
#include <roar_ros/Trajectory.h>
#include <roar_ros/VehicleControl.h>

#include "roar/control/trajectory_tracker.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/param_reading.h"
#include "roar/ros/planning_msg_conversion.h"
#include "roar/sim/vehicle_config.h"
#include "roar/stack/time_trial.h"

using namespace roar;

namespace {

struct ControllerOptions {
  std::string vehicle;
  sim::VehicleParams car;
  control::TrackerOptions tracker;
  double odom_timeout = 1.0;  // s of wall time; 0: never
};

ControllerOptions readParameters(const ros::NodeHandle& nh) {
  using namespace ros_bridge;
  ControllerOptions o;
  const std::string pkg = packagePath();
  o.vehicle = readString(nh, "vehicle", "ego");
  // The car's geometry comes from the same vehicle files the simulator reads.
  o.car = sim::loadVehicleModel(readString(nh, "model", "sedan"), readString(nh, "urdf_dir", pkg + "/urdf"),
                                readString(nh, "vehicle_config_dir", pkg + "/config/vehicles"));
  // Gains come through dynamic_reconfigure (withGains), which reads and range-checks them.
  o.tracker = stack::trackerFor(o.car);
  o.odom_timeout = readDouble(nh, "odom_timeout", o.odom_timeout, 0.0, 3600);
  return o;
}

control::TrackerOptions withGains(control::TrackerOptions t, const roar_ros::ControllerConfig& c) {
  t.lateral = c.lateral_control == "stanley" ? control::LateralMethod::kStanley : control::LateralMethod::kPurePursuit;
  t.lookahead_min = c.lookahead_min;
  t.lookahead_time = c.lookahead_time;
  t.stanley_gain = c.stanley_gain;
  t.yaw_rate_gain = c.yaw_rate_gain;
  t.speed_gain = c.speed_gain;
  t.speed_preview = c.speed_preview;
  t.max_speed = c.max_speed;
  return t;
}

class ControllerNode {
 public:
  ControllerNode(ros::NodeHandle& nh, const ControllerOptions& options)
      // The tracker's feed-forward needs the car's forces and mass, not the road's friction.
      : options_(options), tracker_(options.tracker, planning::vehicleLimits(options.car, 1.0, 1.0)) {
    control_pub_ = nh.advertise<roar_ros::VehicleControl>(options.vehicle + "/control", 10);
    trajectory_sub_ = nh.subscribe(options.vehicle + "/local_trajectory", 2, &ControllerNode::onTrajectory, this,
                                   ros::TransportHints().tcpNoDelay());
    odom_sub_ = nh.subscribe<nav_msgs::Odometry>(
        options.vehicle + "/odom", 10, [this](const nav_msgs::Odometry::ConstPtr& m) { onOdometry(*m, m); },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
    reconfigure_.setCallback([this](const roar_ros::ControllerConfig& config, uint32_t) {
      if (config.lateral_control != "pure_pursuit" && config.lateral_control != "stanley") {
        ROS_ERROR("controller: lateral_control '%s' is neither pure_pursuit nor stanley; keeping the gains as they were",
                  config.lateral_control.c_str());
        return;
      }
      tracker_.setOptions(withGains(tracker_.options(), config));
      ROS_INFO("controller: %s, lookahead %.2f m + %.2f s, Stanley gain %.2f, speed gain %.2f%s",
               config.lateral_control.c_str(), config.lookahead_min, config.lookahead_time, config.stanley_gain,
               config.speed_gain, config.max_speed > 0 ? (", max " + std::to_string(config.max_speed) + " m/s").c_str() : "");
    });
    if (options.odom_timeout > 0) {
      // Wall time: when the simulator (and so /clock) stops, a ros::Timer would stop too.
      watchdog_ = nh.createWallTimer(ros::WallDuration(0.1), &ControllerNode::checkOdometry, this);
    }
  }

 private:
  void onTrajectory(const roar_ros::Trajectory& msg) {
    try {
      const bool first = !tracker_.hasTrajectory();
      tracker_.setTrajectory(ros_bridge::fromMessage(msg));
      if (first && waiting_odom_) {  // the simulator may be waiting for its answer
        const nav_msgs::Odometry::ConstPtr held = waiting_odom_;
        onOdometry(*held, held);
      }
    } catch (const std::exception& e) {
      ROS_ERROR_THROTTLE(2.0, "controller: trajectory on %s refused: %s%s", trajectory_sub_.getTopic().c_str(), e.what(),
                         tracker_.hasTrajectory() ? "; keeping the previous one" : "");
    }
  }

  void onOdometry(const nav_msgs::Odometry& odom, const nav_msgs::Odometry::ConstPtr& keep) {
    if (stale_) {
      ROS_INFO("controller: odometry of '%s' is back", options_.vehicle.c_str());
      stale_ = false;
    }
    control::TrackerInput in;
    in.position = Eigen::Vector2d(odom.pose.pose.position.x, odom.pose.pose.position.y);
    in.yaw = ros_bridge::yawOf(odom.pose.pose.orientation);
    in.speed = odom.twist.twist.linear.x;
    in.yaw_rate = odom.twist.twist.angular.z;
    if (!tracker_.hasTrajectory()) {
      ROS_WARN_THROTTLE(5.0, "controller: waiting for a trajectory on %s", trajectory_sub_.getTopic().c_str());
      waiting_odom_ = keep;
      return;
    }
    waiting_odom_.reset();
    last_odom_ = ros::WallTime::now();
    roar_ros::VehicleControl msg = ros_bridge::toMessage(tracker_.update(in));
    msg.header.stamp = odom.header.stamp;
    control_pub_.publish(msg);
  }

  void checkOdometry(const ros::WallTimerEvent&) {
    if (last_odom_.isZero() || (ros::WallTime::now() - last_odom_).toSec() < options_.odom_timeout) return;
    if (!stale_) {
      ROS_WARN("controller: no odometry on %s for %.1f s: braking '%s' to a stop", odom_sub_.getTopic().c_str(),
               options_.odom_timeout, options_.vehicle.c_str());
      stale_ = true;
    }
    roar_ros::VehicleControl stop;
    stop.brake = 1.0;
    stop.header.stamp = ros::Time::now();
    control_pub_.publish(stop);
  }

  ControllerOptions options_;
  control::TrajectoryTracker tracker_;
  dynamic_reconfigure::Server<roar_ros::ControllerConfig> reconfigure_{ros::NodeHandle("~")};
  ros::Publisher control_pub_;
  ros::Subscriber trajectory_sub_, odom_sub_;
  ros::WallTimer watchdog_;
  ros::WallTime last_odom_;  // of the last odometry answered: the watchdog starts with driving
  nav_msgs::Odometry::ConstPtr waiting_odom_;
  bool stale_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "controller");
  ros::NodeHandle nh, private_nh("~");
  try {
    const ControllerOptions options = readParameters(private_nh);
    ControllerNode node(nh, options);
    ROS_INFO("controller: driving '%s' along %s/local_trajectory", options.vehicle.c_str(), options.vehicle.c_str());
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("controller: %s", e.what());
    return 1;
  }
  return 0;
}
