#pragma once
// The roar_sim node: wires vehicles' topics, their sensors' publishers and the simulator's services to a
// ROS-free session::SimSession (the map, its cars, the ray scene's kept ticks), and runs the stepping
// loop. Parameters come from sim_parameters.h, messages from msg_conversion.h; the service handlers live
// in sim_services.cpp.
//
// The loop runs on wall time on purpose: this node is the source of /clock, so ros::Timer (which follows
// /clock) cannot drive it. Everything it publishes is stamped with simulated time.
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <array>
#include <map>
#include <memory>
#include <optional>

#include "agent_interface.h"
#include "debug_drawing.h"
#include "roar/lockstep/driver_roll.h"
#include "roar/lockstep/recorder_pacing.h"
#include "roar/ros/unread_answers.h"
#include "roar/ros/waking_queue.h"
#include "roar/session/sim_session.h"
#include "roar_ros/AttachSensor.h"
#include "roar_ros/DestroyVehicle.h"
#include "roar_ros/DetachSensor.h"
#include "roar_ros/DrawDebug.h"
#include "roar_ros/GetGeolocation.h"
#include "roar_ros/GetWorldInfo.h"
#include "roar_ros/ListMaps.h"
#include "roar_ros/LoadMap.h"
#include "roar_ros/RenderSensor.h"
#include "roar_ros/ResetEpisode.h"
#include "roar_ros/ResetVehicle.h"
#include "roar_ros/SetStepping.h"
#include "roar_ros/SetVehicleVelocity.h"
#include "roar_ros/SpawnVehicle.h"
#include "roar_ros/Step.h"
#include "roar_ros/VehicleSnapshot.h"
#include "sim_parameters.h"
#include "vehicle_sensors.h"

namespace roar::ros_bridge {

using session::SceneTick;
using session::SpawnRecord;

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
    std::unique_ptr<VehicleSensors> sensors;
    std::unique_ptr<AgentInterface> agent;  // when an RL agent drives the car
  };

  // Spawns a car with its topics, sensors and agent, all or nothing: on any error nothing is left behind
  // (no car in the physics world, no topic) and the error says why. A negative colour: the next of the palette.
  void addVehicle(const std::string& name, const std::string& model, const track::Pose& pose,
                  const std::string& sensor_set, const Eigen::Vector3f& colour = Eigen::Vector3f(-1, -1, -1),
                  const std::string& agent_env = "", int spawn_point = -1,
                  sim::Placement placement = sim::Placement::kOnGround);
  // What every sensor costs together (the cars' and the world's), against sensors::kSimulatorSensorBudget.
  sensors::SensorLoad sensorLoad() const;
  sensors::RigTiming rigTiming() const;  // the world's steps, as every rig is built with
  // The sensors of a car, or the world's own for AttachSensor's WORLD; throws std::invalid_argument for a
  // name that is neither.
  VehicleSensors& sensorsOf(const std::string& host);
  // Whether a sensor host's name is the world's (AttachSensor's WORLD) rather than a car's.
  static bool isWorld(const std::string& host) { return host == roar_ros::AttachSensor::Request::WORLD; }
  // Every rig: each car's, then the world's (sensors fixed in the map frame).
  std::vector<VehicleSensors*> allSensors();
  void removeVehicle(const std::string& name);
  // Lockstep timed out: every driver that has not answered the tick is taken as lost (warned once each).
  // Lockstep: some driver is lost and none that is connected answers.
  bool everyDriverLost() const;
  void markLostDrivers();
  // A driver that had a control publisher and has none now (it died): lost at once, not after a timeout.
  void markDisconnectedDrivers();
  // Warns once, naming the car, and tells race control (~driver_lost, the car's name).
  void driverLost(const std::string& name, const std::string& why);
  void publishStaticTransforms();
  // Builds the world of a map folder (every car gone), from the current tick and time on, and tells
  // every node on /roar_sim/map.
  void loadMap(const std::string& folder, const std::string& reason);
  // A service's pose request (spawn point or pose) as the session takes it.
  track::Pose requestedPose(int spawn_point, const geometry_msgs::Pose& pose) const;
  sim::World& world() { return session_->world(); }
  const sim::World& world() const { return session_->world(); }
  void publishMapInfo(const std::string& reason);
  // What the first tick still waits for (empty: nothing): ~wait_for_recorders, ~wait_for_listeners and
  // ~wait_for_drivers.
  std::string notReadyToStart() const;
  // Async and lockstep: no faster than real_time_factor (0: as fast as possible), measured from the last
  // change of pace (start, map load, stepping change).
  void paceToRealTime();
  void restartPacing();
  // Moves the cars in the ray scene when a sensor or an agent's observation will cast rays this tick;
  // returns their poses (none when nothing casts).
  std::map<std::string, Eigen::Isometry3d> updateRayScene();
  void sampleRaySensors(const std::map<std::string, Eigen::Isometry3d>& poses);
  void onControl(const std::string& name, const roar_ros::VehicleControl::ConstPtr& msg);
  bool applyControl(const std::string& name, const roar_ros::VehicleControl& msg, std::string* why);
  void tick();
  void publishState();
  // In step mode between steps: /clock again at the time it stands at (10 Hz of wall time), so that nodes
  // and tools on simulated time (rostopic, rviz, a controller's timers) start and do not hang.
  void publishIdleClock();
  void publishDebugMarkers();
  bool controlsArrived() const;
  // Recorders that report their progress (a publisher on <recorder>/recorded: race_recorder) are kept
  // within kRecorderMaxLag ticks; those that do not (rosbag record) cannot be, and are named once.
  void subscribeRecorderProgress();
  void setUpRecorderPacing();
  // Whether the next tick may go out as far as the recorders are concerned (warns of one given up).
  bool recordersKeptUp();
  roar_ros::VehicleSnapshot snapshot(const std::string& name) const;
  std::string modeName() const;
  // Serves the services' queue, then waits up to `timeout` for the topics' (the global queue).
  void spinFor(ros::WallDuration timeout);
  // A service that changes the world: refused while a long step runs, saying so.
  template <class Request, class Response>
  void serveBetweenSteps(const std::string& name, bool (SimNode::*handler)(Request&, Response&));
  // A service that only reads the world (or draws over it): answered between the ticks of a long step too.
  template <class Request, class Response>
  void serveAnyTime(const std::string& name, bool (SimNode::*handler)(Request&, Response&));
  // Every service: refused while unread answers hold more than their budget, its answers counted.
  template <class Request, class Response>
  void serve(const std::string& name, const boost::function<bool(Request&, Response&)>& call);
  bool onCancelStep(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);

  bool onSpawn(roar_ros::SpawnVehicle::Request& req, roar_ros::SpawnVehicle::Response& res);
  bool onDestroy(roar_ros::DestroyVehicle::Request& req, roar_ros::DestroyVehicle::Response& res);
  bool onReset(roar_ros::ResetVehicle::Request& req, roar_ros::ResetVehicle::Response& res);
  bool onSetVelocity(roar_ros::SetVehicleVelocity::Request& req, roar_ros::SetVehicleVelocity::Response& res);
  bool onStep(roar_ros::Step::Request& req, roar_ros::Step::Response& res);
  bool onResetEpisode(roar_ros::ResetEpisode::Request& req, roar_ros::ResetEpisode::Response& res);
  bool onAttachSensor(roar_ros::AttachSensor::Request& req, roar_ros::AttachSensor::Response& res);
  bool onDetachSensor(roar_ros::DetachSensor::Request& req, roar_ros::DetachSensor::Response& res);
  bool onLoadMap(roar_ros::LoadMap::Request& req, roar_ros::LoadMap::Response& res);
  bool onListMaps(roar_ros::ListMaps::Request& req, roar_ros::ListMaps::Response& res);
  bool onSetStepping(roar_ros::SetStepping::Request& req, roar_ros::SetStepping::Response& res);
  bool onGetWorldInfo(roar_ros::GetWorldInfo::Request& req, roar_ros::GetWorldInfo::Response& res);
  bool onGetGeolocation(roar_ros::GetGeolocation::Request& req, roar_ros::GetGeolocation::Response& res);
  bool onDrawDebug(roar_ros::DrawDebug::Request& req, roar_ros::DrawDebug::Response& res);
  bool onRenderSensor(roar_ros::RenderSensor::Request& req, roar_ros::RenderSensor::Response& res);

  ros::NodeHandle nh_, private_nh_;
  SimNodeOptions options_;
  // The map, its cars and the ray scene's kept ticks; what SimNode adds per car is in io_.
  std::unique_ptr<session::SimSession> session_;
  std::map<std::string, VehicleIo> io_;
  std::unique_ptr<VehicleSensors> world_sensors_;  // sensors on no car (AttachSensor's WORLD), gone with the map
  DebugDrawing debug_;
  ros::Publisher clock_pub_, map_pub_, debug_pub_, driver_lost_pub_, driver_back_pub_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  // The services have a queue of their own, so that between the ticks of a long step they are answered
  // while the topics (drivers' controls) wait for the step's end (service_inputs rostest); a request's
  // arrival wakes the wait on the topics' queue, so that it is answered at once.
  WakingCallbackQueue service_queue_{ros::getGlobalCallbackQueue()};
  ros::NodeHandle service_nh_;
  std::vector<ros::ServiceServer> services_;
  // Camera frames answered to callers that never read them stay in this process: bounded
  // (test_unread_camera_frames_hold_a_bounded_memory_in_roar_sim).
  static constexpr std::size_t kUnreadAnswersBudget = std::size_t{128} << 20;
  UnreadAnswers unread_answers_{kUnreadAnswersBudget};
  struct LongStep {
    std::uint32_t ticks = 0, done = 0;
    bool cancelled = false;
  };
  std::optional<LongStep> long_step_;  // while /roar_sim/step runs
  ros::WallTime pace_wall_start_;
  ros::WallTime idle_clock_wall_;
  double pace_sim_start_ = 0.0;
  std::unique_ptr<lockstep::RecorderPacing> recorder_pacing_;
  // The drivers lockstep waits for: a car's is connected while its control topic has a publisher.
  lockstep::DriverRoll drivers_{[this](const std::string& car) {
    const auto it = io_.find(car);
    return it != io_.end() && it->second.control.getNumPublishers() > 0;
  }};
  std::map<std::string, ros::Subscriber> recorded_subs_;  // each recorder's progress, by its node's name
};

}  // namespace roar::ros_bridge
