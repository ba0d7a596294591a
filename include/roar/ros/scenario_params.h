#pragma once
// The scenario a node runs in (~scenario) and the map it implies, read the same way by every node.
#include <ros/node_handle.h>

#include <optional>
#include <string>

#include "roar/stack/scenario.h"

namespace roar::ros_bridge {

// ~scenario: a scenario file, or a name in <package>/config/scenarios; unset or empty: none. Throws
// ParamError naming the parameter and the file's problem.
std::optional<stack::Scenario> readScenario(const ros::NodeHandle& nh);

// The map's folder: ~map when set and not empty, else the scenario's map, else roar_ring (in ~maps_dir).
std::string readMapFolder(const ros::NodeHandle& nh, const std::optional<stack::Scenario>& scenario);

}  // namespace roar::ros_bridge
