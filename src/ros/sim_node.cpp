#include "sim_node.h"

#include <roar_ros/MapInfo.h>
#include <ros/callback_queue.h>
#include <ros/master.h>
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/String.h>

#include <filesystem>
#include <map>
#include <set>
#include <type_traits>

#include "roar/ros/frames.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/param_reading.h"
#include "roar/ros/queues.h"
#include "roar/ros/sensor_msg_conversion.h"
#include "roar/ros/service_refusal.h"
#include "roar/ros/wall_throttle.h"
#include "roar/sensors/vehicle_motion.h"

namespace roar::ros_bridge {

namespace {
// No car can take the name of the world's own sensors (AttachSensor's WORLD).
void checkNotWorld(const std::string& name) {
  if (name == roar_ros::AttachSensor::Request::WORLD)
    throw std::invalid_argument("name '" + name + "' is the world's own (its sensors on no car): take another");
}

// Whether a service's reply can say why it was refused (success, message).
template <class Response, class = void>
struct HasSuccess : std::false_type {};
template <class Response>
struct HasSuccess<Response, std::void_t<decltype(std::declval<Response&>().success)>> : std::true_type {};
}  // namespace

SimNode::SimNode(ros::NodeHandle nh, ros::NodeHandle private_nh, const SimNodeOptions& options)
    : nh_(nh), private_nh_(private_nh), options_(options), service_nh_(private_nh) {
  service_nh_.setCallbackQueue(&service_queue_);
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  map_pub_ = private_nh_.advertise<roar_ros::MapInfo>("map", 1, true);
  debug_pub_ = private_nh_.advertise<visualization_msgs::MarkerArray>("debug_markers", 1, true);
  driver_lost_pub_ = private_nh_.advertise<std_msgs::String>("driver_lost", 10, true);
  driver_back_pub_ = private_nh_.advertise<std_msgs::String>("driver_back", 10);
  loadMap(options_.map_folder, "start");
  for (const auto& v : options_.vehicles) {
    if (v.spawn_point >= track::kGridSlots) {
      throw ParamError("vehicle '" + v.name + "': spawn_point " + std::to_string(v.spawn_point) +
                       " does not exist (0.." + std::to_string(track::kGridSlots - 1) + ")");
    }
    addVehicle(v.name, v.model, session_->spawnPose(v.spawn_point), v.sensor_set, v.colour, v.agent, v.spawn_point);
  }
  serveBetweenSteps("spawn_vehicle", &SimNode::onSpawn);
  serveBetweenSteps("destroy_vehicle", &SimNode::onDestroy);
  serveBetweenSteps("reset_vehicle", &SimNode::onReset);
  serveBetweenSteps("set_vehicle_velocity", &SimNode::onSetVelocity);
  serveBetweenSteps("step", &SimNode::onStep);
  serveBetweenSteps("reset_episode", &SimNode::onResetEpisode);
  serveBetweenSteps("attach_sensor", &SimNode::onAttachSensor);
  serveBetweenSteps("detach_sensor", &SimNode::onDetachSensor);
  serveBetweenSteps("load_map", &SimNode::onLoadMap);
  serveBetweenSteps("set_stepping", &SimNode::onSetStepping);
  serveBetweenSteps("render_sensor", &SimNode::onRenderSensor);
  // These only read the world (or draw over it): answered between the ticks of a long step too.
  serveAnyTime("list_maps", &SimNode::onListMaps);
  serveAnyTime("get_world_info", &SimNode::onGetWorldInfo);
  serveAnyTime("get_geolocation", &SimNode::onGetGeolocation);
  serveAnyTime("draw_debug", &SimNode::onDrawDebug);
  serveAnyTime("cancel_step", &SimNode::onCancelStep);
  ROS_INFO("roar_sim: map '%s' (%.0f m), %zu vehicle(s), control_dt %.3f s, physics_dt %.4f s, mode %s",
           session_->track().info().name.c_str(), session_->track().length(), io_.size(), options_.world.control_dt,
           options_.world.physics_dt, modeName().c_str());
}

template <class Request, class Response>
void SimNode::serveBetweenSteps(const std::string& name, bool (SimNode::*handler)(Request&, Response&)) {
  serve<Request, Response>(name, [this, name, handler](Request& req, Response& res) {
    if (long_step_) {
      return refuse(res, name,
                    "a step of " + std::to_string(long_step_->ticks) + " ticks is running (" +
                        std::to_string(long_step_->done) +
                        " done): wait for its reply, or end it early with /roar_sim/cancel_step");
    }
    return (this->*handler)(req, res);
  });
}

template <class Request, class Response>
void SimNode::serveAnyTime(const std::string& name, bool (SimNode::*handler)(Request&, Response&)) {
  serve<Request, Response>(name, [this, handler](Request& req, Response& res) { return (this->*handler)(req, res); });
}

template <class Request, class Response>
void SimNode::serve(const std::string& name, const boost::function<bool(Request&, Response&)>& call) {
  ros::AdvertiseServiceOptions options;
  options.template init<Request, Response>(name, [this, name, call](Request& req, Response& res) {
    if (!unread_answers_.overBudget()) return call(req, res);
    const std::string why = unread_answers_.describe() + ": read them first";
    if constexpr (HasSuccess<Response>::value) {
      return refuse(res, name, why);
    } else {
      ROAR_WARN_WALL_THROTTLE(1.0, "roar_sim: %s refused: %s", name.c_str(), why.c_str());
      return false;  // no field to say it in: the call fails
    }
  });
  options.helper = unread_answers_.counting(options.helper);
  services_.push_back(service_nh_.advertiseService(options));
}

void SimNode::spinFor(ros::WallDuration timeout) {
  // A service request's arrival ends the wait on the topics' queue (WakingCallbackQueue).
  service_queue_.callAvailable(ros::WallDuration(0));
  ros::getGlobalCallbackQueue()->callAvailable(timeout);
  service_queue_.callAvailable(ros::WallDuration(0));
}

std::string SimNode::modeName() const {
  return options_.mode == SteppingMode::kStep       ? "step"
         : options_.mode == SteppingMode::kLockstep ? "lockstep"
                                                    : "async";
}

void SimNode::loadMap(const std::string& folder, const std::string& reason) {
  // The cars' topics, sensors and agents go with them (agents refer to the old track); a broken map throws
  // before anything goes.
  const auto forget_cars = [this] {
    io_.clear();
    drivers_.clear();
  };
  if (!session_) {
    session_ = std::make_unique<session::SimSession>(
        session::SessionOptions{options_.world, options_.urdf_dir, options_.vehicle_config_dir}, folder);
  } else {
    session_->loadMap(folder, forget_cars);
  }
  world_sensors_ =
      std::make_unique<VehicleSensors>(nh_, roar_ros::AttachSensor::Request::WORLD, options_.map_frame, rigTiming(),
                                       session_->track().info().origin, options_.map_frame, sensors::kInTheWorld);
  debug_.clear();
  publishDebugMarkers();
  publishMapInfo(reason);
  restartPacing();
}

void SimNode::publishMapInfo(const std::string& reason) {
  roar_ros::MapInfo info;
  info.header.stamp = toRosTime(world().time());
  info.header.frame_id = options_.map_frame;
  info.name = session_->track().info().name;
  info.folder = session_->mapFolder();
  info.generation = session_->mapGeneration();
  info.reason = reason;
  map_pub_.publish(info);
}

void SimNode::publishDebugMarkers() {
  debug_pub_.publish(debug_.markers(options_.map_frame, toRosTime(world().time())));
}

track::Pose SimNode::requestedPose(int spawn_point, const geometry_msgs::Pose& pose) const {
  return session_->requestedPose(spawn_point, spawn_point < 0 ? fromMessage(pose) : track::Pose{});
}

void SimNode::addVehicle(const std::string& name, const std::string& model, const track::Pose& pose,
                         const std::string& sensor_set, const Eigen::Vector3f& colour, const std::string& agent_env,
                         int spawn_point, sim::Placement placement) {
  const vehicle::VehicleParams params = session_->carToSpawn(name, model);
  checkNotWorld(name);
  // Sensors and agent are read and checked before the car exists, so a bad set leaves nothing half made
  // (their publishers go with them).
  auto vehicle_sensors = std::make_unique<VehicleSensors>(nh_, name, baseFrame(name), rigTiming(),
                                                          session_->track().info().origin, options_.map_frame);
  if (!sensor_set.empty()) {
    sensors::SensorLoad load = sensorLoad();
    for (const auto& spec : sensors::readSensorSet(sensors::resolveSensorSet(sensor_set, options_.sensors_dir))) {
      sensors::checkBudget(load, spec, sensors::kSimulatorSensorBudget);
      load += sensors::loadOf(spec);
      vehicle_sensors->attach(spec, world().time());
    }
  }
  std::unique_ptr<AgentInterface> agent;
  if (!agent_env.empty()) {
    const rl::EnvOptions env = rl::readEnvOptions(agent_env);
    // One agent step is one tick of this simulator.
    if (env.world.control_dt != options_.world.control_dt || env.world.physics_dt != options_.world.physics_dt) {
      throw ParamError("vehicle '" + name + "': the agent's environment " + agent_env + " steps control_dt " +
                       std::to_string(env.world.control_dt) + " / physics_dt " + std::to_string(env.world.physics_dt) +
                       " s, roar_sim " + std::to_string(options_.world.control_dt) + " / " +
                       std::to_string(options_.world.physics_dt) + " s (parameters ~control_dt, ~physics_dt)");
    }
    agent = std::make_unique<AgentInterface>(nh_, name, session_->track(), env,
                                             static_cast<int>(params.gearbox.ratios.size()));
  }
  // The last step that can refuse: overlap, no ground.
  session_->spawn(name, params, pose, {params.model, sensor_set, colour, agent_env, spawn_point}, placement);
  VehicleIo io;
  io.agent = std::move(agent);
  io.sensors = std::move(vehicle_sensors);
  io.odom = nh_.advertise<nav_msgs::Odometry>(name + "/odom", kPerTickQueue);
  io.status = nh_.advertise<roar_ros::VehicleStatus>(name + "/vehicle_status", kPerTickQueue);
  io.joints = nh_.advertise<sensor_msgs::JointState>(name + "/joint_states", kPerTickQueue);
  io.collision = nh_.advertise<roar_ros::CollisionEvent>(name + "/collision", kPerTickQueue);
  io.control = nh_.subscribe<roar_ros::VehicleControl>(
      name + "/control", 10, [this, name](const roar_ros::VehicleControl::ConstPtr& msg) { onControl(name, msg); },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  io_[name] = std::move(io);
  drivers_.add(name);
  publishStaticTransforms();
  ROS_INFO("roar_sim: spawned '%s' (%s) at (%.1f, %.1f)", name.c_str(), params.model.c_str(), pose.position.x(),
           pose.position.y());
}

sensors::SensorLoad SimNode::sensorLoad() const {
  sensors::SensorLoad load = sensors::totalLoad(world_sensors_->rig().specs());
  for (const auto& [name, io] : io_) {
    load += sensors::totalLoad(io.sensors->rig().specs());
  }
  return load;
}

sensors::RigTiming SimNode::rigTiming() const {
  return {options_.world.control_dt, options_.world.physics_dt, options_.world.gravity};
}

VehicleSensors& SimNode::sensorsOf(const std::string& host) {
  if (isWorld(host)) return *world_sensors_;
  const auto it = io_.find(host);
  if (it == io_.end()) throw std::invalid_argument("no vehicle named '" + host + "'");
  return *it->second.sensors;
}

std::vector<VehicleSensors*> SimNode::allSensors() {
  std::vector<VehicleSensors*> all;
  for (auto& [name, io] : io_) all.push_back(io.sensors.get());
  all.push_back(world_sensors_.get());
  return all;
}

void SimNode::removeVehicle(const std::string& name) {
  session_->remove(name);
  io_.erase(name);
  drivers_.remove(name);
}

bool SimNode::applyControl(const std::string& name, const roar_ros::VehicleControl& msg, std::string* why) {
  const session::AppliedControl applied = session_->applyControl(name, fromMessage(msg));
  if (!applied.applied) {
    *why = "control for '" + name + "' rejected: " + applied.problems;
  } else if (!applied.problems.empty()) {
    *why = "control for '" + name + "': " + applied.problems;
  }
  return applied.applied;
}

void SimNode::onControl(const std::string& name, const roar_ros::VehicleControl::ConstPtr& msg) {
  auto it = io_.find(name);
  if (it == io_.end() || !world().hasVehicle(name)) return;
  std::string why;
  const bool applied = applyControl(name, *msg, &why);
  if (!why.empty()) ROAR_WARN_WALL_THROTTLE(1.0, "roar_sim: %s", why.c_str());
  if (applied && drivers_.control(name, msg->header.stamp.toSec())) {
    ROS_INFO("roar_sim: %s's driver is back at t = %.2f s; lockstep waits for it again", name.c_str(), world().time());
    std_msgs::String back;
    back.data = name;
    driver_back_pub_.publish(back);
  }
}

void SimNode::markLostDrivers() {
  for (const auto& name : drivers_.silent(toRosTime(world().time()).toSec())) {
    char why[160];
    std::snprintf(why, sizeof(why), "no control for t = %.2f s within %.1f s of wall time", world().time(),
                  options_.lockstep_timeout);
    driverLost(name, why);
  }
}

void SimNode::markDisconnectedDrivers() {
  for (const auto& name : drivers_.disconnected()) driverLost(name, "its control publisher is gone");
}

void SimNode::driverLost(const std::string& name, const std::string& why) {
  drivers_.lose(name);
  // Once per loss, naming the car: a dead driver must not stall the race, nor pass unnoticed.
  ROS_WARN(
      "roar_sim: %s's driver is lost (%s) at t = %.2f s: lockstep goes on without waiting for it and the "
      "car is brought to a stop on the road",
      name.c_str(), why.c_str(), world().time());
  std_msgs::String msg;
  msg.data = name;
  driver_lost_pub_.publish(msg);
}

void SimNode::publishStaticTransforms() {
  std::vector<geometry_msgs::TransformStamped> all;
  for (const VehicleSensors* rig : allSensors()) {
    const auto t = rig->staticTransforms();
    all.insert(all.end(), t.begin(), t.end());
  }
  if (!all.empty()) static_tf_.sendTransform(all);
}

void SimNode::tick() {
  // Sensor readings of a tick go out before its odometry and clock: a lockstep driver that has the
  // odometry of tick t has been sent every reading up to t.
  world().step([this](double t) {
    for (auto& [name, io] : io_) {
      if (!io.sensors->empty())
        io.sensors->rig().sampleMotion(t, sensors::motionOf(world().vehicleState(name)), *io.sensors);
    }
  });
  sampleRaySensors(updateRayScene());
  if (debug_.expire(world().time())) publishDebugMarkers();
  publishState();
}

std::map<std::string, Eigen::Isometry3d> SimNode::updateRayScene() {
  std::map<std::string, Eigen::Isometry3d> poses;
  bool any = !world_sensors_->empty();
  for (auto& [name, io] : io_) any = any || !io.sensors->empty() || (io.agent && io.agent->needsScene());
  if (!any) return poses;
  // Posing the scene (Embree's refit) is most of a tick's cost with sensors that cast no ray this tick:
  // an unread on-demand camera, sensors between their samples (bench/roar_py_bench.py).
  const double now = world().time();
  bool rays = !world_sensors_->empty() && world_sensors_->rig().castsRaysAt(now, *world_sensors_);
  for (auto& [name, io] : io_) {
    rays = rays || (io.agent && io.agent->needsScene()) ||
           (!io.sensors->empty() && io.sensors->rig().castsRaysAt(now, *io.sensors));
  }
  for (const auto& [name, car] : session_->keepTick(rays).cars) poses[name] = car.pose;
  return poses;
}

void SimNode::sampleRaySensors(const std::map<std::string, Eigen::Isometry3d>& poses) {
  for (auto& [name, io] : io_) {
    if (!io.sensors->empty())
      io.sensors->rig().sampleRays(world().time(), session_->scene(), poses.at(name), session_->sceneId(name),
                                   *io.sensors);
  }
  // The world's sensors are mounted in the map frame and see every car.
  if (!world_sensors_->empty())
    world_sensors_->rig().sampleRays(world().time(), session_->scene(), Eigen::Isometry3d::Identity(), -1,
                                     *world_sensors_);
}

void SimNode::publishIdleClock() {
  const ros::WallTime now = ros::WallTime::now();
  if ((now - idle_clock_wall_).toSec() < 0.1) return;
  idle_clock_wall_ = now;
  rosgraph_msgs::Clock clock;
  clock.clock = toRosTime(world().time());
  clock_pub_.publish(clock);
}

void SimNode::publishState() {
  const ros::Time stamp = toRosTime(world().time());
  rosgraph_msgs::Clock clock;
  clock.clock = stamp;
  clock_pub_.publish(clock);
  std::vector<geometry_msgs::TransformStamped> transforms;
  for (auto& [name, io] : io_) {
    const vehicle::VehicleState state = world().vehicleState(name);
    const std::string base = baseFrame(name);
    io.odom.publish(toOdometry(state, stamp, options_.map_frame, base));
    io.status.publish(toStatus(state, stamp, base));
    for (std::size_t w = 0; w < 4; ++w) {
      io.wheel_angles[w] =
          std::remainder(io.wheel_angles[w] + state.wheels[w].angular_velocity * options_.world.control_dt, 2.0 * M_PI);
    }
    io.joints.publish(toJointState(state, world().vehicleParams(name), io.wheel_angles, stamp));
    transforms.push_back(toTransform(state.pose, stamp, options_.map_frame, base));
    for (const auto& contact : world().contacts(name))
      io.collision.publish(toCollisionEvent(contact, stamp, options_.map_frame));
    if (io.agent) {
      io.agent->afterTick(state, world().contacts(name), world().time(), &session_->scene(), session_->sceneId(name));
    }
  }
  if (!transforms.empty()) tf_.sendTransform(transforms);
}

roar_ros::VehicleSnapshot SimNode::snapshot(const std::string& name) const {
  roar_ros::VehicleSnapshot out;
  out.name = name;
  const bool of_the_world = isWorld(name);  // its sensors' stamps alone
  if (!of_the_world) {
    const ros::Time stamp = toRosTime(world().time());
    const vehicle::VehicleState state = world().vehicleState(name);
    out.odometry = toOdometry(state, stamp, options_.map_frame, baseFrame(name));
    out.status = toStatus(state, stamp, baseFrame(name));
  }
  const VehicleSensors& rig = of_the_world ? *world_sensors_ : *io_.at(name).sensors;
  for (const auto& [sensor, at] : rig.lastStamps()) {
    out.sensor_names.push_back(sensor);
    out.sensor_stamps.push_back(toRosTime(at));
  }
  return out;
}

bool SimNode::everyDriverLost() const { return drivers_.everyDriverLost(); }

bool SimNode::controlsArrived() const {
  // Only drivers that are connected are waited for (a car nobody drives stays parked), and not one taken
  // as lost (a killed driver's publisher can stay registered for a long time).
  return drivers_.answered(toRosTime(world().time()).toSec());
}

namespace {

// The ROS graph as the master knows it: the nodes publishing and subscribing each topic.
struct GraphState {
  std::map<std::string, std::set<std::string>> publishers, subscribers;
};

bool queryGraph(GraphState* graph) {
  XmlRpc::XmlRpcValue request, response, payload;
  request[0] = ros::this_node::getName();
  if (!ros::master::execute("getSystemState", request, response, payload, false)) return false;
  // payload[0]: the publications, payload[1]: the subscriptions, [topic, [node, ...]] each.
  for (int kind = 0; kind < 2; ++kind) {
    auto& table = kind == 0 ? graph->publishers : graph->subscribers;
    for (int i = 0; i < payload[kind].size(); ++i) {
      auto& nodes = table[static_cast<std::string>(payload[kind][i][0])];
      for (int k = 0; k < payload[kind][i][1].size(); ++k)
        nodes.insert(static_cast<std::string>(payload[kind][i][1][k]));
    }
  }
  return true;
}

}  // namespace

std::string SimNode::notReadyToStart() const {
  if (options_.wait_for_recorders.empty() && options_.wait_for_listeners.empty() && !options_.wait_for_drivers)
    return "";
  GraphState graph;
  if (!queryGraph(&graph)) return "the ROS master";
  auto& subscribers = graph.subscribers;
  std::vector<std::string> topics = {ros::names::resolve("/clock")};
  for (const auto& [name, io] : io_) {
    for (const char* topic : {"odom", "vehicle_status", "control"})
      topics.push_back(nh_.resolveName(name + "/" + topic));
  }
  for (const auto& recorder : options_.wait_for_recorders) {
    const std::string node = ros::names::resolve(recorder);
    for (const auto& topic : topics) {
      if (!subscribers[topic].count(node)) return "the recorder " + node + " on " + topic;
    }
    // A recorder that reports its progress: its reports must reach us before the first tick.
    const std::string progress = node + "/recorded";
    const auto sub = recorded_subs_.find(node);
    if (sub != recorded_subs_.end() && graph.publishers[progress].count(node) && sub->second.getNumPublishers() == 0) {
      return "the link to " + progress;
    }
  }
  std::vector<std::string> heard = {ros::names::resolve("/clock")};  // what a listener must listen to
  for (const auto& [name, io] : io_) heard.push_back(nh_.resolveName(name + "/odom"));
  for (const auto& listener : options_.wait_for_listeners) {
    const std::string node = ros::names::resolve(listener);
    for (const auto& topic : heard) {
      if (!subscribers[topic].count(node)) return "the listener " + node + " on " + topic;
    }
  }
  if (options_.wait_for_drivers) {
    for (const auto& car : options_.vehicles) {
      const auto io = io_.find(car.name);
      if (!car.driven || !car.agent.empty() || io == io_.end()) continue;
      const std::string control = nh_.resolveName(car.name + "/control");
      if (graph.publishers[control].empty()) return "a driver of '" + car.name + "' (a publisher on " + control + ")";
      if (io->second.control.getNumPublishers() < graph.publishers[control].size()) return "the driver on " + control;
      // A driver answers a tick it heard: it must listen to the car's odometry or status, or the clock.
      for (const auto& driver : graph.publishers[control]) {
        bool listens = false;
        for (const std::string& topic :
             {nh_.resolveName(car.name + "/odom"), nh_.resolveName(car.name + "/vehicle_status"),
              ros::names::resolve("/clock")}) {
          listens = listens || subscribers[topic].count(driver) > 0;
        }
        if (!listens) return "the driver " + driver + " of '" + car.name + "' to subscribe to its odom";
      }
    }
  }
  // Registered is not yet connected: every subscriber the master knows must be connected to us.
  if (clock_pub_.getNumSubscribers() < subscribers[ros::names::resolve("/clock")].size())
    return "the subscribers of /clock";
  for (const auto& [name, io] : io_) {
    const std::string odom = nh_.resolveName(name + "/odom"), status = nh_.resolveName(name + "/vehicle_status");
    if (io.odom.getNumSubscribers() < subscribers[odom].size()) return "the subscribers of " + odom;
    if (io.status.getNumSubscribers() < subscribers[status].size()) return "the subscribers of " + status;
  }
  return "";
}

void SimNode::subscribeRecorderProgress() {
  for (const auto& recorder : options_.wait_for_recorders) {
    const std::string node = ros::names::resolve(recorder);
    recorded_subs_[node] = nh_.subscribe<rosgraph_msgs::Clock>(
        node + "/recorded", 100,
        [this, node](const rosgraph_msgs::Clock::ConstPtr& m) {
          if (recorder_pacing_ && recorder_pacing_->recorded(node, m->clock.toSec(), ros::WallTime::now().toSec())) {
            ROS_INFO("roar_sim: the recorder %s is recording again at t = %.2f s", node.c_str(), m->clock.toSec());
          }
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  }
}

void SimNode::setUpRecorderPacing() {
  if (options_.wait_for_recorders.empty()) return;
  GraphState graph;
  queryGraph(&graph);
  std::vector<std::string> paced;
  for (const auto& recorder : options_.wait_for_recorders) {
    const std::string node = ros::names::resolve(recorder);
    const std::string topic = node + "/recorded";
    if (!graph.publishers[topic].count(node)) {
      ROS_WARN(
          "roar_sim: the recorder %s reports no progress (no %s): roar_sim cannot keep its pace, and on a busy "
          "machine its recording may miss ticks (race_recorder reports; rosbag record does not)",
          node.c_str(), topic.c_str());
      continue;
    }
    paced.push_back(node);
  }
  recorder_pacing_ =
      std::make_unique<lockstep::RecorderPacing>(paced, options_.world.control_dt, options_.lockstep_timeout);
}

bool SimNode::recordersKeptUp() {
  if (!recorder_pacing_) return true;
  const double wall = ros::WallTime::now().toSec();
  for (const auto& [node, sub] : recorded_subs_) {
    // A recorder whose node is gone (it had connected) is not waited for.
    if (sub.getNumPublishers() == 0 && !recorder_pacing_->givenUp(node) &&
        recorder_pacing_->lastRecorded(node) > -1.0) {
      recorder_pacing_->gone(node);
      ROS_WARN("roar_sim: the recorder %s has gone at t = %.2f s: the race goes on and its recording ends there",
               node.c_str(), world().time());
    }
  }
  std::vector<std::string> given_up;
  const bool kept_up =
      recorder_pacing_->waitingFor(world().time() + options_.world.control_dt, wall, &given_up).empty();
  for (const auto& node : given_up) {
    ROS_WARN(
        "roar_sim: the recorder %s has written nothing for %.0f s (its last tick t = %.2f s): going on without "
        "waiting for it; its recording misses ticks from here",
        node.c_str(), options_.lockstep_timeout, recorder_pacing_->lastRecorded(node));
  }
  return kept_up;
}

void SimNode::restartPacing() {
  pace_wall_start_ = ros::WallTime::now();
  pace_sim_start_ = session_ ? world().time() : 0.0;
}

void SimNode::paceToRealTime() {
  if (options_.real_time_factor <= 0) return;
  const double sim_elapsed = world().time() - pace_sim_start_;
  const ros::WallTime due = pace_wall_start_ + ros::WallDuration(sim_elapsed / options_.real_time_factor);
  while (ros::ok() && ros::WallTime::now() < due) spinFor(due - ros::WallTime::now());
}

void SimNode::run() {
  // Give subscribers a moment to connect before the first state goes out (a recorder needs longer).
  const ros::WallTime settle = ros::WallTime::now() + ros::WallDuration(options_.start_wait);
  while (ros::ok() && ros::WallTime::now() < settle) spinFor(ros::WallDuration(0.05));
  subscribeRecorderProgress();
  // A recorder and the drivers must hear the first tick: wait until they subscribe and connect.
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(60.0);
  for (std::string missing = notReadyToStart(); ros::ok() && !missing.empty(); missing = notReadyToStart()) {
    if (ros::WallTime::now() > give_up) {
      ROS_WARN("roar_sim: still no %s after 60 s; starting without", missing.c_str());
      break;
    }
    spinFor(ros::WallDuration(0.1));
  }
  // The recorder's links to the drivers' control topics are not ours to see: give them a moment.
  if (!options_.wait_for_recorders.empty()) {
    const ros::WallTime links = ros::WallTime::now() + ros::WallDuration(1.0);
    while (ros::ok() && ros::WallTime::now() < links) spinFor(ros::WallDuration(0.05));
  }
  setUpRecorderPacing();
  publishState();
  // Agents' first episodes begin where their cars were spawned; /roar_sim/reset_episode starts others.
  updateRayScene();
  for (auto& [name, io] : io_) {
    if (io.agent)
      io.agent->begin(world().vehicleState(name), world().time(), &session_->scene(), session_->sceneId(name));
  }

  restartPacing();
  ros::WallTime waiting_since = ros::WallTime::now();
  while (ros::ok()) {
    switch (options_.mode) {
      case SteppingMode::kStep:
        spinFor(ros::WallDuration(0.01));
        waiting_since = ros::WallTime::now();
        publishIdleClock();
        break;
      case SteppingMode::kLockstep: {
        spinFor(ros::WallDuration(0.001));
        if (options_.mode != SteppingMode::kLockstep) break;  // /roar_sim/set_stepping just now
        const bool timed_out = (ros::WallTime::now() - waiting_since).toSec() > options_.lockstep_timeout;
        if ((controlsArrived() || timed_out) && recordersKeptUp()) {
          if (timed_out) markLostDrivers();
          markDisconnectedDrivers();
          const ros::WallTime ticked = ros::WallTime::now();
          tick();
          waiting_since = ros::WallTime::now();
          paceToRealTime();
          // With no driver answering there is nobody to race: time runs no faster than real time, so that a
          // driver that paused (a stopped process, a loaded machine) finds its car where a real one would be,
          // within race_control's ~driver_grace (driver_pause rostest).
          if (everyDriverLost()) {
            const ros::WallTime due = ticked + ros::WallDuration(options_.world.control_dt);
            while (ros::ok() && ros::WallTime::now() < due) spinFor(due - ros::WallTime::now());
          }
        }
        break;
      }
      case SteppingMode::kAsync: {
        spinFor(ros::WallDuration(0));
        if (options_.mode != SteppingMode::kAsync) break;  // /roar_sim/set_stepping just now
        if (!recordersKeptUp()) {
          spinFor(ros::WallDuration(0.001));
          break;
        }
        tick();
        paceToRealTime();
        waiting_since = ros::WallTime::now();
        break;
      }
    }
  }
}

}  // namespace roar::ros_bridge
