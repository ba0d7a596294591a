#pragma once
// A race scenario (config/scenarios/<name>.yaml): the map, the laps and the cars (name, model, spawn
// point, colour, sensor set, whether the stack drives it, a speed cap). roar_sim, planner, controller and
// race_control all read the same file, so a launch has one list of cars.
#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

#include "roar/config/package_layout.h"

namespace YAML {
class Node;
}

namespace roar::scenario {

struct ScenarioCar {
  std::string name;
  std::string model = config::kDefaultModel;
  int spawn_point = 0;
  Eigen::Vector3f colour = Eigen::Vector3f(-1, -1, -1);  // linear RGB 0..1; negative: the simulator picks one
  std::string sensors;                                   // a sensor set of config/sensors (empty: none)
  bool driven = true;                                    // the stack's controller drives it (false: yours does)
  double max_speed = 0.0;                                // m/s the stack may drive it at; 0: no cap
  double pace = 1.0;  // share of the planned speeds the stack drives it at (a slower car in a field)
  std::string agent;  // an RL environment of config/rl (or a path): an agent drives it through roar_sim's
                      // RL interface (then driven must be false); empty: none
};

struct Scenario {
  std::string name;
  std::string description;
  std::string map;
  int laps = 2;
  std::vector<ScenarioCar> cars;
};

class ScenarioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Where the names a scenario uses are checked.
struct ScenarioContext {
  std::string maps_dir;
  std::string sensors_dir;
  std::string urdf_dir;
  std::string vehicle_config_dir;
  std::string rl_dir;  // RL environments (config/rl)
};
// The package's own folders.
ScenarioContext contextOf(const config::PackageLayout& layout);

// Reads and checks a scenario: every error names the file and the field (an unknown map, model, sensor
// set or RL environment, two cars with one name or one spawn point, a spawn point past the map's grid).
Scenario loadScenario(const std::string& path, const ScenarioContext& context);
// The cars of a race as a scenario's `cars` or a node's ~vehicles list them: each a name alone (then
// `default_model`, grid slot its place in the list) or a mapping with a scenario car's keys. Every list of
// cars is read and checked here, whatever its source: errors name `source`, `field`[i] and the key.
std::vector<ScenarioCar> readCars(const YAML::Node& list, const std::string& field, const std::string& source,
                                  const ScenarioContext& context,
                                  const std::string& default_model = config::kDefaultModel);
// `name_or_path`: a file, or the name of one in `scenarios_dir` (without .yaml).
std::string resolveScenario(const std::string& name_or_path, const std::string& scenarios_dir);
// An RL environment file: a path, or a name in `rl_dir` (without .yaml). Throws ScenarioError.
std::string resolveAgentEnv(const std::string& name_or_path, const std::string& rl_dir);

}  // namespace roar::scenario
