// Candidate (the fallback): behind the car ahead at its speed; beside a car or with one closing from
// behind holding the lateral place, otherwise on or back to the racing line.
#include <algorithm>
#include <cmath>

#include "plan_context.h"
#include "roar/planning/speed_profile.h"

namespace roar::planning {

using namespace tuning;

OvertakePlanner::Candidate OvertakePlanner::followCandidate(const PlanContext& ctx) const {
  const RaceDecision fallback_path = ctx.keep_place && !ctx.on_line ? move(ctx, RaceMode::kHold, 0, "", ctx.hold_at)
                                     : ctx.on_line ? RaceDecision{RaceMode::kRacingLine, 0, "", 0.0, 0.0, ctx.s, 0.0}
                                                   : move(ctx, RaceMode::kRacingLine, 0, "", 0.0);
  Candidate follow{ctx.on_line                             ? ctx.onLineBase()
                   : fallback_path.mode == RaceMode::kHold ? shifted(ctx.base, fallback_path, ctx.settle_s)
                                                           : shifted(ctx.onLineBase(), fallback_path),
                   fallback_path, true};
  follow.decision.mode = RaceMode::kFollow;
  // Scored on its own path before it is held to the leader's speed now: that speed held over the horizon is
  // no prediction of a leader about to accelerate out of a corner (behind_leader is)
  // (overtaking_test FollowingOutOfASlowCornerIsCreditedWithTheCarAheadSpeedingUp).
  clearOf(follow.window, ctx.s, ctx.speed, {}, &follow.decision.progress);
  if (!ctx.leader) return follow;
  const TrafficCar& leader = *ctx.leader;
  follow.decision.other = leader.name;
  // A leader level beside this car, in a lane of its own, is let by: followed from where it is, at a little
  // less than its speed, not braked for at once to be the follow gap behind it
  // (overtaking_test ACarLevelBesideComingAcrossIsLetByNotBrakedForAtOnce).
  const bool beside = ctx.level_with_leader &&
                      std::abs(leader.lateral - ctx.lateral) >= options_.car.width + 0.5 * options_.margins.lateral;
  const double held = beside ? std::max(0.0, leader.speed - kLetByRate) : leader.speed;
  followBehind(&follow.window, ctx.s, ctx.s + ctx.leader_gap, held,
               beside ? ctx.leader_gap : options_.margins.follow_gap, limits_, ctx.speed);
  // Behind the leader as it is predicted to go, not at the speed it has now.
  follow.decision.progress = std::min(follow.decision.progress, ctx.behind_leader);
  return follow;
}

}  // namespace roar::planning
