#include "roar/ros/race_msg_conversion.h"

#include <algorithm>
#include <cmath>

#include "roar/ros/msg_conversion.h"

namespace roar::ros_bridge {

roar_ros::RaceStatus toRaceStatus(const race::RaceControl& race, double now) {
  roar_ros::RaceStatus msg;
  msg.header.stamp = toRosTime(now);
  msg.map_name = race.track().info().name;
  msg.laps = race.rules().laps;
  msg.finished = race.finished();
  for (const auto& standing : race.standings()) {
    const race::CarRecord& car = race.car(standing.name);
    roar_ros::CarStanding s;
    s.name = standing.name;
    s.position = standing.position;
    s.gap_to_leader = standing.gap_to_leader;
    s.laps_completed = car.timer.lapsCompleted();
    if (car.timer.started()) {
      s.sector = 1 + static_cast<int>(car.timer.progress() / race.track().length() * race.track().info().sectors);
      s.current_lap_time = car.last_time - car.timer.lapStart();
    }
    if (!car.timer.laps().empty()) s.last_lap = car.timer.laps().back().lap_time;
    if (auto best = car.timer.bestLap()) s.best_lap = *best;
    s.distance = std::max(0.0, car.timer.distanceCovered());
    s.penalties = car.penalties;
    s.barrier_contacts = car.barrier_contacts;
    s.car_contacts = car.car_contacts;
    s.track_limit_violations = car.track_limit_violations;
    s.time_in_traffic = car.time_in_traffic;
    const double lost = race.timeLostInTraffic(standing.name);  // NaN until there is a clean lap to compare
    s.traffic_compared = std::isfinite(lost);
    s.time_lost_in_traffic = s.traffic_compared ? lost : 0.0;
    s.finished = car.finished;
    msg.cars.push_back(s);
  }
  return msg;
}

}  // namespace roar::ros_bridge
