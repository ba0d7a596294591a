// Candidate: holding the lateral place, while a car is beside or closing from behind (never squeezing it
// nor crossing its way: overtaking_test ACarAlongsideIsNotSqueezed), or while the way back onto the line
// would brake the car at once.
#include "plan_context.h"

namespace roar::planning {

void OvertakePlanner::holdCandidate(const PlanContext& ctx, std::vector<Candidate>* out) const {
  if ((ctx.beside_or_closing_behind || ctx.way_back_brakes) && !ctx.on_line)
    out->push_back(considerMove(ctx, move(ctx, RaceMode::kHold, 0, "", ctx.hold_at)));
}

}  // namespace roar::planning
