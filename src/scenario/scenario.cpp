#include "roar/scenario/scenario.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>

#include "roar/config/text_file.h"
#include "roar/config/yaml_section.h"
#include "roar/rl/env_options.h"
#include "roar/sensors/sensor_spec.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"

namespace roar::scenario {

ScenarioContext contextOf(const config::PackageLayout& layout) {
  ScenarioContext context;
  context.maps_dir = layout.maps();
  context.sensors_dir = layout.sensors();
  context.urdf_dir = layout.urdf();
  context.vehicle_config_dir = layout.vehicles();
  context.rl_dir = layout.rl();
  return context;
}

namespace fs = std::filesystem;

namespace {
using track::kGridSlots;
}

std::string resolveScenario(const std::string& name_or_path, const std::string& scenarios_dir) {
  if (fs::is_regular_file(name_or_path)) return name_or_path;
  const std::string file = scenarios_dir + "/" + name_or_path + ".yaml";
  if (fs::is_regular_file(file)) return file;
  std::string known;
  if (fs::is_directory(scenarios_dir)) {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(scenarios_dir)) {
      if (entry.path().extension() == ".yaml") names.insert(entry.path().stem().string());
    }
    for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  }
  throw ScenarioError("no scenario '" + name_or_path + "' (a file, or one of: " + known + ")");
}

Scenario loadScenario(const std::string& path, const ScenarioContext& context) {
  YAML::Node root;
  try {
    root = YAML::Load(config::readTextFile<ScenarioError>(path, config::kMaxYamlBytes));
  } catch (const YAML::Exception& e) {
    throw ScenarioError(path + ": " + e.what());
  }
  auto fail = [&](const std::string& field, const std::string& what) {
    throw ScenarioError(path + ": " + field + ": " + what);
  };
  // Strict: a misspelt key (`color:`) is an error naming the nearest known one, not a silent default.
  using Section = config::YamlSection<ScenarioError>;
  Section top(root, "", path);
  Scenario s;
  s.name = fs::path(path).stem().string();
  top.read("name", &s.name);
  top.read("description", &s.description);
  s.map = top.require<std::string>("map");
  top.read("laps", &s.laps);
  const YAML::Node cars = top.raw("cars");
  top.finish();
  if (s.laps < 1) fail("laps", "must be at least 1");
  try {
    track::resolveMapFolder(s.map, context.maps_dir);
  } catch (const track::MapError& e) {
    fail("map", e.what());
  }
  if (!cars || !cars.IsSequence() || cars.size() == 0) fail("cars", "must be a list of at least one car");
  s.cars = readCars(cars, "cars", path, context);
  return s;
}

std::vector<ScenarioCar> readCars(const YAML::Node& list, const std::string& field, const std::string& source,
                                  const ScenarioContext& context, const std::string& default_model) {
  auto fail = [&](const std::string& where, const std::string& what) {
    throw ScenarioError(source + ": " + where + ": " + what);
  };
  if (list && !list.IsNull() && !list.IsSequence()) fail(field, "must be a list of cars");
  using Section = config::YamlSection<ScenarioError>;
  std::vector<ScenarioCar> out;
  std::set<std::string> names;
  std::set<int> slots;
  for (std::size_t i = 0; list && i < list.size(); ++i) {
    const std::string where = field + "[" + std::to_string(i) + "]";
    ScenarioCar car;
    car.model = default_model;
    car.spawn_point = static_cast<int>(i);
    if (list[i].IsScalar()) {
      car.name = list[i].as<std::string>();  // a car by its name alone
    } else {
      Section c(list[i], where, source);
      car.name = c.require<std::string>("name");
      c.read("spawn_point", &car.spawn_point);
      c.read("model", &car.model);
      c.read("sensors", &car.sensors);
      c.read("driven", &car.driven);
      c.read("max_speed", &car.max_speed);
      c.read("pace", &car.pace);
      c.read("agent", &car.agent);
      std::vector<double> rgb;
      if (c.read("colour", &rgb)) {
        if (rgb.size() != 3) fail(where + ".colour", "must be [r, g, b], each 0..1");
        car.colour =
            Eigen::Vector3f(static_cast<float>(rgb[0]), static_cast<float>(rgb[1]), static_cast<float>(rgb[2]));
        if ((car.colour.array() < 0).any() || (car.colour.array() > 1).any())
          fail(where + ".colour", "each of r, g, b must be 0..1");
      }
      c.finish();
    }
    if (car.name.empty() || car.name.find_first_of(" /") != std::string::npos) {
      fail(where + ".name", "'" + car.name + "' must be non-empty, without spaces or '/'");
    }
    if (!names.insert(car.name).second) fail(where + ".name", "'" + car.name + "' is used by another car");
    if (car.spawn_point < 0 || car.spawn_point >= kGridSlots) {
      fail(where + ".spawn_point",
           std::to_string(car.spawn_point) + " is not a grid slot (0.." + std::to_string(kGridSlots - 1) + ")");
    }
    if (!slots.insert(car.spawn_point).second) {
      fail(where + ".spawn_point", std::to_string(car.spawn_point) + " is taken by another car");
    }
    if (!(car.max_speed >= 0 && car.max_speed <= 150)) {
      fail(where + ".max_speed", std::to_string(car.max_speed) + " m/s is outside 0..150 (0: no cap)");
    }
    if (!(car.pace > 0.2 && car.pace <= 1)) {
      fail(where + ".pace", std::to_string(car.pace) + " is outside (0.2, 1] (the share of the planned speeds)");
    }
    try {
      vehicle::loadVehicleModel(car.model, context.urdf_dir, context.vehicle_config_dir);
    } catch (const std::exception& e) {
      fail(where + ".model", e.what());
    }
    if (!car.sensors.empty()) {
      try {
        sensors::readSensorSet(sensors::resolveSensorSet(car.sensors, context.sensors_dir));
      } catch (const std::exception& e) {
        fail(where + ".sensors", e.what());
      }
    }
    if (!car.agent.empty()) {
      if (car.driven) fail(where + ".agent", "an agent's car must have driven: false (the stack would drive it too)");
      try {
        rl::readEnvOptions(resolveAgentEnv(car.agent, context.rl_dir));
      } catch (const std::exception& e) {
        fail(where + ".agent", e.what());
      }
    }
    out.push_back(car);
  }
  return out;
}

std::string resolveAgentEnv(const std::string& name_or_path, const std::string& rl_dir) {
  if (fs::is_regular_file(name_or_path)) return name_or_path;
  const std::string file = rl_dir + "/" + name_or_path + ".yaml";
  if (!fs::is_regular_file(file))
    throw ScenarioError("no RL environment '" + name_or_path + "' (a file, or a name in " + rl_dir + ")");
  return file;
}

}  // namespace roar::scenario
