#include <gtest/gtest.h>

#include "roar/sim/world.h"
#include "test_support.h"

using namespace roar;
using sim::Pose;
using sim::World;
using test::errorOf;

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
  world.spawnVehicle("ego", test::sedan(), sim::poseOnTrack(start));
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
