#include "debug_drawing.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace roar::ros_bridge {

namespace {

void check(const roar_ros::DebugShape& s, std::size_t index) {
  const std::string where = "shapes[" + std::to_string(index) + "]";
  auto fail = [&](const std::string& what) { throw std::invalid_argument(where + ": " + what); };
  std::size_t needed = 1;
  if (s.kind == "line" || s.kind == "arrow") {
    needed = 2;
  } else if (s.kind != "point" && s.kind != "text" && s.kind != "box") {
    fail("kind '" + s.kind + "' is not point, line, arrow, text or box");
  }
  if (s.points.size() < needed) fail("a " + s.kind + " needs at least " + std::to_string(needed) + " point(s)");
  if (s.points.size() > DebugDrawing::kMaxPoints)
    fail("more than " + std::to_string(DebugDrawing::kMaxPoints) + " points");
  for (const auto& p : s.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || std::abs(p.x) > 1e6 ||
        std::abs(p.y) > 1e6 || std::abs(p.z) > 1e6) {
      fail("points must be finite and within 1e6 m of the origin");
    }
  }
  for (const double c : {s.color.r, s.color.g, s.color.b, s.color.a}) {
    if (!(c >= 0 && c <= 1)) fail("color components must be in [0, 1]");
  }
  if (!(s.size >= 0 && s.size <= 100)) fail("size must be in [0, 100] m");
  if (!(s.arrow_size >= 0 && s.arrow_size <= 100)) fail("arrow_size must be in [0, 100] m");
  if (!std::isfinite(s.life_time)) fail("life_time must be finite (<= 0: until cleared)");
  if (s.text.size() > 1000) fail("text longer than 1000 characters");
}

}  // namespace

void DebugDrawing::add(const std::vector<roar_ros::DebugShape>& shapes, double now) {
  for (std::size_t i = 0; i < shapes.size(); ++i) check(shapes[i], i);
  if (shapes_.size() + shapes.size() > kMaxShapes) {
    throw std::invalid_argument("at most " + std::to_string(kMaxShapes) + " shapes at a time (clear first)");
  }
  for (const auto& s : shapes) {
    const double until = s.life_time > 0 ? now + s.life_time : std::numeric_limits<double>::infinity();
    shapes_.push_back({s, until, next_id_++});
  }
}

bool DebugDrawing::expire(double now) {
  const std::size_t before = shapes_.size();
  std::vector<Live> kept;
  for (auto& s : shapes_) {
    if (s.until > now) kept.push_back(std::move(s));
  }
  shapes_ = std::move(kept);
  return shapes_.size() != before;
}

visualization_msgs::MarkerArray DebugDrawing::markers(const std::string& frame, const ros::Time& stamp) const {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker wipe;
  wipe.header.frame_id = frame;
  wipe.header.stamp = stamp;
  wipe.ns = "debug";
  wipe.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(wipe);
  for (const auto& live : shapes_) {
    const roar_ros::DebugShape& s = live.shape;
    visualization_msgs::Marker m;
    m.header.frame_id = frame;
    m.header.stamp = stamp;
    m.ns = "debug";
    m.id = live.id;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.orientation.w = 1.0;
    m.color = s.color;
    if (m.color.a == 0) m.color.a = 1.0;
    const double size = s.size > 0 ? s.size : 0.1;
    if (s.kind == "point") {
      m.type = visualization_msgs::Marker::POINTS;
      m.points = s.points;
      m.scale.x = m.scale.y = size;
    } else if (s.kind == "line") {
      m.type = visualization_msgs::Marker::LINE_STRIP;
      m.points = s.points;
      m.scale.x = size;
    } else if (s.kind == "arrow") {
      m.type = visualization_msgs::Marker::ARROW;
      m.points = {s.points[0], s.points[1]};
      m.scale.x = size;                                          // shaft diameter
      m.scale.y = s.arrow_size > 0 ? s.arrow_size : 2.0 * size;  // head diameter
      m.scale.z = s.arrow_size > 0 ? s.arrow_size : 2.0 * size;  // head length
    } else if (s.kind == "text") {
      m.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
      m.pose.position = s.points[0];
      m.text = s.text;
      m.scale.z = size;
    } else {
      m.type = visualization_msgs::Marker::CUBE;
      m.pose.position = s.points[0];
      m.scale.x = m.scale.y = m.scale.z = size;
    }
    out.markers.push_back(m);
  }
  return out;
}

}  // namespace roar::ros_bridge
