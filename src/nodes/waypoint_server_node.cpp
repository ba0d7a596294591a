// waypoint_server: a map's waypoints, path, rviz markers and spawn points (latched), and queries about the
// track: waypoints ahead, spawn points, projection of a point, routes, the maps available.
#include <geometry_msgs/PoseArray.h>
#include <roar_ros/GetRoute.h>
#include <roar_ros/GetSpawnPoints.h>
#include <roar_ros/GetWaypoints.h>
#include <roar_ros/ListMaps.h>
#include <roar_ros/MapInfo.h>
#include <roar_ros/ProjectPoint.h>
#include <ros/ros.h>
#include <cstdio>

#include "roar/ros/frames.h"
#include "roar/ros/msg_conversion.h"
#include "roar/ros/param_reading.h"
#include "roar/ros/scenario_params.h"
#include "roar/ros/service_refusal.h"
#include "roar/ros/sim_map_follower.h"
#include "roar/ros/track_msg_conversion.h"
#include "roar/track/map_folder.h"
#include "roar/track/pose.h"

using namespace roar;

namespace {

class WaypointServer {
 public:
  WaypointServer(ros::NodeHandle nh, ros::NodeHandle pnh) {
    using namespace ros_bridge;
    const config::PackageLayout pkg = packageLayout();
    maps_dir_ = readString(pnh, "maps_dir", pkg.maps());
    const std::string folder = readMapFolder(pnh, readScenario(pnh));
    frame_ = readMapFrame(pnh);
    grid_ = readInt(pnh, "spawn_points", track::kGridSlots, 1, 1000);
    track_ = std::make_unique<track::Track>(track::loadMapFolder(folder));

    // Latched: late subscribers (rviz, a planner started later) get the track at once.
    waypoints_pub_ = nh.advertise<roar_ros::WaypointArray>("waypoints", 1, true);
    path_pub_ = nh.advertise<nav_msgs::Path>("waypoints/path", 1, true);
    markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("track/markers", 1, true);
    spawn_pub_ = nh.advertise<geometry_msgs::PoseArray>("spawn_points", 1, true);
    publishTrack();
    // The map roar_sim simulates: a map loaded (or reloaded) at run time is served from then on.
    if (readBool(pnh, "follow_sim_map", true)) {
      map_follower_ = std::make_unique<SimMapFollower>(
          nh, folder, "waypoint_server", [this](std::unique_ptr<track::Track> track, const roar_ros::MapInfo& info) {
            serve(std::move(track), info);
          });
    }

    services_.push_back(pnh.advertiseService("get_waypoints", &WaypointServer::getWaypoints, this));
    services_.push_back(pnh.advertiseService("get_spawn_points", &WaypointServer::getSpawnPoints, this));
    services_.push_back(pnh.advertiseService("project_point", &WaypointServer::projectPoint, this));
    services_.push_back(pnh.advertiseService("get_route", &WaypointServer::getRoute, this));
    services_.push_back(pnh.advertiseService("list_maps", &WaypointServer::listMaps, this));
    ROS_INFO("waypoint_server: '%s', %zu waypoints, %.0f m", track_->info().name.c_str(), track_->size(),
             track_->length());
  }

 private:
  void publishTrack() {
    using namespace ros_bridge;
    waypoints_pub_.publish(toWaypointArray(*track_, frame_));
    path_pub_.publish(toPath(*track_, frame_));
    markers_pub_.publish(trackMarkers(*track_, frame_));
    geometry_msgs::PoseArray spawns;
    spawns.header.frame_id = frame_;
    for (const auto& p : track_->gridSpawnPoints(grid_)) spawns.poses.push_back(ros_bridge::toMessage(p));
    spawn_pub_.publish(spawns);
  }

  void serve(std::unique_ptr<track::Track> track, const roar_ros::MapInfo& info) {
    track_ = std::move(track);
    publishTrack();
    ROS_INFO("waypoint_server: now serving '%s' (%s by roar_sim), %zu waypoints, %.0f m", track_->info().name.c_str(),
             info.reason.c_str(), track_->size(), track_->length());
  }

  bool getWaypoints(roar_ros::GetWaypoints::Request& req, roar_ros::GetWaypoints::Response& res) {
    // Any finite progress (it wraps round the lap); a length of 0 or less, or infinite, is the whole track.
    if (!std::isfinite(req.from_s)) return ros_bridge::refuse(res, "get_waypoints", "from_s must be finite");
    if (std::isnan(req.length))
      return ros_bridge::refuse(res, "get_waypoints", "length is NaN (0 or less: the whole track)");
    res.waypoints = req.length <= 0 || std::isinf(req.length)
                        ? ros_bridge::waypointMessages(*track_)
                        : ros_bridge::waypointMessages(*track_, track_->indicesAhead(req.from_s, req.length));
    res.success = true;
    return true;
  }

  bool getSpawnPoints(roar_ros::GetSpawnPoints::Request& req, roar_ros::GetSpawnPoints::Response& res) {
    if (req.count < 1 || req.count > 10000)
      return ros_bridge::refuse(res, "get_spawn_points", "count must be in [1, 10000]");
    if (req.kind != "grid" && req.kind != "even") {
      return ros_bridge::refuse(res, "get_spawn_points", "kind must be 'grid' or 'even', got '" + req.kind + "'");
    }
    const auto poses = req.kind == "grid" ? track_->gridSpawnPoints(req.count) : track_->evenSpawnPoints(req.count);
    for (const auto& p : poses) res.poses.push_back(ros_bridge::toMessage(p));
    res.success = true;
    return true;
  }

  bool projectPoint(roar_ros::ProjectPoint::Request& req, roar_ros::ProjectPoint::Response& res) {
    const Eigen::Vector2d point(req.point.x, req.point.y);
    if (!point.allFinite() || point.cwiseAbs().maxCoeff() > track::kMaxCoordinate) {
      return ros_bridge::refuse(res, "project_point", "point must be finite and within 1e6 m of the map's origin");
    }
    if (!std::isfinite(req.yaw)) return ros_bridge::refuse(res, "project_point", "yaw must be finite");
    const track::Projection pr = track_->project(Eigen::Vector2d(req.point.x, req.point.y));
    const std::size_t next = (pr.segment + 1) % track_->size();
    res.nearest_index =
        static_cast<unsigned>((Eigen::Vector2d(req.point.x, req.point.y) - track_->position(pr.segment)).norm() <=
                                      (Eigen::Vector2d(req.point.x, req.point.y) - track_->position(next)).norm()
                                  ? pr.segment
                                  : next);
    res.s = pr.s;
    res.lateral_offset = pr.lateral;
    res.heading_error = track::wrapAngle(req.yaw - pr.heading);
    res.width_left = pr.width_left;
    res.width_right = pr.width_right;
    res.on_track = pr.on_track();
    res.success = true;
    return true;
  }

  bool getRoute(roar_ros::GetRoute::Request& req, roar_ros::GetRoute::Response& res) {
    // From and to places on the track or its run-off: a route from anywhere else would be a guess.
    for (const auto& [what, pose] :
         {std::pair<const char*, const geometry_msgs::Pose*>{"start", &req.start}, {"goal", &req.goal}}) {
      const std::string problem =
          track::offTrackProblem(*track_, Eigen::Vector2d(pose->position.x, pose->position.y), what);
      if (!problem.empty()) return ros_bridge::refuse(res, "get_route", problem);
    }
    const double from = track_->project(Eigen::Vector2d(req.start.position.x, req.start.position.y)).s;
    const double to = track_->project(Eigen::Vector2d(req.goal.position.x, req.goal.position.y)).s;
    if (!track_->closed() && to < from) {
      char why[160];
      std::snprintf(why, sizeof why,
                    "the goal (%.1f m along the course) is behind the start (%.1f m): a point-to-point course is "
                    "driven one way",
                    to, from);
      return ros_bridge::refuse(res, "get_route", why);
    }
    res.distance = track_->forwardDistance(from, to);
    res.waypoints = ros_bridge::waypointMessages(*track_, track_->indicesAhead(from, res.distance));
    res.success = true;
    return true;
  }

  bool listMaps(roar_ros::ListMaps::Request&, roar_ros::ListMaps::Response& res) {
    res.maps = track::listMaps(maps_dir_);
    res.current = track_->info().name;
    return true;
  }

  std::string maps_dir_, frame_;
  int grid_ = track::kGridSlots;
  std::unique_ptr<ros_bridge::SimMapFollower> map_follower_;
  std::unique_ptr<track::Track> track_;
  ros::Publisher waypoints_pub_, path_pub_, markers_pub_, spawn_pub_;
  std::vector<ros::ServiceServer> services_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "waypoint_server");
  ros::NodeHandle nh, pnh("~");
  try {
    WaypointServer server(nh, pnh);
    ros_bridge::refuseUnknownParameters(pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("waypoint_server: %s", e.what());
    return 1;
  }
  return 0;
}
