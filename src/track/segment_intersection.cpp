#include "roar/track/segment_intersection.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <unordered_map>

namespace roar::track {

namespace {
double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }
}  // namespace

bool segmentsCross(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, const Eigen::Vector2d& q1,
                   const Eigen::Vector2d& q2) {
  const Eigen::Vector2d r = p2 - p1, s = q2 - q1;
  const double denom = cross(r, s);
  if (std::abs(denom) < 1e-12) return false;  // parallel: touching collinear edges are not a crossing here
  const double t = cross(q1 - p1, s) / denom;
  const double u = cross(q1 - p1, r) / denom;
  return t > 0 && t < 1 && u > 0 && u < 1;
}

namespace {

// Calls visit(i, j) for each crossing of a segment of `a` with one of `b` until it returns false.
void forEachCrossing(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b,
                     const std::function<bool(std::size_t, std::size_t)>& visit) {
  const bool same = &a == &b;
  const std::size_t na = a.size(), nb = b.size();
  double cell = 1.0;
  for (std::size_t i = 0; i < na; ++i) cell = std::max(cell, (a[(i + 1) % na] - a[i]).norm());
  for (std::size_t i = 0; i < nb; ++i) cell = std::max(cell, (b[(i + 1) % nb] - b[i]).norm());
  auto key = [&](long cx, long cy) { return (cx * 73856093L) ^ (cy * 19349663L); };
  std::unordered_map<long, std::vector<std::size_t>> grid;
  auto cells = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q, auto&& each) {
    const long x0 = std::lround(std::floor(std::min(p.x(), q.x()) / cell));
    const long x1 = std::lround(std::floor(std::max(p.x(), q.x()) / cell));
    const long y0 = std::lround(std::floor(std::min(p.y(), q.y()) / cell));
    const long y1 = std::lround(std::floor(std::max(p.y(), q.y()) / cell));
    for (long cx = x0; cx <= x1; ++cx)
      for (long cy = y0; cy <= y1; ++cy) each(key(cx, cy));
  };
  for (std::size_t j = 0; j < nb; ++j) {
    cells(b[j], b[(j + 1) % nb], [&](long k) { grid[k].push_back(j); });
  }
  bool going = true;
  for (std::size_t i = 0; i < na && going; ++i) {
    const Eigen::Vector2d &p1 = a[i], &p2 = a[(i + 1) % na];
    // A pair met in several cells is one crossing.
    std::vector<std::size_t> met;
    cells(p1, p2, [&](long k) {
      if (!going) return;
      auto it = grid.find(k);
      if (it == grid.end()) return;
      for (std::size_t j : it->second) {
        if (same && (j <= i || j == (i + 1) % na || i == (j + 1) % na)) continue;
        if (std::find(met.begin(), met.end(), j) != met.end()) continue;
        if (segmentsCross(p1, p2, b[j], b[(j + 1) % nb])) {
          met.push_back(j);
          if (!visit(i, j)) going = false;
          if (!going) return;
        }
      }
    });
  }
}

}  // namespace

std::optional<std::pair<std::size_t, std::size_t>> findClosedPolylineCrossing(const std::vector<Eigen::Vector2d>& a,
                                                                              const std::vector<Eigen::Vector2d>& b,
                                                                              const CrossingFilter& passes) {
  std::optional<std::pair<std::size_t, std::size_t>> found;
  forEachCrossing(a, b, [&](std::size_t i, std::size_t j) {
    if (passes && passes(i, j)) return true;
    found = std::make_pair(i, j);
    return false;
  });
  return found;
}

std::vector<std::pair<std::size_t, std::size_t>> closedPolylineSelfCrossings(const std::vector<Eigen::Vector2d>& a) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  forEachCrossing(a, a, [&](std::size_t i, std::size_t j) {
    out.emplace_back(i, j);
    return true;
  });
  return out;
}

}  // namespace roar::track
