#include "roar/control/trajectory_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "roar/control/tracker_option_table.h"
#include "roar/control/tracker_sizing.h"
#include "roar/harness/time_trial.h"
#include "roar/sim/world.h"
#include "roar/track/map_folder.h"
#include "test_support.h"

using namespace roar;

namespace {

// A constant-speed trajectory through points produced by `at(s)` (position, heading, curvature).
template <typename At>
planning::Trajectory constantSpeed(double length, double speed, bool closed, At at) {
  planning::Trajectory t;
  t.closed = closed;
  t.length = length;
  for (double s = 0; s < length - 1e-9; s += 1.0) {
    planning::TrajectoryPoint p;
    at(s, &p);
    p.s = s;
    p.speed = speed;
    t.points.push_back(p);
  }
  return t;
}

struct Tracking {
  double max_error_after_settling = 0.0;
  double final_speed = 0.0;
};

// Drives the sedan on open ground from `start` for `seconds`, measuring the error after `settle` seconds.
Tracking drive(const planning::Trajectory& trajectory, const track::Pose& start, double seconds, double settle) {
  const auto car = test::sedan();
  control::TrajectoryTracker tracker(control::trackerFor(car), planning::vehicleLimits(car, 1.0, 1.0));
  tracker.setTrajectory(trajectory);
  sim::World world(test::openGround(), {});
  world.spawnVehicle("ego", car, start);
  Tracking result;
  while (world.time() < seconds) {
    const auto s = world.vehicleState("ego");
    world.setControl("ego", tracker.update(control::trackerInputOf(s)));
    world.step();
    if (world.time() > settle) {
      result.max_error_after_settling = std::max(result.max_error_after_settling, std::abs(tracker.lateralError()));
    }
    result.final_speed = s.forward_speed;
  }
  return result;
}

}  // namespace

TEST(TrajectoryTracker, HoldsAStraightLineFromAnOffsetStart) {
  const auto line = constantSpeed(2000.0, 25.0, false, [](double s, planning::TrajectoryPoint* p) {
    p->position = {s - 100.0, 0.0};
  });
  track::Pose start;
  start.position = Eigen::Vector3d(-95.0, 1.5, 0.0);  // 1.5 m left of the line
  const auto r = drive(line, start, 30.0, 12.0);
  EXPECT_LT(r.max_error_after_settling, 0.1);
  EXPECT_NEAR(r.final_speed, 25.0, 0.5);
}

TEST(TrajectoryTracker, HoldsAConstantRadiusCircle) {
  const double radius = 60.0, speed = 16.0;  // 4.3 m/s^2, about half the grip
  const auto circle = constantSpeed(2 * M_PI * radius, speed, true, [&](double s, planning::TrajectoryPoint* p) {
    const double a = s / radius;
    p->position = {radius * std::sin(a), radius * (1 - std::cos(a))};
    p->yaw = a;
    p->curvature = 1.0 / radius;
  });
  const auto r = drive(circle, {}, 40.0, 15.0);
  EXPECT_LT(r.max_error_after_settling, 0.25);
  EXPECT_NEAR(r.final_speed, speed, 0.5);
}

TEST(TrajectoryTracker, BrakesWithoutATrajectoryAndKeepsTheOldOneOnBadInput) {
  const auto car = test::sedan();
  control::TrajectoryTracker tracker(control::trackerFor(car), planning::vehicleLimits(car, 1.0, 1.0));
  const auto none = tracker.update({{0, 0}, 0, 10.0, 0});
  EXPECT_EQ(none.brake, 1.0);
  EXPECT_EQ(none.throttle, 0.0);

  auto line = constantSpeed(200.0, 20.0, false, [](double s, planning::TrajectoryPoint* p) { p->position = {s, 0.0}; });
  tracker.setTrajectory(line);
  auto bad = line;
  bad.points[7].curvature = NAN;
  EXPECT_THROW(tracker.setTrajectory(bad), planning::TrajectoryError);
  bad.points.clear();
  EXPECT_THROW(tracker.setTrajectory(bad), planning::TrajectoryError);
  ASSERT_TRUE(tracker.hasTrajectory());
  EXPECT_EQ(tracker.trajectory().points.size(), line.points.size());
  const auto c = tracker.update({{10, 0}, 0, 10.0, 0});
  EXPECT_GT(c.throttle, 0.5) << "10 m/s below the line's 20 m/s";
  EXPECT_TRUE(std::isfinite(c.steer));
}

// A trajectory somewhere else (a window of the map before a switch) is not steered at: the car brakes.
TEST(TrajectoryTracker, BrakesRatherThanSteerAtATrajectoryFarFromTheCar) {
  const auto car = test::sedan();
  control::TrajectoryTracker tracker(control::trackerFor(car), planning::vehicleLimits(car, 1.0, 1.0));
  tracker.setTrajectory(constantSpeed(200.0, 20.0, false, [](double s, planning::TrajectoryPoint* p) {
    p->position = {s, 0.0};
  }));
  const auto near = tracker.update({{10, 5}, 0, 10.0, 0});
  EXPECT_FALSE(tracker.tooFar());
  EXPECT_GT(near.throttle, 0.5) << "5 m beside the line: driven back to it";
  const auto far = tracker.update({{10, 40}, 0, 10.0, 0});
  EXPECT_TRUE(tracker.tooFar());
  EXPECT_NEAR(tracker.distance(), 40.0, 1e-6);
  EXPECT_EQ(far.brake, 1.0);
  EXPECT_EQ(far.throttle, 0.0);
  EXPECT_EQ(far.steer, 0.0);
  auto options = tracker.options();
  options.max_distance = 0.0;
  tracker.setOptions(options);
  EXPECT_GT(tracker.update({{10, 40}, 0, 10.0, 0}).throttle, 0.5) << "max_distance 0: no limit";
}

// The profile is a speed along the path: a car sliding at 30 degrees with its speed on the profile is not
// slow, though only 87 % of its speed is forward (taken for slow, it was floored mid-slide).
TEST(TrajectoryTracker, ASlidingCarIsNotTakenForASlowOne) {
  const auto car = test::sedan();
  control::TrajectoryTracker tracker(control::trackerFor(car), planning::vehicleLimits(car, 1.0, 1.0));
  tracker.setTrajectory(constantSpeed(400.0, 20.0, false, [](double s, planning::TrajectoryPoint* p) {
    p->position = {s, 0.0};
  }));
  const double forward = 20.0 * std::cos(M_PI / 6), sideways = 20.0 * std::sin(M_PI / 6);
  const auto on_profile = tracker.update({{50, 0}, 0, 20.0, 0});
  const auto sliding = tracker.update({{50, 0}, 0, forward, 0, sideways});
  const auto slow = tracker.update({{50, 0}, 0, forward, 0});
  EXPECT_NEAR(sliding.throttle, on_profile.throttle, 1e-9) << "sliding at the profile's speed";
  EXPECT_NEAR(sliding.brake, on_profile.brake, 1e-9);
  EXPECT_GT(slow.throttle, on_profile.throttle + 0.5) << "the same forward speed without the slide is slow";
}

// A recorded lap's own pedal is fed forward where the car is (its speeds already hold the car's response), with
// the speed error trimming it; a planned trajectory's profile is read ahead instead.
TEST(TrajectoryTracker, RecordedPedalsAreFedForward) {
  // A lap of a 100 m circle, 2 m a sample: full throttle for its first half, full brake for its second.
  const double radius = 100.0;
  std::vector<Eigen::Vector2d> positions;
  std::vector<double> speeds, pedals;
  for (int i = 0; i < 314; ++i) {
    const double a = 2.0 * i / radius;
    positions.emplace_back(radius * std::sin(a), radius * (1 - std::cos(a)));
    speeds.push_back(20.0);
    pedals.push_back(i < 157 ? 1.0 : -1.0);
  }
  auto at = [&](double s) {
    return Eigen::Vector2d(radius * std::sin(s / radius), radius * (1 - std::cos(s / radius)));
  };
  const auto car = test::sedan();
  const control::TrackerOptions options = control::trackerFor(car);
  // A tracker of its own for each place: the car jumps between them.
  auto control = [&](double s, double speed) {
    control::TrajectoryTracker tracker(options, planning::vehicleLimits(car, 1.0, 1.0));
    tracker.setTrajectory(planning::recordedTrajectory(positions, speeds, pedals));
    return tracker.update({at(s), s / radius, speed, 0.0});
  };
  const auto throttle = control(60.0, 20.0);
  EXPECT_DOUBLE_EQ(throttle.throttle, 1.0) << "the pedal that drove the lap at 60 m, though its speed is held";
  EXPECT_DOUBLE_EQ(throttle.brake, 0.0);
  const auto before = control(312.0, 20.0);
  EXPECT_DOUBLE_EQ(before.throttle, 1.0) << "2 m before the braking point at 314 m: not read ahead";
  const auto brake = control(400.0, 20.0);
  EXPECT_DOUBLE_EQ(brake.brake, 1.0);
  EXPECT_NEAR(control(60.0, 25.0).throttle, 1.0 - 5.0 * options.recorded_speed_gain, 1e-9) << "5 m/s too fast";

  pedals[3] = 1.5;
  EXPECT_THROW(planning::recordedTrajectory(positions, speeds, pedals), planning::TrajectoryError);
  pedals.pop_back();
  EXPECT_THROW(planning::recordedTrajectory(positions, speeds, pedals), planning::TrajectoryError);
}

// Every shipped circuit, with either lateral controller: the whole stack (planner's line and profile,
// tracker) drives clean flying laps within 3% of what the profile promises, on the road all the way.
TEST(TimeTrial, EveryShippedCircuitIsRacedCleanCloseToThePromisedLap) {
  const auto maps = track::listMaps(test::sourceDir() + "/maps");
  ASSERT_GE(maps.size(), 3u);
  for (const auto lateral : {control::LateralMethod::kPurePursuit, control::LateralMethod::kStanley}) {
    const bool stanley = lateral == control::LateralMethod::kStanley;
    for (const auto& name : maps) {
      SCOPED_TRACE(name + (stanley ? " with Stanley" : " with pure pursuit"));
      const auto track = track::loadMapFolder(test::sourceDir() + "/maps/" + name);
      harness::TimeTrialOptions options;
      options.laps = 1;
      options.tracker.lateral = lateral;
      const auto r = harness::runTimeTrial(track, test::sedan(), options);
      ASSERT_TRUE(r.finished);
      ASSERT_EQ(r.lap_times.size(), 1u);
      EXPECT_EQ(r.barrier_contacts, 0);
      EXPECT_LT(r.worst_offroad, 0.0) << "base_link stays on the road";
      EXPECT_LT(r.lap_times[0], 1.03 * r.promised_lap);
      EXPECT_GT(r.lap_times[0], 0.99 * r.promised_lap) << "faster than the plan would mean a short cut";
      // Stanley steers on the front axle's error alone and tracks looser (roar_bench --stanley).
      EXPECT_LT(r.max_lateral_error, stanley ? 3.5 : 2.5);
      if (!stanley) {
        RecordProperty(name + "_lap_s", std::to_string(r.lap_times[0]));
        RecordProperty(name + "_promised_s", std::to_string(r.promised_lap));
      }
    }
  }
}

// Every blueprint round every shipped circuit: the stack plans with the car's own limits (hatchback's
// economy tyres, the race car's slicks and downforce) and drives a clean flying lap close to its promise.
TEST(TimeTrial, EveryBlueprintRacesEveryShippedCircuitClean) {
  const auto maps = track::listMaps(test::sourceDir() + "/maps");
  for (const std::string model : {"hatchback", "racecar"}) {
    const auto car = test::vehicle(model);
    for (const auto& name : maps) {
      SCOPED_TRACE(model + " on " + name);
      const auto track = track::loadMapFolder(test::sourceDir() + "/maps/" + name);
      harness::TimeTrialOptions options;
      options.laps = 1;
      const auto r = harness::runTimeTrial(track, car, options);
      ASSERT_TRUE(r.finished);
      EXPECT_EQ(r.barrier_contacts, 0);
      EXPECT_LT(r.worst_offroad, 0.0) << "base_link stays on the road";
      EXPECT_LT(r.lap_times[0], 1.04 * r.promised_lap);
      EXPECT_GT(r.lap_times[0], 0.99 * r.promised_lap);
      std::printf("%s on %s: lap %.2f s, promised %.2f s, max error %.2f m, worst off-road %.2f m\n", model.c_str(),
                  name.c_str(), r.lap_times[0], r.promised_lap, r.max_lateral_error, r.worst_offroad);
      RecordProperty(model + "_" + name + "_lap_s", std::to_string(r.lap_times[0]));
    }
  }
}

// A crossing circuit lapped three times by each of the three blueprints ROAR programs spawn: every lap clean
// and lap 3 within 1 % of lap 2 (nothing the stack carries from lap to lap changes how it drives; a car
// that slid and was floored for it spun on a later lap of Suzuka's Spoon).
TEST(TimeTrial, ACrossingCircuitsLapsRepeatCleanForEveryBlueprint) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_eight");
  for (const std::string model : {"sedan", "hatchback", "carla_model3"}) {
    SCOPED_TRACE(model);
    harness::TimeTrialOptions options;
    options.laps = 3;
    const auto r = harness::runTimeTrial(track, test::vehicle(model), options);
    ASSERT_TRUE(r.finished);
    ASSERT_EQ(r.lap_times.size(), 3u);
    EXPECT_EQ(r.barrier_contacts, 0);
    EXPECT_LT(r.worst_offroad, 0.0) << "base_link stays on the road";
    EXPECT_NEAR(r.lap_times[2], r.lap_times[1], 0.01 * r.lap_times[1]);
    std::printf("%s on roar_eight: laps %.2f, %.2f, %.2f s, promised %.2f s\n", model.c_str(), r.lap_times[0],
                r.lap_times[1], r.lap_times[2], r.promised_lap);
  }
}

TEST(TrackerOptionTable, SetsByNameAndRefusesWhatTheNodeRefuses) {
  control::TrackerOptions t;
  control::setTrackerOption(&t, "lookahead_time", "0.45", "controller");
  control::setTrackerOption(&t, "lateral_control", "stanley", "controller");
  EXPECT_EQ(t.lookahead_time, 0.45);
  EXPECT_EQ(t.lateral, control::LateralMethod::kStanley);
  auto message = [&](const std::string& name, const std::string& text) {
    try {
      control::setTrackerOption(&t, name, text, "controller");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("stanley_gain", "60"), "controller stanley_gain 60 is outside [0.01, 50]");
  EXPECT_NE(message("lookahed_time", "1").find("did you mean 'lookahead_time'?"), std::string::npos);
  EXPECT_EQ(message("lateral_control", "mpc"), "controller lateral_control 'mpc' is neither pure_pursuit nor stanley");
  EXPECT_NE(message("speed_gain", "fast").find("speed_gain"), std::string::npos);
  EXPECT_EQ(t.stanley_gain, control::TrackerOptions().stanley_gain);  // refused values leave the option as it was
}
