#include "sim_parameters.h"

#include <set>

#include "roar/ros/param_reading.h"
#include "roar/ros/scenario_params.h"
#include "roar/sim/slipstream.h"
#include "roar/track/map_folder.h"

namespace roar::ros_bridge {

namespace {

// ~vehicles: a list of {name, model, spawn_point, sensors, agent}; all but name are optional.
std::vector<VehicleSpawn> readVehicles(const ros::NodeHandle& nh, const std::string& default_model,
                                       const std::string& default_sensor_set, const std::string& rl_dir) {
  XmlRpc::XmlRpcValue list;
  if (!nh.getParam("vehicles", list)) {
    VehicleSpawn ego;
    ego.name = "ego";
    ego.model = default_model;
    ego.sensor_set = default_sensor_set;
    return {ego};
  }
  const std::string where = nh.resolveName("vehicles");
  if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) {
    throw ParamError("parameter " + where + " must be a list of {name, model, spawn_point}");
  }
  std::vector<VehicleSpawn> out;
  std::set<std::string> names;
  std::set<int> points;
  for (int i = 0; i < list.size(); ++i) {
    const std::string item = where + "[" + std::to_string(i) + "]";
    XmlRpc::XmlRpcValue& v = list[i];
    if (v.getType() != XmlRpc::XmlRpcValue::TypeStruct || !v.hasMember("name") ||
        v["name"].getType() != XmlRpc::XmlRpcValue::TypeString) {
      throw ParamError("parameter " + item + " must have a string 'name'");
    }
    VehicleSpawn spawn;
    spawn.name = static_cast<std::string>(v["name"]);
    spawn.model = default_model;
    spawn.spawn_point = i;
    spawn.sensor_set = default_sensor_set;
    if (v.hasMember("sensors")) {
      if (v["sensors"].getType() != XmlRpc::XmlRpcValue::TypeString)
        throw ParamError("parameter " + item + ".sensors must be a string");
      spawn.sensor_set = static_cast<std::string>(v["sensors"]);
    }
    if (v.hasMember("agent")) {
      if (v["agent"].getType() != XmlRpc::XmlRpcValue::TypeString)
        throw ParamError("parameter " + item + ".agent must be a string");
      try {
        spawn.agent = stack::resolveAgentEnv(static_cast<std::string>(v["agent"]), rl_dir);
      } catch (const std::exception& e) {
        throw ParamError("parameter " + item + ".agent: " + e.what());
      }
    }
    if (v.hasMember("model")) {
      if (v["model"].getType() != XmlRpc::XmlRpcValue::TypeString)
        throw ParamError("parameter " + item + ".model must be a string");
      spawn.model = static_cast<std::string>(v["model"]);
    }
    if (v.hasMember("spawn_point")) {
      if (v["spawn_point"].getType() != XmlRpc::XmlRpcValue::TypeInt || static_cast<int>(v["spawn_point"]) < 0) {
        throw ParamError("parameter " + item + ".spawn_point must be a non-negative integer");
      }
      spawn.spawn_point = static_cast<int>(v["spawn_point"]);
    }
    if (!names.insert(spawn.name).second)
      throw ParamError("parameter " + item + ": vehicle name '" + spawn.name + "' is used twice");
    if (!points.insert(spawn.spawn_point).second) {
      throw ParamError("parameter " + item + ": spawn point " + std::to_string(spawn.spawn_point) +
                       " is taken by another vehicle");
    }
    out.push_back(spawn);
  }
  return out;
}

}  // namespace

SimNodeOptions readSimParameters(const ros::NodeHandle& nh) {
  SimNodeOptions o;
  const std::string pkg = packagePath();
  const auto scenario = readScenario(nh);
  o.map_folder = readMapFolder(nh, scenario);
  o.maps_dir = readString(nh, "maps_dir", pkg + "/maps");
  o.urdf_dir = readString(nh, "urdf_dir", pkg + "/urdf");
  o.vehicle_config_dir = readString(nh, "vehicle_config_dir", pkg + "/config/vehicles");
  o.default_model = readString(nh, "default_model", o.default_model);
  o.sensors_dir = readString(nh, "sensors_dir", pkg + "/config/sensors");
  o.default_sensor_set = readString(nh, "sensor_set", "");
  o.rl_dir = readString(nh, "rl_dir", pkg + "/config/rl");
  o.map_frame = readString(nh, "map_frame", o.map_frame);
  o.world.control_dt = readDouble(nh, "control_dt", o.world.control_dt, 1e-4, 1.0);
  o.world.physics_dt = readDouble(nh, "physics_dt", o.world.physics_dt, 1e-4, 0.05);
  o.world.control_timeout = readDouble(nh, "control_timeout", o.world.control_timeout, 0.0, 1e6);
  // The wake model (sim/slipstream.h): ~slipstream false for free air behind every car.
  auto& wake = o.world.slipstream;
  wake.enabled = readBool(nh, "slipstream", wake.enabled);
  wake.max_reduction = readDouble(nh, "slipstream_max_reduction", wake.max_reduction, sim::kMaxReductionRange.low,
                                  sim::kMaxReductionRange.high);
  wake.decay_length = readDouble(nh, "slipstream_decay_length", wake.decay_length, sim::kDecayLengthRange.low,
                                 sim::kDecayLengthRange.high);
  const std::string mode = readChoice(nh, "mode", "async", {"async", "step", "lockstep"});
  o.mode = mode == "step" ? SteppingMode::kStep : mode == "lockstep" ? SteppingMode::kLockstep : SteppingMode::kAsync;
  o.real_time_factor = readDouble(nh, "real_time_factor", o.real_time_factor, 0.0, 1e6);
  o.lockstep_timeout = readDouble(nh, "lockstep_timeout", o.lockstep_timeout, 0.01, 3600.0);
  o.start_wait = readDouble(nh, "start_wait", o.start_wait, 0.0, 600.0);
  o.wait_for_recorders = readStringList(nh, "wait_for_recorders", {});
  o.wait_for_drivers = readBool(nh, "wait_for_drivers", o.wait_for_drivers);
  if (scenario) {
    // The scenario's cars (checked when it was read) instead of ~vehicles.
    for (const auto& car : scenario->cars) {
      VehicleSpawn spawn;
      spawn.name = car.name;
      spawn.model = car.model;
      spawn.spawn_point = car.spawn_point;
      spawn.sensor_set = car.sensors.empty() ? o.default_sensor_set : car.sensors;
      spawn.colour = car.colour;
      spawn.driven = car.driven;
      if (!car.agent.empty()) spawn.agent = stack::resolveAgentEnv(car.agent, o.rl_dir);
      o.vehicles.push_back(spawn);
    }
  } else {
    o.vehicles = readVehicles(nh, o.default_model, o.default_sensor_set, o.rl_dir);
  }
  return o;
}

}  // namespace roar::ros_bridge
