#pragma once
// The racing stack in one process, without ROS: the simulator world, the planner's racing trajectory, the
// trajectory tracker and the lap timer, ticking in lockstep. What roar_bench measures and the tests drive.
#include <functional>
#include <string>
#include <vector>

#include "roar/control/trajectory_tracker.h"
#include "roar/planning/trajectory.h"
#include "roar/sim/world.h"
#include "roar/track/track.h"
#include "roar/vehicle/vehicle_params.h"

namespace roar::harness {

struct TimeTrialOptions {
  int laps = 1;  // timed flying laps after an untimed out-lap from the grid (a point-to-point course: its one run)
  double time_limit = 0.0;  // s simulated; 0: three times the promised time plus a minute
  double grip_use = 0.85;   // share of the road's friction the plan uses
  planning::PlannerOptions planner;
  control::TrackerOptions tracker;  // wheelbase and steering angle are taken from the vehicle
  // Called after every tick with the simulated time and the car's state (a trace for a report or a plot).
  std::function<void(double, const vehicle::VehicleState&)> on_tick;
};

struct TimeTrialResult {
  std::vector<double> lap_times;   // s, each flying lap
  double out_lap = 0.0;            // s from the first crossing of the line after the grid (not timed)
  double promised_lap = 0.0;       // s, the planner's profile
  double max_lateral_error = 0.0;  // m from the racing line
  double rms_lateral_error = 0.0;
  int barrier_contacts = 0;     // separate contacts (a scrape over several ticks counts once)
  double worst_offroad = -1e9;  // m of base_link beyond the road edge at its worst (negative: inside)
  double sim_time = 0.0;        // s simulated
  bool finished = false;        // every lap done within the time limit
  double best_lap() const;
};

// Plans with the vehicle's own limits (planning::vehicleLimits) and drives from the grid's pole position.
TimeTrialResult runTimeTrial(const track::Track& track, const vehicle::VehicleParams& vehicle,
                             const TimeTrialOptions& options);

// The same with a trajectory of the caller's (a recorded lap: planning::recordedTrajectory), tracked from the
// grid's pole position; options.planner is not used.
TimeTrialResult driveTrajectory(const track::Track& track, const vehicle::VehicleParams& vehicle,
                                planning::Trajectory trajectory, const TimeTrialOptions& options);

}  // namespace roar::harness
