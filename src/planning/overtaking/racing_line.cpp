// Candidate: the racing line, or back onto it. Also the planning of any move but a pass.
#include "plan_context.h"

namespace roar::planning {

using namespace tuning;

OvertakePlanner::Candidate OvertakePlanner::considerMove(const PlanContext& ctx, const RaceDecision& d) const {
  const Trajectory& from = d.mode == RaceMode::kRacingLine ? ctx.onLineBase() : ctx.base;
  // Holding a lane while still drifting from the move before: settling there as on the line
  // (overtaking_test ACarHoldingItsLaneWhileStillMovingSidewaysIsPlannedOnLessGrip).
  const double settle = d.mode == RaceMode::kHold ? ctx.settle_s : -kInf;
  Candidate c{shifted(from, d, settle), d, true};
  // A move under way goes on with half the margin it needed to start: hysteresis, not dithering.
  const RaceDecision& last = ctx.last();
  const bool under_way = last.mode == d.mode && last.side == d.side && last.other == d.other;
  c.clear = clearOf(c.window, ctx.s, ctx.speed, ctx.predicted, &c.decision.progress, under_way ? 0.5 : 1.0, kInf);
  return c;
}

void OvertakePlanner::racingLineCandidate(const PlanContext& ctx, std::vector<Candidate>* out) const {
  if (ctx.on_line) {
    Candidate c{ctx.onLineBase(), {RaceMode::kRacingLine, 0, "", 0.0, 0.0, ctx.s, 0.0}, true};
    c.clear = clearOf(c.window, ctx.s, ctx.speed, ctx.predicted, &c.decision.progress);
    out->push_back(std::move(c));
  } else if (!ctx.way_back_brakes) {
    out->push_back(considerMove(ctx, move(ctx, RaceMode::kRacingLine, 0, "", 0.0)));
  }
}

}  // namespace roar::planning
