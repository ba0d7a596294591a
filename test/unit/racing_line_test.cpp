#include "roar/planning/racing_line.h"
#include "roar/planning/minimum_time.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numeric>

#include "roar/planning/trajectory.h"
#include "roar/track/map_folder.h"
#include "test_support.h"

using namespace roar;

namespace {

double sumSquaredCurvature(const planning::RacingLine& line) {
  double sum = 0.0;
  for (std::size_t i = 0; i < line.curvature.size(); ++i) sum += line.curvature[i] * line.curvature[i] * line.step[i];
  return sum;
}

}  // namespace

// Every shipped circuit: the line stays inside the track less half the car and the margin, converges, bends
// less than the centre line, and its speed profile promises a faster lap than the centre line's.
TEST(RacingLine, StaysInsideTheMarginsAndBendsLessThanTheCentreLine) {
  const auto limits = planning::vehicleLimits(test::sedan(), 1.0, 0.85);
  for (const auto& name : track::listMaps(test::sourceDir() + "/maps")) {
    SCOPED_TRACE(name);
    const auto track = track::loadMapFolder(test::sourceDir() + "/maps/" + name);
    planning::RacingLineOptions options;
    const auto started = std::chrono::steady_clock::now();
    const auto line = planning::minimumCurvatureLine(track, options);
    RecordProperty(
        name + "_plan_ms",
        std::to_string(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count()));
    const double keep = 0.5 * options.vehicle_width + options.safety_margin;
    for (std::size_t i = 0; i < line.points.size(); ++i) {
      const auto pr = track.project(line.points[i]);
      ASSERT_LE(pr.lateral, pr.width_left - keep + 0.02) << "point " << i;
      ASSERT_GE(pr.lateral, -(pr.width_right - keep) - 0.02) << "point " << i;
    }
    EXPECT_LT(line.last_curvature_change, options.curvature_tolerance) << "converged in " << line.iterations;
    EXPECT_GT(line.iterations, 1);
    const auto centre = planning::centreLine(track, options.step);
    EXPECT_LT(sumSquaredCurvature(line), 0.8 * sumSquaredCurvature(centre));
    const auto promised = planning::computeSpeedProfile(line.step, line.curvature, limits, line.closed).total_time;
    const auto on_centre =
        planning::computeSpeedProfile(centre.step, centre.curvature, limits, centre.closed).total_time;
    EXPECT_LT(promised, 0.97 * on_centre);
    // It uses the track: somewhere close to each edge.
    const auto [lo, hi] = std::minmax_element(line.offset.begin(), line.offset.end());
    EXPECT_LT(*lo, 0.0);
    EXPECT_GT(*hi, 0.0);
  }
}

TEST(RacingLine, ACircleIsDrivenOnItsInsideEdge) {
  // On a ring, the tighter inside circle is the shorter way round: the least curvature per metre of
  // line travelled... and the line must hug the inside margin all the way.
  const auto track = test::circleTrack(100.0, 20.0);
  planning::RacingLineOptions options;
  const auto line = planning::minimumCurvatureLine(track, options);
  const double keep = 0.5 * options.vehicle_width + options.safety_margin;
  for (double offset : line.offset) EXPECT_NEAR(offset, 10.0 - keep, 0.05);
}

TEST(RacingLine, ATrackNarrowerThanTheCarIsAClearError) {
  const auto track = test::circleTrack(100.0, 2.0);
  const std::string error = test::errorOf([&] { planning::minimumCurvatureLine(track, {}); });
  EXPECT_NE(error.find("narrower than the car"), std::string::npos) << error;
}

TEST(Trajectory, WindowRunsOnPastTheEndOfTheLap) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_sprint");
  const auto limits = planning::vehicleLimits(test::sedan(), 1.0, 0.85);
  const auto lap = planning::planRacingTrajectory(track, limits, {});
  ASSERT_NO_THROW(planning::validate(lap));
  const auto window = planning::windowAround(lap, lap.length - 50.0, 10.0, 200.0);
  EXPECT_FALSE(window.closed);
  ASSERT_NO_THROW(planning::validate(window));
  EXPECT_NEAR(window.points.front().s, lap.length - 60.0, 1e-9);
  EXPECT_GT(window.points.back().s, lap.length + 140.0) << "s keeps increasing over the line";
  // The same place on the circuit has the same speed in the window and in the lap.
  const auto in_window = planning::sampleAt(window, lap.length + 20.0);
  const auto in_lap = planning::sampleAt(lap, 20.0);
  EXPECT_NEAR((in_window.position - in_lap.position).norm(), 0.0, 0.05);
  EXPECT_NEAR(in_window.speed, in_lap.speed, 0.05);
}

TEST(Trajectory, NonFiniteOrShortTrajectoriesAreRefusedByName) {
  planning::Trajectory t;
  t.closed = false;
  EXPECT_NE(test::errorOf([&] { planning::validate(t); }).find("at least 2 points"), std::string::npos);
  t.points.resize(3);
  for (int i = 0; i < 3; ++i) t.points[i].s = i;
  EXPECT_NO_THROW(planning::validate(t));
  t.points[1].speed = NAN;
  EXPECT_NE(test::errorOf([&] { planning::validate(t); }).find("point 1 has a non-finite speed"), std::string::npos);
  t.points[1].speed = 1.0;
  t.points[2].s = 0.5;
  EXPECT_NE(test::errorOf([&] { planning::validate(t); }).find("does not increase at point 2"), std::string::npos);
}

TEST(MinimumTimeLine, IsFasterThanItsStartAndStaysInsideTheMargins) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_sprint");
  const auto limits = planning::vehicleLimits(test::sedan(), 1.0, 0.85);
  planning::RacingLineOptions margins;
  const auto start = planning::minimumCurvatureLine(track, margins);
  planning::MinimumTimeOptions options;
  options.max_iterations = 10;
  const auto result = planning::minimumTimeLine(track, start, limits, margins, options);
  const double promised = planning::computeSpeedProfile(start.step, start.curvature, limits, true).total_time;
  EXPECT_NEAR(result.start_lap_time, promised, 1e-9);
  EXPECT_LT(result.lap_time, result.start_lap_time);
  EXPECT_GT(result.lap_time, 0.97 * result.start_lap_time) << "the minimum-curvature line is close to minimum time";
  const double keep = 0.5 * margins.vehicle_width + margins.safety_margin;
  for (std::size_t i = 0; i < result.line.points.size(); ++i) {
    const auto pr = track.project(result.line.points[i]);
    ASSERT_LE(pr.lateral, pr.width_left - keep + 0.05) << "point " << i;
    ASSERT_GE(pr.lateral, -(pr.width_right - keep) - 0.05) << "point " << i;
  }
  // Its lap time is the profile of the line it returns.
  const double again = planning::computeSpeedProfile(result.line.step, result.line.curvature, limits, true).total_time;
  EXPECT_NEAR(again, result.lap_time, 1e-6);
}
