#pragma once
// The unit vectors of a heading in the map frame (radians anticlockwise from x, east): the way it points
// and the way to its left. Every place that moves a point sideways off a line or splits a velocity into
// along and across takes them from here.
#include <Eigen/Core>
#include <cmath>

namespace roar::track {

inline Eigen::Vector2d forwardOf(double heading) { return {std::cos(heading), std::sin(heading)}; }

// A quarter turn anticlockwise of forwardOf: positive offsets from a line are to its left.
inline Eigen::Vector2d leftOf(double heading) { return {-std::sin(heading), std::cos(heading)}; }

}  // namespace roar::track
