#pragma once
// Reading ROS parameters in one place per node, failing loudly with the parameter's full name.
#include <ros/node_handle.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "roar/config/package_layout.h"

namespace roar::ros_bridge {

class ParamError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The value, or `fallback` when unset; throws ParamError when set with the wrong type or outside [lo, hi].
double readDouble(const ros::NodeHandle& nh, const std::string& name, double fallback, double lo, double hi);
int readInt(const ros::NodeHandle& nh, const std::string& name, int fallback, int lo, int hi);
bool readBool(const ros::NodeHandle& nh, const std::string& name, bool fallback);
std::string readString(const ros::NodeHandle& nh, const std::string& name, const std::string& fallback);
// One of `choices`.
std::string readChoice(const ros::NodeHandle& nh, const std::string& name, const std::string& fallback,
                       const std::vector<std::string>& choices);
std::vector<std::string> readStringList(const ros::NodeHandle& nh, const std::string& name,
                                        const std::vector<std::string>& fallback);

// Every reader above records the name it was asked for. A parameter a node takes without a reader (a
// dynamic_reconfigure one, a structure read whole) is marked known here.
void markParameterKnown(const ros::NodeHandle& nh, const std::string& name);
// Throws ParamError naming every parameter under the node's private namespace that no reader asked for,
// with the nearest known name: a misspelt `_real_time_factr:=2` is an error, not a silent default
// (test_ros_habits test_a_misspelt_private_parameter_is_refused). Call after every parameter is read.
void refuseUnknownParameters(const ros::NodeHandle& private_nh);

// The package's own folders (the default paths of maps, URDFs, car models, sensor sets, scenarios, RL options).
config::PackageLayout packageLayout();

}  // namespace roar::ros_bridge
