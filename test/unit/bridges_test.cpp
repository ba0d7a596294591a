// Circuits that cross themselves: one branch raised onto a bridge, the crossing checked for clearance,
// the barriers on the deck leaving the road below clear.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>

#include "roar/planning/field_planner.h"
#include "roar/race/lap_timer.h"
#include "roar/rl/track_progress.h"
#include "roar/sim/safe_stop.h"
#include "roar/sim/world.h"
#include "roar/track/bridges.h"
#include "roar/track/circuit_builder.h"
#include "roar/track/map_folder.h"
#include "roar/track/road_mesh.h"
#include "roar/track/segment_intersection.h"
#include "test_support.h"

using namespace roar;
using test::errorOf;
namespace fs = std::filesystem;

namespace {

// A lemniscate of Bernoulli `a` metres from its centre to each tip: its diagonals cross at right angles.
std::vector<track::CentreLinePoint> figureEight(double a) {
  std::vector<track::ControlPoint> controls;
  for (int k = 0; k < 28; ++k) {
    const double t = 2 * M_PI * k / 28, d = 1 + std::sin(t) * std::sin(t);
    controls.push_back({a * std::cos(t) / d, a * std::sin(t) * std::cos(t) / d, 12.0});
  }
  return track::buildCircuit(controls, 2.0);
}

// The heights of the two branches where the centre line crosses itself.
std::pair<double, double> heightsAtTheCrossing(const std::vector<track::CentreLinePoint>& points) {
  std::vector<Eigen::Vector2d> xy;
  for (const auto& p : points) xy.emplace_back(p.x, p.y);
  const auto crossings = track::closedPolylineSelfCrossings(xy);
  EXPECT_EQ(crossings.size(), 1u);
  if (crossings.empty()) return {0.0, 0.0};
  return {points[crossings[0].first].z, points[crossings[0].second].z};
}

struct TempFolder {
  fs::path path = fs::temp_directory_path() / ("roar_bridges_test_" + std::to_string(::getpid()));
  TempFolder() { fs::create_directories(path); }
  ~TempFolder() { fs::remove_all(path); }
};

}  // namespace

TEST(Bridges, OneBranchOfAFigureEightIsRaisedClearOfTheOtherOnGentleRamps) {
  const auto flat = figureEight(380.0);
  const auto [below, above] = heightsAtTheCrossing(flat);
  EXPECT_EQ(below, above) << "built flat";
  std::vector<track::RaisedBridge> raised;
  const auto points = track::raiseBridges(flat, 3.0, &raised);
  ASSERT_EQ(raised.size(), 1u);
  EXPECT_NEAR(raised[0].x, 0.0, 1.0);
  EXPECT_NEAR(raised[0].y, 0.0, 1.0);
  EXPECT_DOUBLE_EQ(raised[0].rise, track::kBridgeRise);
  const auto [z1, z2] = heightsAtTheCrossing(points);
  EXPECT_GE(std::abs(z1 - z2), track::kBridgeClearance);
  std::size_t untouched = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    const auto& q = points[(i + 1) % points.size()];
    const double grade = std::abs(q.z - p.z) / std::hypot(q.x - p.x, q.y - p.y);
    EXPECT_LE(grade, 1.01 * track::kBridgeMaxGrade) << "at point " << i;
    untouched += p.z == 0.0;
  }
  EXPECT_GT(untouched, points.size() / 2) << "the other branch and both lobes stay on the ground";
  // Raised once: a crossing that has its clearance is left alone.
  std::vector<track::RaisedBridge> again;
  const auto twice = track::raiseBridges(points, 3.0, &again);
  EXPECT_TRUE(again.empty());
  EXPECT_EQ(twice[points.size() / 3].z, points[points.size() / 3].z);
}

TEST(Bridges, ACrossingWithoutClearanceIsRefusedAndOneWithItLoads) {
  TempFolder dir;
  track::TrackInfo info;
  info.name = "eight";
  const auto flat = figureEight(380.0);
  const std::string msg = errorOf([&] { track::writeMapFolder(dir.path.string(), flat, info); });
  EXPECT_NE(msg.find("crosses"), std::string::npos) << msg;
  EXPECT_NE(msg.find("must pass 5.0 m over the other"), std::string::npos) << msg;
  EXPECT_NE(msg.find("0.00 m apart in height"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir.path / "centerline.csv")) << "nothing written";

  // Raised too little: still refused, saying by how much it is.
  auto low = flat;
  for (auto& p : low) p.z = 0.0;
  const auto raised = track::raiseBridges(flat, 3.0);
  for (std::size_t i = 0; i < low.size(); ++i) low[i].z = 0.5 * raised[i].z;
  const std::string low_msg = errorOf([&] { track::writeMapFolder(dir.path.string(), low, info); });
  EXPECT_NE(low_msg.find("3.00 m apart in height"), std::string::npos) << low_msg;

  ASSERT_EQ(errorOf([&] { track::writeMapFolder(dir.path.string(), raised, info); }), "");
  const auto track = track::loadMapFolder(dir.path.string());
  EXPECT_NEAR(track.length(), 1991.0, 5.0);
}

TEST(Bridges, TooLittleCourseBetweenTheBranchesForTheRampsIsRefusedSayingHowMuchIsNeeded) {
  const std::string msg = errorOf([] { track::raiseBridges(figureEight(60.0), 3.0); });
  EXPECT_NE(msg.find("the centre line crosses itself at (0.0, 0.0) with only"), std::string::npos) << msg;
  EXPECT_NE(msg.find("needs"), std::string::npos) << msg;
}

TEST(Bridges, TheBarriersOnTheDeckLeaveTheRoadBelowClear) {
  track::TrackInfo info;
  info.barrier_offset = 3.0;
  const track::Track track(track::raiseBridges(figureEight(380.0), info.barrier_offset), info);
  const auto deck = track::bridgeDeckPoints(track);
  const auto on_deck = std::count(deck.begin(), deck.end(), true);
  EXPECT_GT(on_deck, 5);
  EXPECT_LT(on_deck, 40) << "the deck spans the crossing, not the ramps";
  const auto mesh = track::barrierMesh(track);
  // Over the road of the branch below (within its half-width of its centre line), nothing of a barrier
  // lower than the clearance less the deck: a car and its roof sensors pass under.
  int over_the_road = 0;
  for (const auto& v : mesh.vertices) {
    for (std::size_t i = 0; i < track.size(); ++i) {
      const auto& p = track.point(i);
      if (p.z > 0.5 || std::hypot(v.x() - p.x, v.y() - p.y) > p.width_left) continue;
      ++over_the_road;
      EXPECT_GE(v.z() - p.z, track::kBridgeClearance - track::kDeckDepth) << "barrier vertex at " << v.transpose();
      break;
    }
  }
  EXPECT_GT(over_the_road, 0) << "the bridge's parapets do pass over the road below";
}

TEST(Bridges, AtTheCrossingAPointIsOnTheBranchAtItsHeight) {
  track::TrackInfo info;
  const track::Track track(track::raiseBridges(figureEight(380.0), info.barrier_offset), info);
  const auto [below, above] = heightsAtTheCrossing(track.points());
  ASSERT_GE(above - below, track::kBridgeClearance);
  const auto low = track.projectAtHeight(Eigen::Vector3d(0.0, 0.0, below + 0.3));
  const auto high = track.projectAtHeight(Eigen::Vector3d(0.0, 0.0, above + 0.3));
  EXPECT_NEAR(track.surfaceHeightAt(low.s, 0.0), below, 0.1);
  EXPECT_NEAR(track.surfaceHeightAt(high.s, 0.0), above, 0.1);
  EXPECT_GT(std::abs(track::wrapAngle(low.heading - high.heading)), 1.0) << "two roads at right angles";
}

// A car whose driver is lost under the bridge is stopped along its own road, not steered onto the one above.
TEST(Bridges, ACarStoppedUnderTheBridgeKeepsToItsOwnRoad) {
  track::TrackInfo info;
  const track::Track track(track::raiseBridges(figureEight(380.0), info.barrier_offset), info);
  for (const double height : {0.0, track::kBridgeRise}) {
    SCOPED_TRACE(height);
    const auto road = track.projectAtHeight(Eigen::Vector3d(0.0, 0.0, height + 0.3));
    vehicle::VehicleState state;
    state.pose.position = Eigen::Vector3d(0.0, 0.0, height + 0.3);
    state.pose.orientation = Eigen::AngleAxisd(road.heading, Eigen::Vector3d::UnitZ());
    state.forward_speed = state.speed = 20.0;
    const auto control = sim::safeStopControl(track, state, test::sedan(), {});
    EXPECT_LT(std::abs(control.steer), 0.1) << "straight on along the diagonal it is on";
    EXPECT_GT(control.brake, 0.0);
  }
}

// In the simulator: a car asked for at the crossing is put on the road at the height asked for (the grid
// and race control's respawns give the road's own); driven along either road, it passes under the deck or
// over it without touching a barrier.
TEST(Bridges, ACarDrivesUnderTheBridgeAndOverIt) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_eight");
  const auto deck = track::bridgeDeckPoints(track);
  ASSERT_GT(std::count(deck.begin(), deck.end(), true), 0);
  for (const double height : {0.0, track::kBridgeRise}) {
    SCOPED_TRACE(height);
    const auto road = track.projectAtHeight(Eigen::Vector3d(0.0, 0.0, height));
    ASSERT_NEAR(track.surfaceHeightAt(road.s, 0.0), height, 0.1);
    // 60 m before the crossing on that road, at the height the track gives there.
    const auto start = track.poseAt(road.s - 60.0);
    sim::World world(track, {});
    world.spawnVehicle("ego", test::sedan(), track::poseOnTrack(start));
    EXPECT_NEAR(world.vehicleState("ego").pose.position.z(), start.height, 0.5);
    vehicle::VehicleControl go;
    go.throttle = 0.5;
    int barrier = 0;
    double lowest = 1e9, highest = -1e9;
    for (int i = 0; i < 200; ++i) {  // 10 s: through the crossing and on
      world.setControl("ego", go);
      world.step();
      for (const auto& c : world.contacts("ego")) barrier += c.other == "barrier";
      const auto p = world.vehicleState("ego").pose.position;
      if (p.head<2>().norm() < 5.0) lowest = std::min(lowest, p.z()), highest = std::max(highest, p.z());
    }
    EXPECT_EQ(barrier, 0);
    ASSERT_LT(lowest, 1e9) << "the car went through the crossing";
    EXPECT_NEAR(lowest, height, 0.5) << "on its own road there";
    EXPECT_NEAR(highest, height, 0.5);
  }
}

TEST(Bridges, ASpawnAtTheCrossingGoesOnTheRoadAtTheHeightAskedFor) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_eight");
  for (const double height : {0.0, track::kBridgeRise}) {
    sim::World world(track, {});
    track::Pose pose;
    pose.position = Eigen::Vector3d(0.0, 0.0, height);
    world.spawnVehicle("ego", test::sedan(), pose);
    EXPECT_NEAR(world.vehicleState("ego").pose.position.z(), height, 0.5);
  }
}

// The first sight of a car decides which road it is followed on from then on (each later projection
// searches only near the last): a car first seen at the crossing is put on the road at its height by the
// lap timer (race control), the planner and the RL environment's progress, not on whichever branch is
// nearer sideways.
TEST(Bridges, ACarFirstSeenAtTheCrossingIsFollowedOnTheRoadAtItsHeight) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_eight");
  const planning::VehicleLimits limits = planning::vehicleLimits(test::sedan(), track.info().friction, 0.85);
  const planning::Trajectory line = planning::planRacingTrajectory(track, limits, {});
  for (const double height : {0.0, track::kBridgeRise}) {
    SCOPED_TRACE(height);
    const Eigen::Vector3d base_link(0.0, 0.0, height + 0.3);

    race::LapTimer timer(track);
    timer.update(0.0, base_link);
    const double timed_s = track.wrap(track.info().start_finish_s + timer.progress());
    EXPECT_NEAR(track.surfaceHeightAt(timed_s, 0.0), height, 0.1) << "lap timer";

    planning::FieldPlanner field(track, line, limits, {});
    field.locate("ego", base_link, 0.0, 0.0);
    EXPECT_NEAR(planning::sampleAt(line, field.onLine("ego").s).z, height, 0.1) << "planner";

    rl::TrackProgress progress(track);
    progress.reset(base_link);
    EXPECT_NEAR(track.surfaceHeightAt(progress.projection().s, 0.0), height, 0.1) << "RL progress";
  }
}

// CARLA's Model 3 corners at 3 g: planned for it, the racing line over Roar Eight's bridge keeps at least
// kMinCrestLoad of its weight on the tyres over the crest, where it used to fly and land in the barrier.
TEST(Bridges, TheLineOverTheBridgeKeepsAFastCarOnTheRoad) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_eight");
  const auto limits = planning::vehicleLimits(test::vehicle("carla_model3"), track.info().friction, 0.85);
  const planning::Trajectory line = planning::planRacingTrajectory(track, limits, {});
  constexpr double kSpan = 15.0;  // m: the crest's curvature over the span the planner reads it
  double crest_speed = 0.0;
  for (const auto& p : line.points) {
    const double before = planning::sampleAt(line, p.s - kSpan).z, after = planning::sampleAt(line, p.s + kSpan).z;
    const double vertical = (after - 2.0 * p.z + before) / (kSpan * kSpan);
    if (vertical >= -1e-5) continue;
    crest_speed = std::max(crest_speed, p.speed);
    EXPECT_GE(limits.gravity + p.speed * p.speed * vertical,
              planning::VehicleLimits::kMinCrestLoad * limits.gravity - 0.05)
        << "at s = " << p.s << " m, " << p.speed << " m/s";
  }
  EXPECT_GT(crest_speed, 40.0) << "the crest was found and driven fast";
}
