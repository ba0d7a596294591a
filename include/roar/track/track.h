#pragma once
// A closed circuit, or a point-to-point course (a sprint, a hill climb: the road runs from its first point
// to its last): a centre line with right and left widths, in the map frame (x east, y north, metres). The
// driving direction is the order of the points; progress `s` is the distance along the centre line.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace roar::track {

// How much a metre of height counts against a metre sideways when a point is projected at its height: a
// road one bridge's clearance above or below is never the one a point is on, though its centre line may be
// nearer sideways than the point's own road's edge.
inline constexpr double kProjectionHeightWeight = 3.0;

// The start grid's slots a race places its cars on (scenarios, roar_sim, waypoint_server's spawn points).
inline constexpr int kGridSlots = 20;
// The grid: pole this far behind the start line, each further slot this much further back.
inline constexpr double kGridFirstGap = 10.0;
inline constexpr double kGridSpacing = 8.0;
// Road a point-to-point course needs behind its start line for every grid slot (and a car's length).
inline constexpr double kGridLength = kGridFirstGap + kGridSpacing * (kGridSlots - 1) + 5.0;

struct CentreLinePoint {
  double x = 0.0;
  double y = 0.0;
  double width_right = 0.0;  // metres from the centre line to the right edge
  double width_left = 0.0;   // metres from the centre line to the left edge
  double z = 0.0;            // metres, elevation of the centre line (optional CSV column z_m)
  double banking = 0.0;      // rad, roll of the road surface: positive raises the left edge (optional banking_rad)
};

// Physical ranges of a centre line, which every map reader and the Track itself check: beyond them a
// file is broken (or scaled wrong), not a circuit.
inline constexpr std::size_t kMaxCentreLinePoints = 200000;  // a 200 km course at 1 m
inline constexpr double kMaxCoordinate = 1e6;                // m from the map's origin, x and y
inline constexpr double kMaxElevation = 1e4;                 // m, |z|
inline constexpr double kMaxEdgeDistance = 100.0;            // m from the centre line to an edge
inline constexpr double kMaxBanking = 0.785398;              // rad, 45 degrees (Daytona's steepest is 31)
inline constexpr double kMinRoadWidth = 2.5;                 // m edge to edge: a car (1.85 m) and a hand
inline constexpr double kMaxGrade = 0.4;  // rise over run between points (the steepest streets ~0.35)
// Empty when the point is within those ranges, else what is not (the column, its value and its range).
std::string centreLinePointProblem(const CentreLinePoint& point);

// A waypoint as ROAR_PY has it: the centre of the drivable road, the road's roll/pitch/yaw, the lane width.
struct Waypoint {
  Eigen::Vector3d location = Eigen::Vector3d::Zero();        // m, map frame (x forward/east, y left/north, z up)
  Eigen::Vector3d roll_pitch_yaw = Eigen::Vector3d::Zero();  // rad; yaw is the road heading
  double lane_width = 0.0;                                   // m
};

struct GeoOrigin {
  double latitude = 0.0;   // degrees
  double longitude = 0.0;  // degrees
  double altitude = 0.0;   // metres
};

struct TrackInfo {
  std::string name;
  GeoOrigin origin;              // geodetic position of the map frame's origin
  double friction = 1.0;         // tyre-road friction coefficient of the road surface
  double ground_friction = 0.6;  // off the road (grass, gravel)
  double start_finish_s = 0.0;   // progress of the start/finish line along the centre line, metres
  // false: a point-to-point course. Its race is one run from the start line (start_finish_s) to the
  // finish line (finish_s), and the road after the finish is where the cars stop.
  bool closed = true;
  double finish_s = 0.0;        // point-to-point only: progress of the finish line, metres
  int sectors = 3;              // equal-length sectors starting at the start/finish line
  double barrier_offset = 3.0;  // run-off: barriers stand this far outside each road edge, metres
  double barrier_height = 1.0;  // metres
};

// A pose on the track at some progress, interpolated between centre-line points.
struct TrackPose {
  Eigen::Vector2d position;
  double height = 0.0;   // m, the road surface's there (which road, where one runs over another)
  double heading = 0.0;  // radians, direction of travel
  double width_right = 0.0;
  double width_left = 0.0;
};

// Where a point lies relative to the track.
struct Projection {
  std::size_t segment = 0;  // index of the centre-line segment [segment, segment+1)
  double s = 0.0;           // progress of the nearest centre-line point, in [0, length)
  double lateral = 0.0;     // signed distance from the centre line, positive to the left
  double heading = 0.0;     // track heading at s
  double width_right = 0.0;
  double width_left = 0.0;
  double past_end = 0.0;  // m before a point-to-point course's first point or after its last, along the road
  bool on_track() const { return lateral <= width_left && -lateral <= width_right && past_end <= 0.0; }
  // Metres beyond the nearer road edge or end (negative: on the road, that far inside the edge on its side).
  double beyondEdge() const {
    const double side = lateral >= 0 ? lateral - width_left : -lateral - width_right;
    return past_end > 0.0 ? std::max(side, past_end) : side;
  }
};

class Track {
 public:
  // Throws std::invalid_argument when there are fewer than 3 points or two consecutive points coincide, or
  // when a point-to-point course's start and finish lines are not on its road in that order, with the
  // grid's length of road behind the start.
  Track(std::vector<CentreLinePoint> points, TrackInfo info);

  const TrackInfo& info() const { return info_; }
  // The waypoints the map's source recorded, one per centre-line point (ROAR_PY's own for ROAR's maps: their
  // heights, rotations and lane widths as recorded); empty: waypointsOf derives them from the centre line.
  const std::vector<Waypoint>& recordedWaypoints() const { return recorded_waypoints_; }
  // Throws std::invalid_argument unless there is one per centre-line point, each within 5 cm of it.
  void setRecordedWaypoints(std::vector<Waypoint> waypoints);
  std::size_t size() const { return points_.size(); }
  double length() const { return length_; }
  const std::vector<CentreLinePoint>& points() const { return points_; }
  const CentreLinePoint& point(std::size_t i) const { return points_[i]; }
  Eigen::Vector2d position(std::size_t i) const { return {points_[i].x, points_[i].y}; }
  double s(std::size_t i) const { return s_[i]; }
  double heading(std::size_t i) const { return heading_[i]; }
  // Signed curvature (1/m), positive for a left turn.
  double curvature(std::size_t i) const { return curvature_[i]; }
  Eigen::Vector2d leftEdge(std::size_t i, double extra = 0.0) const;
  Eigen::Vector2d rightEdge(std::size_t i, double extra = 0.0) const;
  // Height of the road surface at a signed lateral offset (positive left) from centre-line point i.
  double surfaceHeight(std::size_t i, double lateral) const {
    return points_[i].z + lateral * std::tan(points_[i].banking);
  }
  // The same between points: height and banking interpolated at progress s.
  double surfaceHeightAt(double s, double lateral) const;
  double lowestPoint() const;

  bool closed() const { return info_.closed; }
  // Centre-line segments: a circuit's last point leads back to its first, a course's leads nowhere.
  std::size_t segments() const;
  // Progress on the course: a circuit's wrapped into [0, length), a point-to-point course's clamped to its road.
  double wrap(double s) const;
  // Distance travelled forward from s_from to reach s_to: in [0, length) on a circuit; on a point-to-point
  // course s_to - s_from, and infinity when s_to is behind (no way forward reaches it).
  double forwardDistance(double s_from, double s_to) const;
  // Progress of the line a race finishes on: the start/finish line of a circuit, a course's finish line.
  double finishLine() const { return closed() ? info_.start_finish_s : info_.finish_s; }
  // Metres after the start line along the race to progress s: a circuit's in [0, length), a course's
  // negative before its start line.
  double raceProgress(double s) const {
    return closed() ? forwardDistance(info_.start_finish_s, s) : s - info_.start_finish_s;
  }
  // Metres a race covers from its start line to its finish: a lap, or the run of a point-to-point course.
  double raceDistance() const { return closed() ? length_ : info_.finish_s - info_.start_finish_s; }
  TrackPose poseAt(double s) const;
  Projection project(const Eigen::Vector2d& p) const;
  // The nearest in 3D, the road's surface height counted: under a bridge, the branch at the point's height.
  Projection projectAtHeight(const Eigen::Vector3d& p) const;
  // Only segments within `window` metres of progress `near_s`: cheap for a car that was near there recently.
  Projection projectNear(const Eigen::Vector2d& p, double near_s, double window) const;

  // Start grid: slot 0 (pole) `first_gap` metres behind the start/finish line, then alternating sides.
  // Races place cars on the first kGridSlots slots.
  std::vector<TrackPose> gridSpawnPoints(int count, double first_gap = kGridFirstGap,
                                         double spacing = kGridSpacing) const;
  // Indices of the centre-line points with progress in (from_s, from_s + length], the forward way round
  // (on a point-to-point course, up to its last point).
  std::vector<std::size_t> indicesAhead(double from_s, double length) const;

  // `count` spawn points evenly round the lap (a course: from its start line to its finish line) on the
  // centre line, the first on the start/finish line.
  std::vector<TrackPose> evenSpawnPoints(int count) const;

 private:
  std::size_t segmentAt(double s) const;
  void checkCourseLines() const;
  Projection projectOnSegment(const Eigen::Vector2d& p, std::size_t i, double* dist2) const;

  std::vector<CentreLinePoint> points_;
  TrackInfo info_;
  std::vector<Waypoint> recorded_waypoints_;
  std::vector<double> s_;
  std::vector<double> heading_;
  std::vector<double> curvature_;
  double length_ = 0.0;
};

double wrapAngle(double a);

// Why a point given to place a car or ask about the track is not on the track or its run-off (within the
// barriers), naming it as `what`; empty when it is. Non-finite points and points beyond kMaxCoordinate
// are refused before anything is projected.
std::string offTrackProblem(const Track& track, const Eigen::Vector2d& point, const std::string& what);

}  // namespace roar::track
