// Point-to-point courses (a sprint, a hill climb): the road runs from its first point to its last, a race is
// one run from the start line to the finish line, and the cars stop on the road past the finish.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "roar/planning/racing_line.h"
#include "roar/planning/speed_profile.h"
#include "roar/planning/trajectory.h"
#include "roar/planning/vehicle_limits.h"
#include "roar/race/lap_timer.h"
#include "roar/race/race_control.h"
#include "roar/rl/episode.h"
#include "roar/sensors/ray_scene.h"
#include "roar/track/bridges.h"
#include "roar/track/map_folder.h"
#include "test_support.h"

using namespace roar;
using test::errorOf;
using test::TempDir;
namespace fs = std::filesystem;

namespace {

// An L: 300 m east, a left quarter circle of 60 m radius, 300 m north; 10 m of road, a point every 2 m.
std::vector<track::CentreLinePoint> lShapedRoad(double climb = 0.0) {
  std::vector<track::CentreLinePoint> pts;
  auto add = [&](double x, double y) { pts.push_back({x, y, 5.0, 5.0}); };
  for (double x = 0; x < 300; x += 2) add(x, 0);
  const int arc = static_cast<int>(std::round(0.5 * M_PI * 60 / 2));
  for (int k = 0; k < arc; ++k) {
    const double a = -0.5 * M_PI + 0.5 * M_PI * k / arc;
    add(300 + 60 * std::cos(a), 60 + 60 * std::sin(a));
  }
  for (double y = 60; y <= 360; y += 2) add(360, y);
  double s = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (i) s += std::hypot(pts[i].x - pts[i - 1].x, pts[i].y - pts[i - 1].y);
    pts[i].z = climb * s;
  }
  return pts;
}

track::TrackInfo courseInfo(double start = 200.0, double finish = 600.0) {
  track::TrackInfo info;
  info.name = "L course";
  info.closed = false;
  info.start_finish_s = start;
  info.finish_s = finish;
  return info;
}

sensors::RayHit castOne(const sensors::RayScene& scene, const Eigen::Vector3d& origin,
                        const Eigen::Vector3f& direction) {
  sensors::RayHit hit;
  scene.cast(origin, &direction, 1, -1, 100.0f, false, &hit);
  return hit;
}

}  // namespace

TEST(Course, RunsFromItsFirstPointToItsLastWithoutALapRoundToItsStart) {
  const track::Track course(lShapedRoad(), courseInfo());
  EXPECT_FALSE(course.closed());
  EXPECT_EQ(course.segments(), course.size() - 1);
  EXPECT_NEAR(course.length(), 300 + 0.5 * M_PI * 60 + 300, 2.0) << "no way back from the last point to the first";
  EXPECT_DOUBLE_EQ(course.length(), course.s(course.size() - 1));
  EXPECT_DOUBLE_EQ(course.raceDistance(), 400.0);
  EXPECT_DOUBLE_EQ(course.finishLine(), 600.0);
  // Progress is clamped to the road, and nothing behind is reached by going forwards.
  EXPECT_DOUBLE_EQ(course.wrap(-5.0), 0.0);
  EXPECT_DOUBLE_EQ(course.wrap(course.length() + 5.0), course.length());
  EXPECT_DOUBLE_EQ(course.forwardDistance(100.0, 150.0), 50.0);
  EXPECT_EQ(course.forwardDistance(150.0, 100.0), std::numeric_limits<double>::infinity());
  // The ends look along the road: east at the start, north at the end, and straight.
  EXPECT_NEAR(course.heading(0), 0.0, 1e-9);
  EXPECT_NEAR(course.heading(course.size() - 1), 0.5 * M_PI, 1e-9);
  EXPECT_NEAR(course.curvature(0), 0.0, 1e-9);
  EXPECT_NEAR(course.curvature(course.size() - 1), 0.0, 1e-9);
  // The last points are not joined to the first: no centre-line points past the end.
  const auto ahead = course.indicesAhead(course.length() - 10.0, 100.0);
  ASSERT_FALSE(ahead.empty());
  EXPECT_EQ(ahead.back(), course.size() - 1);
  // Spawn points spread from the start line to the finish line.
  const auto spawns = course.evenSpawnPoints(4);
  EXPECT_NEAR(course.project(spawns[3].position).s, 200.0 + 300.0, 1.0);
}

TEST(Course, APointBeyondEitherEndIsOffTheRoad) {
  const track::Track course(lShapedRoad(), courseInfo());
  const auto before = course.project({-6.0, 1.0});
  EXPECT_NEAR(before.past_end, 6.0, 1e-9);
  EXPECT_FALSE(before.on_track());
  EXPECT_NEAR(before.beyondEdge(), 6.0, 1e-9);
  const auto after = course.project({361.0, 380.0});
  EXPECT_NEAR(after.past_end, 380.0 - course.position(course.size() - 1).y(), 1e-6);
  EXPECT_FALSE(after.on_track());
  EXPECT_TRUE(course.project({100.0, 2.0}).on_track());
  EXPECT_NE(track::offTrackProblem(course, {361.0, 380.0}, "spawn"), "") << "past the barrier across the end";
  // A closed circuit's projection never lies past an end.
  EXPECT_EQ(test::circleTrack(50.0).project({80.0, 0.0}).past_end, 0.0);
}

TEST(Course, StartAndFinishLinesMustLeaveTheGridAndARunOnTheRoad) {
  EXPECT_NE(errorOf([] { track::Track(lShapedRoad(), courseInfo(50.0, 600.0)); }).find("start_finish.s = 50"),
            std::string::npos)
      << "the grid needs road behind the start line";
  EXPECT_NE(errorOf([] { track::Track(lShapedRoad(), courseInfo(200.0, 900.0)); }).find("finish.s = 900"),
            std::string::npos)
      << "the finish line lies beyond the road's end";
  EXPECT_NE(errorOf([] { track::Track(lShapedRoad(), courseInfo(200.0, 250.0)); }).find("finish.s = 250"),
            std::string::npos);
  // The grid behind the start line: every slot on the road, pole 10 m behind the line.
  const track::Track course(lShapedRoad(), courseInfo());
  const auto grid = course.gridSpawnPoints(track::kGridSlots);
  EXPECT_NEAR(course.project(grid[0].position).s, 200.0 - track::kGridFirstGap, 0.1);
  for (const auto& slot : grid) EXPECT_TRUE(course.project(slot.position).on_track());
}

TEST(Course, TrackYamlSaysPointToPointAndNamesItsFinishLine) {
  TempDir dir;
  writeCentreLineCsv(dir.str() + "/centerline.csv", lShapedRoad());
  dir.write("track.yaml", "name: L\ncourse: point_to_point\nstart_finish: {s: 200}\nfinish: {s: 600}\n");
  const auto course = track::loadMapFolder(dir.str());
  EXPECT_FALSE(course.closed());
  EXPECT_DOUBLE_EQ(course.finishLine(), 600.0);
  // Written back, it reads the same.
  track::writeTrackYaml(dir.str() + "/again.yaml", course.info());
  const auto again = track::readTrackYaml(dir.str() + "/again.yaml");
  EXPECT_FALSE(again.closed);
  EXPECT_DOUBLE_EQ(again.finish_s, 600.0);

  dir.write("track.yaml", "name: L\ncourse: point_to_point\nstart_finish: {s: 200}\n");
  EXPECT_NE(errorOf([&] { track::loadMapFolder(dir.str()); }).find("finish: a point-to-point course needs its finish"),
            std::string::npos);
  dir.write("track.yaml", "name: L\ncourse: hill\nstart_finish: {s: 200}\nfinish: {s: 600}\n");
  EXPECT_NE(errorOf([&] { track::loadMapFolder(dir.str()); }).find("'hill' is neither"), std::string::npos);
  dir.write("track.yaml", "name: L\nstart_finish: {s: 200}\nfinish: {s: 600}\n");
  EXPECT_NE(errorOf([&] { track::loadMapFolder(dir.str()); }).find("a circuit finishes on its start_finish line"),
            std::string::npos);
  // Without `course:` the open line is a circuit that does not close, and the message says what to write.
  dir.write("track.yaml", "name: L\nstart_finish: {s: 200}\n");
  const std::string not_closed = errorOf([&] { track::loadMapFolder(dir.str()); });
  EXPECT_NE(not_closed.find("does not close"), std::string::npos) << not_closed;
  EXPECT_NE(not_closed.find("course: point_to_point"), std::string::npos) << not_closed;
  // A start line without the grid's road behind it is refused naming the file.
  dir.write("track.yaml", "name: L\ncourse: point_to_point\nstart_finish: {s: 20}\nfinish: {s: 600}\n");
  const std::string short_grid = errorOf([&] { track::loadMapFolder(dir.str()); });
  EXPECT_NE(short_grid.find("track.yaml"), std::string::npos) << short_grid;
  EXPECT_NE(short_grid.find("start_finish.s = 20"), std::string::npos) << short_grid;
}

TEST(Course, TheRunIsTimedFromTheStartLineToTheFinishLineOnce) {
  const track::Track course(lShapedRoad(), courseInfo());
  race::LapTimer timer(course);
  const double speed = 20.0, dt = 0.05;
  int runs = 0;
  race::LapRecord run;
  // From pole, 10 m behind the start line, to 80 m past the finish along the centre line.
  for (double t = 0; t <= 480.0 / speed; t += dt) {
    const auto pose = course.poseAt(190.0 + speed * t);
    if (auto lap = timer.update(t, {pose.position.x(), pose.position.y(), 0.0})) {
      ++runs;
      run = *lap;
    }
    if (t > 0.6) {
      EXPECT_TRUE(timer.started()) << "started at the start line, 10 m from pole";
    }
  }
  EXPECT_EQ(runs, 1);
  EXPECT_NEAR(run.lap_time, 400.0 / speed, 0.05);
  EXPECT_NEAR(run.finish_time, 410.0 / speed, 0.05);
  ASSERT_EQ(run.sector_times.size(), 3u);
  for (double s : run.sector_times) EXPECT_NEAR(s, 400.0 / 3 / speed, 0.05);
  EXPECT_NEAR(timer.distanceCovered(), 470.0, 1.0) << "metres from the start line";
}

TEST(Course, RaceControlFinishesEveryCarAtTheFinishLineAfterOneRun) {
  const track::Track course(lShapedRoad(), courseInfo());
  race::RaceRules rules;
  rules.laps = 3;  // a course is raced once, whatever a scenario asks
  race::RaceControl control(course, rules, {"a", "b"});
  EXPECT_EQ(control.rules().laps, 1);
  for (double t = 0; t < 30.0; t += 0.05) {
    for (const auto& [name, speed] : {std::pair<std::string, double>{"a", 25.0}, {"b", 20.0}}) {
      const auto pose = course.poseAt(190.0 + speed * t - (name == "b" ? 8.0 : 0.0));
      control.updatePosition(name, t, {pose.position.x(), pose.position.y(), 0.0});
    }
  }
  EXPECT_TRUE(control.finished());
  EXPECT_TRUE(control.car("a").finished);
  EXPECT_NEAR(control.car("a").finish_time, 410.0 / 25.0, 0.05);
  EXPECT_NEAR(control.car("b").finish_time, 418.0 / 20.0, 0.05);
  EXPECT_EQ(control.standings().front().name, "a");
}

TEST(Course, TheRacingLineRunsEndToEndAndTheCarStopsBeforeTheRoadEnds) {
  const track::Track course(lShapedRoad(), courseInfo());
  const auto line = planning::minimumCurvatureLine(course, {});
  EXPECT_FALSE(line.closed);
  EXPECT_LT((line.points.front() - course.position(0)).norm(), 5.0);
  EXPECT_LT((line.points.back() - course.position(course.size() - 1)).norm(), 5.0);
  EXPECT_NEAR(line.length, line.s.back(), 1e-9) << "no step back to the start";
  EXPECT_LT(line.last_curvature_change, planning::RacingLineOptions().curvature_tolerance);
  // It cuts the corner: inside (left) at the apex.
  const auto apex =
      std::min_element(line.offset.begin(), line.offset.end(), [](double a, double b) { return -a < -b; });
  EXPECT_GT(*apex, 2.0);

  const auto limits = planning::vehicleLimits(test::sedan(), 1.0, 0.85);
  const auto trajectory = planning::planRacingTrajectory(course, limits, {});
  EXPECT_FALSE(trajectory.closed);
  EXPECT_EQ(trajectory.points.back().speed, 0.0);
  for (const auto& p : trajectory.points) {
    if (p.s > trajectory.length - planning::kCourseStopMargin) {
      EXPECT_EQ(p.speed, 0.0) << "at s = " << p.s;
    }
  }
  // The promise: the run from a standing start on pole, longer than the flying run's time over the line.
  const auto at = [&](double track_s) {
    std::size_t i = 0;
    while (i + 1 < line.track_s.size() && line.track_s[i + 1] <= track_s) ++i;
    return trajectory.points[i].time;
  };
  EXPECT_GT(trajectory.lap_time, at(600.0) - at(200.0));
  EXPECT_LT(trajectory.lap_time, at(600.0) - at(200.0) + 5.0);
  // Windows end where the trajectory ends.
  const auto window = planning::windowAround(trajectory, trajectory.length - 30.0, 10.0, 200.0);
  EXPECT_NEAR(window.points.back().s, trajectory.points.back().s, 1e-9);
  EXPECT_FALSE(window.closed);
  EXPECT_EQ(planning::lapLength(trajectory), 0.0);
  EXPECT_EQ(planning::aheadOnLap(900.0, 100.0, planning::lapLength(trajectory)), 800.0) << "no lap to wrap round";
}

TEST(Course, ClimbingTakesFromTheDriveAndDescendingFromTheBrakes) {
  const auto limits = planning::vehicleLimits(test::sedan(), 1.0, 0.85);
  const std::vector<double> step(200, 2.0), curvature(200, 0.0);
  planning::SpeedProfileOptions level, uphill, downhill;
  for (auto* o : {&level, &uphill, &downhill}) {
    o->start_speed = 0.0;
    o->end_speed = 0.0;
  }
  uphill.grade.assign(200, 0.08);
  downhill.grade.assign(200, -0.08);
  const auto flat = planning::computeSpeedProfile(step, curvature, limits, false, level);
  const auto up = planning::computeSpeedProfile(step, curvature, limits, false, uphill);
  const auto down = planning::computeSpeedProfile(step, curvature, limits, false, downhill);
  // Accelerating from rest: slower uphill, faster downhill, by about g sin(slope) over the first 20 m.
  const double g = limits.gravity * 0.08;
  EXPECT_NEAR(up.speed[10] * up.speed[10], flat.speed[10] * flat.speed[10] - 2 * g * 20.0, 8.0);
  EXPECT_GT(down.speed[10], flat.speed[10]);
  // Braking to the stop at the end: later uphill (gravity helps), earlier downhill.
  EXPECT_GT(up.speed[190], flat.speed[190]);
  EXPECT_LT(down.speed[190], flat.speed[190]);
  EXPECT_GT(up.total_time, flat.total_time);
  EXPECT_LT(down.total_time, flat.total_time);
  planning::SpeedProfileOptions bad = level;
  bad.grade.assign(10, 0.0);
  EXPECT_NE(errorOf([&] { planning::computeSpeedProfile(step, curvature, limits, false, bad); }).find("10 grades"),
            std::string::npos);
}

TEST(Course, WallsCloseBothEndsOfTheRoad) {
  const track::Track course(lShapedRoad(), courseInfo());
  sensors::RayScene scene(course);
  // Along the road from near its end: the barrier across it, barrier_offset past the last point.
  const auto end = course.poseAt(course.length() - 5.0);
  const auto ahead = castOne(scene, {end.position.x(), end.position.y(), 0.5}, {0, 1, 0});
  ASSERT_TRUE(ahead.hit);
  EXPECT_EQ(ahead.semantic, sensors::SemanticClass::kBarrier);
  EXPECT_NEAR(ahead.distance, 5.0 + course.info().barrier_offset, 0.1);
  // And back from near its start.
  const auto back = castOne(scene, {5.0, 0.0, 0.5}, {-1, 0, 0});
  ASSERT_TRUE(back.hit);
  EXPECT_EQ(back.semantic, sensors::SemanticClass::kBarrier);
  EXPECT_NEAR(back.distance, 5.0 + course.info().barrier_offset, 0.1);
  // Across the road, the side barriers still stand where they do on a circuit.
  const auto side = castOne(scene, {100.0, 0.0, 0.5}, {0, 1, 0});
  ASSERT_TRUE(side.hit);
  EXPECT_NEAR(side.distance, 5.0 + course.info().barrier_offset, 0.1);
}

// An RL episode on a course ends at its finish line, its progress counted without wrapping.
TEST(Course, AnEpisodeEndsAtTheFinishLine) {
  const track::Track course(lShapedRoad(), courseInfo());
  rl::Episode episode(course, {}, {});
  auto stateAt = [&](double s) {
    vehicle::VehicleState state;
    const auto pose = course.poseAt(s);
    state.pose.position = {pose.position.x(), pose.position.y(), 0.0};
    state.speed = 20.0;
    return state;
  };
  double t = 0.0;
  episode.begin(stateAt(150.0), t);
  rl::StepOutcome out;
  for (double s = 151.0; s <= 650.0 && !out.terminated; s += 1.0) out = episode.step(stateAt(s), {}, t += 0.05);
  EXPECT_TRUE(out.terminated);
  EXPECT_FALSE(out.info.off_track);
  EXPECT_EQ(out.info.laps, 1);
  EXPECT_NEAR(out.info.progress, 600.0 - 150.0, 1.5);
}

// Braking to follow a car counts the road's slope: downhill it starts sooner (a car planned braking as hard
// downhill as on the level ran into the one ahead on roar_eight's bridge ramp).
TEST(Course, FollowingBrakesSoonerDownhill) {
  const auto limits = planning::vehicleLimits(test::sedan(), 1.0, 0.85);
  auto straight = [](double grade) {
    planning::Trajectory t;
    t.closed = false;
    for (int i = 0; i <= 150; ++i) {
      planning::TrajectoryPoint p;
      p.s = 2.0 * i;
      p.position = {p.s, 0.0};
      p.z = grade * p.s;
      p.speed = 40.0;
      t.points.push_back(p);
    }
    t.length = t.points.back().s;
    return t;
  };
  planning::Trajectory level = straight(0.0), downhill = straight(-0.08);
  EXPECT_NEAR(planning::slopes(downhill)[10], -0.08 / std::hypot(1.0, 0.08), 1e-9);
  EXPECT_EQ(planning::slopes(level)[10], 0.0);
  for (auto* t : {&level, &downhill}) planning::followBehind(t, 0.0, 250.0, 0.0, 10.0, limits);
  EXPECT_LT(downhill.points[85].speed, level.points[85].speed - 1.0);
  EXPECT_EQ(downhill.points[125].speed, 0.0) << "stopped 10 m behind the stopped car";
  EXPECT_NEAR(planning::decelerationAt(limits, 20.0, 0.0, -0.08),
              planning::decelerationAt(limits, 20.0, 0.0) - limits.gravity * 0.08, 1e-9);
}

// A course that crosses itself (east, a 270 degree left loop, then south across its own start) goes over
// itself on a bridge as a circuit does; unbridged it is refused.
TEST(Course, ACourseThatCrossesItselfGoesOverItselfOnABridge) {
  std::vector<track::CentreLinePoint> pts;
  auto add = [&](double x, double y) { pts.push_back({x, y, 5.0, 5.0}); };
  for (double x = -300; x < 300; x += 2) add(x, 0);
  const int arc = static_cast<int>(std::round(1.5 * M_PI * 150 / 2));
  for (int k = 0; k < arc; ++k) {
    const double a = -0.5 * M_PI + 1.5 * M_PI * k / arc;
    add(300 + 150 * std::cos(a), 150 + 150 * std::sin(a));
  }
  for (double y = 148.7; y >= -600; y -= 2) add(150.5, y);  // the roads cross between points, not at one
  const track::TrackInfo info = courseInfo(200.0, 1700.0);
  std::vector<track::RaisedBridge> raised;
  const auto bridged = track::raiseBridges(pts, info.barrier_offset, &raised, false);
  ASSERT_EQ(raised.size(), 1u);
  EXPECT_NEAR(raised[0].x, 150.0, 1.0);
  EXPECT_NEAR(raised[0].y, 0.0, 1.0);
  EXPECT_GT(raised[0].s, 1000.0) << "the later branch goes over";
  TempDir dir;
  track::writeMapFolder(dir.str() + "/bridged", bridged, info);
  const auto course = track::loadMapFolder(dir.str() + "/bridged");
  EXPECT_FALSE(course.closed());
  const auto deck = track::bridgeDeckPoints(course);
  EXPECT_GT(std::count(deck.begin(), deck.end(), true), 5);
  const std::string flat = errorOf([&] { track::writeMapFolder(dir.str() + "/flat", pts, info); });
  EXPECT_NE(flat.find("crosses"), std::string::npos) << flat;
}
