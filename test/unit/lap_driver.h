#pragma once
// Drives the default car round a track with the centre-line follower, for tests that need a real lap.
#include "roar/control/centreline_follower.h"
#include "roar/sim/world.h"
#include "test_support.h"

namespace roar::test {

struct LapResult {
  double travelled = 0.0;      // m along the ground
  double time = 0.0;           // s, simulated, when the lap (or the time limit) was reached
  int barrier_ticks = 0;       // ticks with a barrier contact
  double worst_offroad = -1e9; // m of base_link beyond the road edge at its worst (negative: always inside)
  bool clean(const track::Track& track) const { return travelled >= track.length() && barrier_ticks == 0; }
};

inline LapResult driveLap(const track::Track& track, double time_limit = 600.0) {
  sim::World world(track, {});
  const auto car = sedan();
  world.spawnVehicle("ego", car, sim::poseOnTrack(track.gridSpawnPoints(1)[0]));
  control::FollowerOptions o;
  o.wheelbase = car.wheelbase();
  o.max_steer_angle = car.steering.max_angle;
  control::CentrelineFollower follower(track, o);
  LapResult r;
  Eigen::Vector3d last = world.vehicleState("ego").pose.position;
  while (r.travelled < track.length() + 20 && world.time() < time_limit) {
    const auto s = world.vehicleState("ego");
    const Eigen::Vector3d fwd = s.pose.orientation * Eigen::Vector3d::UnitX();
    world.setControl("ego", follower.update({s.pose.position.head<2>(), std::atan2(fwd.y(), fwd.x()), s.forward_speed,
                                             s.body_angular_velocity.z()}));
    world.step();
    const auto now = world.vehicleState("ego").pose.position;
    r.travelled += (now - last).head<2>().norm();
    last = now;
    const auto pr = track.project(now.head<2>());
    r.worst_offroad = std::max(r.worst_offroad, std::abs(pr.lateral) - (pr.lateral > 0 ? pr.width_left : pr.width_right));
    for (const auto& c : world.contacts("ego")) r.barrier_ticks += c.other == "barrier";
  }
  r.time = world.time();
  return r;
}

}  // namespace roar::test
