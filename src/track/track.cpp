#include "roar/track/track.h"

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "roar/track/heading.h"

namespace roar::track {

double wrapAngle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a < 0) a += 2.0 * M_PI;
  return a - M_PI;
}

std::string centreLinePointProblem(const CentreLinePoint& p) {
  char buf[160];
  auto outside = [&](const char* column, double v, double lo, double hi) {
    if (v >= lo && v <= hi) return false;
    std::snprintf(buf, sizeof buf, "column %s = %g is outside [%g, %g]", column, v, lo, hi);
    return true;
  };
  if (outside("x_m", p.x, -kMaxCoordinate, kMaxCoordinate) || outside("y_m", p.y, -kMaxCoordinate, kMaxCoordinate) ||
      outside("w_tr_right_m", p.width_right, 1e-3, kMaxEdgeDistance) ||
      outside("w_tr_left_m", p.width_left, 1e-3, kMaxEdgeDistance) ||
      outside("z_m", p.z, -kMaxElevation, kMaxElevation) ||
      outside("banking_rad", p.banking, -kMaxBanking, kMaxBanking)) {
    return buf;
  }
  return "";
}

Track::Track(std::vector<CentreLinePoint> points, TrackInfo info) : points_(std::move(points)), info_(std::move(info)) {
  const std::size_t n = points_.size();
  if (n < 3) throw std::invalid_argument("a track needs at least 3 centre-line points, got " + std::to_string(n));
  if (n > kMaxCentreLinePoints) {
    throw std::invalid_argument("a track has at most " + std::to_string(kMaxCentreLinePoints) +
                                " centre-line points, got " + std::to_string(n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::string problem = centreLinePointProblem(points_[i]);
    if (!problem.empty()) throw std::invalid_argument("centre-line point " + std::to_string(i) + ": " + problem);
  }
  s_.resize(n);
  heading_.resize(n);
  curvature_.resize(n);
  double s = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    s_[i] = s;
    if (!closed() && i + 1 == n) break;
    const double seg = (position((i + 1) % n) - position(i)).norm();
    if (seg < 1e-9) {
      throw std::invalid_argument("centre-line points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
                                  " coincide");
    }
    s += seg;
  }
  length_ = s;
  for (std::size_t i = 0; i < n; ++i) {
    // A course's ends look one way only: their heading along their one segment, their curvature their
    // neighbour's.
    if (!closed() && (i == 0 || i + 1 == n)) {
      const Eigen::Vector2d d = i == 0 ? position(1) - position(0) : position(i) - position(i - 1);
      heading_[i] = std::atan2(d.y(), d.x());
      continue;
    }
    const Eigen::Vector2d prev = position((i + n - 1) % n), cur = position(i), next = position((i + 1) % n);
    const Eigen::Vector2d d = next - prev;
    heading_[i] = std::atan2(d.y(), d.x());
    // Menger curvature of the three points: 4 * area / product of the sides, signed by the turn direction.
    const Eigen::Vector2d a = cur - prev, b = next - cur;
    const double cross = a.x() * b.y() - a.y() * b.x();
    const double denom = a.norm() * b.norm() * (next - prev).norm();
    curvature_[i] = denom > 0 ? 2.0 * cross / denom : 0.0;
  }
  if (!closed()) {
    curvature_[0] = curvature_[1];
    curvature_[n - 1] = curvature_[n - 2];
    checkCourseLines();
  }
}

void Track::checkCourseLines() const {
  char buf[256];
  const double start = info_.start_finish_s, finish = info_.finish_s;
  if (!(start >= kGridLength && finish > start + kGridLength && finish <= length_)) {
    std::snprintf(buf, sizeof buf,
                  "a point-to-point course needs its start line (start_finish.s = %g m) at least %g m (the grid) "
                  "from its road's start and its finish line (finish.s = %g m) at least %g m past the start and on "
                  "its road (%g m long)",
                  start, kGridLength, finish, kGridLength, length_);
    throw std::invalid_argument(buf);
  }
}

Eigen::Vector2d Track::leftEdge(std::size_t i, double extra) const {
  const double h = heading_[i];
  return position(i) + (points_[i].width_left + extra) * track::leftOf(h);
}

Eigen::Vector2d Track::rightEdge(std::size_t i, double extra) const {
  const double h = heading_[i];
  return position(i) - (points_[i].width_right + extra) * track::leftOf(h);
}

double Track::surfaceHeightAt(double s, double lateral) const {
  s = wrap(s);
  const std::size_t i = segmentAt(s), j = (i + 1) % size();
  const double seg = (j == 0 ? length_ : s_[j]) - s_[i];
  const double t = (s - s_[i]) / seg;
  const double z = (1 - t) * points_[i].z + t * points_[j].z;
  const double banking = (1 - t) * points_[i].banking + t * points_[j].banking;
  return z + lateral * std::tan(banking);
}

void Track::setRecordedWaypoints(std::vector<Waypoint> waypoints) {
  if (waypoints.size() != points_.size()) {
    throw std::invalid_argument(std::to_string(waypoints.size()) + " recorded waypoints for " +
                                std::to_string(points_.size()) + " centre-line points (one each)");
  }
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    const Eigen::Vector2d off = waypoints[i].location.head<2>() - position(i);
    if (!waypoints[i].location.allFinite() || !waypoints[i].roll_pitch_yaw.allFinite() || off.norm() > 0.05 ||
        !(waypoints[i].lane_width > 0 && waypoints[i].lane_width <= 2 * kMaxEdgeDistance)) {
      throw std::invalid_argument("recorded waypoint " + std::to_string(i) + " is not centre-line point " +
                                  std::to_string(i) + " (" + std::to_string(off.norm()) +
                                  " m from it, or not finite, or its lane width out of range)");
    }
  }
  recorded_waypoints_ = std::move(waypoints);
}

double Track::lowestPoint() const {
  double lowest = 0.0;
  for (std::size_t i = 0; i < size(); ++i) {
    lowest = std::min({lowest, surfaceHeight(i, points_[i].width_left), surfaceHeight(i, -points_[i].width_right)});
  }
  return lowest;
}

double Track::wrap(double s) const {
  if (!closed()) return std::clamp(s, 0.0, length_);
  s = std::fmod(s, length_);
  return s < 0 ? s + length_ : s;
}

double Track::forwardDistance(double s_from, double s_to) const {
  if (!closed()) return s_to >= s_from ? s_to - s_from : std::numeric_limits<double>::infinity();
  return wrap(s_to - s_from);
}

std::size_t Track::segments() const { return closed() ? size() : size() - 1; }

std::size_t Track::segmentAt(double s) const {
  s = wrap(s);
  auto it = std::upper_bound(s_.begin(), s_.end(), s);
  return std::min(static_cast<std::size_t>(std::distance(s_.begin(), it)) - 1, segments() - 1);
}

TrackPose Track::poseAt(double s) const {
  s = wrap(s);
  const std::size_t i = segmentAt(s), j = (i + 1) % size();
  const double seg = (j == 0 ? length_ : s_[j]) - s_[i];
  const double t = (s - s_[i]) / seg;
  TrackPose pose;
  pose.position = (1 - t) * position(i) + t * position(j);
  pose.heading = heading_[i] + t * wrapAngle(heading_[j] - heading_[i]);
  pose.width_right = (1 - t) * points_[i].width_right + t * points_[j].width_right;
  pose.width_left = (1 - t) * points_[i].width_left + t * points_[j].width_left;
  pose.height = surfaceHeightAt(s, 0.0);
  return pose;
}

Projection Track::projectOnSegment(const Eigen::Vector2d& p, std::size_t i, double* dist2) const {
  const std::size_t j = (i + 1) % size();
  const Eigen::Vector2d a = position(i), d = position(j) - a;
  const double seg2 = d.squaredNorm();
  const double along = (p - a).dot(d) / seg2;
  const double t = std::clamp(along, 0.0, 1.0);
  const Eigen::Vector2d foot = a + t * d;
  *dist2 = (p - foot).squaredNorm();
  Projection pr;
  pr.segment = i;
  pr.s = wrap(s_[i] + t * std::sqrt(seg2));
  const Eigen::Vector2d rel = p - foot;
  pr.lateral = (d.x() * rel.y() - d.y() * rel.x()) / std::sqrt(seg2);
  pr.heading = heading_[i] + t * wrapAngle(heading_[j] - heading_[i]);
  pr.width_right = (1 - t) * points_[i].width_right + t * points_[j].width_right;
  pr.width_left = (1 - t) * points_[i].width_left + t * points_[j].width_left;
  if (!closed() && i == 0 && along < 0) pr.past_end = -along * std::sqrt(seg2);
  if (!closed() && i + 2 == size() && along > 1) pr.past_end = (along - 1) * std::sqrt(seg2);
  return pr;
}

Projection Track::project(const Eigen::Vector2d& p) const {
  Projection best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < segments(); ++i) {
    double d2;
    Projection pr = projectOnSegment(p, i, &d2);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = pr;
    }
  }
  return best;
}

Projection Track::projectAtHeight(const Eigen::Vector3d& p) const {
  Projection best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < segments(); ++i) {
    double d2;
    Projection pr = projectOnSegment(p.head<2>(), i, &d2);
    const double dz = kProjectionHeightWeight * (p.z() - surfaceHeightAt(pr.s, pr.lateral));
    d2 += dz * dz;
    if (d2 < best_d2) {
      best_d2 = d2;
      best = pr;
    }
  }
  return best;
}

Projection Track::projectNear(const Eigen::Vector2d& p, double near_s, double window) const {
  if (window * 2 >= length_) return project(p);
  Projection best;
  double best_d2 = std::numeric_limits<double>::infinity();
  std::size_t i = segmentAt(near_s - window);
  const std::size_t last = segmentAt(near_s + window);
  for (;; i = (i + 1) % segments()) {
    double d2;
    Projection pr = projectOnSegment(p, i, &d2);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = pr;
    }
    if (i == last) break;
  }
  return best;
}

std::vector<std::size_t> Track::indicesAhead(double from_s, double length) const {
  std::vector<std::size_t> out;
  if (length <= 0) return out;
  length = std::min(length, length_);
  std::size_t i = (segmentAt(from_s) + 1) % size();
  while (out.size() < size() && forwardDistance(from_s, s_[i]) <= length && forwardDistance(from_s, s_[i]) > 0) {
    out.push_back(i);
    if (!closed() && i + 1 == size()) break;
    i = (i + 1) % size();
  }
  return out;
}

std::vector<TrackPose> Track::evenSpawnPoints(int count) const {
  std::vector<TrackPose> out;
  for (int k = 0; k < count; ++k) out.push_back(poseAt(info_.start_finish_s + k * raceDistance() / count));
  return out;
}

std::vector<TrackPose> Track::gridSpawnPoints(int count, double first_gap, double spacing) const {
  std::vector<TrackPose> grid;
  for (int k = 0; k < count; ++k) {
    TrackPose pose = poseAt(info_.start_finish_s - first_gap - spacing * k);
    const double side = (k % 2 == 0) ? 0.25 * pose.width_left : -0.25 * pose.width_right;
    pose.position += side * track::leftOf(pose.heading);
    pose.height = surfaceHeightAt(info_.start_finish_s - first_gap - spacing * k, side);
    grid.push_back(pose);
  }
  return grid;
}

std::string offTrackProblem(const Track& track, const Eigen::Vector2d& point, const std::string& what) {
  char buf[256];
  if (!point.allFinite() || point.cwiseAbs().maxCoeff() > kMaxCoordinate) {
    std::snprintf(buf, sizeof buf, "%s (%g, %g) must be finite and within %g m of the map's origin", what.c_str(),
                  point.x(), point.y(), kMaxCoordinate);
    return buf;
  }
  const Projection where = track.project(point);
  const double barrier = track.info().barrier_offset;
  if (where.beyondEdge() <= barrier) return "";
  std::snprintf(buf, sizeof buf,
                "%s (%.1f, %.1f) is off the track: %.1f m beyond the road's edge, past the barriers %.1f m from it",
                what.c_str(), point.x(), point.y(), where.beyondEdge(), barrier);
  return buf;
}

}  // namespace roar::track
