#include "roar/planning/overtaking.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "roar/planning/speed_profile.h"
#include "roar/track/heading.h"
#include "roar/track/track.h"

namespace roar::planning {

namespace {

// m across per m along: a pass path changing its offset from the line less than this holds it steady.
constexpr double kSteadyOffsetSlope = 0.005;

// w log(1 + e^(x / w)): x for x well above 0, 0 well below, and a bend of about 2w between.
double softPlus(double x, double w) { return x > 20.0 * w ? x : w * std::log1p(std::exp(x / w)); }
constexpr double kMarginBend = 0.3;  // m: a pass path bends onto a road margin over about 2 x this

double smoothStep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

}  // namespace

const char* raceModeName(RaceMode mode) {
  switch (mode) {
    case RaceMode::kRacingLine:
      return "racing_line";
    case RaceMode::kFollow:
      return "follow";
    case RaceMode::kPass:
      return "pass";
    case RaceMode::kHold:
      return "hold";
    case RaceMode::kYield:
      return "yield";
    case RaceMode::kDefend:
      return "defend";
  }
  return "unknown";
}

std::string describe(const RaceDecision& d) {
  if (d.mode == RaceMode::kRacingLine) return "racing line";
  std::string text = raceModeName(d.mode);
  if (!d.other.empty()) {
    const bool towards = d.mode == RaceMode::kYield;
    const bool against = d.mode == RaceMode::kDefend;
    text += towards ? " to " : against ? " against " : (d.mode == RaceMode::kHold ? " beside " : " ");
    text += d.other;
  }
  if (d.side != 0 && d.mode != RaceMode::kFollow && d.mode != RaceMode::kHold) {
    text += d.side > 0 ? " on the left" : " on the right";
  }
  return text;
}

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

namespace {

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

double OvertakePlanner::roomLeft(double s) const {
  return interpolateWrapped(room_s_, room_left_, lapLength(line_), s);
}
double OvertakePlanner::roomRight(double s) const {
  return interpolateWrapped(room_s_, room_right_, lapLength(line_), s);
}

double OvertakePlanner::laneNeed(double margin_share) const {
  return 1.5 * options_.car_width + margin_share * options_.lateral_margin + options_.edge_margin;
}

double OvertakePlanner::laneShare(int side, double run) const {
  const double length = line_.closed ? lapLength(line_) : line_.points.back().s - line_.points.front().s;
  constexpr double kStep = 1.0;  // m
  const auto n = static_cast<std::size_t>(std::floor(length / kStep));
  if (n == 0) return 0.0;
  const double need = laneNeed(1.0);
  std::vector<char> lane(n);
  const double s0 = line_.points.front().s;
  for (std::size_t i = 0; i < n; ++i) {
    const double at = s0 + kStep * static_cast<double>(i);
    lane[i] = (side > 0 ? roomLeft(at) : roomRight(at)) >= need;
  }
  // Metres of lane from each point on, backwards round the lap (twice, for a closed line's wrap).
  std::vector<double> on(n, 0.0);
  const std::size_t passes = line_.closed ? 2 : 1;
  double ahead = 0.0;
  for (std::size_t k = passes * n; k-- > 0;) {
    const std::size_t i = k % n;
    ahead = lane[i] ? ahead + kStep : 0.0;
    on[i] = std::min(ahead, length);
  }
  const auto starts = std::count_if(on.begin(), on.end(), [&](double m) { return m > 0.0 && m >= run; });
  return static_cast<double>(starts) / static_cast<double>(n);
}

double OvertakePlanner::laneRun(int side, double s, double beside, double longest) const {
  // A pass's lane as one under way keeps it: half its air from the car.
  const double need = beside + laneNeed(0.5);
  double run = 0.0;
  for (; run < longest; run += options_.sample_step) {
    if ((side > 0 ? roomLeft(s + run) : roomRight(s + run)) < need) break;
  }
  return std::min(run, longest);
}

Trajectory OvertakePlanner::shifted(const Trajectory& window, double ramp_s, double from, double to, double back_s,
                                    double drag_share, bool for_pass, double settle_s, double ramp_speed) const {
  Trajectory out = window;
  // shift_time is for a move of a car's width and air (3 m); a longer one takes longer, so that it asks
  // no more sideways acceleration (which grows with the move and falls with the square of its length).
  const double move = std::max(std::abs(to - from), std::abs(to));
  const double stretch = std::sqrt(std::max(1.0, move / (options_.car_width + options_.lateral_margin + 0.3)));
  // At the car's speed, not the line's: behind a slow car the line's is far above it (72 m/s on Roar
  // Speedway's straight, 45 behind the pace car), and a move sized for the line took 180 m, 4 s, the guard
  // holding the passer to the slow car's speed until it was clear of it sideways.
  const double line_speed = sampleAt(line_, ramp_s).speed;
  const double move_speed = ramp_speed > 0.0 ? std::min(ramp_speed, line_speed) : line_speed;
  const double shift_length = std::max(options_.min_shift_length, stretch * options_.shift_time * move_speed);
  auto& pts = out.points;
  const double half = 0.5 * options_.car_width + options_.edge_margin;
  // Where a pass may run at line s (m left of the line): the edge margin from either edge (the right one
  // where the road is narrower than both margins).
  auto passBounds = [&](double at) {
    const double lo = half - roomRight(at);
    return std::pair{lo, std::max(lo, roomLeft(at) - half)};
  };
  // A pass keeps the edge margin, so where the racing line runs nearer the edge than that (along an edge
  // before and after a corner) the car is pushed off it at once. The move starts from there: a ramp from
  // the car's place on the line would be held flat on that bound and then leave it, a kink the pass's
  // speeds brake for (44 m/s on a straight the line does at 72, at Roar Speedway).
  if (for_pass) {
    const auto [lo, hi] = passBounds(ramp_s);
    from = std::clamp(from, lo, hi);
  }
  const std::size_t n = pts.size();
  std::vector<double> d(n, 0.0);  // m each point is moved left off the racing line
  for (std::size_t k = 0; k < n; ++k) {
    auto& p = pts[k];
    double shift = from + (to - from) * smoothStep(aheadOnLap(p.s, ramp_s, lapLength(line_)) / shift_length);
    if (std::isfinite(back_s) && p.s > back_s) shift -= to * smoothStep((p.s - back_s) / shift_length);
    // Inside the road by the margin. Any move but a pass comes no nearer the edge than the racing line
    // itself does (at an apex it runs nearer): a path moved by nothing is the racing line. A pass keeps
    // the margin even there, pushed off the line (see below).
    if (for_pass) {
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
  if (n < 3) return out;
  std::vector<double> step(n, 0.0), curvature(n, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) step[k] = std::max(1e-3, (pts[k + 1].position - pts[k].position).norm());
  if (for_pass) {
    // A pass is planned on the curvature of its moved points, differenced: rougher than the exact one
    // below (up to half as much again at the line's small kinks and where the edge margin pushes it off
    // at an apex), so slower, and a pass is begun only where it gains on that. Planned exactly, passes
    // are begun that the next corner squeezes: roar_bench --traffic --seeds=6 completed 88.7% of 353
    // attempts that way, 92.1% of 353 this way.
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
  } else {
    // The moved path's heading and curvature exactly, from the racing line's own (smooth) ones and the
    // offset's derivatives along the line (Frenet): differenced from the moved points, a move back onto
    // the line was planned up to 10 m/s slower than the line where it was already back on it.
    std::vector<double> heading(n, 0.0), path_per_line(n, 1.0);
    auto along = [&](std::size_t a, std::size_t b) { return std::max(1e-3, pts[b].s - pts[a].s); };
    // The neighbours a derivative at k is taken between: the next points either side, but at least
    // kMinSpan apart. A window begins at a point sampled anywhere on the line, often centimetres before the
    // line's next point, and over those centimetres the offset's slope (and the heading's) differed enough
    // to plan the window's first point as a hairpin and the car at a third of the line's speed.
    constexpr double kMinSpan = 1.0;  // m; the line's points are 2-3 m apart
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
  }
  SpeedProfileOptions profile_options;
  profile_options.start_speed = -1.0;
  profile_options.grade = slopes(out);
  // Where the path moves across the line the car is moving sideways as well: it is planned there with a
  // share of the grip (the whole grip at a steady offset and back on the line: a pass's window after it).
  VehicleLimits limits = limits_;
  limits.drag_coefficient *= drag_share;
  VehicleLimits offline = limits;
  offline.friction *= options_.offline_grip;
  VehicleLimits settling_limits = limits;
  settling_limits.friction *= options_.settle_grip;
  auto settlingAt = [&](std::size_t k) {
    return std::isfinite(settle_s) && aheadOnLap(pts[k].s, settle_s, lapLength(line_)) < 0.0;
  };
  const SpeedProfile on_grip = computeSpeedProfile(step, curvature, limits, false, profile_options);
  const SpeedProfile off_grip = computeSpeedProfile(step, curvature, offline, false, profile_options);
  const SpeedProfile settle_grip = n > 0 && settlingAt(0)
                                       ? computeSpeedProfile(step, curvature, settling_limits, false, profile_options)
                                       : SpeedProfile{};
  for (std::size_t k = 0; k < n; ++k) {
    pts[k].curvature = curvature[k];
    // A path moving across the line is planned on offline_grip (sideways motion takes grip); at a steady
    // offset it is a line of its own and has all of it. roar_bench --traffic over 90 races (--seeds=6):
    // 343 of 363 passes completed (94.5%) this way, 318 of 344 (92.4%) on offline_grip all the way. The
    // same for every move, not only a pass: a car holding its place at the offset it passed at is on the
    // same path and grip as the pass was (within the seeds' swing on the traffic benchmark either way).
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
  out.lap_time = 0.0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    pts[k].acceleration = (pts[k + 1].speed * pts[k + 1].speed - pts[k].speed * pts[k].speed) / (2.0 * step[k]);
    const double mean = 0.5 * (pts[k].speed + pts[k + 1].speed);
    if (mean > 1e-6) out.lap_time += step[k] / mean;
  }
  pts.back().acceleration = 0.0;
  return out;
}

Trajectory OvertakePlanner::shifted(const Trajectory& window, const RaceDecision& move, double settle_s) const {
  return shifted(window, move.ramp_s, move.ramp_from, move.offset, std::numeric_limits<double>::infinity(), 1.0, false,
                 settle_s, move.ramp_speed);
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

namespace {
constexpr double kPredictionStep = 0.1;       // s
constexpr double kShownPredictionStep = 0.5;  // s between the predicted positions kept for rviz
constexpr double kHeldSlack = 0.3;            // m/s a car held to a speed is predicted above it (its wobble)
constexpr double kInf = std::numeric_limits<double>::infinity();
// How fast a car is moving across the line this moment: its velocity's where known. A door closing is seen
// from the first message of the turn (smoothed over places, a car swerving at 1 m/s was seen at 0.5 m/s
// 0.2 s late: the cut-in rostest's passer, still closing at 7 m/s, gave up too late and touched it).
double sidewaysNow(const TrafficCar& o) {
  return std::isfinite(o.lateral_velocity) ? o.lateral_velocity : o.lateral_speed;
}
constexpr double kSettledLateralSpeed = 0.5;  // m/s sideways across the line a car is settled under
constexpr double kSettleTime = 2.0;           // s at speed it is planned on settle_grip after that
constexpr double kMoveBrakeSlack = 1.5;       // m/s a move's window may ask the car to shed at once
constexpr double kPassedLevelGap = 0.1;  // m taken as the gap to the car a pass is level with (its nose may be past)
constexpr double kLetByRate = 3.0;       // m/s below a car level beside it that a car lets it by at
}  // namespace

double OvertakePlanner::Prediction::at(double t) const {
  const double k = std::clamp(t / kPredictionStep, 0.0, static_cast<double>(ahead.size() - 1));
  const auto a = static_cast<std::size_t>(k);
  const std::size_t b = std::min(a + 1, ahead.size() - 1);
  return ahead[a] + (k - static_cast<double>(a)) * (ahead[b] - ahead[a]);
}

double OvertakePlanner::plannedLateral(const Trajectory* plan, double now, double s) const {
  if (!plan || plan->points.size() < 2) return now;
  // The window's s runs on from where the car was when it was planned: bring s onto the same lap.
  const double mid = 0.5 * (plan->points.front().s + plan->points.back().s);
  if (line_.closed) s += std::floor((mid - s) / line_.length + 0.5) * line_.length;
  if (s < plan->points.front().s || s > plan->points.back().s) return now;
  return sampleAt(*plan, s).offset - sampleAt(line_, s).offset;
}

const Trajectory* OvertakePlanner::trustedPlan(const TrafficCar& car) const {
  // A car's plan predicts it only while it drives it: one that is elsewhere than its plan says (another
  // driver at the wheel, a car swerving) is predicted by where it is.
  const auto it = plans_.find(car.name);
  if (it == plans_.end()) return nullptr;
  return std::abs(plannedLateral(&it->second, car.lateral, car.s) - car.lateral) <= options_.plan_trust ? &it->second
                                                                                                        : nullptr;
}

double OvertakePlanner::plannedLateral(const TrafficCar& car, double s) const {
  return plannedLateral(trustedPlan(car), car.lateral, s);
}

double OvertakePlanner::lateralAt(const Prediction& p, double t) const {
  const double drift = p.lateral + p.lateral_speed * std::min(t, options_.lateral_lookahead);
  return plannedLateral(p.plan, drift, p.s + (p.at(t) - p.ahead.front()));
}

OvertakePlanner::Prediction OvertakePlanner::predict(const TrafficCar& other, double s0) const {
  Prediction p;
  p.lateral = other.lateral;
  p.lateral_speed = other.lateral_speed;
  p.s = other.s;
  p.plan = trustedPlan(other);
  const double now = other.speed / std::max(1.0, sampleAt(line_, other.s).speed);
  const double share = std::clamp(other.line_share > 0 ? std::max(other.line_share, now) : now, 0.2, 1.1);
  const double held_cap = other.held_speed > 0.0 ? other.held_speed + kHeldSlack : kInf;
  double along = aheadOnLap(other.s, s0, lapLength(line_));
  const int steps = static_cast<int>(std::ceil(options_.horizon / kPredictionStep)) + 1;
  p.ahead.reserve(static_cast<std::size_t>(steps) + 1);
  p.ahead.push_back(along);
  // From the speed it has now, gaining speed no faster than an engine like ours gives.
  double v = other.speed;
  for (int k = 0; k < steps; ++k) {
    const double cap = std::min(share * sampleAt(line_, s0 + along).speed, held_cap);
    const double v_next =
        std::min(cap, v + kPredictionStep * std::max(0.0, limits_.driveForce(v)) / limits_.effectiveMass());
    along += kPredictionStep * 0.5 * (v + std::max(v_next, 0.0));
    v = v_next;
    p.ahead.push_back(along);
  }
  return p;
}

double OvertakePlanner::driveAlong(const Trajectory& plan, double s0, double v0, const MotionVisitor& visit) const {
  // The car's own motion along the plan: from its speed now (not the plan's: a car held up behind another
  // is slower than its plan there), no faster than the plan, accelerating at most as the engine can.
  const auto& pts = plan.points;
  double t = 0.0, v = std::clamp(v0, 0.0, pts.empty() ? 0.0 : sampleAt(plan, s0).speed), s = s0;
  for (std::size_t k = 0; k + 1 < pts.size() && t < options_.horizon; ++k) {
    if (pts[k + 1].s <= s0) continue;
    const double ds = pts[k + 1].s - std::max(s, pts[k].s);
    const double v_next = std::min(
        pts[k + 1].speed, std::sqrt(v * v + 2.0 * std::max(0.0, limits_.driveForce(v)) / limits_.effectiveMass() * ds));
    t += ds / std::max(0.5, 0.5 * (v + v_next));
    v = v_next;
    s = pts[k + 1].s;
    if (!visit(k + 1, t, s, v)) break;
  }
  return s;
}

bool OvertakePlanner::clearOf(const Trajectory& plan, double s0, double v0, const std::vector<Prediction>& others,
                              double* progress, double margin_share, double within) const {
  const auto& pts = plan.points;
  double last_check = -1e9;
  bool clear = true;
  const double length = levelDistance();
  const double width = options_.car_width + margin_share * options_.lateral_margin;
  const double d0 = pts.empty() ? 0.0 : sampleAt(plan, s0).offset - sampleAt(line_, s0).offset;
  std::vector<char> merged(others.size(), 0);  // the plan has moved into that car's lane, in front of it
  double end_time = 0.0, end_speed = 0.0;
  const double s = driveAlong(plan, s0, v0, [&](std::size_t k, double t, double s_now, double v) {
    end_time = t;
    end_speed = v;
    if (s_now - last_check < options_.sample_step) return true;
    last_check = s_now;
    if (t < 0.3 || t > within) return true;  // too soon to change anything, or for later plans to see to
    const double d = pts[k].offset - sampleAt(line_, s_now).offset;
    for (std::size_t i = 0; i < others.size(); ++i) {
      const auto& o = others[i];
      // A car behind needs room to brake too: moving across into its lane in front of it keeps
      // rejoin_time at speed (staying in the lane one is already in, ahead of it, is its to mind, and
      // so is the lane once moved into with that room: a pass is not given up for a car it has passed).
      const double ahead_of_it = (s_now - s0) - o.at(t);
      const double theirs = lateralAt(o, t);
      // Moved across: this plan's car is in that car's lane where, had it kept its own place, it would not
      // be. A car moving into this one's lane behind it is that car's to mind (Roar Ring: a pass already out
      // in its lane was given up for a car moving in 21 m behind it, held to 26.5 m as if it had cut in).
      const bool moved_across = std::abs(d0 - theirs) >= width;
      const bool in_lane = std::abs(d - theirs) < width;
      const double keep_ahead = length + (moved_across && !merged[i] ? options_.rejoin_time * v : 0.0);
      if (ahead_of_it > -length && ahead_of_it < keep_ahead && in_lane) {
        clear = false;
        return false;
      }
      if (in_lane && ahead_of_it >= keep_ahead) merged[i] = 1;
    }
    return true;
  });
  // A window that ends before the horizon does (400 m is 6 s at 67 m/s) is driven on at its last speed:
  // cut at the window's end, every candidate got as far as the window and none gained on following.
  *progress = s - s0 + (clear ? std::max(0.0, options_.horizon - end_time) * end_speed : 0.0);
  return clear;
}

double OvertakePlanner::passCompleteAt(const Trajectory& plan, double s0, double v0, const Prediction& leader) const {
  // As far ahead as clearOf asks of a car moving across in front of another, and a little more.
  const double clear_ahead = levelDistance() + 2.0;
  double at = std::numeric_limits<double>::infinity();
  driveAlong(plan, s0, v0, [&](std::size_t, double t, double s, double v) {
    if ((s - s0) - leader.at(t) <= clear_ahead + options_.rejoin_time * v) return true;
    at = s;
    return false;
  });
  return at;
}

bool OvertakePlanner::drawsAlongside(const Trajectory& plan, double s0, double v0, const Prediction& leader) const {
  bool alongside = false;
  driveAlong(plan, s0, v0, [&](std::size_t, double t, double s, double) {
    alongside = (s - s0) - leader.at(t) > -options_.car_length;
    return !alongside;
  });
  return alongside;
}

Trajectory OvertakePlanner::plan(const std::string& car, double s, double lateral, double speed,
                                 const std::vector<TrafficCar>& traffic, double behind, double ahead_m, double pace) {
  const double L = lapLength(line_);
  Trajectory base = windowAround(line_, s, behind, ahead_m);
  scaleSpeeds(&base, pace);
  // A car still moving sideways after a move (back from a pass, say) is planned on settle_grip for the next
  // kSettleTime at its speed on the line, on its way back to it and in a lane it holds: it has less grip to
  // brake and turn with. Only after a move (a car alone on the line never settles: its own tracking is the
  // line's business), and not a pass or any other move across the road (they plan their own moving across).
  Trajectory line_base;     // the racing line's window as a car settling drives it; empty: `base`
  double settle_s = -kInf;  // line s up to which the car is settling
  auto settle_it = settle_.find(car);
  const RaceDecision& last = decisions_[car];
  const bool after_move = settle_it != settle_.end() || last.mode != RaceMode::kRacingLine || last.ramp_from != 0.0;
  for (const auto& o : traffic) {
    if (o.name == car && after_move && std::abs(o.lateral_speed) > kSettledLateralSpeed)
      settle_it = settle_.insert_or_assign(car, s + kSettleTime * speed).first;
  }
  if (settle_it != settle_.end()) {
    if (aheadOnLap(s, settle_it->second, L) >= 0.0) {
      settle_.erase(settle_it);
    } else {
      settle_s = settle_it->second;
      line_base = shifted(base, s, 0.0, 0.0, kInf, 1.0, false, settle_s);
    }
  }
  const Trajectory& on_line_base = line_base.points.empty() ? base : line_base;

  // Cars that matter: alongside or ahead, within the window; behind, those near enough to need room, and
  // those closing fast enough to be level within a move's time (a car slow off the line, say after a spin,
  // must not move back onto it in front of them: at its own low speed, "near" is a few metres).
  std::vector<TrafficCar> others;
  const TrafficCar* leader = nullptr;
  std::size_t leader_index = 0;  // the leader's place in `others` (and so in `predicted`)
  double leader_gap = ahead_m;
  bool alongside = false;
  bool closing_behind = false;  // a car closing from behind within a move's time: keep the place, as alongside
  const double near = levelDistance();
  for (const auto& o : traffic) {
    if (o.name == car) continue;
    const double rel = aheadOnLap(o.s, s, L);
    const double closing_in = std::max(0.0, o.speed - speed) * options_.shift_time;
    if (rel < -(near + std::max(options_.rejoin_time * speed, closing_in)) || rel > ahead_m) continue;
    others.push_back(o);
    if (std::abs(rel) < near) alongside = true;
    if (rel <= -near && -rel < near + closing_in) closing_behind = true;
    // The car a pass is on stays the car ahead while level with it, wherever it is across the road: the pass
    // is done only once clear ahead of it. Taken as done the moment the nose drew level, a pass turned to
    // the next car up the road, braked beside the car it was passing and dropped back behind it (Roar
    // Eight's reverse grid, seed 0, 55-61 s). Not once it turns across towards this car: the pass is given
    // up and the car holds its place beside it.
    const bool passing_it = last.mode == RaceMode::kPass && o.name == last.other && std::abs(rel) < near &&
                            last.side * sidewaysNow(o) <= 0.5;
    if (passing_it || (rel > 0 && rel < leader_gap &&
                       std::abs(o.lateral - lateral) < options_.car_width + options_.lateral_margin + 2.0)) {
      leader_gap = passing_it ? std::max(rel, kPassedLevelGap) : rel;
      leader = &o;
      leader_index = others.size() - 1;
    }
  }
  std::vector<Prediction> predicted;
  for (const auto& o : others) predicted.push_back(predict(o, s));
  if (options_.keep_predictions) {
    auto& shown = predictions_[car];
    shown.clear();
    for (std::size_t i = 0; i < others.size(); ++i) {
      PredictedPath path{others[i].name, kShownPredictionStep, {}};
      const Prediction& p = predicted[i];
      for (double t = 0.0; t <= options_.horizon + 1e-9; t += kShownPredictionStep) {
        const TrajectoryPoint on_line = sampleAt(line_, p.s + (p.at(t) - p.ahead.front()));
        path.positions.push_back(on_line.position + lateralAt(p, t) * track::leftOf(on_line.yaw));
      }
      shown.push_back(std::move(path));
    }
  }
  const Prediction leader_prediction = leader ? predicted[leader_index] : Prediction{};
  // How far in the horizon a car gets behind the leader as the leader is predicted to go: what following
  // gets at most, and a pass still behind it at the end no more.
  const double behind_leader = leader ? leader_prediction.at(options_.horizon) - options_.follow_gap : kInf;
  // In the leader's slipstream a pass is planned with the speed the tow gives (and carries out of it).
  const double tow = leader ? vehicle::slipstreamReduction(leader_gap - options_.car_length, lateral - leader->lateral,
                                                           leader->speed, options_.car_width, options_.slipstream)
                            : 0.0;
  const Trajectory towed_base = tow > 0.01 ? towed(base, 1.0 - tow) : Trajectory{};
  RaceDecision& memory = decisions_[car];
  Abort& abort = aborts_[car];
  if (abort.plans_left > 0) --abort.plans_left;
  // Whether the leader is near enough to pass, and not one a pass on was given up just now.
  const double engage = options_.car_length + options_.engage_time * std::max(speed, 5.0);
  const bool passing_leader = leader && memory.mode == RaceMode::kPass && memory.other == leader->name;
  // A pass begins from behind the car (its tail ahead of this one's nose): beside a car that is going
  // by, staying there is holding a place, not passing it (that "pass" was given up as the other completed).
  const bool can_pass = leader && leader_gap < (passing_leader ? 1.5 * engage : engage) &&
                        (passing_leader || (speed >= options_.min_pass_speed && leader_gap >= options_.car_length)) &&
                        !(abort.plans_left > 0 && abort.other == leader->name);
  const bool level_with_leader = leader && leader_gap < near;
  std::vector<Candidate> candidates;
  // A move the car is already making goes on from where it began; a new one starts here.
  auto make = [&](RaceMode mode, int side, const std::string& other, double to) {
    RaceDecision d{mode, side, other, to, 0.0, s, lateral, speed};
    const bool same_move = mode == RaceMode::kPass || mode == RaceMode::kYield
                               ? memory.mode == mode && memory.side == side && memory.other == other
                               : (memory.mode == mode || memory.mode == RaceMode::kFollow) && memory.side == 0;
    // A pass goes out to wherever the car passed now is, but never back towards it (the ramp is never
    // restarted: a ramp begun afresh each tick never moves the car); any other move keeps its target unless
    // that changed. Following the car passed as it moved away took a pass across the road towards it: at
    // Roar Ring, closing at 9 m/s from 9 m behind a car that moved 3 m the other way, into its lane, where
    // the pass was given up and touched it.
    if (same_move && (mode == RaceMode::kPass || std::abs(memory.offset - to) < 0.5)) {
      d.ramp_s = memory.ramp_s;
      d.ramp_from = memory.ramp_from;
      d.ramp_speed = memory.ramp_speed;
      if (mode != RaceMode::kPass || side * (memory.offset - to) > 0.0) d.offset = memory.offset;
    }
    return d;
  };
  auto consider = [&](const RaceDecision& d) {
    const bool slingshot = d.mode == RaceMode::kPass && tow > 0.01;
    const Trajectory& from = slingshot ? towed_base : d.mode == RaceMode::kRacingLine ? on_line_base : base;
    const double drag_share = slingshot ? 1.0 - tow : 1.0;
    const bool pass = d.mode == RaceMode::kPass;
    // Holding a lane while still drifting from the move before: settling there as on the line (a car that
    // gave up a pass outside a fast curve at Roar Speedway, drifting out at 1.6 m/s, held its lane on all the
    // grip at 59 m/s, slid 3.7 m wide of it and into the barrier).
    const double settle = d.mode == RaceMode::kHold ? settle_s : -kInf;
    Candidate c{shifted(from, d.ramp_s, d.ramp_from, d.offset, kInf, drag_share, pass, settle, d.ramp_speed), d, true};
    Trajectory staying_out;  // a pass's window that does not come back onto the line within it
    if (d.mode == RaceMode::kPass && leader) {
      // Back onto the racing line once clear ahead of the car passed: off the line no longer than needed.
      const double back_s = passCompleteAt(c.window, s, speed, leader_prediction);
      if (std::isfinite(back_s)) {
        staying_out = std::move(c.window);
        c.window = shifted(from, d.ramp_s, d.ramp_from, d.offset, back_s, drag_share, pass, -kInf, d.ramp_speed);
      }
    }
    // A move under way goes on with half the margin it needed to start: hysteresis, not dithering.
    const bool under_way = memory.mode == d.mode && memory.side == d.side && memory.other == d.other;
    const double margin_share = under_way ? 0.5 : 1.0;
    // Level with the car passed, a pass is given up only for what it could not drop back from later.
    const double within = under_way && d.mode == RaceMode::kPass && level_with_leader ? options_.abort_time : kInf;
    c.clear = clearOf(c.window, s, speed, predicted, &c.decision.progress, margin_share, within);
    if (!c.clear && !staying_out.points.empty()) {
      // Coming back is planned where the car passed is cleared at the speeds of the path staying out; the
      // way back (a curve, slower) may not clear it yet. Then the pass stays out beside the line for now:
      // a pass is not given up for the way back in.
      double progress = 0.0;
      if (clearOf(staying_out, s, speed, predicted, &progress, margin_share, within)) {
        c.window = std::move(staying_out);
        c.decision.progress = progress;
        c.clear = true;
      }
    }
    const bool pass_on_leader = d.mode == RaceMode::kPass && leader;
    bool draws_alongside = pass_on_leader && drawsAlongside(c.window, s, speed, leader_prediction);
    // A new pass must at least draw alongside within the horizon: off the line and no nearer, it only
    // loses time (and meets the next corner still behind the car).
    if (c.clear && pass_on_leader && !passing_leader && !draws_alongside) c.clear = false;
    if (pass_on_leader) {
      // Or: stay behind the car at its speed until beside it with room, then go by.
      Candidate patient = c;
      followBehind(&patient.window, s, s + leader_gap, leader->speed, options_.follow_gap, limits_, speed);
      const double wide = options_.car_width + options_.lateral_margin;
      bool beside = false;
      for (std::size_t k = 0; k < c.window.points.size(); ++k) {
        const auto& p = c.window.points[k];
        beside = beside || (p.s > s && std::abs(p.offset - sampleAt(line_, p.s).offset - leader->lateral) >= wide);
        if (beside) patient.window.points[k].speed = p.speed;
      }
      // Waiting behind the car off the line is following it there: only worth it if it then draws
      // alongside within the horizon.
      patient.clear = clearOf(patient.window, s, speed, predicted, &patient.decision.progress, margin_share, within) &&
                      drawsAlongside(patient.window, s, speed, leader_prediction);
      if (patient.clear && (!c.clear || patient.decision.progress > c.decision.progress)) {
        c = std::move(patient);
        draws_alongside = true;
      }
      // A pass that does not draw alongside within the horizon gets no further in it than following: the
      // car it passes is still ahead at the end. Credited with its own path's speeds, such a pass under way
      // went on looking better than following (doc/traffic_history.md).
      if (!draws_alongside) {
        c.decision.progress = std::min(c.decision.progress, behind_leader);
      }
    }
    // A pass is begun only on a side whose lane stays open until it is done: until the car is a car's
    // length and margin ahead of the car it passes, gaining on it as this plan does over the horizon. A
    // lane that closes sooner squeezes the pass onto the line beside the car (Monza's reverse grid: a pass
    // level on the left where the line ran over to the left edge was planned down to 30 m/s there, braked
    // beside the car, fell 37 m back and was given up).
    if (c.clear && pass_on_leader && !passing_leader) {
      // Metres gained on the car per metre driven; alongside from level behind it to level ahead.
      const double rate = (leader_gap + c.decision.progress - leader_prediction.at(options_.horizon)) /
                          std::max(1.0, c.decision.progress);
      const double level_at = std::max(0.0, leader_gap - near) / std::max(rate, 1e-3);
      const double alongside_for = std::min(L, 2.0 * near / std::max(rate, 1e-3));
      if (laneRun(d.side, s + level_at, d.side * leader->lateral, alongside_for) < alongside_for) c.clear = false;
    }
    candidates.push_back(std::move(c));
  };
  // What is chosen goes under the guard and is remembered: the decision, and the window others predict it by.
  auto commit = [&](Trajectory window, const RaceDecision& decision, bool clear_pass = false) {
    guard(&window, s, speed, others, predicted, clear_pass);
    memory = decision;
    plans_[car] = window;
    return window;
  };
  // Blue flags: a car a lap up closing from behind is let by. The car moves aside (the side with more room,
  // kept until it has been lapped) at its own pace, where that is clear of everyone.
  if (options_.blue_flags) {
    const TrafficCar* blue = nullptr;
    double blue_rel = -std::numeric_limits<double>::infinity();
    const auto yielding_to = yields_.find(car);
    for (const auto& o : traffic) {
      if (o.name == car || !o.lapping) continue;
      const double rel = aheadOnLap(o.s, s, L);
      const bool closing = rel < 0 && -rel < options_.car_length + options_.blue_flag_time * std::max(o.speed, 1.0);
      // Let by means clear ahead: aside until the car is as far ahead as a pass leaves the car passed.
      const bool going_by = yielding_to != yields_.end() && yielding_to->second.first == o.name && rel >= 0 &&
                            rel < near + 2.0 + options_.rejoin_time * std::max(speed, o.speed);
      if ((closing || going_by) && rel > blue_rel) {
        blue = &o;
        blue_rel = rel;
      }
    }
    if (!blue) yields_.erase(car);
    if (blue) {
      // One side for the whole of being lapped: never across the lapping car's way.
      auto side_it = yields_.find(car);
      if (side_it == yields_.end() || side_it->second.first != blue->name) {
        side_it =
            yields_.insert_or_assign(car, std::make_pair(blue->name, roomLeft(s) >= roomRight(s) ? +1 : -1)).first;
      }
      const int side = side_it->second.second;
      const bool yielding = memory.mode == RaceMode::kYield && memory.other == blue->name && memory.side == side;
      const RaceDecision d =
          make(RaceMode::kYield, side, blue->name, side * (options_.car_width + options_.lateral_margin + 0.3));
      Candidate c{shifted(base, d), d, true};
      // Clear of everyone but the car it makes room for: that one goes by wherever it is.
      std::vector<Prediction> but_blue;
      for (std::size_t i = 0; i < others.size(); ++i)
        if (others[i].name != blue->name) but_blue.push_back(predicted[i]);
      if (clearOf(c.window, s, speed, but_blue, &c.decision.progress, yielding ? 0.5 : 1.0)) {
        holds_.erase(car);
        return commit(std::move(c.window), c.decision);
      }
    }
  }
  // Defending: not while busy with a car ahead (passing, following it close, holding beside someone).
  const bool free_to_defend = memory.mode == RaceMode::kRacingLine || memory.mode == RaceMode::kDefend ||
                              (memory.mode == RaceMode::kFollow && !can_pass);
  if (options_.defend && free_to_defend && !alongside) {
    Candidate c = defend(car, s, lateral, speed, traffic, base, predicted, memory);
    if (c.decision.mode == RaceMode::kDefend) {
      holds_.erase(car);
      return commit(std::move(c.window), c.decision);
    }
  }
  // Alone on the line (nobody near, no move under way): the racing line's window as it is, so that a car
  // racing alone drives exactly as without this planner, its tracking error notwithstanding.
  if (others.empty() && memory.mode == RaceMode::kRacingLine && memory.ramp_from == 0.0) {
    memory = {RaceMode::kRacingLine, 0, "", 0.0, 0.0, s, 0.0};
    plans_.erase(car);  // on the racing line: its lateral place now predicts it
    return on_line_base;
  }
  const bool on_line = std::abs(lateral) < 0.5 && memory.mode != RaceMode::kPass;
  // Holding a place beside another car means the place planned, not wherever the car has drifted to: a
  // target that followed the car's tracking error would walk it into the car alongside. (Only a car keeping
  // its place, below, holds it; its planned place is forgotten once it no longer does.)
  // A place taken afresh is the car's own, but no further out than the lane it was planned in (a pass or
  // a place held): a car sliding wide of its lane took its place again each time where it had slid to and
  // slid on (Roar Speedway's reverse grid: a pass 3.5 m out held at 4.1, 5.5, then 6.5 m, braked to half
  // its speed there and came back onto the line into the car behind).
  const auto held = holds_.find(car);
  const bool in_a_lane = memory.mode == RaceMode::kPass || memory.mode == RaceMode::kHold;
  const bool wide_of_it = in_a_lane && memory.offset * lateral > 0.0 && std::abs(lateral) > std::abs(memory.offset);
  const double hold_at = held != holds_.end() ? held->second : wide_of_it ? memory.offset : lateral;
  // Off the line in a fast curve, the way back onto it turns harder than the curve does, and a car at the
  // curve's speed would have to brake while turning harder: it slides (Roar Speedway, a pass given up 4.5 m
  // outside the line at 57 m/s on a 435 m curve planned its way back at 52 m/s from where the car was, and the
  // car spun). It keeps its lane until the way back is drivable at the speed it has.
  bool way_back_brakes = false;
  if (!on_line) {
    auto brakesAtOnce = [&](const RaceDecision& d, const Trajectory& from) {
      return sampleAt(shifted(from, d), s).speed < speed - kMoveBrakeSlack;
    };
    way_back_brakes = brakesAtOnce(make(RaceMode::kRacingLine, 0, "", 0.0), on_line_base) &&
                      !brakesAtOnce(make(RaceMode::kHold, 0, "", hold_at), base);
  }
  if (on_line) {
    Candidate c{on_line_base, {RaceMode::kRacingLine, 0, "", 0.0, 0.0, s, 0.0}, true};
    c.clear = clearOf(c.window, s, speed, predicted, &c.decision.progress);
    candidates.push_back(std::move(c));
  } else if (!way_back_brakes) {
    consider(make(RaceMode::kRacingLine, 0, "", 0.0));  // back to the line
  }
  // Off the line and closing on the car ahead fast enough to reach it within a move's time: the way back
  // onto the line runs into its back (a pass given up in a braking zone, 18 m behind at 10 m/s more, went
  // back towards the line while braking and touched it). The fallback keeps the car's lane until it has
  // the other's speed.
  const bool closing_ahead = leader && std::abs(lateral) >= 0.5 &&
                             std::abs(lateral - leader->lateral) >= options_.car_width + options_.guard_lateral &&
                             leader_gap < near + std::max(0.0, speed - leader->speed) * options_.shift_time;
  // The place is held while a car is beside or closing from behind (holding it is then a candidate of its
  // own), and as the fallback while closing on the car ahead.
  const bool beside_or_closing_behind = alongside || closing_behind;
  const bool keep_place = beside_or_closing_behind || closing_ahead || way_back_brakes;
  if (held != holds_.end() && !keep_place) holds_.erase(held);
  if ((beside_or_closing_behind || way_back_brakes) && !on_line) consider(make(RaceMode::kHold, 0, "", hold_at));
  if (can_pass) {
    // Close behind a car, a pass goes by on the side the car is already on: never across its tail.
    const bool close = leader_gap < 2.0 * options_.car_length;
    const int near_side = lateral >= leader->lateral ? +1 : -1;
    for (int side : {+1, -1}) {
      if (close && side != near_side && !(passing_leader && memory.side == side)) continue;
      const double to = leader->lateral + side * (options_.car_width + options_.lateral_margin + 0.3);
      if (std::abs(to) > options_.max_pass_offset) continue;  // round a car far off the line: the other side
      if (side * sidewaysNow(*leader) > 0.5 && !passing_leader) continue;  // not into a door that is closing
      consider(make(RaceMode::kPass, side, leader->name, to));
    }
  }
  // The fallback: behind the leader at its speed; beside a car or with one closing from behind, holding the
  // lateral place (never squeezing it nor crossing its way), otherwise on or back to the racing line.
  const RaceDecision fallback_path = keep_place && !on_line ? make(RaceMode::kHold, 0, "", hold_at)
                                     : on_line ? RaceDecision{RaceMode::kRacingLine, 0, "", 0.0, 0.0, s, 0.0}
                                               : make(RaceMode::kRacingLine, 0, "", 0.0);
  Candidate follow{on_line                                 ? on_line_base
                   : fallback_path.mode == RaceMode::kHold ? shifted(base, fallback_path, settle_s)
                                                           : shifted(on_line_base, fallback_path),
                   fallback_path, true};
  follow.decision.mode = RaceMode::kFollow;
  // Scored on its own path before it is held to the leader's speed now: that speed held over the horizon is
  // no prediction of a leader about to accelerate out of a corner (behind_leader, below, is). Scored held,
  // following was credited 20 m short in Roar Eight's loops, and a pass on the outside of the loop, gaining
  // 0.5 m/s on the car ahead, looked 30 m better than following: it stayed out the whole loop and came
  // back onto the line 20 m behind (reverse grid, seed 1, 21.6-37.0 s).
  clearOf(follow.window, s, speed, {}, &follow.decision.progress);
  if (leader) {
    follow.decision.other = leader->name;
    // A leader level beside this car, in a lane of its own, is let by: followed from where it is, at a little
    // less than its speed, not braked for at once to be the follow gap behind it. Braking so, from 45 to
    // 37 m/s in 1.25 s into a braking curve, a car being passed slid 1.5 m wide into the car passing it
    // (Monza's reverse grid over 8 laps, seed 1, 617.2 s).
    const bool beside =
        level_with_leader && std::abs(leader->lateral - lateral) >= options_.car_width + 0.5 * options_.lateral_margin;
    const double held = beside ? std::max(0.0, leader->speed - kLetByRate) : leader->speed;
    followBehind(&follow.window, s, s + leader_gap, held, beside ? leader_gap : options_.follow_gap, limits_, speed);
    // Behind the leader as it is predicted to go, not at the speed it has now.
    follow.decision.progress = std::min(follow.decision.progress, behind_leader);
  }

  const Candidate* chosen = nullptr;
  if (memory.mode != RaceMode::kPass) headways_.erase(car);  // a pass begun afresh has all its time
  if (memory.mode == RaceMode::kPass) {
    // A committed pass keeps its side while it stays clear and the car passed is still ahead; it is never
    // switched to the other side (that is how cars get squeezed).
    for (const auto& c : candidates) {
      // ...and while it still gains on following (a pass squeezed onto the line by the road's edge is
      // following by another name).
      if (c.clear && c.decision.mode == RaceMode::kPass && c.decision.side == memory.side &&
          c.decision.other == memory.other &&
          c.decision.progress > follow.decision.progress + 0.5 * options_.min_gain) {
        chosen = &c;
      }
    }
    // A pass is trusted (its doubts cleared) only while it gains on following, not merely while it is clear:
    // a clear pass getting less far than following stayed out into Monza's first chicane, 7 m behind the car
    // it passed, planned on its outside lane at 10 m/s where that car took 24 m/s, and fell 40 m back.
    const Candidate* gaining = chosen;
    const bool still_ahead = leader && leader->name == memory.other;
    // A pass that makes no headway on the car from further back than following it (its gap closing by a
    // metre within stall_time) is given up: off the line and no nearer, it only loses time. Close behind,
    // waiting for room beside the car is part of the pass.
    Headway& headway = headways_[car];
    if (still_ahead) {
      if (headway.other != memory.other || leader_gap < headway.best_gap - 1.0)
        headway = {memory.other, leader_gap, 0.0};
      if (leader_gap > options_.follow_gap + options_.car_length) headway.stalled += options_.plan_period;
      if (headway.stalled > options_.stall_time) chosen = nullptr;
    }
    const bool stalled = still_ahead && headway.stalled > options_.stall_time;
    // The car passed moving across towards this one's side while this one is still behind it: the door is
    // closing, and a pass that chases it sideways asks more than the car can do. Given up at once.
    const bool cutting_in = still_ahead && leader_gap > options_.car_length && memory.side * sidewaysNow(*leader) > 0.5;
    if (cutting_in) chosen = nullptr;
    // One plan's doubt is not an abort: predictions jitter with the odometry's timing, and the guard keeps
    // the car off the back of anyone in its path meanwhile.
    int& doubts = doubts_[car];
    if (!chosen && still_ahead && !stalled && !cutting_in && ++doubts < options_.abort_plans) {
      for (const auto& c : candidates) {
        if (c.decision.mode == RaceMode::kPass && c.decision.side == memory.side && c.decision.other == memory.other) {
          chosen = &c;
        }
      }
    }
    if (chosen && chosen == gaining) doubts = 0;
    if (!chosen && still_ahead) {
      chosen = &follow;  // aborted: fall in behind, holding the lateral place while beside anyone
    } else if (!chosen) {
      // The passed car is no longer ahead: the pass is complete; hold beside it while it is alongside.
      for (const auto& c : candidates) {
        if (c.clear && (c.decision.mode == RaceMode::kRacingLine || c.decision.mode == RaceMode::kHold) &&
            (!chosen || c.decision.mode == RaceMode::kRacingLine)) {
          chosen = &c;
        }
      }
    }
  }
  if (!chosen) {
    for (const auto& c : candidates) {
      if (!c.clear) continue;
      if (c.decision.mode == RaceMode::kPass && c.decision.progress < follow.decision.progress + options_.min_gain)
        continue;
      if (!chosen || c.decision.progress > chosen->decision.progress + 0.5 ||
          (c.decision.mode == RaceMode::kRacingLine && c.decision.progress >= chosen->decision.progress - 0.5)) {
        chosen = &c;
      }
    }
  }
  if (!chosen) chosen = &follow;
  if (memory.mode == RaceMode::kPass && chosen->decision.mode == RaceMode::kFollow)
    abort = {memory.other, options_.retry_plans};
  const bool holding = keep_place && (chosen->decision.mode == RaceMode::kHold || (chosen == &follow && !on_line));
  if (holding) {
    holds_[car] = hold_at;
  } else {
    holds_.erase(car);
  }
  return commit(chosen->window, chosen->decision, chosen->clear && chosen->decision.mode == RaceMode::kPass);
}

OvertakePlanner::Candidate OvertakePlanner::defend(const std::string& car, double s, double lateral, double speed,
                                                   const std::vector<TrafficCar>& traffic, const Trajectory& base,
                                                   const std::vector<Prediction>& predicted,
                                                   const RaceDecision& memory) {
  const double L = lapLength(line_);
  const double reach = options_.car_length + options_.defend_time * std::max(speed, 5.0);
  const double beside = levelDistance();
  Defence& defence = defences_[car];
  bool against_near = false;
  const TrafficCar* attacker = nullptr;
  double attacker_rel = -std::numeric_limits<double>::infinity();
  for (const auto& o : traffic) {
    if (o.name == car || o.lapping) continue;  // a car a lap up is let by (blue flags), not defended against
    const double rel = aheadOnLap(o.s, s, L);
    // The car defended against is near until it has gone by or dropped well back.
    if (o.name == defence.against && rel < options_.car_length && rel > -2.0 * reach) against_near = true;
    if (rel >= -beside || rel < -reach || rel <= attacker_rel) continue;
    attacker = &o;
    attacker_rel = rel;
  }
  if (!against_near) defence = {};
  Candidate none{Trajectory{}, RaceDecision{}, false};
  if (!attacker) return none;
  // A move is held for defend_hold at most: covering a line, not driving off the racing line for good.
  const bool defending = memory.mode == RaceMode::kDefend && memory.other == attacker->name &&
                         ++defence.plans * options_.plan_period <= options_.defend_hold;
  const double across = attacker->lateral - lateral;
  const int side = across > 0 ? +1 : -1;
  // A threat: at racing speed (not the grid), close behind, pulled out off the racing line and to one
  // side of this car by half a car's width each, and not dropping back; this car on its line.
  const double half = 0.5 * options_.car_width;
  const bool threat = speed >= options_.min_pass_speed && std::abs(across) > half &&
                      std::abs(attacker->lateral) > half && std::abs(lateral) < half && attacker->speed > speed - 0.5;
  if (!defending && (!threat || !defence.against.empty())) return none;  // one move, no second
  RaceDecision d{RaceMode::kDefend,
                 side,
                 attacker->name,
                 lateral + side * std::min(std::abs(across), options_.defend_shift),
                 0.0,
                 s,
                 lateral};
  if (defending) {  // the move goes on where it began, to where it was going
    d.side = memory.side;
    d.offset = memory.offset;
    d.ramp_s = memory.ramp_s;
    d.ramp_from = memory.ramp_from;
  }
  Candidate c{shifted(base, d), d, true};
  // Never across in front of a car that could not brake for it: the move is begun only while the car
  // behind, closing at the speed it has, stays a car's length and margin behind until the move is made
  // and rejoin_time after. The cars ahead and beside are checked as any plan is.
  const double closing = std::max(0.0, attacker->speed - speed);
  if (!defending && -attacker_rel - closing * (options_.shift_time + options_.rejoin_time) < beside) return none;
  std::vector<Prediction> ahead;
  for (const auto& p : predicted) {
    if (aheadOnLap(p.s, s, L) > 0.0) ahead.push_back(p);
  }
  c.clear = clearOf(c.window, s, speed, ahead, &c.decision.progress, defending ? 0.5 : 1.0);
  if (!c.clear) return none;
  if (!defending) defence = {attacker->name, 0};
  return c;
}

void OvertakePlanner::guard(Trajectory* window, double s, double speed, const std::vector<TrafficCar>& others,
                            const std::vector<Prediction>& predicted, bool clear_pass) const {
  // Whatever was chosen, never faster than a car ahead in the plan's own path allows: the nearest car
  // ahead whose lateral place overlaps the plan's where it is is followed at a short gap.
  const double gap = levelDistance() + options_.guard_time * speed;
  const TrafficCar* nearest = nullptr;
  const Prediction* nearest_prediction = nullptr;
  double nearest_rel = 0.0;
  // Where a pass gets along its plan in one and two seconds (-inf: not reached within it).
  const double level = levelDistance();
  double travelled[3] = {0.0, -kInf, -kInf};
  if (clear_pass) {
    driveAlong(*window, s, speed, [&](std::size_t, double t, double s_now, double) {
      for (int i : {1, 2}) {
        if (t >= i && travelled[i] == -kInf) travelled[i] = s_now - s;
      }
      return t < 2.0;
    });
  }
  const double width = options_.car_width + options_.guard_lateral;
  for (std::size_t j = 0; j < others.size(); ++j) {
    const TrafficCar& o = others[j];
    const double rel = aheadOnLap(o.s, s, lapLength(line_));
    if (rel <= 0.0 || (nearest && rel >= nearest_rel)) continue;
    // In the path now, or in it over the next two seconds. For a clear pass (checked against every car's
    // prediction, with margins), later only while the car is still ahead then, and a car level now only by
    // moving across into it: the pass's own way back onto the line in front of the car it passes is not
    // that car in its path (a pass drawn level at Monza was held a gap behind the car it passed, braked
    // 5 m/s beside it and fell 37 m back). Any other plan (following is checked against nobody) keeps
    // every time: a car falling in behind one braking hard met it where it would have been level.
    const bool level_now = rel < level;
    bool in_path = false;
    for (int i : {0, 1, 2}) {
      const double tau = i;
      if (clear_pass && i > 0 && predicted[j].at(tau) - travelled[i] < level) continue;
      const double at = rel + tau * o.speed;
      const double d = sampleAt(*window, s + at).offset - sampleAt(line_, s + at).offset;
      const double drift = o.lateral + o.lateral_speed * std::min(tau, options_.lateral_lookahead);
      const double theirs = tau == 0.0 ? o.lateral : plannedLateral(trustedPlan(o), drift, o.s + tau * o.speed);
      const bool moved_in = std::abs(d - o.lateral) >= width;
      in_path = in_path || (std::abs(d - theirs) < width && (i == 0 || !clear_pass || !level_now || moved_in));
    }
    if (!in_path) continue;
    nearest = &o;
    nearest_prediction = &predicted[j];
    nearest_rel = rel;
  }
  if (!nearest) return;
  // Without guard_predicted, or already nearer than the gap: held from where the car ahead is now.
  if (!options_.guard_predicted || nearest_rel < gap) {
    followBehind(window, s, s + nearest_rel, nearest->speed, gap, limits_, speed);
    return;
  }
  // guard_predicted: held to that car's speed from where, driving the window, the car would first come
  // within the gap of it as it is predicted to go on (held short of where it is now at its speed now, a car
  // 5% faster needs (v^2 - v_ahead^2) / 2a more room to go faster: 17 m at 60 m/s for 3 m/s).
  const Prediction& ahead = *nearest_prediction;
  double meet_s = kInf, meet_speed = nearest->speed;
  driveAlong(*window, s, speed, [&](std::size_t, double t, double s_now, double) {
    if (t > options_.horizon) return false;
    if (s_now - s < ahead.at(t) - gap) return true;
    meet_s = s_now;
    meet_speed = (ahead.at(t + kPredictionStep) - ahead.at(t)) / kPredictionStep;
    return false;
  });
  if (std::isfinite(meet_s)) followBehind(window, s, meet_s + gap, std::max(0.0, meet_speed), gap, limits_);
}

std::vector<PredictedPath> OvertakePlanner::predictions(const std::string& car) const {
  auto it = predictions_.find(car);
  return it == predictions_.end() ? std::vector<PredictedPath>{} : it->second;
}

RaceDecision OvertakePlanner::decision(const std::string& car) const {
  auto it = decisions_.find(car);
  return it == decisions_.end() ? RaceDecision{} : it->second;
}

}  // namespace roar::planning
