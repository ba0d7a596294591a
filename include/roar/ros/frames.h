#pragma once
// The fixed frame the world is published in: the default of the one parameter every node names it by,
// ~map_frame (roar_sim, planner, waypoint_server), and the frame of race_control's markers.
#include <ros/node_handle.h>

#include <string>

namespace roar::ros_bridge {

inline constexpr char kMapFrame[] = "map";

// ~map_frame, kMapFrame by default.
std::string readMapFrame(const ros::NodeHandle& nh);

}  // namespace roar::ros_bridge
