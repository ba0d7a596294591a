#include "roar/sim/lap_bound.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "roar/harness/time_trial.h"
#include "roar/planning/racing_line.h"
#include "roar/track/map_folder.h"
#include "test_support.h"

using namespace roar;

namespace {

constexpr double kG = 9.81;

// A circle of `radius` as a line of `points`.
sim::LapBound roundCircle(const vehicle::VehicleParams& car, double radius, double friction = 1.0, int points = 200) {
  const std::vector<double> curvature(points, 1.0 / radius), step(points, 2 * M_PI * radius / points);
  return sim::quasiSteadyStateLap(curvature, step, true, car, friction);
}

vehicle::VehicleParams linearTyred(vehicle::VehicleParams car) {
  car.tyre.load_sensitivity = 0.0;
  car.aero.downforce_area = 0.0;
  return car;
}

}  // namespace

TEST(LapBound, ATyreWithoutLoadSensitivityCornersNearItsFrictionWhateverTheWeightMoves) {
  // Each axle carries its weight's share of the cornering force and has its weight's share of the grip; the
  // slip angles' drag takes a little of the rear's for drive, so the car corners just under its friction.
  auto car = linearTyred(test::sedan());
  const double radius = 100.0, friction = 0.9;
  const double at_friction = std::sqrt(friction * car.tyre.grip * kG * radius);
  const auto bound = roundCircle(car, radius, friction);
  EXPECT_LT(bound.corner_speed[0], at_friction);
  EXPECT_GT(bound.corner_speed[0], 0.97 * at_friction);
  EXPECT_NEAR(bound.lap_time, 2 * M_PI * radius / bound.corner_speed[0], 1e-3 * bound.lap_time);
  car.suspension.roll_influence = 1.0;
  car.chassis.centre_of_mass.z() += 0.4;
  EXPECT_NEAR(roundCircle(car, radius, friction).corner_speed[0], bound.corner_speed[0], 1e-3 * at_friction);
}

TEST(LapBound, ASoftTyreCornersSlowerForItsSlipAnglesDrag) {
  // CarSimEd's tyre at CARLA's default stiffness reaches its friction only at large slip angles, whose drag
  // the motor must meet: the same friction corners slower than on a stiff tyre.
  auto stiff = test::vehicle("vehicle.tesla.model3");
  stiff.tyre.lateral_stiffness = 200.0;
  auto soft = stiff;
  soft.tyre.lateral_stiffness = 17.0;
  EXPECT_LT(roundCircle(soft, 150.0).corner_speed[0], 0.97 * roundCircle(stiff, 150.0).corner_speed[0]);
}

TEST(LapBound, WeightMovedAcrossALoadSensitiveTyreCostsGrip) {
  const auto linear = linearTyred(test::sedan());
  auto sensitive = linear;
  sensitive.tyre.load_sensitivity = 0.08;
  const double v_linear = roundCircle(linear, 80.0).corner_speed[0];
  const double v_sensitive = roundCircle(sensitive, 80.0).corner_speed[0];
  EXPECT_LT(v_sensitive, v_linear);
  auto tall = sensitive;
  tall.chassis.centre_of_mass.z() += 0.3;
  tall.suspension.roll_influence = 1.0;
  EXPECT_LT(roundCircle(tall, 80.0).corner_speed[0], v_sensitive) << "a higher centre of mass moves more weight";
}

TEST(LapBound, DownforceRaisesTheCornerSpeedMoreInFastCorners) {
  auto flat = linearTyred(test::sedan());
  auto winged = flat;
  winged.aero.downforce_area = 1.0;
  const double slow = roundCircle(winged, 30.0).corner_speed[0] / roundCircle(flat, 30.0).corner_speed[0];
  const double fast = roundCircle(winged, 300.0).corner_speed[0] / roundCircle(flat, 300.0).corner_speed[0];
  EXPECT_GT(slow, 1.0);
  EXPECT_GT(fast, slow);
}

TEST(LapBound, AStraightFromAStandRisesToTheTopSpeedTheTelemetryShows) {
  // carla_model3's top speed: 257.6 km/h in CARLA's telemetry (physics_test pins the simulated car's).
  const auto car = test::vehicle("vehicle.tesla.model3");
  const int points = 2000;
  const std::vector<double> curvature(points, 0.0), step(points, 5.0);
  const auto bound = sim::quasiSteadyStateLap(curvature, step, false, car, 1.0);
  EXPECT_NEAR(bound.top_speed * 3.6, 257.6, 0.015 * 257.6);
  EXPECT_EQ(bound.speed[0], 0.0);
  for (int i = 1; i < points; ++i) {
    ASSERT_GE(bound.speed[i], bound.speed[i - 1]) << "at point " << i;
    ASSERT_LE(bound.speed[i], bound.top_speed + 1e-9);
  }
  EXPECT_GT(bound.speed.back(), 0.97 * bound.top_speed);
}

TEST(LapBound, BrakingForACornerStartsWhereTheBrakesNeedIt) {
  // A straight into a hairpin (closed: the hairpin leads back onto the straight): the speed falls to the
  // hairpin's over a stretch at least as long as the brakes' deceleration needs, and no shorter.
  const auto car = test::sedan();
  std::vector<double> curvature(400, 0.0), step(400, 2.0);
  for (int i = 300; i < 320; ++i) curvature[i] = 1.0 / 15.0;
  const auto bound = sim::quasiSteadyStateLap(curvature, step, true, car, 1.0);
  const double entry = bound.speed[300], fastest = *std::max_element(bound.speed.begin(), bound.speed.end());
  EXPECT_NEAR(entry, bound.corner_speed[300], 1e-9);
  EXPECT_GT(fastest, 2 * entry);
  // The brakes can give at most their torque at the road: the braking distance is no shorter than that allows.
  const double most =
      2 * (car.brakes.max_torque_front + car.brakes.max_torque_rear) / car.wheels[0].radius / car.chassis.mass;
  int braking = 0;
  for (int i = 1; i <= 300; ++i) braking += bound.speed[i] < bound.speed[i - 1];
  EXPECT_GE(braking * 2.0, (fastest * fastest - entry * entry) / (2 * most));
}

TEST(LapBound, TheSimulatedCarDoesNotBeatItsBound) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_ring");
  const auto car = test::sedan();
  harness::TimeTrialOptions options;
  options.laps = 2;
  const auto line = planning::minimumCurvatureLine(track, options.planner.line);
  const auto bound = sim::quasiSteadyStateLap(line.curvature, line.step, true, car, track.info().friction);
  const auto trial = harness::runTimeTrial(track, car, options);
  ASSERT_TRUE(trial.finished);
  EXPECT_GT(trial.best_lap(), bound.lap_time);
  EXPECT_LT(trial.best_lap(), 1.2 * bound.lap_time) << "a bound far below any lap bounds nothing";
}

TEST(LapBound, ALineItCannotReadIsRefusedByName) {
  const auto car = test::sedan();
  EXPECT_THROW(sim::quasiSteadyStateLap({0.0}, {1.0}, true, car, 1.0), std::invalid_argument);
  EXPECT_THROW(sim::quasiSteadyStateLap({0.0, 0.0}, {1.0}, true, car, 1.0), std::invalid_argument);
  try {
    sim::quasiSteadyStateLap({0.0, 0.0, 0.0}, {1.0, 0.0, 1.0}, true, car, 1.0);
    FAIL() << "a zero step was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("step 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sim::quasiSteadyStateLap({0.0, 0.0}, {1.0, 1.0}, true, car, 0.0), std::invalid_argument);
}
