// Candidates: a pass on the car ahead, on either side. A pass comes back onto the racing line once clear
// ahead of the car it passes; it may wait behind the car at its speed until beside it with room; it is
// begun only if it draws alongside within the horizon and on a side whose lane stays open until it is done.
#include <algorithm>
#include <cmath>

#include "plan_context.h"
#include "roar/planning/speed_profile.h"

namespace roar::planning {

using namespace tuning;

void OvertakePlanner::passCandidates(const PlanContext& ctx, std::vector<Candidate>* out) const {
  const TrafficCar& leader = *ctx.leader;
  const RaceDecision& last = ctx.last();
  // Close behind a car, a pass goes by on the side the car is already on: never across its tail.
  const bool close = ctx.leader_gap < 2.0 * options_.car.length;
  const int near_side = ctx.lateral >= leader.lateral ? +1 : -1;
  for (int side : {+1, -1}) {
    if (close && side != near_side && !(ctx.passing_leader && last.side == side)) continue;
    const double to = leader.lateral + side * (options_.car.width + options_.margins.lateral + kMoveAir);
    if (std::abs(to) > options_.passing.max_offset) continue;  // round a car far off the line: the other side
    if (side * sidewaysNow(leader) > kClosingDoor && !ctx.passing_leader) continue;  // not into a closing door
    out->push_back(considerPass(ctx, move(ctx, RaceMode::kPass, side, leader.name, to)));
  }
}

OvertakePlanner::Candidate OvertakePlanner::considerPass(const PlanContext& ctx, const RaceDecision& d) const {
  const TrafficCar& leader = *ctx.leader;
  const bool slingshot = ctx.tow > kMinTow;
  const Trajectory& from = slingshot ? ctx.towed_base : ctx.base;
  const double drag_share = slingshot ? 1.0 - ctx.tow : 1.0;
  Move move = Move::of(d);
  move.pass = true;
  MoveGrip grip;
  grip.drag_share = drag_share;
  Candidate c{shifted(from, move, grip), d, true};
  // Back onto the racing line once clear ahead of the car passed: off the line no longer than needed.
  Trajectory staying_out;  // the window that does not come back onto the line within it
  const double back_s = passCompleteAt(c.window, ctx.s, ctx.speed, ctx.leader_prediction);
  if (std::isfinite(back_s)) {
    staying_out = std::move(c.window);
    move.back_s = back_s;
    c.window = shifted(from, move, grip);
  }
  // A move under way goes on with half the margin it needed to start; level with the car passed, a pass is
  // given up only for what it could not drop back from later
  // (overtaking_test APassAlongsideIsGivenUpOnlyForAConflictWithinTheAbortTime).
  const RaceDecision& last = ctx.last();
  const bool under_way = last.mode == d.mode && last.side == d.side && last.other == d.other;
  const double margin_share = under_way ? 0.5 : 1.0;
  const double within = under_way && ctx.level_with_leader ? options_.passing.abort_time : kInf;
  c.clear = clearOf(c.window, ctx.s, ctx.speed, ctx.predicted, &c.decision.progress, margin_share, within);
  if (!c.clear && !staying_out.points.empty()) {
    // The way back (a curve, slower) may not clear the car passed yet: the pass stays out beside the line
    // for now rather than being given up for the way back in.
    double progress = 0.0;
    if (clearOf(staying_out, ctx.s, ctx.speed, ctx.predicted, &progress, margin_share, within)) {
      c.window = std::move(staying_out);
      c.decision.progress = progress;
      c.clear = true;
    }
  }
  bool draws_alongside = drawsAlongside(c.window, ctx.s, ctx.speed, ctx.leader_prediction);
  // A new pass must at least draw alongside within the horizon: off the line and no nearer, it only loses
  // time (overtaking_test APassIsBegunOnlyIfItDrawsAlongsideWithinTheHorizon).
  if (c.clear && !ctx.passing_leader && !draws_alongside) c.clear = false;
  // Or: stay behind the car at its speed until beside it with room, then go by.
  Candidate patient = c;
  followBehind(&patient.window, ctx.s, ctx.s + ctx.leader_gap, leader.speed, options_.margins.follow_gap, limits_,
               ctx.speed);
  const double wide = options_.car.width + options_.margins.lateral;
  bool beside = false;
  for (std::size_t k = 0; k < c.window.points.size(); ++k) {
    const auto& p = c.window.points[k];
    beside = beside || (p.s > ctx.s && std::abs(p.offset - sampleAt(line_, p.s).offset - leader.lateral) >= wide);
    if (beside) patient.window.points[k].speed = p.speed;
  }
  // Waiting behind the car off the line is following it there: only worth it if it then draws alongside.
  patient.clear =
      clearOf(patient.window, ctx.s, ctx.speed, ctx.predicted, &patient.decision.progress, margin_share, within) &&
      drawsAlongside(patient.window, ctx.s, ctx.speed, ctx.leader_prediction);
  if (patient.clear && (!c.clear || patient.decision.progress > c.decision.progress)) {
    c = std::move(patient);
    draws_alongside = true;
  }
  // A pass that does not draw alongside within the horizon gets no further in it than following
  // (overtaking_test APassThatDoesNotDrawAlongsideIsCreditedNoFurtherThanFollowing).
  if (!draws_alongside) c.decision.progress = std::min(c.decision.progress, ctx.behind_leader);
  // Begun only on a side whose lane stays open until it is done: until the car is level-distance ahead of
  // the car it passes, gaining on it as this plan does over the horizon
  // (overtaking_test APassIsBegunOnlyWhereItsLaneStaysOpenUntilItIsDone).
  if (c.clear && !ctx.passing_leader) {
    const double rate = (ctx.leader_gap + c.decision.progress - ctx.leader_prediction.at(options_.prediction.horizon)) /
                        std::max(1.0, c.decision.progress);
    const double level_at = std::max(0.0, ctx.leader_gap - ctx.near) / std::max(rate, 1e-3);
    const double alongside_for = std::min(ctx.L, 2.0 * ctx.near / std::max(rate, 1e-3));
    if (laneRun(d.side, ctx.s + level_at, d.side * leader.lateral, alongside_for) < alongside_for) c.clear = false;
  }
  return c;
}

}  // namespace roar::planning
