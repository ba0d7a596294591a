// policy_driver: drives a car of the race with a trained policy (rl_train's policy.yaml) instead of the
// planner and controller. For every odometry message of ~vehicle it builds the observation the policy
// was trained on (the RL core's ObservationBuilder, with the car followed along the map's centre line)
// and answers with the policy's action as a control stamped with the odometry's time, as lockstep wants.
// It reads what odometry carries: a policy that observes a camera, LiDAR or IMU is refused at start.
#include <nav_msgs/Odometry.h>
#include <roar_ros/VehicleControl.h>
#include <ros/ros.h>

#include <optional>

#include "roar/rl/action.h"
#include "roar/rl/policy.h"
#include "roar/rl/track_progress.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/param_reading.h"
#include "roar/ros/queues.h"
#include "roar/ros/scenario_params.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"

using namespace roar;

namespace {

struct PolicyDriverOptions {
  std::string vehicle;
  std::string policy_file;
  std::string map_folder;
  int forward_gears = 0;
};

PolicyDriverOptions readParameters(const ros::NodeHandle& nh) {
  using namespace ros_bridge;
  PolicyDriverOptions o;
  const config::PackageLayout pkg = packageLayout();
  const auto scenario = readScenario(nh);
  o.map_folder = readMapFolder(nh, scenario);
  o.vehicle = readString(nh, "vehicle", "ego");
  std::string model = readString(nh, "model", config::kDefaultModel);
  for (const auto& car : readRaceCars(nh, scenario, model)) {
    if (car.name == o.vehicle) model = car.model;
  }
  o.forward_gears = static_cast<int>(vehicle::loadVehicleModel(model, readString(nh, "urdf_dir", pkg.urdf()),
                                                               readString(nh, "vehicle_config_dir", pkg.vehicles()))
                                         .gearbox.ratios.size());
  o.policy_file = readString(nh, "policy", "");
  if (o.policy_file.empty())
    throw ParamError("parameter " + nh.resolveName("policy") + " must name a policy file (rl_train's policy.yaml)");
  return o;
}

class PolicyDriver {
 public:
  PolicyDriver(ros::NodeHandle& nh, const PolicyDriverOptions& options)
      // The topics first, before the policy and map load: lockstep waits for connected drivers only, and
      // odometry that arrives meanwhile waits in the queue (callbacks run only in ros::spin, after this).
      : control_(nh.advertise<roar_ros::VehicleControl>(options.vehicle + "/control", ros_bridge::kPerTickQueue)),
        odom_(nh.subscribe<nav_msgs::Odometry>(
            options.vehicle + "/odom", 10, [this](const nav_msgs::Odometry::ConstPtr& m) { onOdometry(*m); },
            ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay())),
        options_(options),
        track_(track::loadMapFolder(options.map_folder)),
        policy_(rl::MlpPolicy::load(options.policy_file)),
        observer_(track_, policy_.observation()),
        progress_(track_),
        action_space_(rl::actionSpace({}, options.forward_gears)) {
    const rl::ObservationOptions& seen = policy_.observation();
    if (observer_.needsScene() || seen.imu) {
      throw ros_bridge::ParamError("policy " + options.policy_file +
                                   " observes a camera, LiDAR or IMU; policy_driver reads odometry only (speed, "
                                   "velocity, angular_velocity, waypoints_information)");
    }
  }

 private:
  void onOdometry(const nav_msgs::Odometry& odom) {
    const vehicle::VehicleState state = ros_bridge::fromOdometry(odom);
    const Eigen::Vector3d& at = state.pose.position;
    if (!started_) {
      progress_.reset(at);
      started_ = true;
    } else {
      progress_.update(at.head<2>());
    }
    const rl::Value action = policy_.act(action_space_, observer_.observe(state, progress_.projection(), nullptr, -1));
    roar_ros::VehicleControl msg = ros_bridge::toMessage(rl::toControl(action_space_, action));
    msg.header.stamp = odom.header.stamp;
    control_.publish(msg);
  }

  ros::Publisher control_;
  ros::Subscriber odom_;
  PolicyDriverOptions options_;
  track::Track track_;
  rl::MlpPolicy policy_;
  rl::ObservationBuilder observer_;
  rl::TrackProgress progress_;
  rl::Space action_space_;
  bool started_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "policy_driver");
  ros::NodeHandle nh, private_nh("~");
  try {
    const PolicyDriverOptions options = readParameters(private_nh);
    PolicyDriver driver(nh, options);
    ros_bridge::refuseUnknownParameters(private_nh);
    ROS_INFO("policy_driver: %s drives %s", options.policy_file.c_str(), options.vehicle.c_str());
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("policy_driver: %s", e.what());
    return 1;
  }
  return 0;
}
