#include "roar/planning/racing_line.h"

#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <string>

#include "roar/track/heading.h"

namespace roar::planning {

namespace {

// Even resampling of a polyline; an open one keeps both its ends.
std::vector<Eigen::Vector2d> resample(const std::vector<Eigen::Vector2d>& pts, double step, bool closed) {
  const std::size_t n = pts.size(), segments = closed ? n : n - 1;
  std::vector<double> cumulative(segments + 1, 0.0);
  for (std::size_t i = 0; i < segments; ++i) cumulative[i + 1] = cumulative[i] + (pts[(i + 1) % n] - pts[i]).norm();
  const double length = cumulative[segments];
  const std::size_t count = std::max<std::size_t>(8, static_cast<std::size_t>(std::round(length / step)));
  const double ds = length / static_cast<double>(count);
  std::vector<Eigen::Vector2d> out;
  out.reserve(count + 1);
  std::size_t seg = 0;
  for (std::size_t k = 0; k < count + (closed ? 0 : 1); ++k) {
    if (k == count) {
      out.push_back(pts.back());
      break;
    }
    const double s = k * ds;
    while (seg + 1 < segments && cumulative[seg + 1] <= s) ++seg;
    const double len = cumulative[seg + 1] - cumulative[seg];
    const double t = len > 0 ? (s - cumulative[seg]) / len : 0.0;
    out.push_back((1 - t) * pts[seg] + t * pts[(seg + 1) % n]);
  }
  return out;
}

// Solves min 0.5 x'Hx + g'x subject to lo <= x <= hi with a primal active-set method (projected Newton):
// variables at a bound whose gradient pushes outwards are held there, the others solved exactly with a
// sparse Cholesky factorisation, and the result projected on the box, until the active set settles.
// The curvature objective is nearly flat along some directions (moving the whole line sideways), where
// first-order methods such as ADMM crawl; exact solves do not.
Eigen::VectorXd solveBoxQp(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& g, const Eigen::VectorXd& lo,
                           const Eigen::VectorXd& hi) {
  const Eigen::Index n = g.size();
  // A rigid shift of the line has no curvature: a whisper of regularisation makes H definite.
  Eigen::SparseMatrix<double> Hr = H;
  for (Eigen::Index i = 0; i < n; ++i) Hr.coeffRef(i, i) += 1e-10;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n).cwiseMax(lo).cwiseMin(hi);
  std::vector<signed char> state(static_cast<std::size_t>(n), 0);  // -1 at lo, +1 at hi, 0 free
  for (int iteration = 0; iteration < 200; ++iteration) {
    const Eigen::VectorXd gradient = Hr * x + g;
    bool changed = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      signed char next = 0;
      if (x[i] <= lo[i] && gradient[i] > 0) next = -1;
      if (x[i] >= hi[i] && gradient[i] < 0) next = 1;
      changed = changed || next != state[static_cast<std::size_t>(i)];
      state[static_cast<std::size_t>(i)] = next;
    }
    if (!changed && iteration > 0) break;
    // Free variables: H_FF x_F = -(g_F + H_FA x_A).
    std::vector<Eigen::Index> free_index(static_cast<std::size_t>(n), -1);
    Eigen::Index free_count = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (state[static_cast<std::size_t>(i)] == 0) free_index[static_cast<std::size_t>(i)] = free_count++;
    }
    if (free_count == 0) break;
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(free_count);
    for (Eigen::Index col = 0; col < Hr.outerSize(); ++col) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(Hr, col); it; ++it) {
        const Eigen::Index r = free_index[static_cast<std::size_t>(it.row())];
        if (r < 0) continue;
        const Eigen::Index c = free_index[static_cast<std::size_t>(col)];
        if (c >= 0) {
          entries.emplace_back(r, c, it.value());
        } else {
          rhs[r] -= it.value() * x[col];
        }
      }
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Index r = free_index[static_cast<std::size_t>(i)];
      if (r >= 0) rhs[r] -= g[i];
    }
    Eigen::SparseMatrix<double> K(free_count, free_count);
    K.setFromTriplets(entries.begin(), entries.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(K);
    if (solver.info() != Eigen::Success) throw RacingLineError("racing line: the curvature QP could not be factored");
    const Eigen::VectorXd free_x = solver.solve(rhs);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Index r = free_index[static_cast<std::size_t>(i)];
      if (r >= 0) x[i] = std::clamp(free_x[r], lo[i], hi[i]);
    }
  }
  return x;
}

// Root mean square of the change in curvature, compared at equal fractions of each line's length.
double curvatureChange(const RacingLine& a, const RacingLine& b) {
  double change = 0.0;
  for (std::size_t i = 0; i < b.points.size(); ++i) {
    const double f = b.s[i] / b.length * a.length;
    const std::size_t j = std::min(
        a.points.size() - 1, static_cast<std::size_t>(std::upper_bound(a.s.begin(), a.s.end(), f) - a.s.begin()) - 1);
    const std::size_t k = (j + 1) % a.points.size();
    const double t = a.step[j] > 0 ? std::clamp((f - a.s[j]) / a.step[j], 0.0, 1.0) : 0.0;
    const double d = b.curvature[i] - ((1 - t) * a.curvature[j] + t * a.curvature[k]);
    change += d * d;
  }
  return std::sqrt(change / static_cast<double>(b.points.size()));
}

}  // namespace

void computeShape(const std::vector<Eigen::Vector2d>& p, std::vector<double>* step, std::vector<double>* heading,
                  std::vector<double>* curvature, bool closed) {
  const std::size_t n = p.size();
  step->assign(n, 0.0);
  heading->assign(n, 0.0);
  curvature->assign(n, 0.0);
  if (!closed) {
    // An open line's ends: heading along their one step, curvature the nearest point's that has two
    // neighbours each side.
    for (std::size_t i = 0; i + 1 < n; ++i) (*step)[i] = (p[i + 1] - p[i]).norm();
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d chord = p[std::min(i + 1, n - 1)] - p[i == 0 ? 0 : i - 1];
      (*heading)[i] = std::atan2(chord.y(), chord.x());
      if (n < 5) continue;
      const std::size_t m = std::clamp<std::size_t>(i, 2, n - 3);
      const Eigen::Vector2d &a = p[m - 2], &b = p[m], &c = p[m + 2];
      const double cross = (b - a).x() * (c - b).y() - (b - a).y() * (c - b).x();
      (*curvature)[i] = 2.0 * cross / ((b - a).norm() * (c - b).norm() * (c - a).norm());
    }
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    (*step)[i] = (p[(i + 1) % n] - p[i]).norm();
    // Heading from the neighbours; curvature of the circle through the points two either side, which
    // averages out the millimetre jitter that resampling leaves.
    const Eigen::Vector2d& a = p[(i + n - 2) % n];
    const Eigen::Vector2d& b = p[i];
    const Eigen::Vector2d& c = p[(i + 2) % n];
    const Eigen::Vector2d chord = p[(i + 1) % n] - p[(i + n - 1) % n];
    (*heading)[i] = std::atan2(chord.y(), chord.x());
    const double cross = (b - a).x() * (c - b).y() - (b - a).y() * (c - b).x();
    (*curvature)[i] = 2.0 * cross / ((b - a).norm() * (c - b).norm() * (c - a).norm());
  }
}

void computeGeometry(const track::Track& track, RacingLine* line) {
  const auto& p = line->points;
  const std::size_t n = p.size();
  computeShape(p, &line->step, &line->heading, &line->curvature, line->closed);
  line->s.assign(n, 0.0);
  line->track_s.assign(n, 0.0);
  line->offset.assign(n, 0.0);
  for (std::size_t i = 1; i < n; ++i) line->s[i] = line->s[i - 1] + line->step[i - 1];
  line->length = line->s.back() + (line->closed ? line->step.back() : 0.0);
  double near = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const track::Projection pr = i == 0 ? track.project(p[i]) : track.projectNear(p[i], near, 80.0);
    near = pr.s;
    line->track_s[i] = pr.s;
    line->offset[i] = pr.lateral;
  }
}

RacingLine centreLine(const track::Track& track, double step) {
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(track.size());
  for (std::size_t i = 0; i < track.size(); ++i) pts.push_back(track.position(i));
  RacingLine line;
  line.closed = track.closed();
  line.points = resample(pts, step, line.closed);
  computeGeometry(track, &line);
  return line;
}

RacingLine minimumCurvatureLine(const track::Track& track, const RacingLineOptions& options) {
  if (!(options.step > 0) || !(options.vehicle_width > 0) || options.safety_margin < 0 || options.max_iterations < 1) {
    throw RacingLineError("racing line: step and vehicle width must be positive, margin and iterations not negative");
  }
  const double keep = 0.5 * options.vehicle_width + options.safety_margin;
  RacingLine line = centreLine(track, options.step);
  double step_share = 1.0;  // of each solve's move taken
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    const std::size_t n = line.points.size();
    std::vector<Eigen::Vector2d> normal(n);
    Eigen::VectorXd lo(n), hi(n);
    for (std::size_t i = 0; i < n; ++i) {
      normal[i] = track::leftOf(line.heading[i]);
      const track::TrackPose pose = track.poseAt(line.track_s[i]);
      const double cos_diff = std::max(0.2, std::cos(track::wrapAngle(line.heading[i] - pose.heading)));
      const double left = pose.width_left - keep - line.offset[i], right = -(pose.width_right - keep) - line.offset[i];
      if (pose.width_left + pose.width_right < 2.0 * keep) {
        throw RacingLineError("racing line: the track is " + std::to_string(pose.width_left + pose.width_right) +
                              " m wide at s = " + std::to_string(line.track_s[i]) +
                              " m, narrower than the car and its safety margins (" + std::to_string(2 * keep) + " m)");
      }
      lo[static_cast<Eigen::Index>(i)] = right / cos_diff;
      hi[static_cast<Eigen::Index>(i)] = left / cos_diff;
    }
    // Second difference of point i: p[i-1] - 2 p[i] + p[i+1], with p = r + alpha n: linear in alpha.
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(6 * n);
    Eigen::VectorXd d(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
      if (!line.closed && (i == 0 || i + 1 == n)) {
        // An open line's ends have one neighbour: no curvature of their own to minimise.
        for (int axis = 0; axis < 2; ++axis) d[static_cast<int>(2 * i + axis)] = 0.0;
        continue;
      }
      const std::size_t a = (i + n - 1) % n, c = (i + 1) % n;
      const Eigen::Vector2d second = line.points[a] - 2.0 * line.points[i] + line.points[c];
      for (int axis = 0; axis < 2; ++axis) {
        const auto row = static_cast<int>(2 * i + axis);
        d[row] = second[axis];
        entries.emplace_back(row, static_cast<int>(a), normal[a][axis]);
        entries.emplace_back(row, static_cast<int>(i), -2.0 * normal[i][axis]);
        entries.emplace_back(row, static_cast<int>(c), normal[c][axis]);
      }
    }
    Eigen::SparseMatrix<double> A(static_cast<Eigen::Index>(2 * n), static_cast<Eigen::Index>(n));
    A.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SparseMatrix<double> H = Eigen::SparseMatrix<double>(A.transpose()) * A;
    const Eigen::VectorXd g = A.transpose() * d;
    const Eigen::VectorXd alpha = solveBoxQp(H, g, lo, hi);

    std::vector<Eigen::Vector2d> moved(n);
    for (std::size_t i = 0; i < n; ++i) {
      moved[i] = line.points[i] + step_share * alpha[static_cast<Eigen::Index>(i)] * normal[i];
    }
    RacingLine next;
    next.closed = line.closed;
    next.points = resample(moved, options.step, next.closed);
    computeGeometry(track, &next);
    // Resampling may cut a corner by a few millimetres: keep every point inside the margins.
    bool clamped = false;
    for (std::size_t i = 0; i < next.points.size(); ++i) {
      const track::TrackPose pose = track.poseAt(next.track_s[i]);
      const double limited = std::clamp(next.offset[i], -(pose.width_right - keep), pose.width_left - keep);
      if (limited != next.offset[i]) {
        next.points[i] += (limited - next.offset[i]) * track::leftOf(pose.heading);
        clamped = true;
      }
    }
    if (clamped) computeGeometry(track, &next);
    next.iterations = iteration;
    next.last_curvature_change = curvatureChange(line, next);
    // A line that changes no less than it did the time before is swinging between two shapes (a corner's
    // constraint on and off the edge in turn): the moves are halved from then on, until it settles.
    if (iteration > 1 && next.last_curvature_change >= line.last_curvature_change) step_share *= 0.5;
    line = std::move(next);
    if (line.last_curvature_change < options.curvature_tolerance) break;
  }
  return line;
}

}  // namespace roar::planning
