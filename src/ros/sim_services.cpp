// roar_sim's services: every request is checked before anything changes, and a refused one says why in
// its reply (success false, message) and leaves the simulation as it was.
#include <filesystem>

#include "roar/ros/msg_conversion.h"
#include "roar/ros/sensor_msg_conversion.h"
#include "roar/ros/service_refusal.h"
#include "roar/sensors/inertial.h"
#include "roar/sensors/sensor_spec.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"
#include "sim_node.h"

#ifndef ROAR_ROS_VERSION
#define ROAR_ROS_VERSION "unknown"
#endif

namespace roar::ros_bridge {

namespace {

// The most ticks one step request may ask for: an hour of racing at the default 20 Hz. A caller waits for
// the reply, but the other services are answered meanwhile and /roar_sim/cancel_step ends it.
constexpr std::uint32_t kMaxStepTicks = 72000;

Eigen::Vector3d vectorOf(const geometry_msgs::Vector3& v) { return {v.x, v.y, v.z}; }

// A spawn point is always set on the road; a pose as asked.
sim::Placement placementOf(int spawn_point, bool as_given) {
  return spawn_point < 0 && as_given ? sim::Placement::kAsGiven : sim::Placement::kOnGround;
}

}  // namespace

bool SimNode::onSpawn(roar_ros::SpawnVehicle::Request& req, roar_ros::SpawnVehicle::Response& res) {
  try {
    const auto& c = req.colour;
    for (const float channel : {c.r, c.g, c.b, c.a}) {
      if (!(channel >= 0.0f && channel <= 1.0f)) throw std::invalid_argument("colour channels must be in [0, 1]");
    }
    const Eigen::Vector3f colour = c.a > 0 ? Eigen::Vector3f(c.r, c.g, c.b) : Eigen::Vector3f(-1, -1, -1);
    // A caller names a set in ~sensors_dir; it never points roar_sim at a file.
    if (!req.sensor_set.empty()) sensors::sensorSetByName(req.sensor_set, options_.sensors_dir);
    addVehicle(req.name, req.model.empty() ? options_.default_model : req.model,
               requestedPose(req.spawn_point, req.pose), req.sensor_set, colour, "", req.spawn_point,
               placementOf(req.spawn_point, req.as_given));
    res.success = true;
    res.message = "spawned " + req.name;
  } catch (const std::exception& e) {
    return refuse(res, "spawn_vehicle", e.what());
  }
  return true;
}

bool SimNode::onDestroy(roar_ros::DestroyVehicle::Request& req, roar_ros::DestroyVehicle::Response& res) {
  try {
    removeVehicle(req.name);
    res.success = true;
    res.message = "destroyed " + req.name;
  } catch (const std::exception& e) {
    return refuse(res, "destroy_vehicle", e.what());
  }
  return true;
}

bool SimNode::onReset(roar_ros::ResetVehicle::Request& req, roar_ros::ResetVehicle::Response& res) {
  try {
    if (!session_->has(req.name)) throw sim::SpawnError("no vehicle named '" + req.name + "'");
    world().resetVehicle(req.name, requestedPose(req.spawn_point, req.pose),
                         placementOf(req.spawn_point, req.as_given));
    res.success = true;
    res.message = "reset " + req.name;
  } catch (const std::exception& e) {
    return refuse(res, "reset_vehicle", e.what());
  }
  return true;
}

bool SimNode::onSetVelocity(roar_ros::SetVehicleVelocity::Request& req, roar_ros::SetVehicleVelocity::Response& res) {
  try {
    if (!session_->has(req.name)) throw sim::SpawnError("no vehicle named '" + req.name + "'");
    world().setVehicleVelocity(req.name, vectorOf(req.linear), vectorOf(req.angular));
    res.success = true;
    res.message = "set the velocities of " + req.name;
  } catch (const std::exception& e) {
    return refuse(res, "set_vehicle_velocity", e.what());
  }
  return true;
}

bool SimNode::onStep(roar_ros::Step::Request& req, roar_ros::Step::Response& res) {
  res.tick = world().tick();
  res.stamp = toRosTime(world().time());
  if (req.ticks > 0 && options_.mode != SteppingMode::kStep) {
    return refuse(res, "step", "step is only served in mode 'step' (now " + modeName() + "; /roar_sim/set_stepping)");
  }
  if (req.ticks > kMaxStepTicks) {
    return refuse(res, "step", "ticks must be in [0, " + std::to_string(kMaxStepTicks) + "] (an hour at 20 Hz)");
  }
  if (req.vehicle_names.size() != req.controls.size()) {
    return refuse(res, "step", "vehicle_names and controls must have the same length");
  }
  std::vector<std::string> observed;
  bool observe_world = false;  // the world's own sensors' stamps: a snapshot named WORLD
  for (const auto* names : {&req.vehicle_names, &req.observe}) {
    for (const auto& name : *names) {
      if (names == &req.observe && isWorld(name)) {
        observe_world = true;
        continue;
      }
      if (!io_.count(name)) return refuse(res, "step", "no vehicle named '" + name + "'");
      if (std::find(observed.begin(), observed.end(), name) == observed.end()) observed.push_back(name);
    }
  }
  // Every control is checked before the first tick: a refused one moves nothing.
  std::string warnings;
  for (std::size_t i = 0; i < req.controls.size(); ++i) {
    const session::AppliedControl checked = session_->checkControl(req.vehicle_names[i], fromMessage(req.controls[i]));
    if (!checked.applied) {
      return refuse(res, "step", "control for '" + req.vehicle_names[i] + "' rejected: " + checked.problems);
    }
  }
  std::map<std::string, std::vector<roar_ros::CollisionEvent>> collisions;
  // Between ticks, every kServeEvery of wall time, the other services are answered (those that change the
  // world refused as busy) and /roar_sim/cancel_step can end the step early.
  constexpr double kServeEvery = 0.02;  // s of wall time
  long_step_ = LongStep{req.ticks, 0, false};
  // Whatever ends the step, an error in a tick too, the other services are served again after it.
  struct EndOfStep {
    std::optional<LongStep>& step;
    ~EndOfStep() { step.reset(); }
  } end_of_step{long_step_};
  ros::WallTime served = ros::WallTime::now();
  for (std::uint32_t k = 0; k < req.ticks && !long_step_->cancelled; ++k) {
    if ((ros::WallTime::now() - served).toSec() >= kServeEvery) {
      service_queue_.callAvailable(ros::WallDuration(0));
      served = ros::WallTime::now();
    }
    // The request's controls hold for each of its ticks (a long step is no dead driver).
    for (std::size_t i = 0; i < req.controls.size(); ++i) {
      std::string why;
      applyControl(req.vehicle_names[i], req.controls[i], &why);
      if (k == 0 && !why.empty()) warnings += why + "; ";
    }
    tick();
    for (const auto& name : observed) {
      for (const auto& contact : world().contacts(name)) {
        collisions[name].push_back(toCollisionEvent(contact, toRosTime(world().time()), options_.map_frame));
      }
    }
    long_step_->done = k + 1;
  }
  const LongStep step = *long_step_;
  res.success = true;
  res.message = warnings;
  if (step.cancelled) {
    res.message += "cancelled after " + std::to_string(step.done) + " of " + std::to_string(step.ticks) + " ticks";
  }
  res.tick = world().tick();
  res.stamp = toRosTime(world().time());
  for (const auto& name : observed) {
    res.vehicles.push_back(snapshot(name));
    res.vehicles.back().collisions = collisions[name];
  }
  if (observe_world) res.vehicles.push_back(snapshot(roar_ros::AttachSensor::Request::WORLD));
  return true;
}

bool SimNode::onCancelStep(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  if (!long_step_) return refuse(res, "cancel_step", "no step is running");
  long_step_->cancelled = true;
  res.success = true;
  res.message =
      "the step ends after tick " + std::to_string(long_step_->done + 1) + " of " + std::to_string(long_step_->ticks);
  return true;
}

bool SimNode::onResetEpisode(roar_ros::ResetEpisode::Request& req, roar_ros::ResetEpisode::Response& res) {
  auto it = io_.find(req.vehicle);
  if (it == io_.end() || !it->second.agent) {
    return refuse(res, "reset_episode",
                  "no agent's car named '" + req.vehicle + "' (a car whose scenario entry names an agent environment)");
  }
  AgentInterface& agent = *it->second.agent;
  try {
    world().resetVehicle(req.vehicle, agent.nextSpawn(req.seed));
  } catch (const std::exception& e) {
    return refuse(res, "reset_episode", e.what());
  }
  // The car settles, held by its brakes, before the episode's first observation.
  agent.pause();
  for (int i = 0; i < rl::settleTicks(agent.options()); ++i) {
    world().setControl(req.vehicle, vehicle::parkedControl());
    tick();
  }
  updateRayScene();
  res.observation = agent.begin(world().vehicleState(req.vehicle), world().time(), &session_->scene(),
                                session_->sceneId(req.vehicle));
  res.stamp = res.observation.header.stamp;
  res.success = true;
  res.message = "episode of '" + req.vehicle + "' begins at t = " + std::to_string(world().time()) + " s";
  return true;
}

bool SimNode::onAttachSensor(roar_ros::AttachSensor::Request& req, roar_ros::AttachSensor::Response& res) {
  try {
    VehicleSensors& rig = sensorsOf(req.vehicle);
    if (req.sensor_yaml.size() > 100000) throw std::invalid_argument("sensor_yaml is longer than 100000 characters");
    const auto specs =
        sensors::parseSensorSetYaml("sensors: [" + req.sensor_yaml + "]", "attach_sensor's sensor_yaml", rig.bounds());
    if (specs.size() != 1) throw std::invalid_argument("sensor_yaml must describe exactly one sensor");
    if (&rig == world_sensors_.get() && !sensors::seesFromAnywhere(specs.front().type)) {
      throw std::invalid_argument("sensor '" + specs.front().name + "': type " + sensors::typeName(specs.front().type) +
                                  " measures the car it rides on: a sensor on no car is a camera, lidar or radar");
    }
    sensors::checkBudget(sensorLoad(), specs.front(), sensors::kSimulatorSensorBudget);
    rig.attach(specs.front(), world().time());
    publishStaticTransforms();
    res.success = true;
    res.message = "attached " + specs.front().name + " to " + req.vehicle;
  } catch (const std::exception& e) {
    return refuse(res, "attach_sensor", e.what());
  }
  return true;
}

bool SimNode::onDetachSensor(roar_ros::DetachSensor::Request& req, roar_ros::DetachSensor::Response& res) {
  try {
    res.success = sensorsOf(req.vehicle).detach(req.sensor);
  } catch (const std::invalid_argument&) {
    res.success = false;
  }
  res.message = res.success ? "detached " + req.sensor
                            : "no sensor '" + req.sensor + "' on a vehicle named '" + req.vehicle + "'";
  return true;
}

bool SimNode::onLoadMap(roar_ros::LoadMap::Request& req, roar_ros::LoadMap::Response& res) {
  std::string folder;
  try {
    folder = req.map.empty() ? session_->mapFolder() : track::resolveMapFolder(req.map, options_.maps_dir);
  } catch (const std::exception& e) {
    return refuse(res, "load_map", e.what());
  }
  std::map<std::string, SpawnRecord> respawn;
  if (req.respawn_vehicles) respawn = session_->records();
  try {
    loadMap(folder, req.map.empty() ? "reload" : "load");
  } catch (const std::exception& e) {
    return refuse(res, "load_map", std::string(e.what()) + " (the map in use stays)");
  }
  std::string missing;
  for (const auto& [name, was] : respawn) {
    try {
      if (was.spawn_point < 0) throw std::invalid_argument("it was spawned at a pose of the old map");
      addVehicle(name, was.model, session_->spawnPose(was.spawn_point), was.sensor_set, was.colour, was.agent,
                 was.spawn_point);
    } catch (const std::exception& e) {
      missing += (missing.empty() ? "" : "; ") + name + ": " + e.what();
    }
  }
  res.success = true;
  res.name = session_->track().info().name;
  res.folder = session_->mapFolder();
  res.message = "loaded " + res.name + " (" + folder + ")" + (missing.empty() ? "" : "; not respawned: " + missing);
  ROS_INFO("roar_sim: %s", res.message.c_str());
  return true;
}

bool SimNode::onListMaps(roar_ros::ListMaps::Request&, roar_ros::ListMaps::Response& res) {
  res.maps = track::listMaps(options_.maps_dir);
  res.current = std::filesystem::path(session_->mapFolder()).filename().string();
  return true;
}

bool SimNode::onSetStepping(roar_ros::SetStepping::Request& req, roar_ros::SetStepping::Response& res) {
  auto answer = [&] {
    res.mode = modeName();
    res.control_dt = options_.world.control_dt;
    res.physics_dt = options_.world.physics_dt;
    res.real_time_factor = options_.real_time_factor;
  };
  answer();
  SteppingMode mode = options_.mode;
  if (req.mode == "async") {
    mode = SteppingMode::kAsync;
  } else if (req.mode == "step") {
    mode = SteppingMode::kStep;
  } else if (req.mode == "lockstep") {
    mode = SteppingMode::kLockstep;
  } else if (!req.mode.empty()) {
    return refuse(res, "set_stepping", "mode '" + req.mode + "' is not async, step or lockstep");
  }
  // 0 or negative keeps a value; NaN is no value at all.
  for (const auto& [field, value] : {std::pair<const char*, double>{"control_dt", req.control_dt},
                                     {"physics_dt", req.physics_dt},
                                     {"real_time_factor", req.real_time_factor}}) {
    if (std::isnan(value)) return refuse(res, "set_stepping", std::string(field) + " is NaN (0 or negative: keep)");
  }
  const double control_dt = req.control_dt > 0 ? req.control_dt : options_.world.control_dt;
  const double physics_dt = req.physics_dt > 0 ? req.physics_dt : options_.world.physics_dt;
  const double rtf = req.real_time_factor >= 0 ? req.real_time_factor : options_.real_time_factor;
  if (!(control_dt >= 1e-4 && control_dt <= 1.0))
    return refuse(res, "set_stepping", "control_dt must be in [0.0001, 1] s");
  if (!(physics_dt >= 1e-4 && physics_dt <= 0.05))
    return refuse(res, "set_stepping", "physics_dt must be in [0.0001, 0.05] s");
  // Slower than a thousandth of real time, a "running" simulation stands still.
  if (!(rtf <= 1e6) || (rtf > 0 && rtf < 1e-3)) {
    return refuse(res, "set_stepping", "real_time_factor must be 0 (as fast as possible) or in [0.001, 1e6]");
  }
  if (control_dt != options_.world.control_dt || physics_dt != options_.world.physics_dt) {
    // Every check before any change: the world's steps, every sensor's rate, every agent's environment.
    try {
      const auto check_rates = [&](const VehicleSensors& rig, const std::string& whose) {
        for (const auto& spec : rig.rig().specs()) {
          try {
            sensors::SensorRig::checkRate(spec, control_dt, physics_dt);
          } catch (const std::exception& e) {
            throw std::invalid_argument(whose + ": " + e.what());
          }
        }
      };
      for (const auto& [name, io] : io_) {
        if (io.agent) {
          throw std::invalid_argument("vehicle '" + name +
                                      "' is driven by an RL agent whose environment steps control_dt " +
                                      std::to_string(io.agent->options().world.control_dt) + " s");
        }
        check_rates(*io.sensors, "vehicle '" + name + "'");
      }
      check_rates(*world_sensors_, "the world's sensors");
      world().setTiming(control_dt, physics_dt);
    } catch (const std::exception& e) {
      return refuse(res, "set_stepping", e.what());
    }
    for (VehicleSensors* rig : allSensors()) rig->rig().setTiming(control_dt, physics_dt);
    options_.world.control_dt = control_dt;
    options_.world.physics_dt = physics_dt;
  }
  options_.mode = mode;
  options_.real_time_factor = rtf;
  restartPacing();
  answer();
  res.success = true;
  res.message = "mode " + res.mode + ", control_dt " + std::to_string(control_dt) + " s, physics_dt " +
                std::to_string(physics_dt) + " s, real_time_factor " + std::to_string(rtf);
  ROS_INFO("roar_sim: %s", res.message.c_str());
  return true;
}

bool SimNode::onGetWorldInfo(roar_ros::GetWorldInfo::Request&, roar_ros::GetWorldInfo::Response& res) {
  res.version = ROAR_ROS_VERSION;
  res.map = std::filesystem::path(session_->mapFolder()).filename().string();
  res.folder = session_->mapFolder();
  res.map_generation = session_->mapGeneration();
  res.mode = modeName();
  res.control_dt = options_.world.control_dt;
  res.physics_dt = options_.world.physics_dt;
  res.real_time_factor = options_.real_time_factor;
  res.tick = world().tick();
  res.stamp = toRosTime(world().time());
  for (const auto& [name, io] : io_) {
    res.vehicles.push_back(
        toVehicleInfo(name, world().vehicleParams(name), io.sensors->rig().specs(), session_->record(name).agent));
  }
  for (const auto& model : vehicle::listVehicleModels(options_.urdf_dir, options_.vehicle_config_dir))
    res.blueprints.push_back(toBlueprintInfo(model));
  res.maps = track::listMaps(options_.maps_dir);
  return true;
}

bool SimNode::onGetGeolocation(roar_ros::GetGeolocation::Request& req, roar_ros::GetGeolocation::Response& res) {
  if (req.points.size() > 1000000) return refuse(res, "get_geolocation", "at most 1000000 points a request");
  for (const auto& p : req.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || std::abs(p.x) > 1e7 ||
        std::abs(p.y) > 1e7 || std::abs(p.z) > 1e5) {
      return refuse(res, "get_geolocation", "points must be finite and within 10,000 km of the map origin");
    }
  }
  for (const auto& p : req.points) {
    const sensors::GnssFix fix = sensors::toGeodetic({p.x, p.y, p.z}, session_->track().info().origin);
    res.latitude.push_back(fix.latitude);
    res.longitude.push_back(fix.longitude);
    res.altitude.push_back(fix.altitude);
  }
  res.success = true;
  return true;
}

bool SimNode::onRenderSensor(roar_ros::RenderSensor::Request& req, roar_ros::RenderSensor::Response& res) {
  try {
    sensors::SensorRig& rig = sensorsOf(req.vehicle).rig();
    const bool world = isWorld(req.vehicle);
    sensors::SensorType type = sensors::SensorType::kCameraRgb;
    for (const auto& spec : rig.specs()) {
      if (spec.name == req.sensor) type = spec.type;
    }
    // Stamp 0 is the frame of now (asynchronous readers): the world as it is, whether or not a tick's
    // scene was kept since the camera came (test_roar_py_ros test_an_asynchronous_camera_sees_now).
    const SceneTick now = session_->sceneNow();
    const SceneTick* tick = &now;
    if (!req.stamp.isZero()) tick = &session_->keptTick(req.stamp.toSec(), world ? "" : req.vehicle);
    session_->poseScene(*tick);
    const Eigen::Isometry3d mount_frame = world ? Eigen::Isometry3d::Identity() : tick->cars.at(req.vehicle).pose;
    const sensors::CameraFrame& frame = rig.renderCamera(req.sensor, session_->scene(), mount_frame, nullptr);
    res.image = toImage(frame, type, toRosTime(tick->time), req.vehicle + "/" + req.sensor + "_optical");
    res.success = true;
    res.message = "rendered " + req.vehicle + "/" + req.sensor + " at t = " + std::to_string(tick->time);
  } catch (const std::exception& e) {
    return refuse(res, "render_sensor", e.what());
  }
  return true;
}

bool SimNode::onDrawDebug(roar_ros::DrawDebug::Request& req, roar_ros::DrawDebug::Response& res) {
  try {
    if (req.clear) {
      DebugDrawing fresh;  // a refused request clears nothing either
      fresh.add(req.shapes, world().time());
      debug_ = std::move(fresh);
    } else {
      debug_.add(req.shapes, world().time());
    }
  } catch (const std::exception& e) {
    res.drawn = static_cast<std::uint32_t>(debug_.size());
    return refuse(res, "draw_debug", e.what());
  }
  publishDebugMarkers();
  res.success = true;
  res.drawn = static_cast<std::uint32_t>(debug_.size());
  res.message = "drawing " + std::to_string(res.drawn) + " shape(s)";
  return true;
}

}  // namespace roar::ros_bridge
