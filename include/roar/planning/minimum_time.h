#pragma once
// A minimum-time line: starting from a line (the minimum-curvature one), the lateral offsets are moved
// by a pattern search on the lap time of the speed profile itself, inside the same margins.
// Slower than the minimum-curvature QP (seconds, not a fraction of one), so it is the yardstick roar_bench
// measures the planner's line against, and a planner option for who can wait.
#include "roar/planning/racing_line.h"
#include "roar/planning/speed_profile.h"

namespace roar::planning {

struct MinimumTimeOptions {
  int knot_spacing = 4;      // line points between the optimised offsets (linear in between)
  int max_iterations = 200;  // sweeps over every knot
  double first_move = 1.0;   // m: the first push of a bump
  double stop_move = 0.05;   // m: the smallest
};

struct MinimumTimeResult {
  RacingLine line;
  double start_lap_time = 0.0;  // s of the line it started from
  double lap_time = 0.0;        // s of the result
  int iterations = 0;           // sweeps
};

MinimumTimeResult minimumTimeLine(const track::Track& track, const RacingLine& start, const VehicleLimits& limits,
                                  const RacingLineOptions& margins, const MinimumTimeOptions& options = {});

}  // namespace roar::planning
