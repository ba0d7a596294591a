#include "roar/harness/time_trial.h"

#include <algorithm>
#include <cmath>

#include "roar/control/tracker_sizing.h"
#include "roar/race/lap_timer.h"
#include "roar/sim/world.h"

namespace roar::harness {

double TimeTrialResult::best_lap() const {
  return lap_times.empty() ? 0.0 : *std::min_element(lap_times.begin(), lap_times.end());
}

TimeTrialResult runTimeTrial(const track::Track& track, const vehicle::VehicleParams& vehicle,
                             const TimeTrialOptions& options) {
  const planning::VehicleLimits limits = planning::vehicleLimits(vehicle, track.info().friction, options.grip_use);
  return driveTrajectory(track, vehicle, planning::planRacingTrajectory(track, limits, options.planner), options);
}

TimeTrialResult driveTrajectory(const track::Track& track, const vehicle::VehicleParams& vehicle,
                                planning::Trajectory trajectory, const TimeTrialOptions& options) {
  const planning::VehicleLimits limits = planning::vehicleLimits(vehicle, track.info().friction, options.grip_use);
  control::TrajectoryTracker tracker(control::trackerFor(vehicle, options.tracker), limits);
  tracker.setTrajectory(std::move(trajectory));

  TimeTrialResult result;
  result.promised_lap = tracker.trajectory().lap_time;
  const double time_limit =
      options.time_limit > 0 ? options.time_limit : 3.0 * result.promised_lap * (options.laps + 1) + 60.0;

  sim::World world(track, {});
  world.spawnVehicle("ego", vehicle, track::poseOnTrack(track.gridSpawnPoints(1)[0]));
  race::LapTimer timer(track);
  double squared_error = 0.0;
  long samples = 0;
  bool touching = false;
  // One untimed out-lap from the grid, then the timed flying laps. A point-to-point course: its one timed
  // run from the start line, then the stop in the run-off past the finish.
  const int runs = track.closed() ? options.laps + 1 : 1;
  auto done = [&] {
    return timer.lapsCompleted() >= runs && (track.closed() || world.vehicleState("ego").speed < 0.1);
  };
  while (world.time() < time_limit && !done()) {
    world.setControl("ego", tracker.update(control::trackerInputOf(world.vehicleState("ego"))));
    world.step();
    if (options.on_tick) options.on_tick(world.time(), world.vehicleState("ego"));
    const bool timed = track.closed() ? timer.lapsCompleted() >= 1 : timer.started() && timer.lapsCompleted() < 1;
    if (timed) {  // tracking error over the flying laps (a course: over its run)
      result.max_lateral_error = std::max(result.max_lateral_error, std::abs(tracker.lateralError()));
      squared_error += tracker.lateralError() * tracker.lateralError();
      ++samples;
    }
    const Eigen::Vector3d position = world.vehicleState("ego").pose.position;
    timer.update(world.time(), position);
    const auto pr = track.projectNear(position.head<2>(), timer.progress() + track.info().start_finish_s, 80.0);
    result.worst_offroad =
        std::max(result.worst_offroad, pr.lateral > 0 ? pr.lateral - pr.width_left : -pr.lateral - pr.width_right);
    const auto& contacts = world.contacts("ego");
    const bool barrier =
        std::any_of(contacts.begin(), contacts.end(), [](const sim::Contact& c) { return c.other == "barrier"; });
    if (barrier && !touching) ++result.barrier_contacts;
    touching = barrier;
  }
  for (const auto& lap : timer.laps()) {
    if (lap.lap == 1 && track.closed()) {
      result.out_lap = lap.lap_time;
    } else {
      result.lap_times.push_back(lap.lap_time);
    }
  }
  result.rms_lateral_error = samples ? std::sqrt(squared_error / samples) : 0.0;
  result.sim_time = world.time();
  result.finished = timer.lapsCompleted() >= runs;
  return result;
}

}  // namespace roar::harness
