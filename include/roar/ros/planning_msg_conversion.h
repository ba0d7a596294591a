#pragma once
// Racing trajectories <-> roar_ros/Trajectory and nav_msgs/Path; a WaypointArray -> the track it describes.
#include <nav_msgs/Path.h>
#include <roar_ros/Trajectory.h>
#include <roar_ros/WaypointArray.h>

#include "roar/planning/trajectory.h"
#include "roar/track/track.h"

namespace roar::ros_bridge {

roar_ros::Trajectory toMessage(const planning::Trajectory& trajectory, const std::string& frame,
                               const std::string& map_name);
// Copies every field; planning::validate tells whether the result is usable.
planning::Trajectory fromMessage(const roar_ros::Trajectory& msg);
nav_msgs::Path toPath(const planning::Trajectory& trajectory, const std::string& frame);

// Throws std::invalid_argument naming the problem: no waypoints, not a closed circuit, a bad friction,
// a non-finite location or width.
track::Track trackFromMessage(const roar_ros::WaypointArray& msg);

}  // namespace roar::ros_bridge
