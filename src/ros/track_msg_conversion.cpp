#include "roar/ros/track_msg_conversion.h"

#include <cmath>

#include "roar/ros/msg_conversion.h"
#include "roar/track/bridges.h"
#include "roar/track/heading.h"
#include "roar/track/road_mesh.h"

namespace roar::ros_bridge {

namespace {

geometry_msgs::Point point(double x, double y, double z) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

visualization_msgs::Marker marker(const std::string& frame, const std::string& ns, int type, double width, float r,
                                  float g, float b) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.ns = ns;
  m.id = 0;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = width;
  if (type == visualization_msgs::Marker::TRIANGLE_LIST) m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color.r = r;
  m.color.g = g;
  m.color.b = b;
  m.color.a = 1.0f;
  return m;
}

}  // namespace

roar_ros::Waypoint toMessage(const track::Waypoint& w, double s) {
  roar_ros::Waypoint msg;
  msg.location = point(w.location.x(), w.location.y(), w.location.z());
  msg.roll = w.roll_pitch_yaw.x();
  msg.pitch = w.roll_pitch_yaw.y();
  msg.yaw = w.roll_pitch_yaw.z();
  msg.lane_width = w.lane_width;
  msg.s = s;
  return msg;
}

std::vector<roar_ros::Waypoint> waypointMessages(const track::Track& track, const std::vector<std::size_t>& indices) {
  const auto waypoints = track::waypointsOf(track);
  std::vector<roar_ros::Waypoint> out;
  if (indices.empty()) {
    for (std::size_t i = 0; i < waypoints.size(); ++i) out.push_back(toMessage(waypoints[i], track.s(i)));
  } else {
    for (std::size_t i : indices) out.push_back(toMessage(waypoints[i], track.s(i)));
  }
  return out;
}

roar_ros::WaypointArray toWaypointArray(const track::Track& track, const std::string& frame) {
  roar_ros::WaypointArray msg;
  msg.header.frame_id = frame;
  msg.map_name = track.info().name;
  msg.track_length = track.length();
  msg.closed = track.closed();
  msg.start_s = track.info().start_finish_s;
  msg.finish_s = track.finishLine();
  msg.friction = track.info().friction;
  msg.waypoints = waypointMessages(track);
  return msg;
}

nav_msgs::Path toPath(const track::Track& track, const std::string& frame) {
  nav_msgs::Path path;
  path.header.frame_id = frame;
  for (std::size_t i = 0; i < track.size() + (track.closed() ? 1 : 0); ++i) {  // a circuit: back to the first point
    const std::size_t k = i % track.size();
    geometry_msgs::PoseStamped pose;
    pose.header.frame_id = frame;
    track::Pose p;
    p.position = Eigen::Vector3d(track.position(k).x(), track.position(k).y(), 0.0);
    p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(track.heading(k), Eigen::Vector3d::UnitZ()));
    pose.pose = toMessage(p);
    path.poses.push_back(pose);
  }
  return path;
}

visualization_msgs::MarkerArray trackMarkers(const track::Track& track, const std::string& frame) {
  using visualization_msgs::Marker;
  visualization_msgs::MarkerArray out;
  Marker road = marker(frame, "road", Marker::TRIANGLE_LIST, 1.0, 0.3f, 0.3f, 0.3f);
  const auto mesh = track::roadSurfaceMesh(track, -0.01);
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k)
      road.points.push_back(point(mesh.vertices[t[k]].x(), mesh.vertices[t[k]].y(), mesh.vertices[t[k]].z()));
  }
  out.markers.push_back(road);
  // The grass run-off from the road's edges to the barriers, a centimetre below the road as the road is.
  Marker runoff = marker(frame, "runoff", Marker::TRIANGLE_LIST, 1.0, 0.2f, 0.45f, 0.15f);
  const auto grass = track::runoffMesh(track);
  for (const auto& t : grass.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& v = grass.vertices[t[k]];
      runoff.points.push_back(point(v.x(), v.y(), v.z() - 0.02));
    }
  }
  out.markers.push_back(runoff);
  // The cameras' red and white kerbs: stripes alternate every 2 m of the centre line.
  Marker kerbs = marker(frame, "kerbs", Marker::TRIANGLE_LIST, 1.0, 1, 1, 1);
  const track::KerbMesh kerb = track::kerbMesh(track);
  for (std::size_t t = 0; t < kerb.mesh.triangles.size(); ++t) {
    const bool red =
        static_cast<long>(std::floor(track.s(static_cast<std::size_t>(kerb.segment_of[t])) / 2.0)) % 2 == 0;
    std_msgs::ColorRGBA colour;
    colour.r = red ? 0.85f : 0.95f;
    colour.g = colour.b = red ? 0.1f : 0.95f;
    colour.a = 1.0f;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& v = kerb.mesh.vertices[kerb.mesh.triangles[t][k]];
      kerbs.points.push_back(point(v.x(), v.y(), v.z()));
      kerbs.colors.push_back(colour);
    }
  }
  if (!kerbs.points.empty()) out.markers.push_back(kerbs);
  // The lines lie on the road (its height, banking and bridges), 2 cm up; on a bridge's deck the barriers
  // are its parapets at the road's edge.
  const std::vector<bool> deck = track::bridgeDeckPoints(track);
  auto strip = [&](const std::string& ns, double width, float r, float g, float b, auto&& at) {
    Marker m = marker(frame, ns, Marker::LINE_STRIP, width, r, g, b);
    for (std::size_t i = 0; i < track.size() + (track.closed() ? 1 : 0); ++i) {
      const Eigen::Vector3d p = at(i % track.size());
      m.points.push_back(point(p.x(), p.y(), p.z() + 0.02));
    }
    out.markers.push_back(m);
  };
  auto onRoad = [&](std::size_t i, const Eigen::Vector2d& p, double lateral) {
    return Eigen::Vector3d(p.x(), p.y(), track.surfaceHeight(i, lateral));
  };
  auto barrier = [&](std::size_t i) { return deck[i] ? track::kParapetOffset : track.info().barrier_offset; };
  const auto& pts = track.points();
  strip("edges", 0.3, 1, 1, 1, [&](std::size_t i) { return onRoad(i, track.leftEdge(i), pts[i].width_left); });
  out.markers.back().id = 0;
  strip("edges", 0.3, 1, 1, 1, [&](std::size_t i) { return onRoad(i, track.rightEdge(i), -pts[i].width_right); });
  out.markers.back().id = 1;
  strip("centre_line", 0.1, 1, 0.85f, 0.2f, [&](std::size_t i) { return onRoad(i, track.position(i), 0.0); });
  strip("barriers", 0.5, 0.2f, 0.35f, 0.9f,
        [&](std::size_t i) { return onRoad(i, track.leftEdge(i, barrier(i)), pts[i].width_left); });
  out.markers.back().id = 0;
  strip("barriers", 0.5, 0.2f, 0.35f, 0.9f,
        [&](std::size_t i) { return onRoad(i, track.rightEdge(i, barrier(i)), -pts[i].width_right); });
  out.markers.back().id = 1;
  auto across = [&](const std::string& ns, double s, float r, float g, float b, int id) {
    Marker m = marker(frame, ns, Marker::LINE_LIST, 0.8, r, g, b);
    m.id = id;
    const track::TrackPose p = track.poseAt(s);
    const Eigen::Vector2d n = track::leftOf(p.heading);
    const Eigen::Vector2d a = p.position + n * p.width_left, c = p.position - n * p.width_right;
    m.points = {point(a.x(), a.y(), track.surfaceHeightAt(s, p.width_left) + 0.05),
                point(c.x(), c.y(), track.surfaceHeightAt(s, -p.width_right) + 0.05)};
    out.markers.push_back(m);
  };
  across("start_finish", track.info().start_finish_s, 1, 0.1f, 0.1f, 0);
  if (!track.closed()) across("start_finish", track.finishLine(), 1, 0.1f, 0.1f, 1);  // a course's finish line
  for (int k = 1; k < track.info().sectors; ++k) {
    across("sectors", track.info().start_finish_s + k * track.raceDistance() / track.info().sectors, 1, 0.8f, 0, k);
  }
  return out;
}

}  // namespace roar::ros_bridge
