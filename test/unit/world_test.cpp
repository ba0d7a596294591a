#include <gtest/gtest.h>

#include "roar/sim/world.h"
#include "roar/track/map_folder.h"
#include "test_support.h"

using namespace roar;
using sim::World;
using test::errorOf;
using track::Pose;

namespace {

Pose at(double x, double y, double yaw = 0.0) {
  Pose p;
  p.position = {x, y, 0};
  p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return p;
}

}  // namespace

TEST(World, OptionsMustBeConsistent) {
  const auto track = test::openGround();
  sim::WorldOptions o;
  o.control_dt = 0.05;
  o.physics_dt = 0.003;
  EXPECT_NE(errorOf([&] { World w(track, o); }).find("whole multiple"), std::string::npos);
  o.physics_dt = 0.1;
  EXPECT_THROW(World(track, o), std::invalid_argument);
}

TEST(World, TimeAdvancesByExactControlTicks) {
  const auto track = test::openGround();
  World world(track, {});
  for (int i = 0; i < 7; ++i) world.step();
  EXPECT_EQ(world.tick(), 7u);
  EXPECT_DOUBLE_EQ(world.time(), 7 * 0.05);
}

TEST(World, TimingChangesAtRunTimeKeepTheClockGoingForward) {
  const auto track = test::openGround();
  World world(track, {}, {100, 5.0});  // a world that replaces one at tick 100, t = 5 s
  world.spawnVehicle("ego", test::sedan(), at(0, 0));
  world.step();
  EXPECT_EQ(world.tick(), 101u);
  EXPECT_DOUBLE_EQ(world.time(), 5.05);
  world.setTiming(0.02, 0.01);
  for (int i = 0; i < 5; ++i) world.step();
  EXPECT_EQ(world.tick(), 106u);
  EXPECT_NEAR(world.time(), 5.15, 1e-12);
  EXPECT_DOUBLE_EQ(world.options().control_dt, 0.02);
  EXPECT_NE(errorOf([&] { world.setTiming(0.05, 0.003); }).find("whole multiple"), std::string::npos);
  EXPECT_DOUBLE_EQ(world.options().control_dt, 0.02) << "a refused change changes nothing";
  EXPECT_THROW(world.setTiming(0.01, 0.02), std::invalid_argument);
  world.step();
  EXPECT_NEAR(world.time(), 5.17, 1e-12);
  EXPECT_LT(world.vehicleState("ego").speed, 0.05) << "the parked car stays parked across the change";
}

// CARLA spawns an actor at the transform asked and lets it fall: ROAR's competition runner spawns its car
// a metre above the first waypoint and waits 20 ticks.
TEST(World, SpawnedAsGivenAboveTheRoadFallsOntoIt) {
  const auto track = test::openGround();
  World world(track, {});
  Pose high = at(10, 20, 0.5);
  high.position.z() = 1.0;
  world.spawnVehicle("ego", test::sedan(), high, sim::Placement::kAsGiven);
  EXPECT_NEAR(world.vehicleState("ego").pose.position.z(), 1.0, 1e-9) << "placed at the height asked";
  world.step();
  EXPECT_LT(world.vehicleState("ego").pose.position.z(), 1.0) << "it falls";
  EXPECT_LT(world.vehicleState("ego").linear_velocity.z(), -0.2);
  for (int i = 0; i < 40; ++i) world.step();
  const auto s = world.vehicleState("ego");
  EXPECT_NEAR(s.pose.position.z(), -0.02, 0.01) << "and comes to rest on the road";
  EXPECT_LT(s.speed, 0.05);
  Pose below = at(30, 20);
  below.position.z() = -3.0;
  world.spawnVehicle("low", test::sedan(), below, sim::Placement::kAsGiven);
  EXPECT_GT(world.vehicleState("low").pose.position.z(), -0.1) << "never below the ground";
  Pose tilted = at(10, 20, 0.0);
  tilted.position.z() = 0.5;
  tilted.orientation = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY());
  world.resetVehicle("ego", tilted, sim::Placement::kAsGiven);
  const Eigen::Vector3d fwd = world.vehicleState("ego").pose.orientation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::asin(-fwd.z()), 0.2, 1e-6) << "pitch as given";
}

TEST(World, SpawnRestsOnTheGroundAtTheRideHeight) {
  const auto track = test::openGround();
  World world(track, {});
  world.spawnVehicle("ego", test::sedan(), at(10, 20, 0.5));
  for (int i = 0; i < 40; ++i) world.step();
  const auto s = world.vehicleState("ego");
  EXPECT_NEAR(s.pose.position.z(), -0.02, 0.01) << "base_link on the ground (2 cm below road level)";
  EXPECT_NEAR(s.pose.position.x(), 10, 0.01);
  EXPECT_NEAR(s.pose.position.y(), 20, 0.01);
  const Eigen::Vector3d fwd = s.pose.orientation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(fwd.y(), fwd.x()), 0.5, 1e-3);
  for (const auto& w : s.wheels) {
    EXPECT_TRUE(w.in_contact);
    EXPECT_NEAR(w.compression, 0.0, 0.01) << "static sag matches the URDF wheel height";
  }
}

TEST(World, SpawnErrorsGiveReasons) {
  const auto track = test::openGround();
  World world(track, {});
  world.spawnVehicle("ego", test::sedan(), at(0, 0));
  EXPECT_NE(errorOf([&] { world.spawnVehicle("ego", test::sedan(), at(50, 0)); }).find("already exists"),
            std::string::npos);
  const auto msg = errorOf([&] { world.spawnVehicle("rival", test::sedan(), at(2, 1)); });
  EXPECT_NE(msg.find("overlap vehicle 'ego'"), std::string::npos) << msg;
  EXPECT_FALSE(world.hasVehicle("rival"));
  world.spawnVehicle("rival", test::sedan(), at(0, 4));  // side by side with a gap
  EXPECT_EQ(world.vehicleNames(), (std::vector<std::string>{"ego", "rival"}));
  EXPECT_NE(errorOf([&] { world.destroyVehicle("ghost"); }).find("no vehicle named 'ghost'"), std::string::npos);
  world.destroyVehicle("rival");
  EXPECT_FALSE(world.hasVehicle("rival"));
  world.step();
}

TEST(World, ResetPutsTheCarBackAtRest) {
  const auto track = test::openGround();
  World world(track, {});
  world.spawnVehicle("ego", test::sedan(), at(0, 0));
  vehicle::VehicleControl go;
  go.throttle = 1.0;
  for (int i = 0; i < 60; ++i) {
    world.setControl("ego", go);
    world.step();
  }
  ASSERT_GT(world.vehicleState("ego").speed, 10.0);
  world.resetVehicle("ego", at(-100, 0, M_PI));
  world.step();
  const auto s = world.vehicleState("ego");
  EXPECT_NEAR(s.pose.position.x(), -100, 0.05);
  EXPECT_LT(s.speed, 0.2);
  EXPECT_EQ(s.gear, 1);
  for (const auto& w : s.wheels) EXPECT_LT(std::abs(w.angular_velocity), 0.5);
}

TEST(World, VelocitiesSetAtRunTimeCarryTheCarOn) {
  const auto track = test::openGround();
  sim::WorldOptions o;
  o.control_timeout = 0.0;
  World world(track, o);
  world.spawnVehicle("ego", test::sedan(), at(0, 0, M_PI / 2));  // heading north
  for (int i = 0; i < 20; ++i) world.step();
  vehicle::VehicleControl coast;
  world.setControl("ego", coast);
  world.setVehicleVelocity("ego", {0, 20, 0}, {0, 0, 0});
  world.step();
  const auto s = world.vehicleState("ego");
  EXPECT_NEAR(s.forward_speed, 20.0, 0.3) << "moving north at 20 m/s, the wheels rolling with it";
  EXPECT_NEAR(s.pose.position.y(), 1.0, 0.05);
  EXPECT_LT(std::abs(s.wheels[0].slip_ratio), 0.05);
  EXPECT_THROW(world.setVehicleVelocity("ego", {1e6, 0, 0}, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(world.setVehicleVelocity("ego", {0, 0, 0}, {0, 0, NAN}), std::invalid_argument);
  EXPECT_THROW(world.setVehicleVelocity("nobody", {0, 0, 0}, {0, 0, 0}), sim::SpawnError);
}

// A moved car keeps its motion in its own frame: turned by a quarter turn in a skid, it skids on as before
// relative to its body, at the new speed, its steering and wheels as they were.
TEST(World, AMovedCarKeepsItsSlipYawRateAndInnerStates) {
  const auto track = test::openGround();
  sim::WorldOptions o;
  o.control_timeout = 0.0;
  World world(track, o);
  world.spawnVehicle("ego", test::sedan(), at(0, 0));
  for (int i = 0; i < 20; ++i) world.step();
  vehicle::VehicleControl turn;
  turn.throttle = 0.5;
  turn.steer = 0.3;
  world.setControl("ego", turn);
  world.setVehicleVelocity("ego", {20, 0, 0}, {0, 0, 0});
  for (int i = 0; i < 20; ++i) world.step();
  const auto before = world.vehicleState("ego");
  ASSERT_GT(before.body_angular_velocity.z(), 0.2) << "turning left";
  const double yaw = track::yawOf(before.pose.orientation) + M_PI / 2;
  world.moveVehicle("ego", {50.0, 80.0}, yaw, 0.5 * before.speed);
  const auto after = world.vehicleState("ego");
  EXPECT_NEAR(after.pose.position.x(), 50.0, 1e-6);
  EXPECT_NEAR(after.pose.position.y(), 80.0, 1e-6);
  EXPECT_NEAR(after.pose.position.z(), before.pose.position.z(), 1e-6) << "its height kept";
  EXPECT_NEAR(track::yawOf(after.pose.orientation), std::remainder(yaw, 2 * M_PI), 1e-6);
  EXPECT_NEAR(after.speed, 0.5 * before.speed, 1e-6);
  EXPECT_NEAR(after.body_linear_velocity.y() / after.body_linear_velocity.x(),
              before.body_linear_velocity.y() / before.body_linear_velocity.x(), 1e-6)
      << "the same slip angle";
  EXPECT_NEAR(after.body_angular_velocity.z(), before.body_angular_velocity.z(), 1e-6);
  EXPECT_DOUBLE_EQ(after.steering_angle, before.steering_angle);
  EXPECT_NEAR(after.wheels[2].angular_velocity, 0.5 * before.wheels[2].angular_velocity, 1e-9);
  EXPECT_THROW(world.moveVehicle("ego", {NAN, 0.0}, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(world.moveVehicle("ego", {0.0, 0.0}, 0.0, 200.0), std::invalid_argument);
  EXPECT_THROW(world.moveVehicle("nobody", {0.0, 0.0}, 0.0, 1.0), sim::SpawnError);
}

TEST(World, StaleControlBrakesTheCar) {
  const auto track = test::openGround();
  sim::WorldOptions o;
  o.control_timeout = 0.5;
  World world(track, o);
  world.spawnVehicle("ego", test::sedan(), at(0, 0));
  vehicle::VehicleControl go;
  go.throttle = 1.0;
  world.setControl("ego", go);
  for (int i = 0; i < 11; ++i) world.step();  // the last of these ticks starts exactly 0.5 s after the control
  EXPECT_EQ(world.vehicleState("ego").applied_control.throttle, 1.0);
  world.step();
  EXPECT_EQ(world.vehicleState("ego").applied_control.throttle, 0.0) << "driver silent for longer than the timeout";
  EXPECT_GT(world.vehicleState("ego").applied_control.brake, 0.2);
  EXPECT_FALSE(world.vehicleState("ego").applied_control.hand_brake) << "no locked wheels at speed";
}

// A driver that falls silent in a corner at speed: the car brakes steadily along the road, stays on it,
// and parks once stopped (the old fail-safe, full brakes and the hand brake, spun cars into the barrier).
TEST(World, ACarWhoseDriverFallsSilentStopsOnTheRoad) {
  const auto track = test::circleTrack(100.0, 12.0);
  sim::WorldOptions o;
  o.control_timeout = 0.5;
  World world(track, o);
  const auto start = track.poseAt(0.0);
  world.spawnVehicle("ego", test::sedan(), track::poseOnTrack(start));
  vehicle::VehicleControl cruise;
  cruise.throttle = 0.3;
  world.setControl("ego", cruise);
  world.step();
  world.setVehicleVelocity("ego", {25.0 * std::cos(start.heading), 25.0 * std::sin(start.heading), 0},
                           {0, 0, 25.0 / 100.0});
  double worst = -1e9;
  for (int i = 0; i < 800; ++i) {  // 40 s
    world.step();
    const auto s = world.vehicleState("ego");
    worst = std::max(worst, track.project(s.pose.position.head<2>()).beyondEdge());
    ASSERT_TRUE(world.contacts("ego").empty() || world.contacts("ego").front().other != "barrier") << "at tick " << i;
  }
  const auto end = world.vehicleState("ego");
  EXPECT_LT(worst, -1.0) << "the car's centre stayed at least a metre inside the edges";
  EXPECT_LT(end.speed, 0.5);
  EXPECT_TRUE(end.applied_control.hand_brake) << "parked once stopped";
}

TEST(World, BarrierAndCarContactsAreReportedWithTheOtherBody) {
  // A car driven straight off a circle track's road hits the outer barrier.
  const auto track = test::circleTrack(60.0);
  World world(track, {});
  world.spawnVehicle("ego", test::sedan(), at(60, 0, 0.0));  // on the road facing outwards (+x)
  vehicle::VehicleControl go;
  go.throttle = 0.6;
  bool hit = false;
  for (int i = 0; i < 100 && !hit; ++i) {
    world.setControl("ego", go);
    world.step();
    for (const auto& c : world.contacts("ego")) {
      if (c.other == "barrier") {
        hit = true;
        EXPECT_LT(c.impulse.x(), 0) << "the wall pushes the car back towards the centre";
        EXPECT_NEAR(c.position.head<2>().norm(), 60 + 6 + track.info().barrier_offset, 1.0);
      }
    }
  }
  EXPECT_TRUE(hit);

  World open(test::openGround(), {});
  open.spawnVehicle("a", test::sedan(), at(0, 0));
  open.spawnVehicle("b", test::sedan(), at(30, 0));
  bool touched = false;
  for (int i = 0; i < 100 && !touched; ++i) {
    open.setControl("a", go);
    open.step();
    for (const auto& c : open.contacts("b")) touched = touched || c.other == "a";
  }
  EXPECT_TRUE(touched);
}

TEST(World, ACarInAnotherCarsSlipstreamMeetsLessDrag) {
  // Two cars coasting north at 35 m/s, one 8 m behind the other, and the same pair without the wake model:
  // the car behind keeps more of its speed in the tow; the one ahead loses as much as a car alone.
  auto coast = [](bool slipstream) {
    const auto track = test::openGround();
    sim::WorldOptions o;
    o.control_timeout = 0.0;
    o.slipstream.enabled = slipstream;
    World world(track, o);
    world.spawnVehicle("ahead", test::sedan(), at(0, 8, M_PI / 2));
    world.spawnVehicle("behind", test::sedan(), at(0, 0, M_PI / 2));
    for (int i = 0; i < 20; ++i) world.step();
    vehicle::VehicleControl neutral;
    for (const char* car : {"ahead", "behind"}) {
      world.setControl(car, neutral);
      world.setVehicleVelocity(car, {0, 35, 0}, {0, 0, 0});
    }
    world.step();
    const double share = world.vehicleState("behind").drag_share;
    for (int i = 0; i < 80; ++i) world.step();
    return std::array<double, 3>{world.vehicleState("ahead").forward_speed, world.vehicleState("behind").forward_speed,
                                 share};
  };
  const auto towed = coast(true), free_air = coast(false);
  EXPECT_LT(towed[2], 0.85) << "8 m centre to centre: a strong tow";
  EXPECT_EQ(free_air[2], 1.0);
  EXPECT_NEAR(towed[0], free_air[0], 1e-9) << "the car ahead feels nothing";
  EXPECT_NEAR(free_air[1], free_air[0], 0.05) << "without the wake both slow alike";
  // 4 s of coasting from 35 m/s loses about 3.6 m/s in free air, drag most of it.
  EXPECT_GT(towed[1], towed[0] + 0.2) << "the towed car keeps more of its speed";
}

// A car driven into the barrier at up to 90 m/s (324 km/h), at up to 60 degrees, is held by it: the hit is
// absorbed (VehicleDynamics::absorbCrash), not turned into a roll that throws the car over the 1 m wall.
TEST(World, BarriersHoldACarAtAnySpeed) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_ring");
  const double s0 = track.info().start_finish_s + 300.0;  // on the main straight
  const track::TrackPose on = track.poseAt(s0);
  for (const char* model : {"sedan", "carla_model3"}) {
    for (double speed : {20.0, 45.0, 70.0, 90.0}) {
      for (double angle_deg : {5.0, 15.0, 30.0, 60.0}) {
        World world(track, {});
        track::TrackPose start = on;
        start.heading += angle_deg * M_PI / 180.0;  // towards the left barrier
        world.spawnVehicle("ego", test::vehicle(model), track::poseOnTrack(start));
        const Eigen::Vector2d forward(std::cos(start.heading), std::sin(start.heading));
        world.setVehicleVelocity("ego", Eigen::Vector3d(forward.x(), forward.y(), 0) * speed, Eigen::Vector3d::Zero());
        vehicle::VehicleControl go;
        go.throttle = 1.0;
        double widest = 0.0, highest = 0.0;
        for (int i = 0; i < 20 * 4; ++i) {
          world.setControl("ego", go);
          world.step();
          const auto& state = world.vehicleState("ego");
          widest = std::max(widest, std::abs(track.projectNear(state.pose.position.head<2>(), s0, 300.0).lateral));
          highest = std::max(highest, state.pose.position.z());
        }
        const double wall = std::max(on.width_left, on.width_right) + track.info().barrier_offset + 0.5;
        EXPECT_LT(widest, wall + 1.0) << model << " at " << speed << " m/s, " << angle_deg << " degrees";
        EXPECT_LT(highest, 2.0) << model << " at " << speed << " m/s, " << angle_deg << " degrees: thrown up";
      }
    }
  }
}

// A ROAR_PY program that never steers: the sedan leaves the main straight's end at 61 m/s, meets the barrier
// at a shallow angle and stays inside it (it used to roll up and over, 30 m clear).
TEST(World, TheBarrierHoldsACarDrivenStraightOffTheMainStraight) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_ring");
  World world(track, {});
  world.spawnVehicle("ego", test::sedan(), track::poseOnTrack(track.gridSpawnPoints(20).at(0)));
  vehicle::VehicleControl go;
  go.throttle = 1.0;
  double widest = 0.0, near = track.info().start_finish_s;
  for (int i = 0; i < 20 * 25; ++i) {
    world.setControl("ego", go);
    world.step();
    const auto projection = track.projectNear(world.vehicleState("ego").pose.position.head<2>(), near, 200.0);
    near = projection.s;
    widest = std::max(widest, std::abs(projection.lateral));
  }
  const auto pose = track.poseAt(near);
  EXPECT_LT(widest, std::max(pose.width_left, pose.width_right) + track.info().barrier_offset + 1.5);
}

// Driven straight on with no steering, as a ROAR_PY program that never steers does, a car meets the barrier
// at the end of the straight at full speed: wherever it goes then, it stays within the world's edge.
TEST(World, ACarThrownClearStaysInTheWorld) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_ring");
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (std::size_t i = 0; i < track.size(); ++i) {
    lo = lo.cwiseMin(track.position(i));
    hi = hi.cwiseMax(track.position(i));
  }
  for (const char* model : {"sedan", "carla_model3"}) {
    World world(track, {});
    world.spawnVehicle("ego", test::vehicle(model), track::poseOnTrack(track.gridSpawnPoints(20).at(0)));
    vehicle::VehicleControl go;
    go.throttle = 1.0;
    double farthest = 0.0;
    for (int i = 0; i < 20 * 300; ++i) {
      world.setControl("ego", go);
      world.step();
      const Eigen::Vector3d p = world.vehicleState("ego").pose.position;
      ASSERT_TRUE(p.allFinite()) << model << " at t = " << world.time();
      const Eigen::Vector2d outside = (lo - p.head<2>()).cwiseMax(p.head<2>() - hi).cwiseMax(0.0);
      farthest = std::max(farthest, outside.norm());
    }
    EXPECT_LT(farthest, 100.0) << model << ": metres beyond the circuit's extent";
  }
}

// Beyond the barriers the ground goes on for ever: a car out there (spawned as given, or one that got out)
// driving away meets the world's edge, 50 m beyond the circuit's barriers, and goes no further.
TEST(World, TheWorldsEdgeHoldsACarDrivingAway) {
  const auto track = test::circleTrack(60.0);
  World world(track, {});
  world.spawnVehicle("ego", test::sedan(), at(80, 0, 0.0), sim::Placement::kAsGiven);  // outside, facing out
  world.setVehicleVelocity("ego", Eigen::Vector3d(60, 0, 0), Eigen::Vector3d::Zero());
  vehicle::VehicleControl go;
  go.throttle = 1.0;
  double farthest = 0.0;
  for (int i = 0; i < 20 * 20; ++i) {
    world.setControl("ego", go);
    world.step();
    farthest = std::max(farthest, world.vehicleState("ego").pose.position.head<2>().norm());
  }
  const double barrier = 60.0 + 6.0 + track.info().barrier_offset;  // circleTrack's half-width is 6 m
  EXPECT_LT(farthest, barrier + 50.0 + 20.0);
}

// The run-off (issue 62): on ROAR's Monza a car running at 150 km/h with its right wheels a metre beyond the
// road's edge rolls on over the grass at the road's height: no collision reported (CARLA's collision sensor
// sees cars, barriers and objects, not the ground driven on) and the car stays on its wheels.
TEST(World, TheRunOffCarriesAWheelOverTheEdgeWithoutACollision) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/monza");
  const vehicle::VehicleParams car = test::vehicle("vehicle.tesla.model3");
  // The pit straight, 500 m before the line.
  const double s0 = track.length() - 500.0;
  track::TrackPose pose = track.poseAt(s0);
  const double half_track = 0.5 * car.track_width();
  const Eigen::Vector2d left(-std::sin(pose.heading), std::cos(pose.heading));
  pose.position -= left * (pose.width_right + 1.0 - half_track);  // the right wheels 1 m beyond the edge
  World world(track, {});
  world.spawnVehicle("ego", car, track::poseOnTrack(pose));
  vehicle::VehicleControl hold;
  hold.throttle = 0.6;
  world.setControl("ego", hold);  // before the velocity: a car set moving has its pedals settled at its control
  const Eigen::Vector3d forward(std::cos(pose.heading), std::sin(pose.heading), 0.0);
  world.setVehicleVelocity("ego", forward * (150 / 3.6), Eigen::Vector3d::Zero());
  const double lane = track.projectNear(pose.position, s0, 50.0).lateral;
  double worst_roll = 0.0;
  int contacts = 0, right_on_grass = 0;
  for (int i = 0; i < 40; ++i) {  // 2 s, 83 m, held at that offset from the centre line
    const auto now = world.vehicleState("ego");
    const auto where = track.projectNear(now.pose.position.head<2>(), s0, 200.0);
    const double heading_error = track::wrapAngle(track::yawOf(now.pose.orientation) - where.heading);
    hold.steer = std::clamp(0.02 * (lane - where.lateral) - 0.3 * heading_error, -0.1, 0.1);
    world.setControl("ego", hold);
    world.step();
    contacts += static_cast<int>(world.contacts("ego").size());
    const auto s = world.vehicleState("ego");
    const Eigen::Vector3d up = s.pose.orientation * Eigen::Vector3d::UnitZ();
    worst_roll = std::max(worst_roll, std::acos(std::clamp(up.z(), -1.0, 1.0)));
    for (int w : {1, 3}) right_on_grass += s.wheels[w].in_contact && !s.wheels[w].on_road;
    EXPECT_TRUE(s.wheels[1].in_contact && s.wheels[3].in_contact) << "tick " << i << ": the right wheels on the ground";
  }
  EXPECT_EQ(contacts, 0) << "driving on the run-off is no collision";
  EXPECT_LT(worst_roll, 0.05) << "rad: the car stays level, on its wheels";
  EXPECT_GT(right_on_grass, 60) << "the right wheels did run on the grass";
  EXPECT_GT(world.vehicleState("ego").speed, 140 / 3.6);
}

// The ground beside the road, out to the barrier, is at the road's edge height at that station on every
// shipped map (Roar Eight's bridge among them): a car set down next to the barrier sits at that height.
TEST(World, TheGroundAtTheBarrierIsAtTheRoadsHeightOnEveryShippedMap) {
  const auto car = test::sedan();
  for (const auto& name : track::listMaps(test::sourceDir() + "/maps")) {
    SCOPED_TRACE(name);
    const auto track = track::loadMapFolder(test::sourceDir() + "/maps/" + name);
    World world(track, {});
    int checked = 0;
    for (std::size_t i = 0; i < track.size(); i += std::max<std::size_t>(1, track.size() / 40)) {
      // Away from a crossing, where the other branch's road is nearer than this one's edge.
      bool near_crossing = false;
      for (std::size_t j = 0; j < track.size(); ++j) {
        near_crossing |= std::abs(track.s(i) - track.s(j)) > 100.0 &&
                         std::abs(track.s(i) - track.s(j)) < track.length() - 100.0 &&
                         (track.position(i) - track.position(j)).norm() < 40.0;
      }
      if (near_crossing) continue;
      const auto& p = track.point(i);
      for (int side : {1, -1}) {
        const double offset = track.info().barrier_offset - 0.3;  // just inside the barrier's face
        const Eigen::Vector2d spot = side > 0 ? track.leftEdge(i, offset) : track.rightEdge(i, offset);
        const double edge = track.surfaceHeight(i, side > 0 ? p.width_left : -p.width_right);
        world.spawnVehicle("probe", car, at(spot.x(), spot.y(), track.heading(i)));
        EXPECT_NEAR(world.vehicleState("probe").pose.position.z(), edge, 0.02) << "point " << i << " side " << side;
        world.destroyVehicle("probe");
        ++checked;
      }
    }
    EXPECT_GT(checked, 40);
  }
}
