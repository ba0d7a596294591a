#include "sim_parameters.h"

#include "roar/ros/param_reading.h"
#include "roar/ros/scenario_params.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/slipstream.h"

namespace roar::ros_bridge {

SimNodeOptions readSimParameters(const ros::NodeHandle& nh) {
  SimNodeOptions o;
  const config::PackageLayout pkg = packageLayout();
  const auto scenario = readScenario(nh);
  o.map_folder = readMapFolder(nh, scenario);
  o.maps_dir = readString(nh, "maps_dir", pkg.maps());
  o.urdf_dir = readString(nh, "urdf_dir", pkg.urdf());
  o.vehicle_config_dir = readString(nh, "vehicle_config_dir", pkg.vehicles());
  o.default_model = readString(nh, "default_model", o.default_model);
  o.sensors_dir = readString(nh, "sensors_dir", pkg.sensors());
  o.default_sensor_set = readString(nh, "sensor_set", "");
  o.rl_dir = readString(nh, "rl_dir", pkg.rl());
  o.map_frame = readMapFrame(nh);
  o.world.control_dt = readDouble(nh, "control_dt", o.world.control_dt, 1e-4, 1.0);
  o.world.physics_dt = readDouble(nh, "physics_dt", o.world.physics_dt, 1e-4, 0.05);
  o.world.control_timeout = readDouble(nh, "control_timeout", o.world.control_timeout, 0.0, 1e6);
  // The wake model (sim/slipstream.h): ~slipstream false for free air behind every car.
  auto& wake = o.world.slipstream;
  wake.enabled = readBool(nh, "slipstream", wake.enabled);
  wake.max_reduction = readDouble(nh, "slipstream_max_reduction", wake.max_reduction, vehicle::kMaxReductionRange.low,
                                  vehicle::kMaxReductionRange.high);
  wake.decay_length = readDouble(nh, "slipstream_decay_length", wake.decay_length, vehicle::kDecayLengthRange.low,
                                 vehicle::kDecayLengthRange.high);
  const std::string mode = readChoice(nh, "mode", "async", {"async", "step", "lockstep"});
  o.mode = mode == "step" ? SteppingMode::kStep : mode == "lockstep" ? SteppingMode::kLockstep : SteppingMode::kAsync;
  o.real_time_factor = readDouble(nh, "real_time_factor", o.real_time_factor, 0.0, 1e6);
  o.lockstep_timeout = readDouble(nh, "lockstep_timeout", o.lockstep_timeout, 0.01, 3600.0);
  o.start_wait = readDouble(nh, "start_wait", o.start_wait, 0.0, 600.0);
  o.wait_for_recorders = readStringList(nh, "wait_for_recorders", {});
  o.wait_for_listeners = readStringList(nh, "wait_for_listeners", {});
  o.wait_for_drivers = readBool(nh, "wait_for_drivers", o.wait_for_drivers);
  for (const auto& car : readRaceCars(nh, scenario, o.default_model)) {
    VehicleSpawn spawn;
    spawn.name = car.name;
    spawn.model = car.model;
    spawn.spawn_point = car.spawn_point;
    spawn.sensor_set = car.sensors.empty() ? o.default_sensor_set : car.sensors;
    spawn.colour = car.colour;
    spawn.driven = car.driven;
    if (!car.agent.empty()) spawn.agent = scenario::resolveAgentEnv(car.agent, o.rl_dir);
    o.vehicles.push_back(spawn);
  }
  return o;
}

}  // namespace roar::ros_bridge
