#include "roar/track/bridges.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <unordered_map>

#include "roar/track/segment_intersection.h"

namespace roar::track {

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }
double widest(const CentreLinePoint& p) { return std::max(p.width_left, p.width_right); }

}  // namespace

std::vector<CentreLinePoint> raiseBridges(std::vector<CentreLinePoint> points, double barrier_offset,
                                          std::vector<RaisedBridge>* raised, bool closed) {
  const std::size_t n = points.size();
  if (n < 3) return points;
  std::vector<Eigen::Vector2d> xy(n);
  for (std::size_t i = 0; i < n; ++i) xy[i] = {points[i].x, points[i].y};
  std::vector<double> s(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) s[i + 1] = s[i] + (xy[(i + 1) % n] - xy[i]).norm();
  const double length = s[n];
  for (const auto& [i, j] : closedPolylineSelfCrossings(xy)) {
    if (!closed && (i == n - 1 || j == n - 1)) continue;  // a course's last point leads nowhere
    const Eigen::Vector2d di = xy[(i + 1) % n] - xy[i], dj = xy[(j + 1) % n] - xy[j];
    const double denom = cross(di, dj);
    const double ti = cross(xy[j] - xy[i], dj) / denom, tj = cross(xy[j] - xy[i], di) / denom;
    const Eigen::Vector2d at = xy[i] + ti * di;
    auto heightOn = [&](std::size_t k, double t) { return (1 - t) * points[k].z + t * points[(k + 1) % n].z; };
    const double zi = heightOn(i, ti), zj = heightOn(j, tj);
    if (std::abs(zi - zj) >= kBridgeClearance) continue;
    // The branch already higher goes over (the later one if level).
    const bool raise_j = zj >= zi;
    const std::size_t upper = raise_j ? j : i, lower = raise_j ? i : j;
    const double s_upper = raise_j ? s[j] + tj * dj.norm() : s[i] + ti * di.norm();
    const double s_lower = raise_j ? s[i] + ti * di.norm() : s[j] + tj * dj.norm();
    const double rise = kBridgeRise - std::abs(zi - zj);
    char where[96];
    std::snprintf(where, sizeof where, "the centre line crosses itself at (%.1f, %.1f)", at.x(), at.y());
    const double sin_angle = std::min(1.0, std::abs(denom) / (di.norm() * dj.norm()));
    if (sin_angle < 0.25) {
      throw std::invalid_argument(std::string(where) + " at " + std::to_string(std::asin(sin_angle) * 180 / M_PI) +
                                  " degrees: too shallow a crossing for a bridge (at least 15)");
    }
    const double cos_angle = std::sqrt(std::max(0.0, 1.0 - sin_angle * sin_angle));
    // The deck spans the other road and its run-off (to its barriers), crossed at an angle.
    const double other_half = widest(points[lower]) + barrier_offset + 1.0;
    const double own_half = widest(points[upper]) + kParapetOffset + 0.5;
    const double span_half = other_half / sin_angle + own_half * cos_angle / sin_angle;
    const double ramp = rise * M_PI / (2.0 * kBridgeMaxGrade);
    const double apart = std::fmod(std::abs(s_upper - s_lower), length);
    const double between = closed ? std::min(apart, length - apart) : std::abs(s_upper - s_lower);
    const double needed = span_half + ramp + other_half;
    if (between < needed) {
      throw std::invalid_argument(std::string(where) + " with only " + std::to_string(between) +
                                  " m of course between its two branches: a bridge raising one by " +
                                  std::to_string(rise) + " m with ramps no steeper than " +
                                  std::to_string(100 * kBridgeMaxGrade) + "% needs " + std::to_string(needed) + " m");
    }
    for (std::size_t k = 0; k < n; ++k) {
      const double d = std::fmod(std::abs(s[k] - s_upper), length);
      const double a = closed ? std::min(d, length - d) : std::abs(s[k] - s_upper);
      const double f = a <= span_half         ? 1.0
                       : a < span_half + ramp ? 0.5 * (1.0 + std::cos(M_PI * (a - span_half) / ramp))
                                              : 0.0;
      points[k].z += rise * f;
    }
    if (raised) raised->push_back({at.x(), at.y(), s_upper, rise, 2.0 * span_half, ramp});
  }
  return points;
}

std::vector<bool> bridgeDeckPoints(const Track& track) {
  const std::size_t n = track.size();
  std::vector<bool> deck(n, false);
  // A point's corridor: its road and run-off to the barriers, and a metre.
  auto reach = [&](std::size_t i) { return widest(track.point(i)) + track.info().barrier_offset + 1.0; };
  double cell = 1.0;
  for (std::size_t i = 0; i < n; ++i) cell = std::max(cell, 2.0 * reach(i));
  auto key = [](long cx, long cy) { return (cx * 73856093L) ^ (cy * 19349663L); };
  auto cellOf = [&](double v) { return static_cast<long>(std::floor(v / cell)); };
  std::unordered_map<long, std::vector<std::size_t>> grid;
  for (std::size_t i = 0; i < n; ++i) grid[key(cellOf(track.point(i).x), cellOf(track.point(i).y))].push_back(i);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = track.point(i);
    const long cx = cellOf(p.x), cy = cellOf(p.y);
    for (long x = cx - 1; x <= cx + 1 && !deck[i]; ++x) {
      for (long y = cy - 1; y <= cy + 1 && !deck[i]; ++y) {
        auto it = grid.find(key(x, y));
        if (it == grid.end()) continue;
        for (std::size_t j : it->second) {
          const auto& q = track.point(j);
          if (p.z - q.z >= kBridgeClearance && (track.position(i) - track.position(j)).norm() < reach(i) + reach(j)) {
            deck[i] = true;
            break;
          }
        }
      }
    }
  }
  return deck;
}

}  // namespace roar::track
