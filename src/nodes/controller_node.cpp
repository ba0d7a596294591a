// controller: drives cars along the planner's trajectories (<vehicle>/local_trajectory): the scenario's
// cars that the stack drives (less ~exclude), or ~vehicle. Answers every odometry message with a control stamped with
// the odometry's time, which is what the simulator's lockstep mode waits for. Until a car's first trajectory arrives it
// does not answer, so a lockstep simulator waits for the stack to be ready (an async one holds the car with its control
// timeout). While the planner answers odometry too (its windows carry the odometry's stamp), the controller answers
// tick t with the window of tick t, waiting up to ~window_wait seconds of wall time for it: otherwise a planner that
// fell behind (a busy machine) would let a lockstep race run on with an old window, past its end and into a wall. When
// a car's odometry stops for odom_timeout seconds of wall time it brakes that car to a stop and says so. Gains and
// limits are dynamic_reconfigure parameters (cfg/Controller.cfg), tunable while it drives.
#include <dynamic_reconfigure/server.h>
#include <nav_msgs/Odometry.h>
#include <roar_ros/ControllerConfig.h>
#include <roar_ros/Trajectory.h>
#include <roar_ros/VehicleControl.h>
#include <ros/ros.h>

#include <algorithm>
#include <list>
#include <stdexcept>

#include "roar/control/tracker_option_table.h"
#include "roar/control/tracker_sizing.h"
#include "roar/control/trajectory_tracker.h"
#include "roar/lockstep/window_pairing.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/param_reading.h"
#include "roar/ros/planning_msg_conversion.h"
#include "roar/ros/queues.h"
#include "roar/ros/scenario_params.h"
#include "roar/ros/wall_throttle.h"
#include "roar/vehicle/vehicle_config.h"

using namespace roar;

namespace {

// Wall seconds of odometry without a first trajectory before the controller warns.
constexpr double kFirstWindowPatience = 20.0;
// Simulated seconds a window may lag the odometry before the car follows the racing line instead: a
// window reaches a few seconds ahead, so by then the car is near its end.
constexpr double kStaleWindow = 1.0;

struct DrivenCar {
  std::string name;
  vehicle::VehicleParams params;
  double max_speed = 0.0;  // m/s cap of this car (0: none)
};

struct ControllerOptions {
  std::vector<DrivenCar> cars;
  double odom_timeout = 1.0;  // s of wall time; 0: never
  double window_wait = 1.0;   // s of wall time a tick waits for its window; 0: answer with the latest at once
};

ControllerOptions readParameters(const ros::NodeHandle& nh) {
  using namespace ros_bridge;
  ControllerOptions o;
  const config::PackageLayout pkg = packageLayout();
  const std::string urdf_dir = readString(nh, "urdf_dir", pkg.urdf());
  const std::string config_dir = readString(nh, "vehicle_config_dir", pkg.vehicles());
  // The race's cars the stack drives, but those another driver (a policy_driver) drives instead; each car's
  // geometry from the same vehicle files the simulator reads.
  const std::vector<std::string> exclude = readStringList(nh, "exclude", {});
  for (const auto& car : readRaceCars(nh, readScenario(nh), readString(nh, "model", config::kDefaultModel))) {
    if (car.driven && std::find(exclude.begin(), exclude.end(), car.name) == exclude.end()) {
      o.cars.push_back({car.name, vehicle::loadVehicleModel(car.model, urdf_dir, config_dir), car.max_speed});
    }
  }
  o.odom_timeout = readDouble(nh, "odom_timeout", o.odom_timeout, 0.0, 3600);
  o.window_wait = readDouble(nh, "window_wait", o.window_wait, 0.0, 3600);
  return o;
}

// The tighter of two speed caps, 0 meaning none.
double tighter(double a, double b) { return a <= 0 ? b : b <= 0 ? a : std::min(a, b); }

control::TrackerOptions withGains(control::TrackerOptions t, const roar_ros::ControllerConfig& c, double car_cap,
                                  double pedal_response) {
  control::setTrackerOption(&t, "lateral_control", c.lateral_control, "controller");  // checked on reconfigure
  t.lookahead_min = c.lookahead_min;
  t.lookahead_time = c.lookahead_time;
  t.stanley_gain = c.stanley_gain;
  t.yaw_rate_gain = c.yaw_rate_gain;
  t.speed_gain = c.speed_gain;
  t.speed_preview = std::max(c.speed_preview, pedal_response);  // as control::trackerFor reads the car
  t.max_speed = tighter(c.max_speed, car_cap);
  return t;
}

// One car: its tracker, topics and odometry watchdog.
class Driver {
 public:
  // `racing_line`: the node's one copy of the latched /racing_line (null until it comes).
  Driver(ros::NodeHandle& nh, const DrivenCar& car, double odom_timeout, double window_wait,
         const std::shared_ptr<const planning::Trajectory>& racing_line)
      : car_(car),
        racing_line_(racing_line),
        odom_timeout_(odom_timeout),
        window_wait_(window_wait),
        // The tracker's feed-forward needs the car's forces and mass, not the road's friction.
        tracker_(control::trackerFor(car.params), planning::vehicleLimits(car.params, 1.0, 1.0)),
        pairing_(window_wait) {
    control_pub_ = nh.advertise<roar_ros::VehicleControl>(car.name + "/control", ros_bridge::kPerTickQueue);
    trajectory_sub_ = nh.subscribe(car.name + "/local_trajectory", 2, &Driver::onTrajectory, this,
                                   ros::TransportHints().tcpNoDelay());
    odom_sub_ = nh.subscribe<nav_msgs::Odometry>(
        car.name + "/odom", 10, [this](const nav_msgs::Odometry::ConstPtr& m) { onOdometry(*m, m); },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  }

  void configure(const roar_ros::ControllerConfig& config) {
    tracker_.setOptions(withGains(tracker_.options(), config, car_.max_speed, car_.params.pedalResponseTime()));
  }

  // Wall time: when the simulator (and so /clock) stops, a ros::Timer would stop too.
  void checkOdometry() {
    if (held_odom_ && pairing_.waitedTooLong(ros::WallTime::now().toSec())) {
      ROAR_WARN_WALL_THROTTLE(
          5.0, "controller: no window on %s for t = %.2f s after %.1f s; answering with the window of t = %.2f s",
          trajectory_sub_.getTopic().c_str(), held_odom_->header.stamp.toSec(), window_wait_, pairing_.windowStamp());
      answer(*held_odom_, /*late=*/true);
    }
    // Odometry held for its window is odometry: that wait is the planner's, said above. Only silence
    // since the last odometry received or answered is "no odometry".
    if (odom_timeout_ <= 0 || !driving_ || held_odom_ || (ros::WallTime::now() - last_odom_).toSec() < odom_timeout_)
      return;
    if (!stale_) {
      ROS_WARN("controller: no odometry on %s for %.1f s: braking '%s' to a stop", odom_sub_.getTopic().c_str(),
               odom_timeout_, car_.name.c_str());
      stale_ = true;
    }
    roar_ros::VehicleControl stop;
    stop.brake = 1.0;
    stop.header.stamp = ros::Time::now();
    control_pub_.publish(stop);
  }

 private:
  void onTrajectory(const roar_ros::Trajectory& msg) {
    try {
      tracker_.setTrajectory(ros_bridge::fromMessage(msg));
      if (on_racing_line_) ROS_INFO("controller: windows on %s again", trajectory_sub_.getTopic().c_str());
      on_racing_line_ = false;
      if (pairing_.onWindow(msg.header.stamp.toSec()) && held_odom_) answer(*held_odom_);
    } catch (const std::exception& e) {
      ROAR_ERROR_WALL_THROTTLE(2.0, "controller: trajectory on %s refused: %s%s", trajectory_sub_.getTopic().c_str(),
                               e.what(), tracker_.hasTrajectory() ? "; keeping the previous one" : "");
    }
  }

  // The planner's first window comes once its racing line is made, seconds into a normal start: only a
  // longer wait is news.
  void waitingForTheFirstWindow() {
    const ros::WallTime now = ros::WallTime::now();
    if (first_wait_.isZero()) first_wait_ = now;
    const double waited = (now - first_wait_).toSec();
    if (waited > kFirstWindowPatience) {
      ROAR_WARN_WALL_THROTTLE(5.0, "controller: no trajectory on %s after %.0f s of odometry (is the planner up?)",
                              trajectory_sub_.getTopic().c_str(), waited);
    }
  }

  void onOdometry(const nav_msgs::Odometry& odom, const nav_msgs::Odometry::ConstPtr& keep) {
    if (stale_) {
      ROS_INFO("controller: odometry of '%s' is back", car_.name.c_str());
      stale_ = false;
    }
    last_odom_ = ros::WallTime::now();
    if (!pairing_.onOdometry(odom.header.stamp.toSec(), last_odom_.toSec())) {
      if (!pairing_.hasWindow()) waitingForTheFirstWindow();
      held_odom_ = keep;  // a newer odometry supersedes one still held: the simulator went on without its answer
      return;
    }
    answer(odom);
  }

  // The windows stopped (planner dead or stuck): the car follows the whole racing line, latched, until a
  // fresh window comes (planner_killed rostest).
  void followTheRacingLineIfTheWindowsStopped(double stamp) {
    const bool stale = pairing_.windowStale(stamp, kStaleWindow);
    if (stale && !on_racing_line_ && racing_line_) {
      ROS_WARN("controller: no window on %s since t = %.2f s: '%s' follows the racing line until one comes",
               trajectory_sub_.getTopic().c_str(), pairing_.windowStamp(), car_.name.c_str());
      tracker_.setTrajectory(*racing_line_);
      on_racing_line_ = true;
    }
  }

  void answer(const nav_msgs::Odometry& odom, bool late = false) {
    driving_ = true;
    last_odom_ = ros::WallTime::now();
    followTheRacingLineIfTheWindowsStopped(odom.header.stamp.toSec());
    control::TrackerInput in;
    in.position = Eigen::Vector2d(odom.pose.pose.position.x, odom.pose.pose.position.y);
    in.yaw = ros_bridge::yawOf(odom.pose.pose.orientation);
    in.speed = odom.twist.twist.linear.x;
    in.lateral_speed = odom.twist.twist.linear.y;
    in.yaw_rate = odom.twist.twist.angular.z;
    roar_ros::VehicleControl msg = ros_bridge::toMessage(tracker_.update(in));
    if (tracker_.tooFar()) {
      ROAR_WARN_WALL_THROTTLE(5.0,
                              "controller: '%s' is %.1f m from its trajectory on %s (more than %.1f m: a window of "
                              "another map, or of a car elsewhere): braking until one near it comes",
                              car_.name.c_str(), tracker_.distance(), trajectory_sub_.getTopic().c_str(),
                              tracker_.options().max_distance);
    }
    msg.header.stamp = odom.header.stamp;
    control_pub_.publish(msg);
    if (late) {
      pairing_.answeredLate();
    } else {
      pairing_.answered();
    }
    held_odom_.reset();  // last: `odom` may be the held message itself
  }

  DrivenCar car_;
  const std::shared_ptr<const planning::Trajectory>& racing_line_;  // the planner's whole line: when windows stop
  double odom_timeout_, window_wait_;
  control::TrajectoryTracker tracker_;
  ros::Publisher control_pub_;
  ros::Subscriber trajectory_sub_, odom_sub_;
  bool on_racing_line_ = false;
  ros::WallTime last_odom_;   // of the last odometry received or answered
  ros::WallTime first_wait_;  // of the first odometry that found no trajectory
  bool driving_ = false;      // an odometry message has been answered: the watchdog starts with driving
  lockstep::WindowPairing pairing_;
  nav_msgs::Odometry::ConstPtr held_odom_;  // the odometry pairing_ holds: no trajectory yet, or its window is late
  bool stale_ = false;
};

class ControllerNode {
 public:
  ControllerNode(ros::NodeHandle& nh, const ControllerOptions& options) {
    // One copy of the latched racing line for every car's driver.
    racing_line_sub_ =
        nh.subscribe<roar_ros::Trajectory>("racing_line", 1, [this](const roar_ros::Trajectory::ConstPtr& m) {
          try {
            racing_line_ = std::make_shared<const planning::Trajectory>(ros_bridge::fromMessage(*m));
          } catch (const std::exception& e) {
            ROAR_ERROR_WALL_THROTTLE(2.0, "controller: racing line refused: %s", e.what());
          }
        });
    for (const auto& car : options.cars)
      drivers_.emplace_back(nh, car, options.odom_timeout, options.window_wait, racing_line_);
    reconfigure_.setCallback([this](const roar_ros::ControllerConfig& config, uint32_t) {
      try {
        control::TrackerOptions law;  // the law's name checked by the tracker's own table
        control::setTrackerOption(&law, "lateral_control", config.lateral_control, "controller");
      } catch (const std::invalid_argument& e) {
        ROS_ERROR("%s; keeping the gains as they were", e.what());
        return;
      }
      for (auto& driver : drivers_) driver.configure(config);
      ROS_INFO("controller: %s, lookahead %.2f m + %.2f s, Stanley gain %.2f, speed gain %.2f%s",
               config.lateral_control.c_str(), config.lookahead_min, config.lookahead_time, config.stanley_gain,
               config.speed_gain,
               config.max_speed > 0 ? (", max " + std::to_string(config.max_speed) + " m/s").c_str() : "");
    });
    watchdog_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) {
      for (auto& driver : drivers_) driver.checkOdometry();
    });
  }

 private:
  std::shared_ptr<const planning::Trajectory> racing_line_;  // before the drivers, which refer to it
  ros::Subscriber racing_line_sub_;
  std::list<Driver> drivers_;  // a list: drivers hold subscriptions bound to `this`, so they never move
  dynamic_reconfigure::Server<roar_ros::ControllerConfig> reconfigure_{ros::NodeHandle("~")};
  ros::WallTimer watchdog_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "controller");
  ros::NodeHandle nh, private_nh("~");
  try {
    const ControllerOptions options = readParameters(private_nh);
    ControllerNode node(nh, options);
    // Its gains are dynamic_reconfigure parameters (cfg/Controller.cfg), set by hand or by rqt.
    for (const auto& p : roar_ros::ControllerConfig::__getParamDescriptions__())
      ros_bridge::markParameterKnown(private_nh, p->name);
    ros_bridge::refuseUnknownParameters(private_nh);
    std::string names;
    for (const auto& car : options.cars) names += (names.empty() ? "" : ", ") + car.name;
    ROS_INFO("controller: driving %s along their local trajectories", names.empty() ? "no car" : names.c_str());
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("controller: %s", e.what());
    return 1;
  }
  return 0;
}
