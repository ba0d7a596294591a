#pragma once
// Track and waypoints -> ROS messages: roar_ros waypoints, nav_msgs/Path, rviz markers.
#include <nav_msgs/Path.h>
#include <roar_ros/Waypoint.h>
#include <roar_ros/WaypointArray.h>
#include <visualization_msgs/MarkerArray.h>

#include "roar/track/track.h"
#include "roar/track/waypoints.h"

namespace roar::ros_bridge {

roar_ros::Waypoint toMessage(const track::Waypoint& w, double s);
// The track's waypoints at the given centre-line indices (all of them when `indices` is empty).
std::vector<roar_ros::Waypoint> waypointMessages(const track::Track& track,
                                                 const std::vector<std::size_t>& indices = {});
roar_ros::WaypointArray toWaypointArray(const track::Track& track, const std::string& frame);
nav_msgs::Path toPath(const track::Track& track, const std::string& frame);
// Road surface, edges, centre line, barriers, start/finish line and sector lines, each in its namespace.
visualization_msgs::MarkerArray trackMarkers(const track::Track& track, const std::string& frame);

}  // namespace roar::ros_bridge
