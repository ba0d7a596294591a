#pragma once
// A race of the stack's cars in one process, without ROS: the simulator world, one planner for the field
// (planning::FieldPlanner: following or overtaking), a trajectory tracker per car and race control, ticking
// in lockstep; deterministic. What the traffic benchmark (roar_bench --traffic) runs and gtest drives.
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "roar/control/trajectory_tracker.h"
#include "roar/planning/field_planner.h"
#include "roar/planning/trajectory.h"
#include "roar/race/race_control.h"
#include "roar/track/track.h"
#include "roar/vehicle/vehicle_params.h"

namespace roar::harness {

struct RaceCar {
  std::string name;
  int grid_slot = 0;       // 0 = pole (track::Track::gridSpawnPoints)
  double pace = 1.0;       // share of the planned speeds it is driven at
  double max_speed = 0.0;  // m/s cap; 0: none
};

// One car at one tick, as the race saw it (RaceOptions::on_tick).
struct RaceTick {
  double time = 0.0;  // s
  const std::string* car = nullptr;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double speed = 0.0;  // m/s forward
  planning::TrajectoryProjection on_line;
  planning::RaceDecision decision;
};

struct RaceOptions {
  int laps = 2;
  double time_limit = 0.0;  // s simulated; 0: three times the slowest car's promised race plus a minute
  double grip_use = 0.85;   // share of the road's friction the plan uses
  planning::PlannerOptions planner;
  control::TrackerOptions tracker;  // wheelbase and steering angle are taken from the vehicle
  planning::FieldOptions field;     // car length and width are taken from the vehicle
  race::RaceRules rules;            // laps are taken from `laps`
  double speed_bin = 2.0;           // m of racing line per bin of RaceCarResult::round_speeds
  // Called for every car each tick, before it is stepped: for traces and plots.
  std::function<void(const RaceTick&)> on_tick;
};

// A car's speed at one tick, where it was: the round of the racing line (0 from the grid to the line's
// s = 0, then one more at each crossing of it), line s (m, wrapped) and speed (m/s).
struct SpeedSample {
  int round = 0;
  double s = 0.0;
  double speed = 0.0;
};

// A pass attempt: the passer drew alongside (its nose past the other's tail) in a pass; completed when
// it was clear ahead, aborted when it dropped back behind. Its times and speeds run from the moment the
// planner chose the pass (pulling out) to the end.
struct PassAttempt {
  std::string passer, passed;
  int side = 0;              // +1 on the left of the car passed, -1 on the right
  double caught_time = 0.0;  // s when the passer first followed or went for the car passed (this time round)
  double start_time = 0.0;   // s the planner chose the pass
  double end_time = 0.0;     // s it was complete or aborted
  bool completed = false;
  // Line s (m) where the passer first drew level with the car it passes (its place on the line at or past
  // the other's); NaN if it never did. harness::passPlace tells what kind of place that is.
  double level_s = std::numeric_limits<double>::quiet_NaN();
  // The passer's speed during the pass, sampled each tick.
  std::vector<SpeedSample> samples;
};

struct CarContactRecord {
  double time = 0.0;
  std::string a, b;
  std::string at_fault;  // empty: a racing incident
  std::string kind;      // race::ContactFault::kind
};

struct RaceCarResult {
  std::string name;
  double pace = 1.0;
  int position = 0;  // finishing order (1 = winner)
  bool finished = false;
  double race_time = 0.0;         // s from the start signal, penalties included
  std::vector<double> lap_times;  // s
  int car_contacts = 0, barrier_contacts = 0, track_limit_violations = 0;
  double time_in_traffic = 0.0;  // s spent following a car or passing one
  // The car's speed (m/s) in each speed_bin of the racing line, round by round (SpeedSample::round), as it
  // last went through the bin in that round (NaN: not in it).
  std::vector<std::vector<double>> round_speeds;
};

struct RaceResult {
  std::vector<RaceCarResult> cars;  // in finishing order
  std::vector<PassAttempt> passes;
  // Passes the planner began and gave up before the passer drew alongside (or turned to another car):
  // pulled out and back in, not attempts. Without samples.
  std::vector<PassAttempt> given_up_before_alongside;
  std::vector<race::Overtake> overtakes;
  std::vector<CarContactRecord> contacts;
  double sim_time = 0.0;
  double line_length = 0.0;  // m, the racing line's
  double speed_bin = 2.0;
  bool finished = false;  // every car finished within the time limit
  const RaceCarResult& car(const std::string& name) const;
};

// Throws std::invalid_argument for no cars, repeated names or grid slots, or a pace outside (0, 1].
RaceResult runRace(const track::Track& track, const vehicle::VehicleParams& vehicle, const std::vector<RaceCar>& cars,
                   const RaceOptions& options);

// The mean over a pass's samples of the passer's speed as a share of its free-air speed at the same place
// in the same round: `free_air`, the round_speeds of the same car alone (the same grid slot and pace: on
// the opening lap it too is still gaining speed from the grid; past its last round, its last). NaN when no
// sample has a free-air speed.
double passingSpeedShare(const PassAttempt& pass, const std::vector<std::vector<double>>& free_air, double speed_bin);

// The seconds a lap a car lost in traffic: the mean of its lap times less those of the same car alone (the
// same grid slot, pace and options: `alone`), lap by lap; NaN when either did not finish every lap.
double lapTimeLoss(const RaceCarResult& in_traffic, const RaceCarResult& alone);

// How far a race finished from an order (names, first first): the pairs of its cars that finished the other
// way round. A car of the order not in the race is refused (RaceResult::car's std::out_of_range naming it).
int pairsOutOfOrder(const RaceResult& race, const std::vector<std::string>& order);

}  // namespace roar::harness
