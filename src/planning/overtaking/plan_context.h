#pragma once
// What one plan knows, gathered once and read by every stage and candidate of it.
#include <cmath>
#include <string>
#include <vector>

#include "roar/planning/overtaking/planner.h"
#include "tuning.h"

namespace roar::planning {

struct OvertakePlanner::PlanContext {
  // The car planned for.
  std::string car;
  double s = 0.0, lateral = 0.0, speed = 0.0;
  const std::vector<TrafficCar>* traffic = nullptr;
  double ahead_m = 0.0;
  CarMemory* memory = nullptr;  // its memory; memory->decision is the last plan's until commit
  double L = 0.0;               // the line's lap length

  // The racing line's window, and as a car still settling from a move drives it (empty: base).
  Trajectory base, line_base;
  double settle_s = -tuning::kInf;  // line s up to which the car is settling
  const Trajectory& onLineBase() const { return line_base.points.empty() ? base : line_base; }

  // The cars that matter (alongside or ahead in the window, behind near enough to need room), their
  // predictions in the same order, and the car ahead in the car's lane.
  std::vector<TrafficCar> others;
  std::vector<Prediction> predicted;
  const TrafficCar* leader = nullptr;
  std::size_t leader_index = 0;
  double leader_gap = 0.0;
  Prediction leader_prediction;
  bool alongside = false;       // a car level beside
  bool closing_behind = false;  // a car closing from behind within a move's time
  double near = 0.0;            // levelDistance()
  // How far in the horizon the car gets behind the leader as it is predicted to go (following's most).
  double behind_leader = tuning::kInf;
  double tow = 0.0;  // share of the drag the leader's wake takes away, and the window planned with it
  Trajectory towed_base;

  // Engagement with the leader.
  bool passing_leader = false;     // a pass on it is under way
  bool can_pass = false;           // near enough to pass, and not one a pass on was given up just now
  bool level_with_leader = false;  // level with it

  // The car's lateral place.
  bool on_line = false;
  double hold_at = 0.0;          // the lateral place it holds if it holds one
  bool way_back_brakes = false;  // the way back onto the line asks it to brake at once
  bool closing_ahead = false;    // off the line, closing on the leader within a move's time
  bool beside_or_closing_behind = false;
  bool keep_place = false;

  const RaceDecision& last() const { return memory->decision; }
};

// How fast a car is moving across the line this moment: its velocity's where known, so that a door
// closing is seen from the first message of the turn (overtaking_test
// ACarTurningAcrossIntoAPassIsSeenFromItsVelocityAtOnce).
inline double sidewaysNow(const TrafficCar& o) {
  return std::isfinite(o.lateral_velocity) ? o.lateral_velocity : o.lateral_speed;
}

}  // namespace roar::planning
