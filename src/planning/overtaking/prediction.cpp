// Other cars predicted over the horizon, and a plan driven against those predictions: where it gets, and
// whether it stays clear of every car alongside or ahead.
#include <algorithm>
#include <cmath>

#include "roar/planning/overtaking/planner.h"
#include "tuning.h"

namespace roar::planning {

using namespace tuning;

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
  const auto it = memory_.find(car.name);
  if (it == memory_.end() || !it->second.plan) return nullptr;
  const Trajectory* plan = &*it->second.plan;
  return std::abs(plannedLateral(plan, car.lateral, car.s) - car.lateral) <= options_.prediction.plan_trust ? plan
                                                                                                            : nullptr;
}

double OvertakePlanner::plannedLateral(const TrafficCar& car, double s) const {
  return plannedLateral(trustedPlan(car), car.lateral, s);
}

double OvertakePlanner::lateralAt(const Prediction& p, double t) const {
  const double drift = p.lateral + p.lateral_speed * std::min(t, options_.prediction.lateral_lookahead);
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
  const int steps = static_cast<int>(std::ceil(options_.prediction.horizon / kPredictionStep)) + 1;
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
  for (std::size_t k = 0; k + 1 < pts.size() && t < options_.prediction.horizon; ++k) {
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
  const double width = options_.car.width + margin_share * options_.margins.lateral;
  const double d0 = pts.empty() ? 0.0 : sampleAt(plan, s0).offset - sampleAt(line_, s0).offset;
  std::vector<char> merged(others.size(), 0);  // the plan has moved into that car's lane, in front of it
  double end_time = 0.0, end_speed = 0.0;
  const double s = driveAlong(plan, s0, v0, [&](std::size_t k, double t, double s_now, double v) {
    end_time = t;
    end_speed = v;
    if (s_now - last_check < options_.prediction.sample_step) return true;
    last_check = s_now;
    if (t < kTooSoonToChange || t > within) return true;  // or too late, for later plans to see to
    const double d = pts[k].offset - sampleAt(line_, s_now).offset;
    for (std::size_t i = 0; i < others.size(); ++i) {
      const auto& o = others[i];
      // A car behind needs room to brake too: moving across into its lane in front of it keeps
      // rejoin_time at speed (staying in the lane one is already in, ahead of it, is its to mind, and
      // so is the lane once moved into with that room: a pass is not given up for a car it has passed).
      const double ahead_of_it = (s_now - s0) - o.at(t);
      const double theirs = lateralAt(o, t);
      // Moved across: this plan's car is in that car's lane where, had it kept its own place, it would not
      // be. A car moving into this one's lane behind it is that car's to mind: a pass already out in its
      // lane is not given up for a car moving in behind it as if that car had cut in.
      const bool moved_across = std::abs(d0 - theirs) >= width;
      const bool in_lane = std::abs(d - theirs) < width;
      const double keep_ahead = length + (moved_across && !merged[i] ? options_.margins.rejoin_time * v : 0.0);
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
  *progress = s - s0 + (clear ? std::max(0.0, options_.prediction.horizon - end_time) * end_speed : 0.0);
  return clear;
}

double OvertakePlanner::passCompleteAt(const Trajectory& plan, double s0, double v0, const Prediction& leader) const {
  // As far ahead as clearOf asks of a car moving across in front of another, and a little more.
  const double clear_ahead = levelDistance() + kPassClearAhead;
  double at = std::numeric_limits<double>::infinity();
  driveAlong(plan, s0, v0, [&](std::size_t, double t, double s, double v) {
    if ((s - s0) - leader.at(t) <= clear_ahead + options_.margins.rejoin_time * v) return true;
    at = s;
    return false;
  });
  return at;
}

bool OvertakePlanner::drawsAlongside(const Trajectory& plan, double s0, double v0, const Prediction& leader) const {
  bool alongside = false;
  driveAlong(plan, s0, v0, [&](std::size_t, double t, double s, double) {
    alongside = (s - s0) - leader.at(t) > -options_.car.length;
    return !alongside;
  });
  return alongside;
}

}  // namespace roar::planning
