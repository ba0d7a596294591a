#include "roar/ros/scenario_params.h"

#include "roar/ros/param_reading.h"
#include "roar/track/map_folder.h"

namespace roar::ros_bridge {

std::optional<stack::Scenario> readScenario(const ros::NodeHandle& nh) {
  const std::string pkg = packagePath();
  const std::string name = readString(nh, "scenario", "");
  if (name.empty()) return std::nullopt;
  stack::ScenarioContext context;
  context.maps_dir = readString(nh, "maps_dir", pkg + "/maps");
  context.sensors_dir = readString(nh, "sensors_dir", pkg + "/config/sensors");
  context.urdf_dir = readString(nh, "urdf_dir", pkg + "/urdf");
  context.vehicle_config_dir = readString(nh, "vehicle_config_dir", pkg + "/config/vehicles");
  context.rl_dir = readString(nh, "rl_dir", pkg + "/config/rl");
  try {
    return stack::loadScenario(stack::resolveScenario(name, readString(nh, "scenarios_dir", pkg + "/config/scenarios")),
                               context);
  } catch (const stack::ScenarioError& e) {
    throw ParamError("parameter " + nh.resolveName("scenario") + ": " + e.what());
  }
}

std::string readMapFolder(const ros::NodeHandle& nh, const std::optional<stack::Scenario>& scenario) {
  std::string map = readString(nh, "map", "");
  if (map.empty()) map = scenario ? scenario->map : "roar_ring";
  try {
    return track::resolveMapFolder(map, readString(nh, "maps_dir", packagePath() + "/maps"));
  } catch (const track::MapError& e) {
    throw ParamError("parameter " + nh.resolveName("map") + ": " + e.what());
  }
}

}  // namespace roar::ros_bridge
