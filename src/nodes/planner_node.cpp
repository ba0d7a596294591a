// planner: plans the racing line and its speed profile from the track's waypoints (/waypoints, latched by
// waypoint_server) and the car's own limits (the simulator's vehicle files), publishes the whole
// trajectory latched on /racing_line (+ /racing_line/path) and, for every odometry message of each car,
// the window ahead of it on /<vehicle>/local_trajectory (and as a path on /<vehicle>/local_path), stamped
// with the odometry's time. A tick's windows are planned once every car's odometry of it has come (or
// ~tick_wait s of wall time, lockstep::TickGathering): each sees every other car at that tick, so a
// lockstep race runs the same every time. Which car each one follows or passes is planning::FieldPlanner's decision;
// for rviz, /<vehicle>/manoeuvre shows that decision and the planner's prediction of the cars around the car.
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <variant>

#include "roar/lockstep/tick_gathering.h"
#include "roar/planning/field_planner.h"
#include "roar/planning/field_planner_sizing.h"
#include "roar/planning/overtaking/option_table.h"
#include "roar/planning/trajectory.h"
#include "roar/ros/frames.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/param_reading.h"
#include "roar/ros/planning_msg_conversion.h"
#include "roar/ros/queues.h"
#include "roar/ros/scenario_params.h"
#include "roar/vehicle/vehicle_config.h"

using namespace roar;

namespace {

struct PlannerNodeOptions {
  std::vector<std::string> vehicles;
  std::map<std::string, double> pace;  // share of the planned speeds, per car of the scenario (default 1)
  // Each car is planned for its own model (its grip, power, brakes and size): one racing line per model.
  std::map<std::string, std::string> model_of;           // by car
  std::map<std::string, vehicle::VehicleParams> models;  // by model
  double grip_use = 0.85;
  planning::PlannerOptions planner;
  planning::FieldOptions field;
  std::string frame = ros_bridge::kMapFrame;
  double tick_wait = 0.25;  // s of wall time a tick waits for every car's odometry (lockstep::TickGathering)
};

// ~<group>/<name> for every entry of planning::overtakeOptionTable, in the range the table gives.
void readOvertakeOptions(const ros::NodeHandle& nh, planning::OvertakeOptions* overtake) {
  using namespace ros_bridge;
  for (const auto& entry : planning::overtakeOptionTable(overtake)) {
    std::string param = entry.name;
    std::replace(param.begin(), param.end(), '.', '/');
    if (auto* value = std::get_if<double*>(&entry.field)) {
      **value = readDouble(nh, param, **value, entry.low, entry.high);
    } else if (auto* count = std::get_if<int*>(&entry.field)) {
      **count = readInt(nh, param, **count, static_cast<int>(entry.low), static_cast<int>(entry.high));
    } else {
      bool* flag = std::get<bool*>(entry.field);
      *flag = readBool(nh, param, *flag);
    }
  }
}

PlannerNodeOptions readParameters(const ros::NodeHandle& nh) {
  using namespace ros_bridge;
  PlannerNodeOptions o;
  const config::PackageLayout pkg = packageLayout();
  // Every car of the race: the stack's cars follow or pass any car ahead of them.
  const std::string urdf_dir = readString(nh, "urdf_dir", pkg.urdf());
  const std::string vehicle_config_dir = readString(nh, "vehicle_config_dir", pkg.vehicles());
  for (const auto& car : readRaceCars(nh, readScenario(nh), readString(nh, "model", config::kDefaultModel))) {
    o.vehicles.push_back(car.name);
    o.pace[car.name] = car.pace;
    o.model_of[car.name] = car.model;
    if (!o.models.count(car.model))
      o.models[car.model] = vehicle::loadVehicleModel(car.model, urdf_dir, vehicle_config_dir);
  }
  o.grip_use = readDouble(nh, "grip_use", o.grip_use, 0.05, 1.0);
  auto& line = o.planner.line;
  line.safety_margin = readDouble(nh, "safety_margin", line.safety_margin, 0.0, 10.0);
  line.step = readDouble(nh, "step", line.step, 0.5, 20.0);
  line.max_iterations = readInt(nh, "max_iterations", line.max_iterations, 1, 100);
  o.planner.profile.max_speed = readDouble(nh, "max_speed", 0.0, 0.0, 150.0);
  o.planner.minimum_time = readBool(nh, "minimum_time", false);
  auto& field = o.field;
  field.window_ahead = readDouble(nh, "window_ahead", field.window_ahead, 10.0, 5000.0);
  field.window_behind = readDouble(nh, "window_behind", field.window_behind, 0.0, 100.0);
  o.frame = readMapFrame(nh);
  field.overtaking = readBool(nh, "overtaking", field.overtaking);
  readOvertakeOptions(nh, &field.overtake);
  field.overtake.prediction.keep = true;  // for /<vehicle>/manoeuvre
  o.tick_wait = readDouble(nh, "tick_wait", o.tick_wait, 0.0, 60.0);
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
      car.window_pub = nh.advertise<roar_ros::Trajectory>(name + "/local_trajectory", ros_bridge::kPerTickQueue);
      car.path_pub = nh.advertise<nav_msgs::Path>(name + "/local_path", ros_bridge::kPerTickQueue);
      car.manoeuvre_pub = nh.advertise<visualization_msgs::MarkerArray>(name + "/manoeuvre", 1);
      car.odom_sub = nh.subscribe<nav_msgs::Odometry>(
          name + "/odom", 10, [this, name](const nav_msgs::Odometry::ConstPtr& m) { onOdometry(name, m); },
          ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
    }
    expiry_timer_ = nh.createWallTimer(ros::WallDuration(0.02), [this](const ros::WallTimerEvent&) {
      if (ticks_) plan(ticks_->expire(ros::WallTime::now().toSec()));
    });
    // Alone (rosrun), the planner would wait in silence: it says once what it waits for.
    waiting_timer_ = nh.createWallTimer(
        ros::WallDuration(3.0),
        [this](const ros::WallTimerEvent&) {
          if (fields_.empty()) {
            ROS_INFO("planner: waiting for the track's waypoints on %s (waypoint_server publishes them)",
                     waypoints_sub_.getTopic().c_str());
          }
        },
        true);
  }

 private:
  struct Car {
    ros::Publisher window_pub, path_pub, manoeuvre_pub;
    ros::Subscriber odom_sub;
    nav_msgs::Odometry::ConstPtr last_odom;
    std::deque<nav_msgs::Odometry::ConstPtr> held;  // odometry gathered into ticks not yet planned
  };

  void onWaypoints(const roar_ros::WaypointArray& msg) {
    try {
      const auto started = std::chrono::steady_clock::now();
      const track::Track track = ros_bridge::trackFromMessage(msg);
      std::map<std::string, std::unique_ptr<planning::FieldPlanner>> fields;
      for (const auto& [model, params] : options_.models) fields[model] = fieldFor(track, params);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
      fields_ = std::move(fields);
      ticks_ = std::make_unique<lockstep::TickGathering>(options_.vehicles, options_.tick_wait);
      for (auto& [name, car] : cars_) car.held.clear();
      // /racing_line: the line of the first car's model (the controller's fallback, rviz).
      const planning::Trajectory& line = field(options_.vehicles.front()).line();
      roar_ros::Trajectory out = ros_bridge::toMessage(line, options_.frame, msg.map_name);
      out.header.stamp = ros::Time::now();
      line_pub_.publish(out);
      nav_msgs::Path path = ros_bridge::toPath(line, options_.frame);
      path.header.stamp = out.header.stamp;
      path_pub_.publish(path);
      map_name_ = msg.map_name;
      // A lockstep simulator may be waiting on a car whose odometry came before the line: answer it now.
      for (auto& [name, car] : cars_) {
        if (car.last_odom) onOdometry(name, car.last_odom);
      }
      for (const auto& [model, planner] : fields_) {
        ROS_INFO("planner: racing line of '%s' for the %s (%.0f m, %zu points); the profile promises a %.2f s lap",
                 msg.map_name.c_str(), model.c_str(), planner->line().length, planner->line().points.size(),
                 planner->line().lap_time);
      }
      ROS_INFO("planner: %zu racing line(s) in %.0f ms", fields_.size(), ms);
    } catch (const std::exception& e) {
      ROS_ERROR("planner: waypoints on %s refused: %s%s", waypoints_sub_.getTopic().c_str(), e.what(),
                fields_.empty() ? "" : "; keeping the previous racing lines");
    }
  }

  void onOdometry(const std::string& name, const nav_msgs::Odometry::ConstPtr& odom_msg) {
    Car& car = cars_[name];
    car.last_odom = odom_msg;
    if (fields_.empty()) return;
    car.held.push_back(odom_msg);
    plan(ticks_->arrive(name, odom_msg->header.stamp.toSec(), ros::WallTime::now().toSec()));
  }

  // Every car of a tick located first, then each planned: its window sees every other car at that tick.
  void plan(const std::vector<lockstep::TickGathering::Tick>& ticks) {
    for (const auto& tick : ticks) {
      std::vector<std::pair<std::string, nav_msgs::Odometry::ConstPtr>> odoms;
      for (const auto& name : tick.cars) {
        auto& held = cars_[name].held;
        // Older ones belong to ticks planned without them; a newer one, to a tick still to come.
        while (!held.empty() && held.front()->header.stamp.toSec() < tick.stamp) held.pop_front();
        if (held.empty() || held.front()->header.stamp.toSec() != tick.stamp) continue;
        odoms.emplace_back(name, held.front());
        held.pop_front();
      }
      // Every model's planner knows where every car is: a car passes or follows cars of any model.
      for (const auto& [name, odom] : odoms) {
        const vehicle::VehicleState state = ros_bridge::fromOdometry(*odom);
        for (auto& [model, planner] : fields_) {
          planner->locate(name, state.pose.position, state.forward_speed, odom->header.stamp.toSec(),
                          Eigen::Vector2d(state.linear_velocity.head<2>()));
        }
      }
      for (const auto& [name, odom] : odoms) planAndPublish(name, *odom);
    }
  }

  void planAndPublish(const std::string& name, const nav_msgs::Odometry& odom) {
    Car& car = cars_[name];
    planning::FieldPlanner& planner = field(name);
    const planning::RaceDecision before = planner.decision(name);
    const planning::Trajectory local = planner.window(name);
    const planning::RaceDecision now = planner.decision(name);
    if (now.mode != before.mode || now.other != before.other || now.side != before.side) {
      ROS_INFO("planner: %s: %s at t = %.2f s", name.c_str(), planning::describe(now).c_str(),
               odom.header.stamp.toSec());
    }
    roar_ros::Trajectory window = ros_bridge::toMessage(local, options_.frame, map_name_);
    window.header.stamp = odom.header.stamp;
    car.window_pub.publish(window);
    if (car.path_pub.getNumSubscribers() > 0) {  // for rviz
      nav_msgs::Path path = ros_bridge::toPath(local, options_.frame);
      path.header.stamp = odom.header.stamp;
      car.path_pub.publish(path);
    }
    if (car.manoeuvre_pub.getNumSubscribers() > 0) {  // for rviz: why it passes or waits
      car.manoeuvre_pub.publish(
          ros_bridge::manoeuvreMarkers(name, now, planner.predictions(name), options_.frame, odom.header.stamp));
    }
  }

  // One model's field planner, with every car's pace.
  std::unique_ptr<planning::FieldPlanner> fieldFor(const track::Track& track, const vehicle::VehicleParams& params) {
    auto out = std::make_unique<planning::FieldPlanner>(
        planning::fieldPlannerFor(track, params, options_.grip_use, options_.planner, options_.field));
    for (const auto& [name, pace] : options_.pace) out->setPace(name, pace);
    return out;
  }

  planning::FieldPlanner& field(const std::string& car) { return *fields_.at(options_.model_of.at(car)); }

  PlannerNodeOptions options_;
  std::map<std::string, std::unique_ptr<planning::FieldPlanner>> fields_;  // by model
  std::unique_ptr<lockstep::TickGathering> ticks_;
  ros::WallTimer expiry_timer_, waiting_timer_;
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
    ros_bridge::refuseUnknownParameters(private_nh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("planner: %s", e.what());
    return 1;
  }
  return 0;
}
