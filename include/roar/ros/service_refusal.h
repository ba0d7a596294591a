#pragma once
// A refused service request: success false and the reason in the reply, and in the log as
// "<node>: <service> refused: <why>", at most once a wall second for each kind of reply, so that a
// flood of bad requests does not flood the log (the reply always says why).
#include <ros/this_node.h>

#include <string>

#include "roar/ros/wall_throttle.h"

namespace roar::ros_bridge {

template <class Response>
bool refuse(Response& res, const std::string& service, const std::string& why) {
  res.success = false;
  res.message = why;
  const std::string& node = ros::this_node::getName();
  ROAR_WARN_WALL_THROTTLE(1.0, "%s: %s refused: %s", node.c_str() + (node.empty() ? 0 : 1), service.c_str(),
                          why.c_str());
  return true;
}

}  // namespace roar::ros_bridge
