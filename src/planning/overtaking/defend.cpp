// Candidate: defending. A car on its line at racing speed, with another closing from behind and pulling out
// to pass, makes one move across to cover that side (at most defence.shift, only while the move keeps clear
// of everyone, held at most defence.hold); no second move while that car stays near, and once it is
// alongside the defender holds its place (overtaking_test ADefenceIsOneMoveThenTheDefenderHoldsItsPlace).
#include <algorithm>
#include <cmath>
#include <limits>

#include "plan_context.h"

namespace roar::planning {

using namespace tuning;

std::optional<OvertakePlanner::Candidate> OvertakePlanner::defenceCandidate(PlanContext& ctx) {
  // Not while busy with a car ahead (passing, following it close, holding beside someone).
  CarMemory& m = *ctx.memory;
  const RaceDecision& last = m.decision;
  const bool free_to_defend = last.mode == RaceMode::kRacingLine || last.mode == RaceMode::kDefend ||
                              (last.mode == RaceMode::kFollow && !ctx.can_pass);
  if (!options_.defence.enabled || !free_to_defend || ctx.alongside) return std::nullopt;
  const double reach = options_.car.length + options_.defence.time * std::max(ctx.speed, kMinEngageSpeed);
  const double beside = levelDistance();
  bool against_near = false;
  const TrafficCar* attacker = nullptr;
  double attacker_rel = -std::numeric_limits<double>::infinity();
  for (const auto& o : *ctx.traffic) {
    if (o.name == ctx.car || o.lapping) continue;  // a car a lap up is let by (blue flags), not defended against
    const double rel = aheadOnLap(o.s, ctx.s, ctx.L);
    // The car defended against is near until it has gone by or dropped well back.
    if (o.name == m.defended_against && rel < options_.car.length && rel > -2.0 * reach) against_near = true;
    if (rel >= -beside || rel < -reach || rel <= attacker_rel) continue;
    attacker = &o;
    attacker_rel = rel;
  }
  if (!against_near) {
    m.defended_against.clear();
    m.defence_plans = 0;
  }
  if (!attacker) return std::nullopt;
  // A move is held for defence.hold at most: covering a line, not driving off the racing line for good.
  const bool defending = last.mode == RaceMode::kDefend && last.other == attacker->name &&
                         ++m.defence_plans * options_.prediction.plan_period <= options_.defence.hold;
  const double across = attacker->lateral - ctx.lateral;
  const int side = across > 0 ? +1 : -1;
  // A threat: at racing speed (not the grid), close behind, pulled out off the racing line and to one
  // side of this car by half a car's width each, and not dropping back; this car on its line.
  const double half = 0.5 * options_.car.width;
  const bool threat = ctx.speed >= options_.passing.min_speed && std::abs(across) > half &&
                      std::abs(attacker->lateral) > half && std::abs(ctx.lateral) < half &&
                      attacker->speed > ctx.speed - 0.5;
  if (!defending && (!threat || !m.defended_against.empty())) return std::nullopt;  // one move, no second
  RaceDecision d{RaceMode::kDefend,
                 side,
                 attacker->name,
                 ctx.lateral + side * std::min(std::abs(across), options_.defence.shift),
                 0.0,
                 ctx.s,
                 ctx.lateral};
  if (defending) {  // the move goes on where it began, to where it was going
    d.side = last.side;
    d.offset = last.offset;
    d.ramp_s = last.ramp_s;
    d.ramp_from = last.ramp_from;
  }
  Candidate c{shifted(ctx.base, d), d, true};
  // Never across in front of a car that could not brake for it: the move is begun only while the car
  // behind, closing at the speed it has, stays level-distance behind until the move is made and
  // rejoin_time after. The cars ahead and beside are checked as any plan is.
  const double closing = std::max(0.0, attacker->speed - ctx.speed);
  if (!defending && -attacker_rel - closing * (options_.moves.shift_time + options_.margins.rejoin_time) < beside)
    return std::nullopt;
  std::vector<Prediction> ahead;
  for (const auto& p : ctx.predicted) {
    if (aheadOnLap(p.s, ctx.s, ctx.L) > 0.0) ahead.push_back(p);
  }
  c.clear = clearOf(c.window, ctx.s, ctx.speed, ahead, &c.decision.progress, defending ? 0.5 : 1.0);
  if (!c.clear) return std::nullopt;
  if (!defending) {
    m.defended_against = attacker->name;
    m.defence_plans = 0;
  }
  return c;
}

}  // namespace roar::planning
