#include "roar/planning/trajectory.h"

#include "roar/planning/minimum_time.h"
#include "roar/track/track.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace roar::planning {

namespace {

// Distance from point i to the next (the last of a closed trajectory back to the first).
double stepAfter(const Trajectory& t, std::size_t i) {
  if (i + 1 < t.points.size()) return t.points[i + 1].s - t.points[i].s;
  return t.closed ? t.length - t.points[i].s + t.points.front().s : 0.0;
}

// The time from the start line to the finish line of a course a profile promises, given the track progress
// of its points (rising along an open line) and their times.
double raceTime(const track::Track& track, const std::vector<double>& track_s, const std::vector<double>& time) {
  auto timeAt = [&](double line_s) {
    const auto it = std::lower_bound(track_s.begin(), track_s.end(), line_s);
    const std::size_t j =
        std::clamp<std::size_t>(static_cast<std::size_t>(it - track_s.begin()), 1, track_s.size() - 1);
    const double span = track_s[j] - track_s[j - 1];
    const double f = span > 0 ? std::clamp((line_s - track_s[j - 1]) / span, 0.0, 1.0) : 0.0;
    return (1 - f) * time[j - 1] + f * time[j];
  };
  return timeAt(track.finishLine()) - timeAt(track.info().start_finish_s);
}

// Per point, the sine of the slope to the next point from heights z and the steps between them; an open
// line's last point: the slope to it.
std::vector<double> gradesAlong(const std::vector<double>& z, const std::vector<double>& step, bool closed) {
  const std::size_t n = z.size();
  std::vector<double> grade(n, 0.0);
  for (std::size_t i = 0; i < (closed ? n : n - 1); ++i) {
    const double rise = z[(i + 1) % n] - z[i];
    grade[i] = step[i] > 0 ? rise / std::hypot(step[i], rise) : 0.0;
  }
  if (!closed && n >= 2) grade[n - 1] = grade[n - 2];
  return grade;
}

// Per point, the road's curvature in the vertical plane (1/m, negative over a crest), from its heights
// kVerticalSpan either side: a centimetre of noise between points, as a surveyed or CARLA map has, is no
// crest (roar_bench: Monza's lap holds).
std::vector<double> verticalCurvaturesAlong(const std::vector<double>& z, const std::vector<double>& step,
                                            bool closed) {
  constexpr double kVerticalSpan = 15.0;  // m
  const std::size_t n = z.size();
  std::vector<double> at(n, 0.0);  // distance of each point from the first
  for (std::size_t i = 1; i < n; ++i) at[i] = at[i - 1] + step[i - 1];
  const double length = closed ? at.back() + step.back() : at.back();
  auto heightAt = [&](double d) {
    if (closed) d -= std::floor(d / length) * length;
    if (d <= 0) return z.front();
    if (!closed && d >= at.back()) return z.back();
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(at.begin(), at.end(), d) - at.begin()) - 1;
    const double next_z = k + 1 < n ? z[k + 1] : z.front(), next_at = k + 1 < n ? at[k + 1] : length;
    const double t = next_at > at[k] ? (d - at[k]) / (next_at - at[k]) : 0.0;
    return (1 - t) * z[k] + t * next_z;
  };
  std::vector<double> kappa(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!closed && (at[i] < kVerticalSpan || at[i] > at.back() - kVerticalSpan)) continue;
    kappa[i] = (heightAt(at[i] + kVerticalSpan) - 2.0 * z[i] + heightAt(at[i] - kVerticalSpan)) /
               (kVerticalSpan * kVerticalSpan);
  }
  return kappa;
}

// The racing line's heights at its points, from the road's.
std::vector<double> roadHeights(const track::Track& track, const RacingLine& line) {
  std::vector<double> z(line.points.size());
  for (std::size_t i = 0; i < z.size(); ++i) z[i] = track.surfaceHeightAt(line.track_s[i], line.offset[i]);
  return z;
}

}  // namespace

void validate(const Trajectory& t) {
  if (t.points.size() < 2)
    throw TrajectoryError("trajectory: needs at least 2 points, has " + std::to_string(t.points.size()));
  for (std::size_t i = 0; i < t.points.size(); ++i) {
    const auto& p = t.points[i];
    const std::pair<const char*, double> fields[] = {{"x", p.position.x()},
                                                     {"y", p.position.y()},
                                                     {"z", p.z},
                                                     {"yaw", p.yaw},
                                                     {"s", p.s},
                                                     {"curvature", p.curvature},
                                                     {"speed", p.speed},
                                                     {"acceleration", p.acceleration}};
    for (const auto& [name, value] : fields) {
      if (!std::isfinite(value)) {
        throw TrajectoryError("trajectory: point " + std::to_string(i) + " has a non-finite " + name);
      }
    }
    if (p.speed < 0) throw TrajectoryError("trajectory: point " + std::to_string(i) + " has a negative speed");
    if (i > 0 && !(p.s > t.points[i - 1].s)) {
      throw TrajectoryError("trajectory: s does not increase at point " + std::to_string(i));
    }
  }
  if (t.closed && !(t.length > t.points.back().s - t.points.front().s)) {
    throw TrajectoryError("trajectory: a closed trajectory's length must exceed its last point's s");
  }
}

Trajectory trajectoryOf(const track::Track& track, const RacingLine& line, const SpeedProfile& profile) {
  Trajectory t;
  t.closed = line.closed;
  t.length = line.length;
  t.lap_time = profile.total_time;
  t.points.resize(line.points.size());
  for (std::size_t i = 0; i < line.points.size(); ++i) {
    auto& p = t.points[i];
    p.position = line.points[i];
    p.z = track.surfaceHeightAt(line.track_s[i], line.offset[i]);
    p.yaw = line.heading[i];
    p.s = line.s[i];
    p.curvature = line.curvature[i];
    p.speed = profile.speed[i];
    p.acceleration = profile.acceleration[i];
    p.time = profile.time[i];
    p.offset = line.offset[i];
  }
  return t;
}

Trajectory recordedTrajectory(const std::vector<Eigen::Vector2d>& positions, const std::vector<double>& speeds,
                              const std::vector<double>& pedals, double smoothing) {
  if (positions.size() != speeds.size())
    throw TrajectoryError("recorded trajectory: " + std::to_string(positions.size()) + " positions for " +
                          std::to_string(speeds.size()) + " speeds");
  if (!pedals.empty() && pedals.size() != speeds.size())
    throw TrajectoryError("recorded trajectory: " + std::to_string(pedals.size()) + " pedals for " +
                          std::to_string(speeds.size()) + " speeds");
  Trajectory t;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!positions[i].allFinite() || !std::isfinite(speeds[i]) || speeds[i] < 0)
      throw TrajectoryError("recorded trajectory: sample " + std::to_string(i) +
                            " is not finite or its speed negative");
    if (!pedals.empty() && !(std::abs(pedals[i]) <= 1.0))
      throw TrajectoryError("recorded trajectory: sample " + std::to_string(i) + "'s pedal is not within -1..1");
    // Samples closer than a metre (the car slow, or standing) add nothing but noise to the heading.
    if (!t.points.empty() && (positions[i] - t.points.back().position).norm() < 1.0) continue;
    TrajectoryPoint p;
    p.position = positions[i];
    p.speed = speeds[i];
    if (!pedals.empty()) p.recorded_pedal = pedals[i];
    p.s = t.points.empty() ? 0.0 : t.points.back().s + (positions[i] - t.points.back().position).norm();
    t.points.push_back(p);
  }
  const std::size_t n = t.points.size();
  if (n < 10)
    throw TrajectoryError("recorded trajectory: needs at least 10 points a metre apart, has " + std::to_string(n));
  t.length = t.points.back().s + (t.points.front().position - t.points.back().position).norm();
  // Heading from the points +-smoothing metres away (round the loop), curvature from the heading's change.
  auto ahead = [&](std::size_t i, double metres, int dir) {
    std::size_t j = i;
    double gone = 0.0;
    while (gone < metres) {
      const std::size_t k = (j + n + static_cast<std::size_t>(dir)) % n;
      gone += (t.points[k].position - t.points[j].position).norm();
      j = k;
    }
    return j;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d d = t.points[ahead(i, smoothing, 1)].position - t.points[ahead(i, smoothing, -1)].position;
    t.points[i].yaw = std::atan2(d.y(), d.x());
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = ahead(i, smoothing, -1), b = ahead(i, smoothing, 1);
    double run = 0.0;
    for (std::size_t k = a; k != b; k = (k + 1) % n)
      run += (t.points[(k + 1) % n].position - t.points[k].position).norm();
    t.points[i].curvature = track::wrapAngle(t.points[b].yaw - t.points[a].yaw) / run;
    const double v_next = t.points[(i + 1) % n].speed,
                 step = (t.points[(i + 1) % n].position - t.points[i].position).norm();
    t.points[i].acceleration = (v_next * v_next - t.points[i].speed * t.points[i].speed) / (2.0 * step);
  }
  for (std::size_t i = 1; i < n; ++i) {
    const double mean = 0.5 * (t.points[i].speed + t.points[i - 1].speed);
    t.points[i].time = t.points[i - 1].time + (t.points[i].s - t.points[i - 1].s) / std::max(mean, 0.1);
  }
  t.lap_time = t.points.back().time +
               (t.length - t.points.back().s) / std::max(0.5 * (t.points.back().speed + t.points.front().speed), 0.1);
  validate(t);
  return t;
}

Trajectory planRacingTrajectory(const track::Track& track, const VehicleLimits& limits, const PlannerOptions& options) {
  RacingLine line = minimumCurvatureLine(track, options.line);
  if (options.minimum_time) line = minimumTimeLine(track, line, limits, options.line).line;
  SpeedProfileOptions profile = options.profile;
  const std::vector<double> heights = roadHeights(track, line);
  const std::vector<double> grade = gradesAlong(heights, line.step, line.closed);
  const std::vector<double> vertical = verticalCurvaturesAlong(heights, line.step, line.closed);
  profile.grade = grade;
  profile.vertical_curvature = vertical;
  if (line.closed)
    return trajectoryOf(track, line, computeSpeedProfile(line.step, line.curvature, limits, true, profile));
  // A course's road runs on past its finish line for the cars to stop: stopped kCourseStopMargin before its
  // end (a car's length and more from the wall across it), standing still beyond.
  std::size_t stop = line.points.size() - 1;
  while (stop > 1 && line.s[stop] > line.length - kCourseStopMargin) --stop;
  auto upTo = [&](const std::vector<double>& v) { return std::vector<double>(v.begin(), v.begin() + stop + 1); };
  profile.end_speed = 0.0;
  profile.grade = upTo(grade);
  profile.vertical_curvature = upTo(vertical);
  SpeedProfile run = computeSpeedProfile(upTo(line.step), upTo(line.curvature), limits, false, profile);
  run.speed.resize(line.points.size(), 0.0);
  run.acceleration.resize(line.points.size(), 0.0);
  run.time.resize(line.points.size(), run.time.back());
  Trajectory t = trajectoryOf(track, line, run);
  // The run's promise: from a standing start on pole (the trajectory itself is driven from every slot of
  // the grid, so it does not stop there).
  std::size_t pole = 0;
  while (pole + 1 < stop && line.track_s[pole + 1] <= track.info().start_finish_s - track::kGridFirstGap) ++pole;
  auto from = [&](const std::vector<double>& v) {
    return std::vector<double>(v.begin() + static_cast<long>(pole), v.begin() + static_cast<long>(stop) + 1);
  };
  SpeedProfileOptions standing = profile;
  standing.start_speed = 0.0;
  standing.grade = from(grade);
  standing.vertical_curvature = from(vertical);
  const SpeedProfile from_pole = computeSpeedProfile(from(line.step), from(line.curvature), limits, false, standing);
  t.lap_time = raceTime(track, from(line.track_s), from_pole.time);
  return t;
}

TrajectoryPoint sampleAt(const Trajectory& t, double s) {
  const auto& pts = t.points;
  if (t.closed) {
    s = std::fmod(s - pts.front().s, t.length);
    if (s < 0) s += t.length;
    s += pts.front().s;
  } else {
    s = std::clamp(s, pts.front().s, pts.back().s);
  }
  auto it = std::upper_bound(pts.begin(), pts.end(), s, [](double v, const TrajectoryPoint& p) { return v < p.s; });
  const std::size_t i = it == pts.begin() ? 0 : static_cast<std::size_t>(it - pts.begin()) - 1;
  const std::size_t j = (i + 1) % pts.size();
  const double step = stepAfter(t, i);
  if (step <= 0 || (!t.closed && j == 0)) return pts[i];
  const double f = std::clamp((s - pts[i].s) / step, 0.0, 1.0);
  TrajectoryPoint out = pts[i];
  const auto& b = pts[j];
  out.position = (1 - f) * pts[i].position + f * b.position;
  out.z = (1 - f) * pts[i].z + f * b.z;
  out.yaw = pts[i].yaw + f * std::remainder(b.yaw - pts[i].yaw, 2.0 * M_PI);
  out.s = s;
  out.curvature = (1 - f) * pts[i].curvature + f * b.curvature;
  out.speed = (1 - f) * pts[i].speed + f * b.speed;
  out.acceleration = pts[i].acceleration;      // constant over a segment
  out.recorded_pedal = pts[i].recorded_pedal;  // held, as a control is, until the next sample
  out.offset = (1 - f) * pts[i].offset + f * b.offset;
  return out;
}

namespace {

// The foot of `position` on segment a (from point a to the next): where it is (into *on) and how far along
// (the share *along); returns the squared distance to it.
double footOnSegment(const Trajectory& t, std::size_t a, const Eigen::Vector2d& position, TrajectoryProjection* on,
                     double* along) {
  const std::size_t b = (a + 1) % t.points.size();
  const Eigen::Vector2d pa = t.points[a].position, d = t.points[b].position - pa;
  const double len2 = d.squaredNorm();
  const double f = len2 > 0 ? std::clamp((position - pa).dot(d) / len2, 0.0, 1.0) : 0.0;
  const Eigen::Vector2d r = position - (pa + f * d);
  const double d2 = r.squaredNorm();
  on->segment = a;
  on->s = t.points[a].s + f * stepAfter(t, a);
  const double cross = d.x() * r.y() - d.y() * r.x();
  on->lateral = (cross >= 0 ? 1.0 : -1.0) * std::sqrt(d2);
  *along = f;
  return d2;
}

}  // namespace

TrajectoryProjection project(const Trajectory& t, const Eigen::Vector2d& position, long hint, long window) {
  const long n = static_cast<long>(t.points.size());
  const long segments = t.closed ? n : n - 1;
  long first = 0, count = segments;
  if (hint >= 0 && 2 * window + 1 < segments) {
    first = hint - window;
    count = 2 * window + 1;
  }
  TrajectoryProjection best, on;
  double best_d2 = INFINITY, along;
  for (long k = 0; k < count; ++k) {
    long i = first + k;
    if (t.closed) {
      i = ((i % n) + n) % n;
    } else if (i < 0 || i >= segments) {
      continue;
    }
    const double d2 = footOnSegment(t, static_cast<std::size_t>(i), position, &on, &along);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = on;
    }
  }
  return best;
}

TrajectoryProjection projectAtHeight(const Trajectory& t, const Eigen::Vector3d& position) {
  const std::size_t n = t.points.size();
  const std::size_t segments = t.closed ? n : n - 1;
  TrajectoryProjection best, on;
  double best_d2 = INFINITY, f;
  for (std::size_t a = 0; a < segments; ++a) {
    const double flat = footOnSegment(t, a, position.head<2>(), &on, &f);
    const double road = (1 - f) * t.points[a].z + f * t.points[(a + 1) % n].z;
    const double dz = track::kProjectionHeightWeight * (position.z() - road);
    if (flat + dz * dz < best_d2) {
      best_d2 = flat + dz * dz;
      best = on;
    }
  }
  return best;
}

Trajectory windowAround(const Trajectory& closed, double s, double behind, double ahead) {
  Trajectory w;
  w.closed = false;
  const std::size_t n = closed.points.size();
  const TrajectoryPoint start = sampleAt(closed, s - behind);
  // Unwrapped: the window's s runs on from the sampled start even past the end of the lap. An open
  // trajectory's window ends where it does.
  double s_now = closed.closed ? s - behind : start.s;
  w.points.push_back(start);
  w.points.back().s = s_now;
  auto it = std::upper_bound(closed.points.begin(), closed.points.end(), start.s,
                             [](double v, const TrajectoryPoint& p) { return v < p.s; });
  std::size_t next = static_cast<std::size_t>(it - closed.points.begin()) % n;
  double previous_s = start.s;
  const double end = s + ahead;
  while (closed.closed || next != 0) {
    const TrajectoryPoint& p = closed.points[next];
    double gap = p.s - previous_s;
    if (gap <= 0) gap += closed.length;
    if (s_now + gap > end) break;
    s_now += gap;
    w.points.push_back(p);
    w.points.back().s = s_now;
    previous_s = p.s;
    next = (next + 1) % n;
  }
  // A window at an open trajectory's end: its last point (a window needs two).
  if (w.points.size() < 2) {
    w.points.insert(w.points.begin(), sampleAt(closed, closed.points.back().s - 1.0));
  }
  w.length = w.points.back().s - w.points.front().s;
  for (std::size_t i = 0; i + 1 < w.points.size(); ++i) {
    const double mean = 0.5 * (w.points[i].speed + w.points[i + 1].speed);
    if (mean > 1e-6) w.lap_time += (w.points[i + 1].s - w.points[i].s) / mean;
  }
  return w;
}

}  // namespace roar::planning

namespace roar::planning {

namespace {
// m/s below a speed held within which a car has reached it (its speed loop's wobble).
constexpr double kHeldSpeedReach = 0.3;
}  // namespace

void followBehind(Trajectory* window, double car_s, double leader_s, double leader_speed, double gap,
                  const VehicleLimits& limits, double car_speed) {
  auto& pts = window->points;
  if (pts.size() < 2) return;
  std::vector<double> own;  // the window's accelerations before the cap, for a car still below it
  if (car_speed >= 0.0) {
    own.reserve(pts.size());
    for (const auto& p : pts) own.push_back(p.acceleration);
  }
  const double stop_at = leader_s - gap;
  const double too_close = std::max(0.0, car_s - stop_at);
  const double cap = std::max(0.0, leader_speed - too_close);
  for (auto& p : pts) {
    if (p.s >= stop_at) p.speed = std::min(p.speed, cap);
  }
  const std::vector<double> grade = slopes(*window);
  for (std::size_t k = pts.size() - 1; k-- > 0;) {
    const double ds = pts[k + 1].s - pts[k].s;
    const double a = decelerationAt(limits, pts[k + 1].speed, pts[k + 1].curvature, grade[k]);
    pts[k].speed = std::min(pts[k].speed, std::sqrt(pts[k + 1].speed * pts[k + 1].speed + 2.0 * a * ds));
  }
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
    const double ds = pts[k + 1].s - pts[k].s;
    pts[k].acceleration = (pts[k + 1].speed * pts[k + 1].speed - pts[k].speed * pts[k].speed) / (2.0 * ds);
  }
  pts.back().acceleration = 0.0;
  if (car_speed < 0.0) return;
  double v = car_speed;  // the car's speed at point k, gaining at the window's own acceleration
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
    if (pts[k + 1].s <= car_s) continue;
    if (v > pts[k].speed - kHeldSpeedReach) break;
    pts[k].acceleration = std::max(pts[k].acceleration, own[k]);
    const double ds = pts[k + 1].s - std::max(pts[k].s, car_s);
    v = std::sqrt(std::max(0.0, v * v + 2.0 * std::max(0.0, own[k]) * ds));
  }
}

std::vector<double> slopes(const Trajectory& t) {
  std::vector<double> z, step;
  for (std::size_t i = 0; i < t.points.size(); ++i) {
    z.push_back(t.points[i].z);
    step.push_back(stepAfter(t, i));
  }
  return gradesAlong(z, step, t.closed);
}

double aheadOnLap(double a, double b, double length) {
  const double d = a - b;
  if (length <= 0) return d;
  return d - std::floor(d / length + 0.5) * length;
}

void scaleSpeeds(Trajectory* trajectory, double pace) {
  if (pace == 1.0) return;
  for (auto& p : trajectory->points) {
    p.speed *= pace;
    p.acceleration *= pace * pace;
    p.time /= pace;
  }
  trajectory->lap_time /= pace;
}

}  // namespace roar::planning
