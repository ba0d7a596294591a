#include "roar/planning/overtaking.h"

#include <algorithm>
#include <cmath>

#include "roar/planning/speed_profile.h"
#include "roar/track/track.h"

namespace roar::planning {

namespace {

double smoothStep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

}  // namespace

const char* raceModeName(RaceMode mode) {
  switch (mode) {
    case RaceMode::kRacingLine: return "racing_line";
    case RaceMode::kFollow: return "follow";
    case RaceMode::kPass: return "pass";
    case RaceMode::kHold: return "hold";
  }
  return "unknown";
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

double interpolateWrapped(const std::vector<double>& xs, const std::vector<double>& ys, double length, double x) {
  x -= std::floor(x / length) * length;
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

// Forward distance from b to a round a lap of `length`, in [-length / 2, length / 2).
double ahead(double a, double b, double length) {
  double d = a - b;
  d -= std::floor(d / length + 0.5) * length;
  return d;
}

}  // namespace

double OvertakePlanner::roomLeft(double s) const { return interpolateWrapped(room_s_, room_left_, line_.length, s); }
double OvertakePlanner::roomRight(double s) const { return interpolateWrapped(room_s_, room_right_, line_.length, s); }

Trajectory OvertakePlanner::shifted(const Trajectory& window, double ramp_s, double from, double to) const {
  Trajectory out = window;
  const double shift_length = std::max(options_.min_shift_length, options_.shift_time * sampleAt(line_, ramp_s).speed);
  auto& pts = out.points;
  const double half = 0.5 * options_.car_width + options_.edge_margin;
  for (auto& p : pts) {
    const double shift = from + (to - from) * smoothStep(ahead(p.s, ramp_s, line_.length) / shift_length);
    const double d = std::clamp(shift, -(roomRight(p.s) - half), roomLeft(p.s) - half);
    p.position += d * Eigen::Vector2d(-std::sin(p.yaw), std::cos(p.yaw));
    p.offset += d;
  }
  const std::size_t n = pts.size();
  if (n < 3) return out;
  std::vector<double> step(n, 0.0), curvature(n, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) step[k] = std::max(1e-3, (pts[k + 1].position - pts[k].position).norm());
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = k == 0 ? 0 : k - 1, b = std::min(n - 1, k + 1);
    const Eigen::Vector2d d = pts[b].position - pts[a].position;
    pts[k].yaw = std::atan2(d.y(), d.x());
  }
  for (std::size_t k = 1; k + 1 < n; ++k) {
    double dyaw = pts[k + 1].yaw - pts[k - 1].yaw;
    dyaw = std::atan2(std::sin(dyaw), std::cos(dyaw));
    curvature[k] = dyaw / (step[k - 1] + step[k]);
  }
  curvature[0] = curvature[1];
  curvature[n - 1] = curvature[n - 2];
  SpeedProfileOptions profile_options;
  profile_options.start_speed = -1.0;
  const SpeedProfile profile = computeSpeedProfile(step, curvature, limits_, false, profile_options);
  for (std::size_t k = 0; k < n; ++k) {
    pts[k].curvature = curvature[k];
    pts[k].speed = std::min(pts[k].speed, profile.speed[k]);
  }
  for (std::size_t k = n - 1; k-- > 0;) {  // braking for the slower points the cap made
    const double a = decelerationAt(limits_, pts[k + 1].speed, pts[k + 1].curvature);
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

bool OvertakePlanner::clearOf(const Trajectory& plan, double s0, const std::vector<TrafficCar>& others,
                              double* progress) const {
  const auto& pts = plan.points;
  // The car's own motion along the plan: from its speed now, no faster than the plan, accelerating at
  // most as the engine can.
  double t = 0.0, v = std::max(0.0, pts.empty() ? 0.0 : sampleAt(plan, s0).speed);
  double s = s0, last_check = -1e9;
  bool clear = true;
  const double length = options_.car_length + options_.longitudinal_margin;
  const double width = options_.car_width + options_.lateral_margin;
  for (std::size_t k = 0; k + 1 < pts.size() && t < options_.horizon; ++k) {
    if (pts[k + 1].s <= s0) continue;
    const double s_next = pts[k + 1].s;
    const double ds = s_next - std::max(s, pts[k].s);
    const double v_next = std::min(pts[k + 1].speed,
                                   std::sqrt(v * v + 2.0 * std::max(0.0, limits_.driveForce(v)) / limits_.effectiveMass() * ds));
    t += ds / std::max(0.5, 0.5 * (v + v_next));
    v = v_next;
    s = s_next;
    if (s - last_check < options_.sample_step) continue;
    last_check = s;
    if (t < 0.3) continue;  // too soon to change anything
    const double d = pts[k + 1].offset - sampleAt(line_, s).offset;
    for (const auto& o : others) {
      const double o_s = ahead(o.s, s0, line_.length) + o.speed * t;
      if (std::abs((s - s0) - o_s) < length && std::abs(d - o.lateral) < width) {
        clear = false;
        break;
      }
    }
    if (!clear) break;
  }
  *progress = s - s0;
  return clear;
}

Trajectory OvertakePlanner::plan(const std::string& car, double s, double lateral, double speed,
                                 const std::vector<TrafficCar>& traffic, double behind, double ahead_m) {
  const double L = line_.length;
  const Trajectory base = windowAround(line_, s, behind, ahead_m);
  // Cars that matter: alongside or ahead, within the window.
  std::vector<TrafficCar> others;
  const TrafficCar* leader = nullptr;
  double leader_gap = ahead_m;
  bool alongside = false;
  for (const auto& o : traffic) {
    if (o.name == car) continue;
    const double rel = ahead(o.s, s, L);
    if (rel < -(options_.car_length + options_.longitudinal_margin) || rel > ahead_m) continue;
    others.push_back(o);
    if (std::abs(rel) < options_.car_length + options_.longitudinal_margin) alongside = true;
    if (rel > 0 && rel < leader_gap && std::abs(o.lateral - lateral) < options_.car_width + options_.lateral_margin + 2.0) {
      leader_gap = rel;
      leader = &o;
    }
  }
  RaceDecision& memory = decisions_[car];
  std::vector<Candidate> candidates;
  // A move the car is already making goes on from where it began; a new one starts here.
  auto make = [&](RaceMode mode, int side, const std::string& other, double to) {
    RaceDecision d{mode, side, other, to, 0.0, s, lateral};
    const bool same_move = mode == RaceMode::kPass
                               ? memory.mode == mode && memory.side == side && memory.other == other
                               : (memory.mode == mode || memory.mode == RaceMode::kFollow) && memory.side == 0;
    if (same_move && std::abs(memory.offset - to) < 0.5) {
      d.ramp_s = memory.ramp_s;
      d.ramp_from = memory.ramp_from;
      d.offset = memory.offset;
    }
    return d;
  };
  auto consider = [&](const RaceDecision& d) {
    Candidate c{shifted(base, d.ramp_s, d.ramp_from, d.offset), d, true};
    c.clear = clearOf(c.window, s, others, &c.decision.progress);
    if (d.mode == RaceMode::kPass && leader) {
      // Or: stay behind the car at its speed until beside it with room, then go by.
      Candidate patient = c;
      followBehind(&patient.window, s, s + leader_gap, leader->speed, options_.follow_gap, limits_);
      const double wide = options_.car_width + options_.lateral_margin;
      bool beside = false;
      for (std::size_t k = 0; k < c.window.points.size(); ++k) {
        const auto& p = c.window.points[k];
        beside = beside || (p.s > s && std::abs(p.offset - sampleAt(line_, p.s).offset - leader->lateral) >= wide);
        if (beside) patient.window.points[k].speed = p.speed;
      }
      patient.clear = clearOf(patient.window, s, others, &patient.decision.progress);
      if (patient.clear && (!c.clear || patient.decision.progress > c.decision.progress)) c = std::move(patient);
    }
    candidates.push_back(std::move(c));
  };
  // Alone on the line (nobody near, no move under way): the racing line's window as it is, so that a car
  // racing alone drives exactly as without this planner, its tracking error notwithstanding.
  if (others.empty() && memory.mode == RaceMode::kRacingLine && memory.ramp_from == 0.0) {
    memory = {RaceMode::kRacingLine, 0, "", 0.0, 0.0, s, 0.0};
    return base;
  }
  const bool on_line = std::abs(lateral) < 0.5 && memory.mode != RaceMode::kPass;
  if (on_line) {
    Candidate c{base, {RaceMode::kRacingLine, 0, "", 0.0, 0.0, s, 0.0}, true};
    c.clear = clearOf(c.window, s, others, &c.decision.progress);
    candidates.push_back(std::move(c));
  } else {
    consider(make(RaceMode::kRacingLine, 0, "", 0.0));  // back to the line
  }
  if (alongside && !on_line) consider(make(RaceMode::kHold, 0, "", lateral));
  if (leader) {
    for (int side : {+1, -1}) {
      consider(make(RaceMode::kPass, side, leader->name,
                    leader->lateral + side * (options_.car_width + options_.lateral_margin + 0.3)));
    }
  }
  // The fallback: behind the leader at its speed; beside a car, holding the lateral place (never squeezing
  // it), otherwise on or back to the racing line.
  const RaceDecision fallback_path = alongside && !on_line ? make(RaceMode::kHold, 0, "", lateral)
                                     : on_line             ? RaceDecision{RaceMode::kRacingLine, 0, "", 0.0, 0.0, s, 0.0}
                                                           : make(RaceMode::kRacingLine, 0, "", 0.0);
  Candidate follow{on_line ? base : shifted(base, fallback_path.ramp_s, fallback_path.ramp_from, fallback_path.offset),
                   fallback_path, true};
  follow.decision.mode = RaceMode::kFollow;
  if (leader) {
    follow.decision.other = leader->name;
    followBehind(&follow.window, s, s + leader_gap, leader->speed, options_.follow_gap, limits_);
  }
  clearOf(follow.window, s, {}, &follow.decision.progress);

  const Candidate* chosen = nullptr;
  // A committed pass keeps its side while it stays clear and the car passed is not yet behind.
  if (memory.mode == RaceMode::kPass) {
    for (const auto& c : candidates) {
      if (c.clear && c.decision.mode == RaceMode::kPass && c.decision.side == memory.side &&
          c.decision.other == memory.other) {
        chosen = &c;
      }
    }
    if (!chosen) {
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
      if (c.decision.mode == RaceMode::kPass && c.decision.progress < follow.decision.progress + options_.min_gain) continue;
      if (!chosen || c.decision.progress > chosen->decision.progress + 0.5 ||
          (c.decision.mode == RaceMode::kRacingLine && c.decision.progress >= chosen->decision.progress - 0.5)) {
        chosen = &c;
      }
    }
  }
  if (!chosen) chosen = &follow;
  memory = chosen->decision;
  return chosen->window;
}

RaceDecision OvertakePlanner::decision(const std::string& car) const {
  auto it = decisions_.find(car);
  return it == decisions_.end() ? RaceDecision{} : it->second;
}

}  // namespace roar::planning
