// Candidate: letting a car a lap up by (blue flags). The car moves aside, to the side with more room kept
// until it has been lapped, at its own pace, where that is clear of everyone
// (overtaking_test ACarAboutToBeLappedMovesAsideAndOnlyThen).
#include <limits>

#include "plan_context.h"

namespace roar::planning {

using namespace tuning;

std::optional<OvertakePlanner::Candidate> OvertakePlanner::letByCandidate(PlanContext& ctx) {
  if (!options_.blue_flags.enabled) return std::nullopt;
  CarMemory& m = *ctx.memory;
  const TrafficCar* blue = nullptr;
  double blue_rel = -std::numeric_limits<double>::infinity();
  for (const auto& o : *ctx.traffic) {
    if (o.name == ctx.car || !o.lapping) continue;
    const double rel = aheadOnLap(o.s, ctx.s, ctx.L);
    const bool closing = rel < 0 && -rel < options_.car.length + options_.blue_flags.time * std::max(o.speed, 1.0);
    // Let by means clear ahead: aside until the car is as far ahead as a pass leaves the car passed.
    const bool going_by =
        m.yield && m.yield->first == o.name && rel >= 0 &&
        rel < ctx.near + kPassClearAhead + options_.margins.rejoin_time * std::max(ctx.speed, o.speed);
    if ((closing || going_by) && rel > blue_rel) {
      blue = &o;
      blue_rel = rel;
    }
  }
  if (!blue) {
    m.yield.reset();
    return std::nullopt;
  }
  // One side for the whole of being lapped: never across the lapping car's way.
  if (!m.yield || m.yield->first != blue->name)
    m.yield = std::make_pair(blue->name, roomLeft(ctx.s) >= roomRight(ctx.s) ? +1 : -1);
  const int side = m.yield->second;
  const RaceDecision& last = m.decision;
  const bool yielding = last.mode == RaceMode::kYield && last.other == blue->name && last.side == side;
  const RaceDecision d =
      move(ctx, RaceMode::kYield, side, blue->name, side * (options_.car.width + options_.margins.lateral + kMoveAir));
  Candidate c{shifted(ctx.base, d), d, true};
  // Clear of everyone but the car it makes room for: that one goes by wherever it is.
  std::vector<Prediction> but_blue;
  for (std::size_t i = 0; i < ctx.others.size(); ++i)
    if (ctx.others[i].name != blue->name) but_blue.push_back(ctx.predicted[i]);
  if (!clearOf(c.window, ctx.s, ctx.speed, but_blue, &c.decision.progress, yielding ? 0.5 : 1.0)) return std::nullopt;
  return c;
}

}  // namespace roar::planning
