#pragma once
// Racing trajectories <-> roar_ros/Trajectory and nav_msgs/Path; a WaypointArray -> the track it describes;
// a car's racing decision and its predictions of the cars around it -> rviz markers.
#include <nav_msgs/Path.h>
#include <roar_ros/Trajectory.h>
#include <roar_ros/WaypointArray.h>
#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include "roar/planning/overtaking/planner.h"
#include "roar/planning/trajectory.h"
#include "roar/track/track.h"

namespace roar::ros_bridge {

roar_ros::Trajectory toMessage(const planning::Trajectory& trajectory, const std::string& frame,
                               const std::string& map_name);
// Copies every field; planning::validate tells whether the result is usable.
planning::Trajectory fromMessage(const roar_ros::Trajectory& msg);
nav_msgs::Path toPath(const planning::Trajectory& trajectory, const std::string& frame);

// For rviz (/<car>/manoeuvre): the car's decision as text above it (a carLabel below the timing), coloured by
// its mode, and each predicted car as a line through its predicted positions (in `frame`) with a dot every
// PredictedPath::step seconds. Begins with a DELETEALL, so that the predictions of cars no longer near it go.
visualization_msgs::MarkerArray manoeuvreMarkers(const std::string& car, const planning::RaceDecision& decision,
                                                 const std::vector<planning::PredictedPath>& predictions,
                                                 const std::string& frame, const ros::Time& stamp);

// Throws std::invalid_argument naming the problem: no waypoints, not a closed circuit, a bad friction,
// a non-finite location or width.
track::Track trackFromMessage(const roar_ros::WaypointArray& msg);

}  // namespace roar::ros_bridge
