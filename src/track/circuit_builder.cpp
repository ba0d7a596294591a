#include "roar/track/circuit_builder.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "roar/config/text_file.h"
#include "roar/track/map_folder.h"

namespace roar::track {

namespace {

// One centripetal Catmull-Rom segment between p1 and p2 (Barry-Goldman pyramid), t in [0, 1].
Eigen::Vector3d catmullRom(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                           const Eigen::Vector3d& p3, double u) {
  auto knot = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::sqrt(std::max((b.head<2>() - a.head<2>()).norm(), 1e-9));
  };
  const double t0 = 0, t1 = t0 + knot(p0, p1), t2 = t1 + knot(p1, p2), t3 = t2 + knot(p2, p3);
  const double t = t1 + u * (t2 - t1);
  const Eigen::Vector3d a1 = (t1 - t) / (t1 - t0) * p0 + (t - t0) / (t1 - t0) * p1;
  const Eigen::Vector3d a2 = (t2 - t) / (t2 - t1) * p1 + (t - t1) / (t2 - t1) * p2;
  const Eigen::Vector3d a3 = (t3 - t) / (t3 - t2) * p2 + (t - t2) / (t3 - t2) * p3;
  const Eigen::Vector3d b1 = (t2 - t) / (t2 - t0) * a1 + (t - t0) / (t2 - t0) * a2;
  const Eigen::Vector3d b2 = (t3 - t) / (t3 - t1) * a2 + (t - t1) / (t3 - t1) * a3;
  return (t2 - t) / (t2 - t1) * b1 + (t - t1) / (t2 - t1) * b2;
}

}  // namespace

std::vector<ControlPoint> readControlPoints(const std::string& path) {
  std::istringstream in(config::readTextFile<MapError>(path, config::kMaxTableBytes));
  std::vector<ControlPoint> out;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    ControlPoint c;
    char comma1 = 0, comma2 = 0;
    if (!(ss >> c.x >> comma1 >> c.y >> comma2 >> c.width) || comma1 != ',' || comma2 != ',') {
      throw MapError(path + ":" + std::to_string(line_no) + ": expected x_m,y_m,width_m");
    }
    out.push_back(c);
  }
  return out;
}

std::vector<CentreLinePoint> resampleClosed(const std::vector<CentreLinePoint>& points, double spacing) {
  return resampleLine(points, spacing, true);
}

std::vector<CentreLinePoint> resampleLine(const std::vector<CentreLinePoint>& points, double spacing, bool closed) {
  if (spacing <= 0) throw std::invalid_argument("resampling spacing must be positive");
  const std::size_t n = points.size();
  if (n < 3) throw std::invalid_argument("a centre line needs at least 3 points");
  const std::size_t segments = closed ? n : n - 1;
  std::vector<double> s(segments + 1, 0.0);
  for (std::size_t i = 0; i < segments; ++i) {
    const auto &a = points[i], &b = points[(i + 1) % n];
    s[i + 1] = s[i] + std::hypot(b.x - a.x, b.y - a.y);
  }
  const double length = s[segments];
  const std::size_t count = std::max<std::size_t>(3, static_cast<std::size_t>(std::round(length / spacing)));
  const double step = length / static_cast<double>(count);
  std::vector<CentreLinePoint> out;
  out.reserve(count + 1);
  std::size_t seg = 0;
  // An open line keeps its last point: count steps lead to it.
  for (std::size_t k = 0; k < count + (closed ? 0 : 1); ++k) {
    if (k == count) {
      out.push_back(points.back());
      break;
    }
    const double target = step * static_cast<double>(k);
    while (seg + 1 < segments && s[seg + 1] <= target) ++seg;
    const auto &a = points[seg], &b = points[(seg + 1) % n];
    const double t = (target - s[seg]) / (s[seg + 1] - s[seg]);
    out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.width_right + t * (b.width_right - a.width_right),
                   a.width_left + t * (b.width_left - a.width_left), a.z + t * (b.z - a.z),
                   a.banking + t * (b.banking - a.banking)});
  }
  return out;
}

std::vector<CentreLinePoint> buildCircuit(const std::vector<ControlPoint>& controls, double spacing) {
  const std::size_t n = controls.size();
  if (n < 3) throw std::invalid_argument("a circuit needs at least 3 control points, got " + std::to_string(n));
  if (spacing <= 0) throw std::invalid_argument("spacing must be positive");
  for (std::size_t i = 0; i < n; ++i) {
    if (controls[i].width <= 0)
      throw std::invalid_argument("control point " + std::to_string(i) + ": width must be positive");
  }
  auto at = [&](std::size_t i) {
    const auto& c = controls[i % n];
    return Eigen::Vector3d(c.x, c.y, c.width);
  };
  // Dense sampling first, then an even resampling by arc length.
  std::vector<CentreLinePoint> dense;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p0 = at(i + n - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
    const double chord = (p2.head<2>() - p1.head<2>()).norm();
    if (chord < 1e-6)
      throw std::invalid_argument("control points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
                                  " coincide");
    const int steps = std::max(4, static_cast<int>(std::ceil(chord / (spacing * 0.1))));
    for (int k = 0; k < steps; ++k) {
      const Eigen::Vector3d p = catmullRom(p0, p1, p2, p3, static_cast<double>(k) / steps);
      dense.push_back({p.x(), p.y(), 0.5 * p.z(), 0.5 * p.z()});
    }
  }
  return resampleClosed(dense, spacing);
}

LoopGap loopGap(const std::vector<CentreLinePoint>& points) {
  LoopGap g;
  if (points.size() < 2) return g;
  std::vector<double> steps;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    steps.push_back(std::hypot(points[i + 1].x - points[i].x, points[i + 1].y - points[i].y));
  }
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  g.median_step = steps[steps.size() / 2];
  g.gap = std::hypot(points.front().x - points.back().x, points.front().y - points.back().y);
  const auto& last = points.back();
  const auto& before = points[points.size() - 2];
  const double step = std::hypot(last.x - before.x, last.y - before.y);
  if (step > 0)
    g.ahead =
        ((points.front().x - last.x) * (last.x - before.x) + (points.front().y - last.y) * (last.y - before.y)) / step;
  return g;
}

std::vector<CentreLinePoint> closeLoopGap(const std::vector<CentreLinePoint>& points) {
  const LoopGap g = loopGap(points);
  std::vector<CentreLinePoint> out = points;
  if (points.size() < 2 || !(g.median_step > 0)) return out;
  const auto pieces = static_cast<int>(std::ceil(g.gap / g.median_step));
  const CentreLinePoint a = points.back(), b = points.front();
  for (int k = 1; k < pieces; ++k) {
    const double f = static_cast<double>(k) / pieces;
    auto mix = [f](double u, double v) { return u + f * (v - u); };
    out.push_back({mix(a.x, b.x), mix(a.y, b.y), mix(a.width_right, b.width_right), mix(a.width_left, b.width_left),
                   mix(a.z, b.z), mix(a.banking, b.banking)});
  }
  return out;
}

std::vector<CentreLinePoint> trimRetracedTail(const std::vector<CentreLinePoint>& points, std::size_t* cut) {
  if (cut) *cut = 0;
  const std::size_t n = points.size();
  if (n < 8) return points;
  auto distance = [&](std::size_t a, std::size_t b) {
    return std::hypot(points[a].x - points[b].x, points[a].y - points[b].y);
  };
  // The head: the first quarter of the course at most. A tail point retraces it when it lies within half
  // the road's width (at least 1 m) of a head point, each further tail point on a head point no earlier
  // than the one before: the same road, the same way.
  const std::size_t head = n / 4;
  std::size_t first_retracing = n, last_match = head;
  for (std::size_t k = n; k-- > head;) {
    const double tolerance = std::max(1.0, 0.5 * (points[k].width_left + points[k].width_right));
    std::size_t best = 0;
    double best_distance = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < head; ++j) {
      const double d = distance(k, j);
      if (d < best_distance) best_distance = d, best = j;
    }
    if (best_distance > tolerance || best > last_match) break;
    last_match = best;
    first_retracing = k;
  }
  // At least two points retracing, and the run reaching back to within 10 m of the start along the road.
  double back_to = 0.0;
  for (std::size_t j = 0; j < last_match; ++j) back_to += distance(j, j + 1);
  if (first_retracing + 2 > n || back_to > 10.0) return points;
  // Cut where the course comes back nearest its first point (the run's first points, or the few before
  // them); a closing step of less than half the median spacing would repeat the start, so that point goes too.
  std::size_t nearest = first_retracing;
  for (std::size_t k = first_retracing >= 5 ? first_retracing - 5 : 0; k < n; ++k) {
    if (distance(k, 0) < distance(nearest, 0)) nearest = k;
  }
  const LoopGap g = loopGap(points);
  const std::size_t keep = distance(nearest, 0) < 0.5 * g.median_step ? nearest : nearest + 1;
  if (cut) *cut = n - keep;
  return std::vector<CentreLinePoint>(points.begin(), points.begin() + static_cast<long>(keep));
}

}  // namespace roar::track
