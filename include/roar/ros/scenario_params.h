#pragma once
// The scenario a node runs in (~scenario) and the map it implies, read the same way by every node.
#include <ros/node_handle.h>

#include <optional>
#include <string>

#include "roar/scenario/scenario.h"

namespace roar::ros_bridge {

// ~scenario: a scenario file, or a name in <package>/config/scenarios; unset or empty: none. Throws
// ParamError naming the parameter and the file's problem.
std::optional<scenario::Scenario> readScenario(const ros::NodeHandle& nh);

// The cars of the race, read the same way by every node: the scenario's when there is one, else ~vehicles (a
// list of car names, or of cars with a scenario car's keys: name, model, spawn_point, sensors, driven,
// max_speed, pace, colour, agent; `default_model` for those that name none; a string is read as YAML, as
// rosrun's _vehicles:='[ego, rival]' gives it), else one car, ego. Checked
// as a scenario's cars are (scenario::readCars); throws ParamError naming the parameter, the car and the key.
std::vector<scenario::ScenarioCar> readRaceCars(const ros::NodeHandle& nh,
                                                const std::optional<scenario::Scenario>& scenario,
                                                const std::string& default_model);

// The map's folder: ~map when set and not empty, else the scenario's map, else roar_ring (in ~maps_dir).
std::string readMapFolder(const ros::NodeHandle& nh, const std::optional<scenario::Scenario>& scenario);

}  // namespace roar::ros_bridge
