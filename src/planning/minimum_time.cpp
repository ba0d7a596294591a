#include "roar/planning/minimum_time.h"

#include <algorithm>
#include <cmath>

#include "roar/track/heading.h"

namespace roar::planning {

namespace {

// The line and its lap time for knot offsets `u` (interpolated linearly to every point).
struct LapTimeOfOffsets {
  const std::vector<Eigen::Vector2d>& reference;
  const std::vector<Eigen::Vector2d>& normal;
  const std::vector<double>& lo;
  const std::vector<double>& hi;
  const VehicleLimits& limits;
  int spacing;

  std::vector<Eigen::Vector2d> points(const std::vector<double>& u) const {
    const std::size_t n = reference.size(), knots = u.size();
    std::vector<Eigen::Vector2d> p(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t k = i / static_cast<std::size_t>(spacing);
      const double t = static_cast<double>(i % static_cast<std::size_t>(spacing)) / spacing;
      const double alpha = std::clamp((1 - t) * u[k % knots] + t * u[(k + 1) % knots], lo[i], hi[i]);
      p[i] = reference[i] + alpha * normal[i];
    }
    return p;
  }

  double operator()(const std::vector<double>& u) const {
    std::vector<double> step, heading, curvature;
    computeShape(points(u), &step, &heading, &curvature);
    return computeSpeedProfile(step, curvature, limits, true).total_time;
  }
};

}  // namespace

MinimumTimeResult minimumTimeLine(const track::Track& track, const RacingLine& start, const VehicleLimits& limits,
                                  const RacingLineOptions& margins, const MinimumTimeOptions& options) {
  if (!start.closed) throw RacingLineError("minimum_time: refines a circuit's line; this is a point-to-point course");
  const std::size_t n = start.points.size();
  const double keep = 0.5 * margins.vehicle_width + margins.safety_margin;
  std::vector<Eigen::Vector2d> normal(n);
  std::vector<double> lo(n), hi(n);
  for (std::size_t i = 0; i < n; ++i) {
    normal[i] = track::leftOf(start.heading[i]);
    const track::TrackPose pose = track.poseAt(start.track_s[i]);
    lo[i] = std::min(0.0, -(pose.width_right - keep) - start.offset[i]);
    hi[i] = std::max(0.0, pose.width_left - keep - start.offset[i]);
  }
  const int spacing = std::max(1, options.knot_spacing);
  const std::size_t knots = (n + static_cast<std::size_t>(spacing) - 1) / static_cast<std::size_t>(spacing);
  // A knot may go only where every point it shapes may go.
  std::vector<double> knot_lo(knots, -1e9), knot_hi(knots, 1e9);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = i / static_cast<std::size_t>(spacing);
    for (std::size_t j : {k % knots, (k + 1) % knots}) {
      knot_lo[j] = std::max(knot_lo[j], lo[i]);
      knot_hi[j] = std::min(knot_hi[j], hi[i]);
    }
  }
  const LapTimeOfOffsets lapTime{start.points, normal, lo, hi, limits, spacing};

  // Pattern search with smooth bumps: each knot in turn is pushed left and right by `move`, spread over
  // its neighbours with a cosine window (a wide bump keeps the line smooth, which a one-knot kink would
  // not); a push is kept when the lap gets faster. Bumps narrow and moves shrink as the search settles.
  // Lap time is not smooth in the offsets (the profile takes minima), which defeats gradient descent.
  std::vector<double> u(knots, 0.0), trial(knots);
  MinimumTimeResult result;
  result.start_lap_time = lapTime(u);
  double best = result.start_lap_time;
  int sweeps = 0;
  for (int half_width : {12, 6, 3}) {
    for (double move = options.first_move; move >= options.stop_move && sweeps < options.max_iterations; move *= 0.5) {
      bool improved = true;
      while (improved && sweeps < options.max_iterations) {
        improved = false;
        ++sweeps;
        for (std::size_t k = 0; k < knots; ++k) {
          for (double sign : {1.0, -1.0}) {
            trial = u;
            for (int d = -half_width; d <= half_width; ++d) {
              const std::size_t j = (k + knots + static_cast<std::size_t>(d + static_cast<int>(knots))) % knots;
              const double w = 0.5 * (1.0 + std::cos(M_PI * d / (half_width + 1)));
              trial[j] = std::clamp(u[j] + sign * move * w, knot_lo[j], knot_hi[j]);
            }
            const double time = lapTime(trial);
            if (time < best - 1e-6) {
              best = time;
              u = trial;
              improved = true;
              break;
            }
          }
        }
      }
    }
  }
  result.iterations = sweeps;
  result.lap_time = best;
  result.line.points = lapTime.points(u);
  computeGeometry(track, &result.line);
  result.line.iterations = result.iterations;
  return result;
}

}  // namespace roar::planning
