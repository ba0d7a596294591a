#include <gtest/gtest.h>

#include "roar/control/centreline_follower.h"
#include "roar/sim/world.h"
#include "roar/track/map_folder.h"
#include "lap_driver.h"

using namespace roar;

TEST(CentrelineFollower, SpeedProfileRespectsCornerAndBrakingLimits) {
  const auto track = test::circleTrack(50.0);
  control::FollowerOptions o;
  control::CentrelineFollower f(track, o);
  for (double s = 0; s < track.length(); s += 7) {
    EXPECT_LE(f.targetSpeedAt(s), std::sqrt(o.lateral_accel * 50.0) * 1.01);
    EXPECT_GT(f.targetSpeedAt(s), std::sqrt(o.lateral_accel * 50.0) * 0.95);
  }
  EXPECT_THROW(control::CentrelineFollower(track, [] {
                 control::FollowerOptions bad;
                 bad.lateral_accel = 0;
                 return bad;
               }()),
               std::invalid_argument);
}

TEST(CentrelineFollower, SteersBackTowardsTheLine) {
  const auto track = test::circleTrack(200.0);
  control::CentrelineFollower f(track, {});
  // On the line, heading along it: nearly the circle's own steering angle, to the left.
  auto on = f.update({{200.0, 0.0}, M_PI / 2, 10.0});
  EXPECT_GT(on.steer, 0.0);
  EXPECT_LT(on.steer, 0.1);
  // 3 m outside (to the right of the driver): steer harder left; 3 m inside: steer right of that.
  auto outside = f.update({{203.0, 0.0}, M_PI / 2, 10.0});
  auto inside = f.update({{197.0, 0.0}, M_PI / 2, 10.0});
  EXPECT_GT(outside.steer, on.steer);
  EXPECT_LT(inside.steer, on.steer);
  // Too fast for the corner: brake.
  auto fast = f.update({{200.0, 0.0}, M_PI / 2, 60.0});
  EXPECT_GT(fast.brake, 0.5);
  EXPECT_EQ(fast.throttle, 0.0);
}

// Every shipped circuit: it loads (closed, edges that never cross) and the car drives a clean lap of it.
TEST(CentrelineFollower, DrivesACleanLapOfEveryShippedCircuit) {
  const auto maps = track::listMaps(test::sourceDir() + "/maps");
  ASSERT_GE(maps.size(), 3u);
  for (const auto& name : maps) {
    SCOPED_TRACE(name);
    const auto track = track::loadMapFolder(test::sourceDir() + "/maps/" + name);
    const auto lap = test::driveLap(track);
    EXPECT_GE(lap.travelled, track.length()) << "a whole lap in " << lap.time << " s";
    EXPECT_EQ(lap.barrier_ticks, 0);
    EXPECT_LT(lap.worst_offroad, 0.0) << "base_link stays on the road";
    RecordProperty(name + "_lap_s", std::to_string(lap.time));
  }
}
