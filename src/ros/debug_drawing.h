#pragma once
// Shapes a program draws for debugging (/roar_sim/draw_debug), shown in rviz as the latched
// /roar_sim/debug_markers: points, polylines, arrows, text and boxes in the map frame, each living a span
// of simulated time or until cleared (ROAR_PY users draw their waypoints as arrows).
#include <roar_ros/DebugShape.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

namespace roar::ros_bridge {

class DebugDrawing {
 public:
  static constexpr std::size_t kMaxShapes = 100000;
  static constexpr std::size_t kMaxPoints = 10000;  // per shape

  // Adds shapes drawn at simulated time `now`. Throws std::invalid_argument naming the shape (its index)
  // and the field, adding none of them, for a bad one.
  void add(const std::vector<roar_ros::DebugShape>& shapes, double now);
  void clear() { shapes_.clear(); }
  // Drops the shapes whose life ended by `now`; true when any went.
  bool expire(double now);
  std::size_t size() const { return shapes_.size(); }
  // A DELETEALL marker, then one marker per live shape.
  visualization_msgs::MarkerArray markers(const std::string& frame, const ros::Time& stamp) const;

 private:
  struct Live {
    roar_ros::DebugShape shape;
    double until;  // s of simulated time; +inf: until cleared
    int id;
  };
  std::vector<Live> shapes_;
  int next_id_ = 0;
};

}  // namespace roar::ros_bridge
