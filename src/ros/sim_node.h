#pragma once
// The roar_sim node: owns the World, wires vehicles' topics and the simulator's services to it, and runs
// the stepping loop. Parameters come from sim_parameters.h, messages from msg_conversion.h.
//
// The loop runs on wall time on purpose: this node is the source of /clock, so ros::Timer (which follows
// /clock) cannot drive it. Everything it publishes is stamped with simulated time.
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <array>
#include <map>
#include <memory>

#include "roar/sensors/ray_scene.h"
#include "roar/sim/world.h"
#include "agent_interface.h"
#include "roar_ros/AttachSensor.h"
#include "roar_ros/DetachSensor.h"
#include "roar/track/track.h"
#include "roar_ros/DestroyVehicle.h"
#include "roar_ros/ResetEpisode.h"
#include "roar_ros/ResetVehicle.h"
#include "roar_ros/SpawnVehicle.h"
#include "roar_ros/Step.h"
#include "sim_parameters.h"
#include "vehicle_sensors.h"

namespace roar::ros_bridge {

class SimNode {
 public:
  SimNode(ros::NodeHandle nh, ros::NodeHandle private_nh, const SimNodeOptions& options);
  // Runs until ROS shuts down.
  void run();

 private:
  struct VehicleIo {
    ros::Publisher odom, status, collision, joints;
    std::array<double, 4> wheel_angles{};  // rad, integrated for the URDF's wheel joints
    ros::Subscriber control;
    ros::Time last_control_stamp{0, 0};
    bool control_seen = false;
    int scene_id = -1;
    std::unique_ptr<VehicleSensors> sensors;
    std::unique_ptr<AgentInterface> agent;  // when an RL agent drives the car
  };

  // A negative colour: the next of the palette.
  void addVehicle(const std::string& name, const std::string& model, const sim::Pose& pose,
                  const std::string& sensor_set, const Eigen::Vector3f& colour = Eigen::Vector3f(-1, -1, -1),
                  const std::string& agent_env = "");
  std::string sensorSetPath(const std::string& set) const;
  void publishStaticTransforms();
  // What the first tick still waits for (empty: nothing): ~wait_for_recorders and ~wait_for_drivers.
  std::string notReadyToStart() const;
  // Async and lockstep: no faster than real_time_factor (0: as fast as possible).
  void paceToRealTime(const ros::WallTime& start, std::uint64_t start_tick);
  // Moves the cars in the ray scene when a sensor or an agent's observation will cast rays this tick;
  // returns their poses (none when nothing casts).
  std::map<std::string, Eigen::Isometry3d> updateRayScene();
  void sampleRaySensors(const std::map<std::string, Eigen::Isometry3d>& poses);
  sim::Pose spawnPose(int spawn_point) const;
  // A service's spawn point (>= 0) or, for -1, its pose; throws for a spawn point that does not exist.
  sim::Pose requestedPose(int spawn_point, const geometry_msgs::Pose& pose) const;
  void onControl(const std::string& name, const roar_ros::VehicleControl::ConstPtr& msg);
  bool applyControl(const std::string& name, const roar_ros::VehicleControl& msg, std::string* why);
  void tick();
  void publishState();
  bool controlsArrived() const;

  bool onSpawn(roar_ros::SpawnVehicle::Request& req, roar_ros::SpawnVehicle::Response& res);
  bool onDestroy(roar_ros::DestroyVehicle::Request& req, roar_ros::DestroyVehicle::Response& res);
  bool onReset(roar_ros::ResetVehicle::Request& req, roar_ros::ResetVehicle::Response& res);
  bool onStep(roar_ros::Step::Request& req, roar_ros::Step::Response& res);
  bool onResetEpisode(roar_ros::ResetEpisode::Request& req, roar_ros::ResetEpisode::Response& res);
  bool onAttachSensor(roar_ros::AttachSensor::Request& req, roar_ros::AttachSensor::Response& res);
  bool onDetachSensor(roar_ros::DetachSensor::Request& req, roar_ros::DetachSensor::Response& res);

  ros::NodeHandle nh_, private_nh_;
  SimNodeOptions options_;
  track::Track track_;
  std::unique_ptr<sim::World> world_;
  std::unique_ptr<sensors::RayScene> scene_;
  std::map<std::string, sensors::VisualMesh> looks_;  // by vehicle model
  std::map<std::string, VehicleIo> io_;
  ros::Publisher clock_pub_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  std::vector<ros::ServiceServer> services_;
};

}  // namespace roar::ros_bridge
