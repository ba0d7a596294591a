// planner: plans the racing line and its speed profile from the track's waypoints (/waypoints, latched by
// waypoint_server) and the car's own limits (the simulator's vehicle files), publishes the whole
// trajectory latched on /racing_line (+ /racing_line/path) and, for every odometry message of each car,
// the window ahead of it on /<vehicle>/local_trajectory (and as a path on /<vehicle>/local_path), stamped with the odometry's time. A car ahead
// on the line caps the window's speeds so the car follows it instead of running into it.
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>

#include "roar/planning/overtaking.h"
#include "roar/planning/trajectory.h"
#include "roar/ros/param_reading.h"
#include "roar/ros/planning_msg_conversion.h"
#include "roar/ros/scenario_params.h"
#include "roar/sim/vehicle_config.h"

using namespace roar;

namespace {

struct PlannerNodeOptions {
  std::vector<std::string> vehicles;
  sim::VehicleParams vehicle;
  double grip_use = 0.85;
  planning::PlannerOptions planner;
  double window_ahead = 250.0;  // m
  double window_behind = 10.0;  // m
  double follow_gap = 12.0;     // m kept behind a car ahead on the line (centre to centre)
  double follow_lateral = 3.5;  // m: a car this close to the line is in the way
  std::string frame = "map";
  bool overtaking = false;  // true: OvertakePlanner; false: every car follows the car ahead on the racing line
  planning::OvertakeOptions overtake;
};

PlannerNodeOptions readParameters(const ros::NodeHandle& nh) {
  using namespace ros_bridge;
  PlannerNodeOptions o;
  const std::string pkg = packagePath();
  // Every car of the scenario: the stack's cars follow any car ahead of them.
  if (const auto scenario = readScenario(nh)) {
    for (const auto& car : scenario->cars) o.vehicles.push_back(car.name);
  } else {
    o.vehicles = readStringList(nh, "vehicles", {"ego"});
  }
  o.vehicle = sim::loadVehicleModel(readString(nh, "model", "sedan"), readString(nh, "urdf_dir", pkg + "/urdf"),
                                    readString(nh, "vehicle_config_dir", pkg + "/config/vehicles"));
  o.grip_use = readDouble(nh, "grip_use", o.grip_use, 0.05, 1.0);
  auto& line = o.planner.line;
  line.vehicle_width = o.vehicle.chassis.box_size.y();
  line.safety_margin = readDouble(nh, "safety_margin", line.safety_margin, 0.0, 10.0);
  line.step = readDouble(nh, "step", line.step, 0.5, 20.0);
  line.max_iterations = readInt(nh, "max_iterations", line.max_iterations, 1, 100);
  o.planner.profile.max_speed = readDouble(nh, "max_speed", 0.0, 0.0, 150.0);
  o.planner.minimum_time = readBool(nh, "minimum_time", false);
  o.window_ahead = readDouble(nh, "window_ahead", o.window_ahead, 10.0, 5000.0);
  o.window_behind = readDouble(nh, "window_behind", o.window_behind, 0.0, 100.0);
  o.follow_gap = readDouble(nh, "follow_gap", o.follow_gap, 5.0, 200.0);
  o.frame = readString(nh, "frame", o.frame);
  o.overtaking = readBool(nh, "overtaking", o.overtaking);
  o.overtake.car_length = o.vehicle.chassis.box_size.x();
  o.overtake.car_width = o.vehicle.chassis.box_size.y();
  o.overtake.follow_gap = o.follow_gap;
  o.overtake.lateral_margin = readDouble(nh, "pass_lateral_margin", o.overtake.lateral_margin, 0.2, 5.0);
  o.overtake.horizon = readDouble(nh, "pass_horizon", o.overtake.horizon, 1.0, 20.0);
  return o;
}

class PlannerNode {
 public:
  PlannerNode(ros::NodeHandle& nh, PlannerNodeOptions options) : options_(std::move(options)) {
    line_pub_ = nh.advertise<roar_ros::Trajectory>("racing_line", 1, true);
    path_pub_ = nh.advertise<nav_msgs::Path>("racing_line/path", 1, true);
    waypoints_sub_ = nh.subscribe("waypoints", 1, &PlannerNode::onWaypoints, this);
    for (const auto& name : options_.vehicles) {
      Car& car = cars_[name];
      car.window_pub = nh.advertise<roar_ros::Trajectory>(name + "/local_trajectory", 10);
      car.path_pub = nh.advertise<nav_msgs::Path>(name + "/local_path", 10);
      car.odom_sub = nh.subscribe<nav_msgs::Odometry>(
          name + "/odom", 10, [this, name](const nav_msgs::Odometry::ConstPtr& m) { onOdometry(name, m); },
          ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
    }
  }

 private:
  struct Car {
    ros::Publisher window_pub, path_pub;
    ros::Subscriber odom_sub;
    long hint = -1;
    nav_msgs::Odometry::ConstPtr last_odom;
    planning::TrajectoryProjection on_line;  // where the car was last, on the racing line
    double speed = 0.0;
    bool located = false;
  };

  // The nearest car ahead on the racing line within the window, if one is in the way.
  void followCarAhead(const std::string& name, const Car& car, planning::Trajectory* window) const {
    double nearest = options_.window_ahead;
    const Car* leader = nullptr;
    for (const auto& [other_name, other] : cars_) {
      if (other_name == name || !other.located || std::abs(other.on_line.lateral) > options_.follow_lateral) continue;
      double ahead = other.on_line.s - car.on_line.s;
      ahead -= std::floor(ahead / trajectory_.length) * trajectory_.length;  // forward round the lap
      if (ahead > 0 && ahead < nearest) {
        nearest = ahead;
        leader = &other;
      }
    }
    if (leader) {
      planning::followBehind(window, car.on_line.s, car.on_line.s + nearest, leader->speed, options_.follow_gap, limits_);
    }
  }

  void onWaypoints(const roar_ros::WaypointArray& msg) {
    try {
      const auto started = std::chrono::steady_clock::now();
      const track::Track track = ros_bridge::trackFromMessage(msg);
      const auto limits = planning::vehicleLimits(options_.vehicle, track.info().friction, options_.grip_use);
      planning::Trajectory trajectory = planning::planRacingTrajectory(track, limits, options_.planner);
      limits_ = limits;
      planning::validate(trajectory);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
      trajectory_ = std::move(trajectory);
      if (options_.overtaking) {
        overtaker_ = std::make_unique<planning::OvertakePlanner>(track, trajectory_, limits, options_.overtake);
      }
      for (auto& [name, car] : cars_) {
        car.hint = -1;
        car.located = false;
      }
      roar_ros::Trajectory out = ros_bridge::toMessage(trajectory_, options_.frame, msg.map_name);
      out.header.stamp = ros::Time::now();
      line_pub_.publish(out);
      nav_msgs::Path path = ros_bridge::toPath(trajectory_, options_.frame);
      path.header.stamp = out.header.stamp;
      path_pub_.publish(path);
      map_name_ = msg.map_name;
      // A lockstep simulator may be waiting on a car whose odometry came before the line: answer it now.
      for (auto& [name, car] : cars_) {
        if (car.last_odom) onOdometry(name, car.last_odom);
      }
      ROS_INFO("planner: racing line of '%s' (%.0f m, %zu points) in %.0f ms; the profile promises a %.2f s lap",
               msg.map_name.c_str(), trajectory_.length, trajectory_.points.size(), ms, trajectory_.lap_time);
    } catch (const std::exception& e) {
      ROS_ERROR("planner: waypoints on %s refused: %s%s", waypoints_sub_.getTopic().c_str(), e.what(),
                trajectory_.points.empty() ? "" : "; keeping the previous racing line");
    }
  }

  void onOdometry(const std::string& name, const nav_msgs::Odometry::ConstPtr& odom_msg) {
    Car& car = cars_[name];
    car.last_odom = odom_msg;
    if (trajectory_.points.empty()) return;
    const nav_msgs::Odometry& odom = *odom_msg;
    const Eigen::Vector2d position(odom.pose.pose.position.x, odom.pose.pose.position.y);
    const auto projection = planning::project(trajectory_, position, car.hint);
    car.hint = static_cast<long>(projection.segment);
    car.on_line = projection;
    car.speed = odom.twist.twist.linear.x;
    car.located = true;
    planning::Trajectory local;
    if (overtaker_) {
      std::vector<planning::TrafficCar> traffic;
      for (const auto& [other_name, other] : cars_) {
        if (other.located) traffic.push_back({other_name, other.on_line.s, other.on_line.lateral, other.speed});
      }
      const planning::RaceDecision before = overtaker_->decision(name);
      local = overtaker_->plan(name, projection.s, projection.lateral, car.speed, traffic, options_.window_behind,
                               options_.window_ahead);
      const planning::RaceDecision now = overtaker_->decision(name);
      if (now.mode != before.mode || now.other != before.other || now.side != before.side) {
        ROS_INFO("planner: %s: %s%s%s at t = %.2f s", name.c_str(), planning::raceModeName(now.mode),
                 now.other.empty() ? "" : (" " + now.other).c_str(),
                 now.mode == planning::RaceMode::kPass ? (now.side > 0 ? " on the left" : " on the right") : "",
                 odom.header.stamp.toSec());
      }
    } else {
      local = planning::windowAround(trajectory_, projection.s, options_.window_behind, options_.window_ahead);
      followCarAhead(name, car, &local);
    }
    roar_ros::Trajectory window = ros_bridge::toMessage(local, options_.frame, map_name_);
    window.header.stamp = odom.header.stamp;
    car.window_pub.publish(window);
    if (car.path_pub.getNumSubscribers() > 0) {  // for rviz
      nav_msgs::Path path = ros_bridge::toPath(local, options_.frame);
      path.header.stamp = odom.header.stamp;
      car.path_pub.publish(path);
    }
  }

  PlannerNodeOptions options_;
  planning::Trajectory trajectory_;
  std::unique_ptr<planning::OvertakePlanner> overtaker_;
  planning::VehicleLimits limits_;
  std::string map_name_;
  ros::Publisher line_pub_, path_pub_;
  ros::Subscriber waypoints_sub_;
  std::map<std::string, Car> cars_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "planner");
  ros::NodeHandle nh, private_nh("~");
  try {
    PlannerNode node(nh, readParameters(private_nh));
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("planner: %s", e.what());
    return 1;
  }
  return 0;
}
