#pragma once
// Builds a smooth closed circuit from a few control points: a centripetal Catmull-Rom spline (no cusps or
// self-loops between close points), resampled at an even spacing, with widths interpolated along it.
#include <string>
#include <vector>

#include "roar/track/track.h"

namespace roar::track {

struct ControlPoint {
  double x = 0.0;
  double y = 0.0;
  double width = 12.0;  // full road width at this point, metres, split evenly left and right
};

// Control points from a CSV file of x_m,y_m,width_m lines (# comments); throws MapError naming file and line.
std::vector<ControlPoint> readControlPoints(const std::string& path);

// Throws std::invalid_argument for fewer than 3 control points or a non-positive spacing or width.
std::vector<CentreLinePoint> buildCircuit(const std::vector<ControlPoint>& controls, double spacing);

// Resamples a closed centre line at an even spacing (the last gap absorbs the remainder).
std::vector<CentreLinePoint> resampleClosed(const std::vector<CentreLinePoint>& points, double spacing);

}  // namespace roar::track
