#include "roar/session/sim_session.h"

#include <gtest/gtest.h>

#include "test_support.h"

using namespace roar;
using session::SimSession;
using test::errorOf;

namespace {

session::SessionOptions options() {
  session::SessionOptions o;
  o.urdf_dir = test::sourceDir() + "/urdf";
  o.vehicle_config_dir = test::sourceDir() + "/config/vehicles";
  return o;
}

std::string mapFolder(const std::string& name) { return test::sourceDir() + "/maps/" + name; }

// Spawns a car as roar_sim does: checked first, then put on the grid.
void spawnOnGrid(SimSession& s, const std::string& name, int slot, const std::string& model = "sedan") {
  const vehicle::VehicleParams params = s.carToSpawn(name, model);
  session::SpawnRecord record;
  record.spawn_point = slot;
  s.spawn(name, params, s.spawnPose(slot), record);
}

vehicle::VehicleControl fullThrottle() {
  vehicle::VehicleControl c;
  c.throttle = 1.0;
  return c;
}

}  // namespace

TEST(SimSession, SpawnsCarsWithTheirRecordsAndDistinctPaint) {
  SimSession s(options(), mapFolder("roar_ring"));
  spawnOnGrid(s, "ego", 0);
  spawnOnGrid(s, "rival", 1, "hatchback");
  ASSERT_TRUE(s.has("ego"));
  EXPECT_EQ(s.record("rival").model, "hatchback");
  EXPECT_EQ(s.record("rival").spawn_point, 1);
  EXPECT_NE(s.record("ego").colour, s.record("rival").colour);
  EXPECT_TRUE((s.record("ego").colour.array() >= 0).all());
  EXPECT_NE(s.sceneId("ego"), s.sceneId("rival"));
  EXPECT_EQ(s.records().size(), 2u);
  EXPECT_TRUE(s.world().hasVehicle("rival"));
}

TEST(SimSession, RefusesBadNamesAndTakenNamesBeforeAnythingIsMade) {
  SimSession s(options(), mapFolder("roar_ring"));
  spawnOnGrid(s, "ego", 0);
  EXPECT_NE(errorOf([&] { s.carToSpawn("ego", "sedan"); }).find("already exists"), std::string::npos);
  EXPECT_NE(errorOf([&] { s.carToSpawn("9lives", "sedan"); }).find("must start with a letter"), std::string::npos);
  EXPECT_NE(errorOf([&] { s.carToSpawn("a/b", "sedan"); }).find("letters, digits and underscores"), std::string::npos);
  EXPECT_FALSE(errorOf([&] { s.carToSpawn("other", "no_such_car"); }).empty());
  EXPECT_EQ(s.records().size(), 1u);
}

TEST(SimSession, ASpawnTheWorldRefusesLeavesNothingBehind) {
  SimSession s(options(), mapFolder("roar_ring"));
  spawnOnGrid(s, "ego", 0);
  const vehicle::VehicleParams params = s.carToSpawn("twin", "sedan");
  // On top of ego: the physics world refuses the overlap.
  EXPECT_THROW(s.spawn("twin", params, s.spawnPose(0), {}), sim::SpawnError);
  EXPECT_FALSE(s.has("twin"));
  EXPECT_FALSE(s.world().hasVehicle("twin"));
  spawnOnGrid(s, "twin", 2);
  EXPECT_TRUE(s.has("twin"));
}

TEST(SimSession, RequestedPosesAreCheckedAndNamedWhenWrong) {
  SimSession s(options(), mapFolder("roar_ring"));
  track::Pose p = s.spawnPose(3);
  EXPECT_TRUE(s.requestedPose(3, track::Pose{}).position.isApprox(p.position));
  EXPECT_TRUE(s.requestedPose(-1, p).position.isApprox(p.position));
  EXPECT_NE(errorOf([&] { s.requestedPose(track::kGridSlots, p); }).find("does not exist"), std::string::npos);
  EXPECT_NE(errorOf([&] { s.requestedPose(-2, p); }).find("-1 for pose"), std::string::npos);
  EXPECT_NE(errorOf([&] { s.spawnPose(-1); }).find("does not exist"), std::string::npos);
  track::Pose nan = p;
  nan.position.x() = std::nan("");
  EXPECT_NE(errorOf([&] { s.requestedPose(-1, nan); }).find("finite"), std::string::npos);
  track::Pose high = p;
  high.position.z() = track::kMaxElevation + 1;
  EXPECT_NE(errorOf([&] { s.requestedPose(-1, high); }).find("pose z"), std::string::npos);
  track::Pose far = p;
  far.position.x() += 1e5;
  EXPECT_FALSE(errorOf([&] { s.requestedPose(-1, far); }).empty());
}

TEST(SimSession, ARejectedControlChangesNothingAndAFlawedOneSaysWhy) {
  SimSession s(options(), mapFolder("roar_ring"));
  spawnOnGrid(s, "ego", 0);
  vehicle::VehicleControl bad = fullThrottle();
  bad.throttle = std::nan("");
  const session::AppliedControl rejected = s.applyControl("ego", bad);
  EXPECT_FALSE(rejected.applied);
  EXPECT_FALSE(rejected.problems.empty());
  for (int i = 0; i < 20; ++i) s.world().step();
  EXPECT_LT(s.world().vehicleState("ego").linear_velocity.norm(), 0.5);

  vehicle::VehicleControl over = fullThrottle();
  over.throttle = 1.5;  // clamped, and said
  const session::AppliedControl clamped = s.applyControl("ego", over);
  EXPECT_TRUE(clamped.applied);
  EXPECT_FALSE(clamped.problems.empty());
  EXPECT_TRUE(s.applyControl("ego", fullThrottle()).problems.empty());
}

TEST(SimSession, KeepsTheLastTicksForFramesRenderedAfterThem) {
  SimSession s(options(), mapFolder("roar_ring"));
  spawnOnGrid(s, "ego", 0);
  const double dt = options().world.control_dt;
  for (std::size_t i = 0; i < session::kKeptSceneTicks + 10; ++i) {
    s.applyControl("ego", fullThrottle());  // a driver's, every tick
    s.world().step();
    s.keepTick(i % 7 == 0);
  }
  EXPECT_EQ(s.keptTicks(), session::kKeptSceneTicks);
  const double last = s.world().time();
  const session::SceneTick& kept = s.keptTick(last - 5 * dt, "ego");
  EXPECT_NEAR(kept.time, last - 5 * dt, 1e-9);
  // The car moved since: the kept pose is not the car's now.
  EXPECT_GT((kept.cars.at("ego").pose.translation() - s.sceneNow().cars.at("ego").pose.translation()).norm(), 1.0);
  const std::string dropped = errorOf([&] { s.keptTick(dt, "ego"); });
  EXPECT_NE(dropped.find("is kept"), std::string::npos);
  EXPECT_NE(dropped.find("the last 200 ticks"), std::string::npos);
  // A car spawned since is in no kept tick; the world's sensors (no car) take any.
  spawnOnGrid(s, "late", 5);
  EXPECT_THROW(s.keptTick(last, "late"), std::invalid_argument);
  EXPECT_NO_THROW(s.keptTick(last, ""));
  EXPECT_NO_THROW(s.poseScene(s.keptTick(last, "")));  // the late car out of sight
}

TEST(SimSession, LoadingAMapCountsGenerationsKeepsTheClockAndABrokenOneChangesNothing) {
  SimSession s(options(), mapFolder("roar_ring"));
  EXPECT_EQ(s.mapGeneration(), 0u);
  spawnOnGrid(s, "ego", 0);
  for (int i = 0; i < 10; ++i) s.world().step();
  s.keepTick(false);
  const double time = s.world().time();

  bool told = false;
  EXPECT_THROW(s.loadMap(mapFolder("no_such_map"), [&] { told = true; }), std::exception);
  EXPECT_FALSE(told);
  EXPECT_EQ(s.mapGeneration(), 0u);
  EXPECT_TRUE(s.has("ego"));
  EXPECT_EQ(s.mapFolder(), mapFolder("roar_ring"));

  s.loadMap(mapFolder("roar_sprint"), [&] { told = s.has("ego"); });  // told before the cars go
  EXPECT_TRUE(told);
  EXPECT_EQ(s.mapGeneration(), 1u);
  EXPECT_FALSE(s.has("ego"));
  EXPECT_EQ(s.keptTicks(), 0u);
  EXPECT_DOUBLE_EQ(s.world().time(), time);
  EXPECT_EQ(s.mapFolder(), mapFolder("roar_sprint"));
  spawnOnGrid(s, "ego", 0);  // its name free again
}

TEST(SimSession, AControlCheckedAloneIsJudgedAsApplyingItWouldBeAndChangesNothing) {
  SimSession s(options(), mapFolder("roar_ring"));
  spawnOnGrid(s, "ego", 0);
  vehicle::VehicleControl bad = fullThrottle();
  bad.steer = std::nan("");
  EXPECT_FALSE(s.checkControl("ego", bad).applied);
  EXPECT_EQ(s.checkControl("ego", bad).problems, s.applyControl("ego", bad).problems);
  for (int i = 0; i < 20; ++i) {  // checked, never applied: the car stays parked
    EXPECT_TRUE(s.checkControl("ego", fullThrottle()).applied);
    s.world().step();
  }
  EXPECT_LT(s.world().vehicleState("ego").linear_velocity.norm(), 0.1);
  for (int i = 0; i < 20; ++i) {
    s.applyControl("ego", fullThrottle());
    s.world().step();
  }
  EXPECT_GT(s.world().vehicleState("ego").linear_velocity.norm(), 1.0);
}
