#include "roar/track/waypoints.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "roar/track/npz.h"

namespace roar::track {

namespace {

Eigen::Matrix3d rotation(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

NpyArray rowsOf(const std::vector<Waypoint>& w, int which) {
  NpyArray a;
  a.shape = {w.size(), 3};
  for (const auto& p : w) {
    const Eigen::Vector3d& v = which == 0 ? p.location : p.roll_pitch_yaw;
    a.data.insert(a.data.end(), {v.x(), v.y(), v.z()});
  }
  return a;
}

std::vector<Waypoint> fromArrays(const std::map<std::string, NpyArray>& arrays, const std::string& path, bool widths) {
  const NpyArray& loc = requireArray(arrays, "locations", 3, path);
  const NpyArray& rot = requireArray(arrays, "rotations", 3, path);
  if (rot.rows() != loc.rows()) {
    throw NpzError(path + ": 'rotations' has " + std::to_string(rot.rows()) + " rows, 'locations' " +
                   std::to_string(loc.rows()));
  }
  const NpyArray* width = widths ? &requireArray(arrays, "lane_widths", 1, path) : nullptr;
  if (width && width->rows() != loc.rows()) {
    throw NpzError(path + ": 'lane_widths' has " + std::to_string(width->rows()) + " rows, 'locations' " +
                   std::to_string(loc.rows()));
  }
  std::vector<Waypoint> out(loc.rows());
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].location = Eigen::Vector3d(loc.data[3 * i], loc.data[3 * i + 1], loc.data[3 * i + 2]);
    out[i].roll_pitch_yaw = Eigen::Vector3d(rot.data[3 * i], rot.data[3 * i + 1], rot.data[3 * i + 2]);
    if (width) {
      out[i].lane_width = width->data[i];
      if (out[i].lane_width <= 0)
        throw NpzError(path + ": array 'lane_widths' row " + std::to_string(i) + " is not positive");
    }
  }
  return out;
}

}  // namespace

std::pair<Eigen::Vector3d, Eigen::Vector3d> lineRepresentation(const Waypoint& w) {
  const Eigen::Vector3d half = rotation(w.roll_pitch_yaw) * Eigen::Vector3d(0, 0.5 * w.lane_width, 0);
  return {w.location + half, w.location - half};
}

Waypoint fromLineRepresentation(const Eigen::Vector3d& left, const Eigen::Vector3d& right, double pitch) {
  Waypoint w;
  w.location = 0.5 * (left + right);
  const Eigen::Vector3d across = left - right;
  w.lane_width = across.norm();
  const double yaw = std::atan2(-across.x(), across.y());  // forward is `across` turned a quarter clockwise
  const double roll = std::atan2(across.z(), across.head<2>().norm());
  w.roll_pitch_yaw = Eigen::Vector3d(roll, pitch, yaw);
  return w;
}

Waypoint interpolate(const Waypoint& a, const Waypoint& b, double t) {
  Waypoint w;
  w.location = (1 - t) * a.location + t * b.location;
  for (int k = 0; k < 3; ++k) {
    w.roll_pitch_yaw[k] = wrapAngle(a.roll_pitch_yaw[k] + t * wrapAngle(b.roll_pitch_yaw[k] - a.roll_pitch_yaw[k]));
  }
  w.lane_width = (1 - t) * a.lane_width + t * b.lane_width;
  return w;
}

std::vector<Waypoint> waypointsOf(const Track& track) {
  if (!track.recordedWaypoints().empty()) return track.recordedWaypoints();
  std::vector<Waypoint> out;
  for (std::size_t i = 0; i < track.size(); ++i) {
    Waypoint w;
    const Eigen::Vector2d mid = 0.5 * (track.leftEdge(i) + track.rightEdge(i));
    const auto& p = track.point(i);
    // The slope to the next point (a course's last point: from the one before).
    const bool last = !track.closed() && i + 1 == track.size();
    const std::size_t from = last ? i - 1 : i, to = last ? i : (i + 1) % track.size();
    const double run = (track.position(to) - track.position(from)).norm();
    const double pitch = -std::atan2(track.point(to).z - track.point(from).z, run);  // REP-103: nose down positive
    w.location = Eigen::Vector3d(mid.x(), mid.y(), track.surfaceHeight(i, 0.5 * (p.width_left - p.width_right)));
    w.roll_pitch_yaw = Eigen::Vector3d(p.banking, pitch, track.heading(i));
    w.lane_width = track.point(i).width_left + track.point(i).width_right;
    out.push_back(w);
  }
  return out;
}

Track trackFromWaypoints(const std::vector<Waypoint>& waypoints, const TrackInfo& info) {
  std::vector<CentreLinePoint> pts;
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    const Waypoint& w = waypoints[i];
    if (!(w.lane_width > 0))
      throw std::invalid_argument("waypoint " + std::to_string(i) + ": lane width must be positive");
    if (!pts.empty() && std::hypot(w.location.x() - pts.back().x, w.location.y() - pts.back().y) < 0.01) continue;
    pts.push_back(
        {w.location.x(), w.location.y(), 0.5 * w.lane_width, 0.5 * w.lane_width, w.location.z(), w.roll_pitch_yaw.x()});
  }
  while (info.closed && pts.size() > 3 && std::hypot(pts.front().x - pts.back().x, pts.front().y - pts.back().y) < 0.01)
    pts.pop_back();
  repairElevation(&pts, info.closed);
  return Track(std::move(pts), info);
}

bool repairElevation(std::vector<CentreLinePoint>* points, bool closed, double max_grade, double half_window) {
  auto& p = *points;
  const std::size_t n = p.size();
  std::vector<double> s(n + 1, 0.0);
  bool implausible = false;
  for (std::size_t i = 0; i < (closed ? n : n - 1); ++i) {
    const auto &a = p[i], &b = p[(i + 1) % n];
    const double run = std::hypot(b.x - a.x, b.y - a.y);
    s[i + 1] = s[i] + run;
    implausible = implausible || std::abs(b.z - a.z) > max_grade * run;
  }
  if (!implausible) return false;
  const double length = s[n];
  std::vector<double> smoothed(n);
  for (std::size_t i = 0; i < n; ++i) {
    // Points within the window on both sides, walking round the loop.
    double sum = p[i].z, count = 1;
    for (int dir : {-1, 1}) {
      for (std::size_t k = 1; k < n; ++k) {
        // An open line's window stops at its ends.
        if (!closed && (dir < 0 ? k > i : i + k >= n)) break;
        const std::size_t j = (i + n + static_cast<std::size_t>(dir) * k) % n;
        double d = std::abs(s[j] - s[i]);
        if (closed) d = std::min(d, length - d);
        if (d > half_window) break;
        sum += p[j].z;
        ++count;
      }
    }
    smoothed[i] = sum / count;
  }
  for (std::size_t i = 0; i < n; ++i) p[i].z = smoothed[i];
  return true;
}

std::vector<Waypoint> readRoarWaypoints(const std::string& path) { return fromArrays(readNpz(path), path, true); }

void writeRoarWaypoints(const std::string& path, const std::vector<Waypoint>& waypoints) {
  NpyArray widths;
  widths.shape = {waypoints.size()};
  for (const auto& w : waypoints) widths.data.push_back(w.lane_width);
  writeNpz(path, {{"locations", rowsOf(waypoints, 0)}, {"rotations", rowsOf(waypoints, 1)}, {"lane_widths", widths}});
}

std::vector<Waypoint> readRoarSpawnPoints(const std::string& path) { return fromArrays(readNpz(path), path, false); }

void writeRoarSpawnPoints(const std::string& path, const std::vector<Waypoint>& spawn_points) {
  writeNpz(path, {{"locations", rowsOf(spawn_points, 0)}, {"rotations", rowsOf(spawn_points, 1)}});
}

}  // namespace roar::track
