#pragma once
// The overtaking planner's options, grouped by what they tune. Every one is settable by name through the
// one table of option_table.h (roar_bench --overtake=<group>.<name>=<value>, the planner node's
// ~<group>/<name>); the defaults are what roar_bench --traffic measures.
#include "roar/vehicle/car_size.h"
#include "roar/vehicle/slipstream.h"

namespace roar::planning {

struct OvertakeOptions {
  // Every car's size: a race sets it from the vehicle's body.
  struct Car {
    double length = vehicle::kDefaultCarLength;  // m, bumper to bumper
    double width = vehicle::kDefaultCarWidth;    // m
  } car;

  // The room kept around other cars and the road's edge.
  struct Margins {
    double lateral = 0.9;       // m of air beside another car (to start a move; half of it to go on with one)
    double longitudinal = 1.5;  // m to the car ahead or behind when beside it in the plan
    double edge = 1.0;          // m inside the road edge beyond half the car's width (the tracking error)
    double rejoin_time = 0.5;   // s at speed kept ahead of a car when moving across in front of it
    double follow_gap = 12.0;   // m, centre to centre, kept behind a car followed
  } margins;

  // How far ahead, how finely and how much other cars' plans are trusted.
  struct Prediction {
    double horizon = 6.0;            // s over which cars are predicted and candidates compared
    double sample_step = 2.0;        // m between the points checked against other cars
    double lateral_lookahead = 1.0;  // s a car without a plan to go by goes on moving sideways as it is
    double plan_trust = 0.75;        // m a car may be off its last plan for that plan to predict it
    double plan_period = 0.05;       // s between plans (the odometry's period)
    bool keep = false;               // keep each plan's predictions for predictions() (rviz)
  } prediction;

  // How a lateral move (a pass, a hold, a defence, back onto the line) is shaped and planned.
  struct Moves {
    // s over which a move of a car's width and air is made at the car's speed: 2.5 s asks about 2.8 m/s^2
    // of sideways acceleration for 3 m (overtaking_test
    // APassPullingOutFromBehindASlowCarMovesAcrossInShiftTimeAtItsOwnSpeed).
    double shift_time = 2.5;
    double min_shift_length = 20.0;  // m a move takes at least
    double offline_grip = 0.92;      // share of the grip a path moving across the line is planned with
    double settle_grip = 0.85;       // share a car still moving sideways after a move has for 2 s at speed
  } moves;

  // When a pass is begun, kept and given up.
  struct Passing {
    double min_gain = 4.0;     // m further in the horizon a pass must get than following
    double engage_time = 2.0;  // s at speed (plus a car's length) within which a car ahead is passed
    double min_speed = 8.0;    // m/s the car must be doing to start a pass (not from the grid)
    int abort_plans = 3;       // plans in a row a committed pass must look blocked to be given up
    double stall_time = 3.0;   // s a committed pass may go without gaining a metre on the car
    int retry_plans = 60;      // plans after an aborted pass before another on the same car
    double abort_time = 3.0;   // s within which a conflict gives up a pass drawn level with its car
    double max_offset = 5.0;   // m from the racing line a pass may go
  } passing;

  // The guard under every plan: a car ahead in the plan's path is followed at a car's length plus the
  // longitudinal margin plus `time` at speed.
  struct Guard {
    double lateral = 0.4;    // m beyond the cars' width within which a car ahead is in the path
    double time = 0.15;      // s at speed
    bool predicted = false;  // held from where the car would meet the car ahead as it is predicted to go
  } guard;

  // A car about to be lapped moves aside, to the side with more room, until it has been lapped.
  struct BlueFlags {
    bool enabled = false;
    double time = 3.0;  // s at speed behind within which a car a lap up is let by
  } blue_flags;

  // A car on its line with a faster one pulling out behind makes one move across to cover that side.
  struct Defence {
    bool enabled = false;
    double time = 1.0;                         // s at speed behind within which a car is defended against
    double shift = vehicle::kDefaultCarWidth;  // m at most the move goes across
    double hold = 4.0;                         // s at most a move is held before the car goes back to its line
  } defence;

  // The wake the simulator applies: close behind the car it would pass, a pass is planned with the tow.
  vehicle::SlipstreamOptions slipstream;
};

}  // namespace roar::planning
