// A plan's stages: gather the car's surroundings (the line's window, a settling car's grip, the cars that
// matter and the car ahead), predict them, engage with the car ahead; the decision (transitions.cpp)
// then guards and commits the window chosen.
#include "roar/planning/overtaking/planner.h"

#include <algorithm>
#include <cmath>

#include "plan_context.h"
#include "roar/track/heading.h"
#include "roar/vehicle/slipstream.h"

namespace roar::planning {

using namespace tuning;

Trajectory OvertakePlanner::plan(const std::string& car, double s, double lateral, double speed,
                                 const std::vector<TrafficCar>& traffic, double behind, double ahead_m, double pace) {
  PlanContext ctx = gather(car, s, lateral, speed, traffic, behind, ahead_m, pace);
  return decide(ctx);
}

OvertakePlanner::PlanContext OvertakePlanner::gather(const std::string& car, double s, double lateral, double speed,
                                                     const std::vector<TrafficCar>& traffic, double behind,
                                                     double ahead_m, double pace) {
  PlanContext ctx;
  ctx.car = car;
  ctx.s = s;
  ctx.lateral = lateral;
  ctx.speed = speed;
  ctx.traffic = &traffic;
  ctx.ahead_m = ahead_m;
  ctx.L = lapLength(line_);
  ctx.memory = &memory_[car];
  ctx.near = levelDistance();
  ctx.base = windowAround(line_, s, behind, ahead_m);
  scaleSpeeds(&ctx.base, pace);
  settle(ctx);
  surroundings(ctx);
  predictAll(ctx);
  engagement(ctx);
  return ctx;
}

void OvertakePlanner::settle(PlanContext& ctx) const {
  // A car still moving sideways after a move (back from a pass, say) is planned on settle_grip for the next
  // kSettleTime at its speed on the line, on its way back to it and in a lane it holds: it has less grip to
  // brake and turn with. Only after a move (a car alone on the line never settles: its own tracking is the
  // line's business), and not a pass or any other move across the road (they plan their own moving across).
  CarMemory& m = *ctx.memory;
  const bool after_move =
      m.settle_until.has_value() || m.decision.mode != RaceMode::kRacingLine || m.decision.ramp_from != 0.0;
  for (const auto& o : *ctx.traffic) {
    if (o.name == ctx.car && after_move && std::abs(o.lateral_speed) > kSettledLateralSpeed)
      m.settle_until = ctx.s + kSettleTime * ctx.speed;
  }
  if (!m.settle_until) return;
  if (aheadOnLap(ctx.s, *m.settle_until, ctx.L) >= 0.0) {
    m.settle_until.reset();
  } else {
    ctx.settle_s = *m.settle_until;
    Move on_line;
    on_line.ramp_s = ctx.s;
    MoveGrip grip;
    grip.settle_s = ctx.settle_s;
    ctx.line_base = shifted(ctx.base, on_line, grip);
  }
}

void OvertakePlanner::surroundings(PlanContext& ctx) const {
  // Cars that matter: alongside or ahead, within the window; behind, those near enough to need room, and
  // those closing fast enough to be level within a move's time (a car slow off the line must not move back
  // onto it in front of them: at its own low speed, "near" is a few metres).
  const RaceDecision& last = ctx.last();
  ctx.leader_gap = ctx.ahead_m;
  for (const auto& o : *ctx.traffic) {
    if (o.name == ctx.car) continue;
    const double rel = aheadOnLap(o.s, ctx.s, ctx.L);
    const double closing_in = std::max(0.0, o.speed - ctx.speed) * options_.moves.shift_time;
    if (rel < -(ctx.near + std::max(options_.margins.rejoin_time * ctx.speed, closing_in)) || rel > ctx.ahead_m)
      continue;
    ctx.others.push_back(o);
    if (std::abs(rel) < ctx.near) ctx.alongside = true;
    if (rel <= -ctx.near && -rel < ctx.near + closing_in) ctx.closing_behind = true;
    // The car a pass is on stays the car ahead while level with it, wherever it is across the road: the
    // pass is done only once clear ahead of it (overtaking_test APassLevelWithTheCarItPassesIsNotTurnedToTheCarBeyond).
    // Not once it turns across towards this car: the pass is given up and the car holds its place beside it.
    const bool passing_it = last.mode == RaceMode::kPass && o.name == last.other && std::abs(rel) < ctx.near &&
                            last.side * sidewaysNow(o) <= kClosingDoor;
    const double lane = options_.car.width + options_.margins.lateral + kLeaderLane;
    if (passing_it || (rel > 0 && rel < ctx.leader_gap && std::abs(o.lateral - ctx.lateral) < lane)) {
      ctx.leader_gap = passing_it ? std::max(rel, kPassedLevelGap) : rel;
      ctx.leader = &o;
      ctx.leader_index = ctx.others.size() - 1;
    }
  }
}

void OvertakePlanner::predictAll(PlanContext& ctx) {
  for (const auto& o : ctx.others) ctx.predicted.push_back(predict(o, ctx.s));
  if (options_.prediction.keep) {
    auto& shown = ctx.memory->predictions;
    shown.clear();
    for (std::size_t i = 0; i < ctx.others.size(); ++i) {
      PredictedPath path{ctx.others[i].name, kShownPredictionStep, {}};
      const Prediction& p = ctx.predicted[i];
      for (double t = 0.0; t <= options_.prediction.horizon + 1e-9; t += kShownPredictionStep) {
        const TrajectoryPoint on_line = sampleAt(line_, p.s + (p.at(t) - p.ahead.front()));
        path.positions.push_back(on_line.position + lateralAt(p, t) * track::leftOf(on_line.yaw));
      }
      shown.push_back(std::move(path));
    }
  }
  if (!ctx.leader) return;
  ctx.leader_prediction = ctx.predicted[ctx.leader_index];
  // How far in the horizon a car gets behind the leader as the leader is predicted to go: what following
  // gets at most, and a pass still behind it at the end no more.
  ctx.behind_leader = ctx.leader_prediction.at(options_.prediction.horizon) - options_.margins.follow_gap;
  // In the leader's slipstream a pass is planned with the speed the tow gives (and carries out of it).
  ctx.tow = vehicle::slipstreamReduction(ctx.leader_gap - options_.car.length, ctx.lateral - ctx.leader->lateral,
                                         ctx.leader->speed, options_.car.width, options_.slipstream);
  if (ctx.tow > kMinTow) ctx.towed_base = towed(ctx.base, 1.0 - ctx.tow);
}

void OvertakePlanner::engagement(PlanContext& ctx) const {
  CarMemory& m = *ctx.memory;
  if (m.abort_plans_left > 0) --m.abort_plans_left;
  if (!ctx.leader) return;
  // Whether the leader is near enough to pass, and not one a pass on was given up just now.
  const double engage = options_.car.length + options_.passing.engage_time * std::max(ctx.speed, kMinEngageSpeed);
  ctx.passing_leader = m.decision.mode == RaceMode::kPass && m.decision.other == ctx.leader->name;
  // A pass begins from behind the car (its tail ahead of this one's nose): beside a car that is going by,
  // staying there is holding a place, not passing it.
  ctx.can_pass =
      ctx.leader_gap < (ctx.passing_leader ? kPassStayFactor * engage : engage) &&
      (ctx.passing_leader || (ctx.speed >= options_.passing.min_speed && ctx.leader_gap >= options_.car.length)) &&
      !(m.abort_plans_left > 0 && m.abort_other == ctx.leader->name);
  ctx.level_with_leader = ctx.leader_gap < ctx.near;
}

void OvertakePlanner::place(PlanContext& ctx) const {
  const CarMemory& m = *ctx.memory;
  const RaceDecision& last = m.decision;
  ctx.on_line = std::abs(ctx.lateral) < kOnLine && last.mode != RaceMode::kPass;
  // Holding a place beside another car means the place planned, not wherever the car has drifted to; a
  // place taken afresh is the car's own, but no further out than the lane it was planned in
  // (overtaking_test ACarWideOfItsPassLaneHoldsItsPlaceInTheLane).
  const bool in_a_lane = last.mode == RaceMode::kPass || last.mode == RaceMode::kHold;
  const bool wide_of_it = in_a_lane && last.offset * ctx.lateral > 0.0 && std::abs(ctx.lateral) > std::abs(last.offset);
  ctx.hold_at = m.hold ? *m.hold : wide_of_it ? last.offset : ctx.lateral;
  // Off the line in a fast curve, the way back onto it turns harder than the curve does: the car keeps its
  // lane until the way back is drivable at the speed it has
  // (overtaking_test ACarOutsideTheLineInAFastCurveKeepsItsLaneUntilItCanTurnBackAtItsSpeed).
  if (!ctx.on_line) {
    auto brakesAtOnce = [&](const RaceDecision& d, const Trajectory& from) {
      return sampleAt(shifted(from, d), ctx.s).speed < ctx.speed - kMoveBrakeSlack;
    };
    ctx.way_back_brakes = brakesAtOnce(move(ctx, RaceMode::kRacingLine, 0, "", 0.0), ctx.onLineBase()) &&
                          !brakesAtOnce(move(ctx, RaceMode::kHold, 0, "", ctx.hold_at), ctx.base);
  }
  // Off the line and closing on the car ahead within a move's time, the way back onto the line runs into
  // its back: the car keeps its lane until it has the other's speed
  // (overtaking_test ACarClosingFastOnOneAheadKeepsItsLaneUntilItHasItsSpeed).
  ctx.closing_ahead =
      ctx.leader && std::abs(ctx.lateral) >= kOnLine &&
      std::abs(ctx.lateral - ctx.leader->lateral) >= options_.car.width + options_.guard.lateral &&
      ctx.leader_gap < ctx.near + std::max(0.0, ctx.speed - ctx.leader->speed) * options_.moves.shift_time;
  ctx.beside_or_closing_behind = ctx.alongside || ctx.closing_behind;
  ctx.keep_place = ctx.beside_or_closing_behind || ctx.closing_ahead || ctx.way_back_brakes;
}

RaceDecision OvertakePlanner::move(const PlanContext& ctx, RaceMode mode, int side, const std::string& other,
                                   double to) const {
  // A move the car is already making goes on from where it began; a new one starts here.
  const RaceDecision& last = ctx.last();
  RaceDecision d{mode, side, other, to, 0.0, ctx.s, ctx.lateral, ctx.speed};
  const bool same_move = mode == RaceMode::kPass || mode == RaceMode::kYield
                             ? last.mode == mode && last.side == side && last.other == other
                             : (last.mode == mode || last.mode == RaceMode::kFollow) && last.side == 0;
  // A pass goes out to wherever the car passed now is, but never back towards it (the ramp is never
  // restarted: a ramp begun afresh each tick never moves the car); any other move keeps its target unless
  // that changed (overtaking_test APassUnderWayKeepsItsLaneWhenTheCarItPassesMovesAway).
  if (same_move && (mode == RaceMode::kPass || std::abs(last.offset - to) < kSameTarget)) {
    d.ramp_s = last.ramp_s;
    d.ramp_from = last.ramp_from;
    d.ramp_speed = last.ramp_speed;
    if (mode != RaceMode::kPass || side * (last.offset - to) > 0.0) d.offset = last.offset;
  }
  return d;
}

Trajectory OvertakePlanner::commit(PlanContext& ctx, Trajectory window, const RaceDecision& decision, bool clear_pass) {
  // What is chosen goes under the guard and is remembered: the decision, and the window others predict it by.
  guard(&window, ctx.s, ctx.speed, ctx.others, ctx.predicted, clear_pass);
  ctx.memory->decision = decision;
  ctx.memory->plan = window;
  return window;
}

std::vector<PredictedPath> OvertakePlanner::predictions(const std::string& car) const {
  auto it = memory_.find(car);
  return it == memory_.end() ? std::vector<PredictedPath>{} : it->second.predictions;
}

RaceDecision OvertakePlanner::decision(const std::string& car) const {
  auto it = memory_.find(car);
  return it == memory_.end() ? RaceDecision{} : it->second.decision;
}

}  // namespace roar::planning
