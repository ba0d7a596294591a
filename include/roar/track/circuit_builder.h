#pragma once
// Builds a smooth closed circuit from a few control points: a centripetal Catmull-Rom spline (no cusps or
// self-loops between close points), resampled at an even spacing, with widths interpolated along it.
#include <algorithm>
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
// The same for a closed or an open line (a point-to-point course: both its ends kept).
std::vector<CentreLinePoint> resampleLine(const std::vector<CentreLinePoint>& points, double spacing, bool closed);

// The way from a centre line's last point back to its first, against its steps: a loop whose gap is many
// steps long is not closed (ROAR_PY's BerkMajor waypoints stop 50.7 m short of their start).
struct LoopGap {
  double gap = 0.0;          // m from the last point to the first
  double median_step = 0.0;  // m between consecutive points
  // m the first point lies ahead of the last along the last step's direction: negative when the course
  // runs on past its start (overlapping it, or not a loop at all), which no straight stretch can close.
  double ahead = 0.0;
  bool open() const { return gap > std::max(20.0, 10.0 * median_step); }
  bool bridgeable() const { return ahead > 0.5 * gap; }
};
LoopGap loopGap(const std::vector<CentreLinePoint>& points);
// The points with the gap bridged: points every median step on the straight from the last point to the
// first, widths, elevation and banking interpolated along it.
std::vector<CentreLinePoint> closeLoopGap(const std::vector<CentreLinePoint>& points);

// A recorded lap that drives on past its start, over the road it began on (ROAR_PY's BerkMajor: its last
// 23 points, 46 m, retrace its first within 1.2 m), cut where it comes back nearest its first point; a
// tail that does not retrace the start (a course that is no loop, a figure-eight's crossing) is kept.
// `cut` (if given): the points removed.
std::vector<CentreLinePoint> trimRetracedTail(const std::vector<CentreLinePoint>& points, std::size_t* cut = nullptr);

}  // namespace roar::track
