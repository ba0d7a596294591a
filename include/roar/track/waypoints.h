#pragma once
// Waypoints as ROAR_PY has them: the centre of the drivable road, the road's roll/pitch/yaw, the lane width.
// And ROAR_PY's waypoint files (.npz: locations (N,3), rotations (N,3), lane_widths (N); spawn points:
// locations and rotations).
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "roar/track/track.h"

namespace roar::track {

// ROAR_PY's line representation: the road's left and right edge points, location -/+ R(rpy) [0, w/2, 0].
std::pair<Eigen::Vector3d, Eigen::Vector3d> lineRepresentation(const Waypoint& w);
// The waypoint whose line representation is (left, right), with the given pitch.
Waypoint fromLineRepresentation(const Eigen::Vector3d& left, const Eigen::Vector3d& right, double pitch = 0.0);
// Between a (t = 0) and b (t = 1): locations and widths linearly, angles the short way round.
Waypoint interpolate(const Waypoint& a, const Waypoint& b, double t);

// One waypoint per centre-line point: the ones the map recorded (Track::recordedWaypoints), else the middle
// of the road between its edges with the road's rotation and full width.
std::vector<Waypoint> waypointsOf(const Track& track);
// A track through waypoint locations with half the lane width each side and their roll as banking (closed
// or a point-to-point course as `info` says). Consecutive waypoints closer than 1 cm (and on a circuit a
// last one repeating the first) are merged; an implausible
// height profile is repaired (see repairElevation). Throws std::invalid_argument for fewer than 3 distinct
// waypoints or a non-positive width.
Track trackFromWaypoints(const std::vector<Waypoint>& waypoints, const TrackInfo& info);

// Road profiles are smooth; recorded ones are not always (ROAR_PY's Monza has 0.74 m steps within 2 m, and
// its pitch, like BerkMajor's, is not recorded). When any step between points is steeper than `max_grade`,
// the heights are smoothed by a moving average over +-`half_window` metres of centre line, which turns such
// steps into gentle ramps and keeps hills. A plausible profile is left exactly as it is. Returns whether
// the profile was smoothed.
bool repairElevation(std::vector<CentreLinePoint>* points, bool closed = true, double max_grade = 0.2,
                     double half_window = 15.0);

// ROAR_PY files; errors (NpzError) name the file, the array and the problem.
std::vector<Waypoint> readRoarWaypoints(const std::string& path);
void writeRoarWaypoints(const std::string& path, const std::vector<Waypoint>& waypoints);
std::vector<Waypoint> readRoarSpawnPoints(const std::string& path);  // lane_width 0
void writeRoarSpawnPoints(const std::string& path, const std::vector<Waypoint>& spawn_points);

}  // namespace roar::track
