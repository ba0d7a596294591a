#pragma once
// What the overtaking planner sees of other cars, and what it decides: the race mode, its side and car,
// and the lateral move under way.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

namespace roar::planning {

// Another car as the planner sees it, in the racing line's terms.
struct TrafficCar {
  std::string name;
  double s = 0.0;        // m along the racing line
  double lateral = 0.0;  // m left of the racing line
  double speed = 0.0;    // m/s
  // Its recent speed as a share of the racing line's where it was (smoothed over a second or so); 0:
  // unknown, the share of this moment is taken. How fast it is predicted to go on.
  double line_share = 0.0;
  double lateral_speed = 0.0;  // m/s leftwards across the racing line (smoothed); 0: unknown or none
  bool lapping = false;        // a lap or more ahead of the car planned for in the race (a blue flag for it)
  // m/s the car has been seen held to whatever the line's speed (a pace car, a scripted car): it is
  // predicted no faster. 0: none seen.
  double held_speed = 0.0;
  // m/s leftwards across the racing line this moment (its velocity's, not smoothed): a car turning across
  // is seen moving before its place has. NaN: unknown, lateral_speed is taken.
  double lateral_velocity = std::numeric_limits<double>::quiet_NaN();
};

// Another car as a car's plan predicted it: where it would be, from the moment of the plan on, every
// `step` seconds over the horizon (map frame). What rviz shows of a car's view of the cars around it.
struct PredictedPath {
  std::string name;
  double step = 0.5;  // s
  std::vector<Eigen::Vector2d> positions;
};

// The race modes, as ForzaETH's race stack names its states: on the racing line, following (trailing) a
// car, passing one, holding a lateral place beside one, letting one by (blue flags), defending against one.
enum class RaceMode { kRacingLine, kFollow, kPass, kHold, kYield, kDefend };
const char* raceModeName(RaceMode mode);

struct RaceDecision {
  RaceMode mode = RaceMode::kRacingLine;
  int side = 0;           // kPass: +1 left of the car passed, -1 right; kYield, kDefend: the side moved to
  std::string other;      // the car followed, passed, let by or defended against
  double offset = 0.0;    // m left of the racing line the plan goes to
  double progress = 0.0;  // m the plan gets in the horizon
  // The lateral move under way: from `ramp_from` metres at line s `ramp_s`, reaching `offset` a
  // shift_length later. Kept from tick to tick, so that the move is made rather than restarted.
  double ramp_s = 0.0;
  double ramp_from = 0.0;
  // m/s the car had where the move began: the move takes shift_time at that speed (0: the racing line's).
  double ramp_speed = 0.0;
};

// The decision in words, for logs and rviz: "pass pace on the left", "follow rival", "racing line", ...
std::string describe(const RaceDecision& decision);

}  // namespace roar::planning
