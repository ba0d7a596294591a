#include "roar/ros/scenario_params.h"

#include <yaml-cpp/yaml.h>

#include "roar/ros/param_reading.h"
#include "roar/track/map_folder.h"

namespace roar::ros_bridge {

namespace {

// Where the names a list of cars uses are looked up: the same parameters for every node.
scenario::ScenarioContext contextOf(const ros::NodeHandle& nh) {
  const config::PackageLayout pkg = packageLayout();
  scenario::ScenarioContext context;
  context.maps_dir = readString(nh, "maps_dir", pkg.maps());
  context.sensors_dir = readString(nh, "sensors_dir", pkg.sensors());
  context.urdf_dir = readString(nh, "urdf_dir", pkg.urdf());
  context.vehicle_config_dir = readString(nh, "vehicle_config_dir", pkg.vehicles());
  context.rl_dir = readString(nh, "rl_dir", pkg.rl());
  return context;
}

// A parameter's value as YAML (what the one reader of cars reads).
YAML::Node yamlOf(XmlRpc::XmlRpcValue& v) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeArray: {
      YAML::Node list(YAML::NodeType::Sequence);
      for (int i = 0; i < v.size(); ++i) list.push_back(yamlOf(v[i]));
      return list;
    }
    case XmlRpc::XmlRpcValue::TypeStruct: {
      YAML::Node map(YAML::NodeType::Map);
      for (auto& [key, value] : v) map[key] = yamlOf(value);
      return map;
    }
    case XmlRpc::XmlRpcValue::TypeString:
      return YAML::Node(static_cast<std::string>(v));
    case XmlRpc::XmlRpcValue::TypeInt:
      return YAML::Node(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble:
      return YAML::Node(static_cast<double>(v));
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return YAML::Node(static_cast<bool>(v));
    default:
      return YAML::Node();  // refused by the reader as no car
  }
}

}  // namespace

std::optional<scenario::Scenario> readScenario(const ros::NodeHandle& nh) {
  const config::PackageLayout pkg = packageLayout();
  const std::string name = readString(nh, "scenario", "");
  if (name.empty()) return std::nullopt;
  try {
    return scenario::loadScenario(scenario::resolveScenario(name, readString(nh, "scenarios_dir", pkg.scenarios())),
                                  contextOf(nh));
  } catch (const scenario::ScenarioError& e) {
    throw ParamError("parameter " + nh.resolveName("scenario") + ": " + e.what());
  }
}

std::vector<scenario::ScenarioCar> readRaceCars(const ros::NodeHandle& nh,
                                                const std::optional<scenario::Scenario>& scenario,
                                                const std::string& default_model) {
  // The launch files always pass ~vehicles; a scenario's cars take its place.
  markParameterKnown(nh, "vehicles");
  if (scenario) return scenario->cars;
  const std::string where = nh.resolveName("vehicles");
  XmlRpc::XmlRpcValue list;
  YAML::Node cars(YAML::NodeType::Sequence);
  if (nh.getParam("vehicles", list)) {
    // rosrun's _vehicles:='[ego, rival]' arrives as a string: its YAML.
    cars =
        list.getType() == XmlRpc::XmlRpcValue::TypeString ? YAML::Load(static_cast<std::string>(list)) : yamlOf(list);
  } else {
    cars.push_back("ego");
  }
  try {
    return scenario::readCars(cars, "vehicles", "parameter " + where, contextOf(nh), default_model);
  } catch (const scenario::ScenarioError& e) {
    throw ParamError(e.what());
  } catch (const YAML::Exception& e) {
    throw ParamError("parameter " + where + ": " + e.what());
  }
}

std::string readMapFolder(const ros::NodeHandle& nh, const std::optional<scenario::Scenario>& scenario) {
  std::string map = readString(nh, "map", "");
  if (map.empty()) map = scenario ? scenario->map : config::kDefaultMap;
  try {
    return track::resolveMapFolder(map, readString(nh, "maps_dir", packageLayout().maps()));
  } catch (const track::MapError& e) {
    throw ParamError("parameter " + nh.resolveName("map") + ": " + e.what());
  }
}

}  // namespace roar::ros_bridge
