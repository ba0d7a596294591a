// The race modes' state machine (as ForzaETH's state_machine/transitions.py): each plan the car's next mode
// is taken by the transition out of its mode now, each a named function:
//   any mode   -> kYield       letByCandidate: a car a lap up closing from behind (blue flags)
//   free modes -> kDefend      defenceCandidate: a faster car pulling out behind (defence.enabled)
//   kRacingLine, no move, nobody near -> kRacingLine (the line's window as it is: raceAlone)
//   kPass      -> kPass | kFollow (given up) | kRacingLine, kHold (done)   continuePass
//   any other  -> the best of kRacingLine, kHold, kPass, else kFollow      chooseFreely
#include "plan_context.h"

namespace roar::planning {

using namespace tuning;

Trajectory OvertakePlanner::decide(PlanContext& ctx) {
  CarMemory& m = *ctx.memory;
  if (auto yield = letByCandidate(ctx)) {
    m.hold.reset();
    return commit(ctx, std::move(yield->window), yield->decision);
  }
  if (auto defence = defenceCandidate(ctx)) {
    m.hold.reset();
    return commit(ctx, std::move(defence->window), defence->decision);
  }
  // Alone on the line (nobody near, no move under way): the racing line's window as it is, so that a car
  // racing alone drives exactly as without this planner (overtaking_test NobodyInTheWayKeepsTheRacingLine).
  if (ctx.others.empty() && m.decision.mode == RaceMode::kRacingLine && m.decision.ramp_from == 0.0) {
    m.decision = {RaceMode::kRacingLine, 0, "", 0.0, 0.0, ctx.s, 0.0};
    m.plan.reset();  // on the racing line: its lateral place now predicts it
    return ctx.onLineBase();
  }
  place(ctx);
  std::vector<Candidate> candidates;
  racingLineCandidate(ctx, &candidates);
  holdCandidate(ctx, &candidates);
  if (ctx.can_pass) passCandidates(ctx, &candidates);
  const Candidate follow = followCandidate(ctx);

  const bool passing = m.decision.mode == RaceMode::kPass;
  if (!passing) {  // a pass begun afresh has all its time
    m.headway_other.clear();
    m.headway_best_gap = 0.0;
    m.headway_stalled = 0.0;
  }
  const Candidate* chosen = passing ? continuePass(ctx, candidates, follow) : nullptr;
  if (!chosen) chosen = chooseFreely(ctx, candidates, follow);
  if (!chosen) chosen = &follow;
  if (passing && chosen->decision.mode == RaceMode::kFollow) {  // given up: not again on that car for a while
    m.abort_other = m.decision.other;
    m.abort_plans_left = options_.passing.retry_plans;
  }
  // The place beside another car is remembered only while the car holds it (place() reads it back).
  const bool holding =
      ctx.keep_place && (chosen->decision.mode == RaceMode::kHold || (chosen == &follow && !ctx.on_line));
  m.hold = holding ? std::optional<double>(ctx.hold_at) : std::nullopt;
  return commit(ctx, chosen->window, chosen->decision, chosen->clear && chosen->decision.mode == RaceMode::kPass);
}

const OvertakePlanner::Candidate* OvertakePlanner::continuePass(PlanContext& ctx,
                                                                const std::vector<Candidate>& candidates,
                                                                const Candidate& follow) const {
  CarMemory& m = *ctx.memory;
  const RaceDecision& last = m.decision;
  const Candidate* chosen = nullptr;
  // A committed pass keeps its side while it stays clear, the car passed is still ahead and it still gains
  // on following; it is never switched to the other side (that is how cars get squeezed)
  // (overtaking_test AClearPassThatNoLongerGainsOnFollowingIsGivenUp).
  for (const auto& c : candidates) {
    if (c.clear && c.decision.mode == RaceMode::kPass && c.decision.side == last.side &&
        c.decision.other == last.other &&
        c.decision.progress > follow.decision.progress + 0.5 * options_.passing.min_gain) {
      chosen = &c;
    }
  }
  const Candidate* gaining = chosen;
  const bool still_ahead = ctx.leader && ctx.leader->name == last.other;
  // A pass that makes no headway on the car from further back than following it (its gap closing by a
  // metre within stall_time) is given up. Close behind, waiting for room beside the car is part of it.
  if (still_ahead) {
    if (m.headway_other != last.other || ctx.leader_gap < m.headway_best_gap - 1.0) {
      m.headway_other = last.other;
      m.headway_best_gap = ctx.leader_gap;
      m.headway_stalled = 0.0;
    }
    if (ctx.leader_gap > options_.margins.follow_gap + options_.car.length)
      m.headway_stalled += options_.prediction.plan_period;
    if (m.headway_stalled > options_.passing.stall_time) chosen = nullptr;
  }
  const bool stalled = still_ahead && m.headway_stalled > options_.passing.stall_time;
  // The car passed moving across towards this one's side while this one is still behind it: the door is
  // closing, and the pass is given up at once (overtaking_test APassIsGivenUpAtOnceWhenTheCarAheadMovesAcrossIntoIt).
  const bool cutting_in =
      still_ahead && ctx.leader_gap > options_.car.length && last.side * sidewaysNow(*ctx.leader) > kClosingDoor;
  if (cutting_in) chosen = nullptr;
  // One plan's doubt is not an abort: predictions jitter with the odometry's timing, and the guard keeps
  // the car off the back of anyone in its path meanwhile.
  if (!chosen && still_ahead && !stalled && !cutting_in && ++m.doubts < options_.passing.abort_plans) {
    for (const auto& c : candidates) {
      if (c.decision.mode == RaceMode::kPass && c.decision.side == last.side && c.decision.other == last.other) {
        chosen = &c;
      }
    }
  }
  if (chosen && chosen == gaining) m.doubts = 0;
  if (!chosen && still_ahead) return &follow;  // given up: fall in behind, holding the place while beside anyone
  if (chosen) return chosen;
  // The passed car is no longer ahead: the pass is complete; hold beside it while it is alongside.
  for (const auto& c : candidates) {
    if (c.clear && (c.decision.mode == RaceMode::kRacingLine || c.decision.mode == RaceMode::kHold) &&
        (!chosen || c.decision.mode == RaceMode::kRacingLine)) {
      chosen = &c;
    }
  }
  return chosen;
}

const OvertakePlanner::Candidate* OvertakePlanner::chooseFreely(const PlanContext& ctx,
                                                                const std::vector<Candidate>& candidates,
                                                                const Candidate& follow) const {
  // The clear candidate that gets furthest in the horizon (the racing line on a tie within kBetterBy); a
  // pass only if it gets min_gain further than following.
  const Candidate* chosen = nullptr;
  for (const auto& c : candidates) {
    if (!c.clear) continue;
    if (c.decision.mode == RaceMode::kPass &&
        c.decision.progress < follow.decision.progress + options_.passing.min_gain)
      continue;
    if (!chosen || c.decision.progress > chosen->decision.progress + kBetterBy ||
        (c.decision.mode == RaceMode::kRacingLine && c.decision.progress >= chosen->decision.progress - kBetterBy)) {
      chosen = &c;
    }
  }
  return chosen;
}

}  // namespace roar::planning
