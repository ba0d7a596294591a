#include "roar/ros/planning_msg_conversion.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "roar/ros/car_label.h"
#include "roar/track/waypoints.h"

namespace roar::ros_bridge {

roar_ros::Trajectory toMessage(const planning::Trajectory& t, const std::string& frame, const std::string& map_name) {
  roar_ros::Trajectory msg;
  msg.header.frame_id = frame;
  msg.map_name = map_name;
  msg.closed = t.closed;
  msg.length = t.length;
  msg.lap_time = t.lap_time;
  msg.points.resize(t.points.size());
  for (std::size_t i = 0; i < t.points.size(); ++i) {
    const auto& p = t.points[i];
    auto& m = msg.points[i];
    m.position.x = p.position.x();
    m.position.y = p.position.y();
    m.position.z = p.z;
    m.yaw = p.yaw;
    m.s = p.s;
    m.curvature = p.curvature;
    m.speed = p.speed;
    m.acceleration = p.acceleration;
    m.time = p.time;
    m.offset = p.offset;
  }
  return msg;
}

namespace {

std_msgs::ColorRGBA modeColour(planning::RaceMode mode) {
  std_msgs::ColorRGBA c;
  c.a = 1.0;
  switch (mode) {
    case planning::RaceMode::kPass:  // orange
      c.r = 1.0, c.g = 0.55, c.b = 0.0;
      break;
    case planning::RaceMode::kFollow:  // yellow
      c.r = 1.0, c.g = 0.9, c.b = 0.1;
      break;
    case planning::RaceMode::kDefend:  // red
      c.r = 1.0, c.g = 0.2, c.b = 0.2;
      break;
    case planning::RaceMode::kYield:  // blue
      c.r = 0.3, c.g = 0.6, c.b = 1.0;
      break;
    case planning::RaceMode::kHold:  // cyan
      c.r = 0.2, c.g = 0.9, c.b = 0.9;
      break;
    case planning::RaceMode::kRacingLine:  // white
      c.r = c.g = c.b = 1.0;
      break;
  }
  return c;
}

}  // namespace

visualization_msgs::MarkerArray manoeuvreMarkers(const std::string& car, const planning::RaceDecision& decision,
                                                 const std::vector<planning::PredictedPath>& predictions,
                                                 const std::string& frame, const ros::Time& stamp) {
  visualization_msgs::MarkerArray out;
  auto marker = [&](const std::string& ns, int id, int type) {
    visualization_msgs::Marker m;
    m.header.frame_id = frame;
    m.header.stamp = stamp;
    m.ns = car + "/" + ns;
    m.id = id;
    m.type = type;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.orientation.w = 1.0;
    return m;
  };
  visualization_msgs::Marker clear = marker("", 0, visualization_msgs::Marker::CUBE);
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);
  visualization_msgs::Marker text = carLabel(car, kManoeuvreLabelHeight, 0.7, stamp);
  text.ns = car + "/decision";
  text.color = modeColour(decision.mode);
  text.text = planning::describe(decision);
  out.markers.push_back(text);
  int id = 0;
  for (const auto& p : predictions) {
    visualization_msgs::Marker line = marker("predictions", id, visualization_msgs::Marker::LINE_STRIP);
    visualization_msgs::Marker dots = marker("prediction_steps", id, visualization_msgs::Marker::SPHERE_LIST);
    ++id;
    line.scale.x = 0.15;
    dots.scale.x = dots.scale.y = dots.scale.z = 0.5;
    line.color = dots.color = modeColour(decision.mode);
    line.color.a = 0.5;
    dots.color.a = 0.8;
    for (const auto& xy : p.positions) {
      geometry_msgs::Point point;
      point.x = xy.x();
      point.y = xy.y();
      point.z = 0.5;
      line.points.push_back(point);
      dots.points.push_back(point);
    }
    out.markers.push_back(line);
    out.markers.push_back(dots);
  }
  return out;
}

planning::Trajectory fromMessage(const roar_ros::Trajectory& msg) {
  planning::Trajectory t;
  t.closed = msg.closed;
  t.length = msg.length;
  t.lap_time = msg.lap_time;
  t.points.resize(msg.points.size());
  for (std::size_t i = 0; i < msg.points.size(); ++i) {
    const auto& m = msg.points[i];
    auto& p = t.points[i];
    p.position = Eigen::Vector2d(m.position.x, m.position.y);
    p.z = m.position.z;
    p.yaw = m.yaw;
    p.s = m.s;
    p.curvature = m.curvature;
    p.speed = m.speed;
    p.acceleration = m.acceleration;
    p.time = m.time;
    p.offset = m.offset;
  }
  return t;
}

nav_msgs::Path toPath(const planning::Trajectory& t, const std::string& frame) {
  nav_msgs::Path path;
  path.header.frame_id = frame;
  const std::size_t count = t.points.size() + (t.closed ? 1 : 0);
  for (std::size_t i = 0; i < count; ++i) {
    const auto& p = t.points[i % t.points.size()];
    geometry_msgs::PoseStamped pose;
    pose.header.frame_id = frame;
    pose.pose.position.x = p.position.x();
    pose.pose.position.y = p.position.y();
    pose.pose.position.z = p.z;
    pose.pose.orientation.z = std::sin(0.5 * p.yaw);
    pose.pose.orientation.w = std::cos(0.5 * p.yaw);
    path.poses.push_back(pose);
  }
  return path;
}

track::Track trackFromMessage(const roar_ros::WaypointArray& msg) {
  if (msg.waypoints.empty()) throw std::invalid_argument("the waypoint list is empty");
  if (!(msg.friction > 0) || !std::isfinite(msg.friction)) {
    throw std::invalid_argument("friction " + std::to_string(msg.friction) + " is not a positive number");
  }
  std::vector<track::Waypoint> waypoints(msg.waypoints.size());
  for (std::size_t i = 0; i < msg.waypoints.size(); ++i) {
    const auto& m = msg.waypoints[i];
    for (double v : {m.location.x, m.location.y, m.location.z, m.roll, m.pitch, m.yaw, m.lane_width}) {
      if (!std::isfinite(v)) throw std::invalid_argument("waypoint " + std::to_string(i) + " has a non-finite value");
    }
    waypoints[i].location = Eigen::Vector3d(m.location.x, m.location.y, m.location.z);
    waypoints[i].roll_pitch_yaw = Eigen::Vector3d(m.roll, m.pitch, m.yaw);
    waypoints[i].lane_width = m.lane_width;
  }
  track::TrackInfo info;
  info.name = msg.map_name;
  info.friction = msg.friction;
  info.closed = msg.closed;
  info.start_finish_s = msg.start_s;
  info.finish_s = msg.finish_s;
  return track::trackFromWaypoints(waypoints, info);
}

}  // namespace roar::ros_bridge
