#pragma once
// The fixed frame the world is published in: the default of the one parameter every node names it by,
// ~map_frame (roar_sim, planner, waypoint_server).
#include <ros/node_handle.h>

#include <string>

namespace roar::ros_bridge {

inline constexpr char kMapFrame[] = "map";

// ~map_frame, kMapFrame by default.
std::string readMapFrame(const ros::NodeHandle& nh);

// A car's body frame, which roar_sim publishes its pose and its sensors' mounts in.
inline std::string baseFrame(const std::string& car) { return car + "/base_link"; }

}  // namespace roar::ros_bridge
