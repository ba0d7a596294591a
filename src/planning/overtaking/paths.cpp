// The paths a lateral move follows: the road's room beside the racing line, the racing line's window
// moved sideways and its speeds planned afresh, and the same towed in a slipstream.
#include <algorithm>
#include <cmath>
#include <limits>

#include "roar/planning/overtaking/planner.h"
#include "roar/planning/speed_profile.h"
#include "roar/track/heading.h"
#include "roar/track/track.h"
#include "tuning.h"

namespace roar::planning {

using namespace tuning;

namespace {

// w log(1 + e^(x / w)): x for x well above 0, 0 well below, and a bend of about 2w between.
double softPlus(double x, double w) { return x > 20.0 * w ? x : w * std::log1p(std::exp(x / w)); }

double smoothStep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

// `length` 0: an open line's values, clamped at its ends.
double interpolateWrapped(const std::vector<double>& xs, const std::vector<double>& ys, double length, double x) {
  if (length <= 0) x = std::clamp(x, xs.front(), xs.back() - 1e-9);
  if (length > 0) x -= std::floor(x / length) * length;
  auto it = std::upper_bound(xs.begin(), xs.end(), x);
  const std::size_t b = static_cast<std::size_t>(it - xs.begin()) % xs.size();
  const std::size_t a = (b + xs.size() - 1) % xs.size();
  double span = xs[b] - xs[a];
  double along = x - xs[a];
  if (span <= 0) span += length;
  if (along < 0) along += length;
  const double f = span > 0 ? std::clamp(along / span, 0.0, 1.0) : 0.0;
  return ys[a] + f * (ys[b] - ys[a]);
}

}  // namespace

OvertakePlanner::OvertakePlanner(const track::Track& track, Trajectory line, const VehicleLimits& limits,
                                 OvertakeOptions options)
    : line_(std::move(line)), limits_(limits), options_(options) {
  validate(line_);
  bool first = true;
  double near = 0.0;
  for (const auto& p : line_.points) {
    const track::Projection pr = first ? track.project(p.position) : track.projectNear(p.position, near, 50.0);
    first = false;
    near = pr.s;
    room_s_.push_back(p.s);
    room_left_.push_back(pr.width_left - pr.lateral);
    room_right_.push_back(pr.width_right + pr.lateral);
  }
}

double OvertakePlanner::roomLeft(double s) const {
  return interpolateWrapped(room_s_, room_left_, lapLength(line_), s);
}
double OvertakePlanner::roomRight(double s) const {
  return interpolateWrapped(room_s_, room_right_, lapLength(line_), s);
}

double OvertakePlanner::laneNeed(double margin_share) const {
  return 1.5 * options_.car.width + margin_share * options_.margins.lateral + options_.margins.edge;
}

double OvertakePlanner::laneShare(int side, double run) const {
  const double length = line_.closed ? lapLength(line_) : line_.points.back().s - line_.points.front().s;
  const auto n = static_cast<std::size_t>(std::floor(length / kLaneStep));
  if (n == 0) return 0.0;
  const double need = laneNeed(1.0);
  std::vector<char> lane(n);
  const double s0 = line_.points.front().s;
  for (std::size_t i = 0; i < n; ++i) {
    const double at = s0 + kLaneStep * static_cast<double>(i);
    lane[i] = (side > 0 ? roomLeft(at) : roomRight(at)) >= need;
  }
  // Metres of lane from each point on, backwards round the lap (twice, for a closed line's wrap).
  std::vector<double> on(n, 0.0);
  const std::size_t passes = line_.closed ? 2 : 1;
  double ahead = 0.0;
  for (std::size_t k = passes * n; k-- > 0;) {
    const std::size_t i = k % n;
    ahead = lane[i] ? ahead + kLaneStep : 0.0;
    on[i] = std::min(ahead, length);
  }
  const auto starts = std::count_if(on.begin(), on.end(), [&](double m) { return m > 0.0 && m >= run; });
  return static_cast<double>(starts) / static_cast<double>(n);
}

double OvertakePlanner::laneRun(int side, double s, double beside, double longest) const {
  // A pass's lane as one under way keeps it: half its air from the car.
  const double need = beside + laneNeed(0.5);
  double run = 0.0;
  for (; run < longest; run += options_.prediction.sample_step) {
    if ((side > 0 ? roomLeft(s + run) : roomRight(s + run)) < need) break;
  }
  return std::min(run, longest);
}

OvertakePlanner::Move OvertakePlanner::Move::of(const RaceDecision& d) {
  Move m;
  m.ramp_s = d.ramp_s;
  m.from = d.ramp_from;
  m.to = d.offset;
  m.ramp_speed = d.ramp_speed;
  return m;
}

double OvertakePlanner::shiftLength(const Move& move) const {
  // shift_time is for a move of a car's width and air (3 m); a longer one takes longer, so that it asks
  // no more sideways acceleration (which grows with the move and falls with the square of its length).
  const double across = std::max(std::abs(move.to - move.from), std::abs(move.to));
  const double stretch = std::sqrt(std::max(1.0, across / (options_.car.width + options_.margins.lateral + kMoveAir)));
  // At the car's speed, not the line's: behind a slow car the line's speed is far above it, and a move
  // sized for the line would be several times as long, the guard holding the passer to the slow car's speed
  // until it was clear of it sideways.
  const double line_speed = sampleAt(line_, move.ramp_s).speed;
  const double move_speed = move.ramp_speed > 0.0 ? std::min(move.ramp_speed, line_speed) : line_speed;
  return std::max(options_.moves.min_shift_length, stretch * options_.moves.shift_time * move_speed);
}

std::pair<double, double> OvertakePlanner::passBounds(double s) const {
  // The edge margin from either edge (the right one where the road is narrower than both margins).
  const double half = 0.5 * options_.car.width + options_.margins.edge;
  const double lo = half - roomRight(s);
  return {lo, std::max(lo, roomLeft(s) - half)};
}

std::vector<double> OvertakePlanner::moveWindow(Trajectory* window, Move move) const {
  const double shift_length = shiftLength(move);
  const double half = 0.5 * options_.car.width + options_.margins.edge;
  // A pass keeps the edge margin, so where the racing line runs nearer the edge than that (along an edge
  // before and after a corner) the car is pushed off it at once. The move starts from there: a ramp from
  // the car's place on the line would be held flat on that bound and then leave it, a kink the pass's
  // speeds would brake for on a straight.
  if (move.pass) {
    const auto [lo, hi] = passBounds(move.ramp_s);
    move.from = std::clamp(move.from, lo, hi);
  }
  auto& pts = window->points;
  std::vector<double> d(pts.size(), 0.0);  // m each point is moved left off the racing line
  for (std::size_t k = 0; k < pts.size(); ++k) {
    auto& p = pts[k];
    double shift =
        move.from + (move.to - move.from) * smoothStep(aheadOnLap(p.s, move.ramp_s, lapLength(line_)) / shift_length);
    if (std::isfinite(move.back_s) && p.s > move.back_s)
      shift -= move.to * smoothStep((p.s - move.back_s) / shift_length);
    // Inside the road by the margin. Any move but a pass comes no nearer the edge than the racing line
    // itself does (at an apex it runs nearer): a path moved by nothing is the racing line. A pass keeps
    // the margin even there, pushed off the line (see above).
    if (move.pass) {
      // Bent onto the margins smoothly, not clamped: where the line runs to an edge (an apex, a straight
      // along it) a clamped pass meets the margin at an angle and leaves it again, kinks its speeds brake for.
      const auto [lo, hi] = passBounds(p.s);
      const double above = lo + softPlus(shift - lo, kMarginBend);
      d[k] = std::clamp(hi - softPlus(hi - above, kMarginBend), lo, hi);
    } else {
      d[k] = std::clamp(shift, std::min(0.0, half - roomRight(p.s)), std::max(0.0, roomLeft(p.s) - half));
    }
    p.position += d[k] * track::leftOf(p.yaw);
    p.offset += d[k];
  }
  return d;
}

namespace {

// A pass is planned on the curvature of its moved points, differenced: rougher than the exact one
// (up to half as much again at the line's small kinks and where the edge margin pushes it off at an apex),
// so slower, and a pass is begun only where it gains on that. Planned exactly, passes are begun that the
// next corner squeezes: roar_bench --traffic --seeds=6 completed 88.7% of 353 attempts that way, 92.1% of
// 353 this way. Sets each point's heading; returns the curvatures.
std::vector<double> differencedCurvature(std::vector<TrajectoryPoint>* points, const std::vector<double>& step) {
  auto& pts = *points;
  const std::size_t n = pts.size();
  std::vector<double> curvature(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = k == 0 ? 0 : k - 1, b = std::min(n - 1, k + 1);
    const Eigen::Vector2d chord = pts[b].position - pts[a].position;
    pts[k].yaw = std::atan2(chord.y(), chord.x());
  }
  for (std::size_t k = 1; k + 1 < n; ++k) {
    double dyaw = pts[k + 1].yaw - pts[k - 1].yaw;
    dyaw = std::atan2(std::sin(dyaw), std::cos(dyaw));
    curvature[k] = dyaw / (step[k - 1] + step[k]);
  }
  curvature[0] = curvature[1];
  curvature[n - 1] = curvature[n - 2];
  return curvature;
}

// The moved path's heading and curvature exactly, from the racing line's own (smooth) ones and the offset's
// derivatives along the line (Frenet): differenced from the moved points, a move back onto the line was
// planned up to 10 m/s slower than the line where it was already back on it. Turns each point's heading by
// the move's; returns the curvatures.
std::vector<double> frenetCurvature(std::vector<TrajectoryPoint>* points, const std::vector<double>& d) {
  auto& pts = *points;
  const std::size_t n = pts.size();
  std::vector<double> curvature(n, 0.0), heading(n, 0.0), path_per_line(n, 1.0);
  auto along = [&](std::size_t a, std::size_t b) { return std::max(1e-3, pts[b].s - pts[a].s); };
  // The neighbours a derivative at k is taken between: the next points either side, but at least
  // kMinSpan apart. A window begins at a point sampled anywhere on the line, often centimetres before the
  // line's next point, and over those centimetres the offset's slope (and the heading's) differed enough
  // to plan the window's first point as a hairpin and the car at a third of the line's speed.
  auto span = [&](std::size_t k) {
    std::size_t a = k == 0 ? 0 : k - 1, b = std::min(n - 1, k + 1);
    while (pts[b].s - pts[a].s < kMinSpan && (a > 0 || b + 1 < n)) {
      if (b + 1 < n)
        ++b;
      else
        --a;
    }
    return std::pair{a, b};
  };
  for (std::size_t k = 0; k < n; ++k) {
    const auto [a, b] = span(k);
    const double d_prime = (d[b] - d[a]) / along(a, b);
    const double squeeze = 1.0 - pts[k].curvature * d[k];  // metres of moved path per metre of line, across
    heading[k] = std::atan2(d_prime, squeeze);
    path_per_line[k] = std::max(1e-3, std::hypot(squeeze, d_prime));
  }
  for (std::size_t k = 0; k < n; ++k) {
    const auto [a, b] = span(k);
    curvature[k] = (pts[k].curvature + (heading[b] - heading[a]) / along(a, b)) / path_per_line[k];
    pts[k].yaw = std::remainder(pts[k].yaw + heading[k], 2.0 * M_PI);
  }
  return curvature;
}

}  // namespace

void OvertakePlanner::planMovedSpeeds(Trajectory* window, const std::vector<double>& d, const std::vector<double>& step,
                                      const std::vector<double>& curvature, const MoveGrip& grip) const {
  auto& pts = window->points;
  const std::size_t n = pts.size();
  SpeedProfileOptions profile_options;
  profile_options.start_speed = -1.0;
  profile_options.grade = slopes(*window);
  // Where the path moves across the line the car is moving sideways as well: it is planned there with a
  // share of the grip (the whole grip at a steady offset and back on the line: a pass's window after it).
  VehicleLimits limits = limits_;
  limits.drag_coefficient *= grip.drag_share;
  VehicleLimits offline = limits;
  offline.friction *= options_.moves.offline_grip;
  VehicleLimits settling_limits = limits;
  settling_limits.friction *= options_.moves.settle_grip;
  auto settlingAt = [&](std::size_t k) {
    return std::isfinite(grip.settle_s) && aheadOnLap(pts[k].s, grip.settle_s, lapLength(line_)) < 0.0;
  };
  const SpeedProfile on_grip = computeSpeedProfile(step, curvature, limits, false, profile_options);
  const SpeedProfile off_grip = computeSpeedProfile(step, curvature, offline, false, profile_options);
  const SpeedProfile settle_grip = n > 0 && settlingAt(0)
                                       ? computeSpeedProfile(step, curvature, settling_limits, false, profile_options)
                                       : SpeedProfile{};
  for (std::size_t k = 0; k < n; ++k) {
    pts[k].curvature = curvature[k];
    // A path moving across the line is planned on offline_grip (sideways motion takes grip); at a steady
    // offset it is a line of its own and has all of it (overtaking_test
    // APassHasAllTheGripWhereItHoldsASteadyOffsetAndLessWhereItMovesAcross). The same for every move: a car
    // holding its place at the offset it passed at is on the same path and grip as the pass was.
    const std::size_t a = k == 0 ? 0 : k - 1, b = std::min(n - 1, k + 1);
    const double slope = std::abs(d[b] - d[a]) / std::max(1e-3, pts[b].s - pts[a].s);
    const bool moving_across = slope > kSteadyOffsetSlope;
    const double off = std::abs(d[k]) > 0.05 && moving_across ? 1.0 : 0.0;
    pts[k].speed = std::min(pts[k].speed, on_grip.speed[k] + off * (off_grip.speed[k] - on_grip.speed[k]));
    if (settlingAt(k)) pts[k].speed = std::min(pts[k].speed, settle_grip.speed[k]);
  }
  for (std::size_t k = n - 1; k-- > 0;) {  // braking for the slower points the caps made
    const VehicleLimits& braking = settlingAt(k + 1) ? settling_limits : offline;
    const double a = decelerationAt(braking, pts[k + 1].speed, pts[k + 1].curvature, profile_options.grade[k]);
    pts[k].speed = std::min(pts[k].speed, std::sqrt(pts[k + 1].speed * pts[k + 1].speed + 2.0 * a * step[k]));
  }
  window->lap_time = 0.0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    pts[k].acceleration = (pts[k + 1].speed * pts[k + 1].speed - pts[k].speed * pts[k].speed) / (2.0 * step[k]);
    const double mean = 0.5 * (pts[k].speed + pts[k + 1].speed);
    if (mean > 1e-6) window->lap_time += step[k] / mean;
  }
  pts.back().acceleration = 0.0;
}

Trajectory OvertakePlanner::shifted(const Trajectory& window, const Move& move, const MoveGrip& grip) const {
  Trajectory out = window;
  const std::vector<double> d = moveWindow(&out, move);
  const std::size_t n = out.points.size();
  if (n < 3) return out;
  std::vector<double> step(n, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    step[k] = std::max(1e-3, (out.points[k + 1].position - out.points[k].position).norm());
  }
  const std::vector<double> curvature =
      move.pass ? differencedCurvature(&out.points, step) : frenetCurvature(&out.points, d);
  planMovedSpeeds(&out, d, step, curvature, grip);
  return out;
}

Trajectory OvertakePlanner::shifted(const Trajectory& window, const RaceDecision& move, double settle_s) const {
  MoveGrip grip;
  grip.settle_s = settle_s;
  return shifted(window, Move::of(move), grip);
}

Trajectory OvertakePlanner::towed(const Trajectory& window, double drag_share) const {
  Trajectory out = window;
  auto& pts = out.points;
  const std::size_t n = pts.size();
  if (n < 3 || drag_share >= 1.0) return out;
  std::vector<double> step(n, 1.0), curvature(n, 0.0), speed(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    if (k + 1 < n) step[k] = std::max(1e-3, pts[k + 1].s - pts[k].s);
    curvature[k] = pts[k].curvature;
    speed[k] = pts[k].speed;
  }
  const std::vector<double> faster = towedSpeeds(step, curvature, speed, limits_, drag_share);
  for (std::size_t k = 0; k < n; ++k) pts[k].speed = faster[k];
  return out;
}

}  // namespace roar::planning
