#include "roar/planning/speed_profile.h"

#include <gtest/gtest.h>

#include <cmath>

#include "roar/sim/world.h"
#include "test_support.h"

using namespace roar;

namespace {

planning::VehicleLimits sedanLimits(double friction = 1.0, double grip_use = 1.0) {
  return planning::vehicleLimits(test::sedan(), friction, grip_use);
}

// A closed loop of straights and corners of several radii, sampled every 2 m.
void wavyLoop(std::vector<double>* step, std::vector<double>* curvature) {
  for (int i = 0; i < 1500; ++i) {
    step->push_back(2.0);
    const double phase = 2 * M_PI * i / 1500.0;
    curvature->push_back(0.02 * std::sin(3 * phase) + 0.008 * std::cos(7 * phase));
  }
}

}  // namespace

TEST(VehicleLimits, ComeFromTheSedansParameters) {
  const auto car = test::sedan();
  const auto limits = sedanLimits();
  EXPECT_EQ(limits.mass, car.chassis.mass);
  // Top speed where drive force meets drag: the simulated sedan reaches 287 km/h.
  EXPECT_NEAR(limits.max_speed * 3.6, 287.0, 15.0);
  // First gear pulls harder than the tyres can take, sixth gear at 200 km/h much less.
  EXPECT_GT(limits.driveForce(5.0), limits.gripForce(5.0));
  EXPECT_LT(limits.driveForce(55.0), 0.4 * limits.driveForce(5.0));
  EXPECT_THROW(planning::vehicleLimits(car, 1.0, 1.5), std::invalid_argument);
}

TEST(SpeedProfile, NeverExceedsTheFrictionLimitAndRespectsBraking) {
  std::vector<double> step, kappa;
  wavyLoop(&step, &kappa);
  auto limits = sedanLimits(0.9);
  limits.downforce_coefficient = 0.0;  // then the limit is exactly sqrt(mu g / kappa)
  const auto p = planning::computeSpeedProfile(step, kappa, limits, true);
  const double mu = limits.friction, g = limits.gravity;
  int at_limit = 0;
  for (std::size_t i = 0; i < kappa.size(); ++i) {
    const double v = p.speed[i];
    if (std::abs(kappa[i]) > 1e-6) {
      EXPECT_LE(v, std::sqrt(mu * g / std::abs(kappa[i])) + 1e-9) << "point " << i;
      at_limit += v > 0.999 * std::sqrt(mu * g / std::abs(kappa[i]));
    }
    const std::size_t j = (i + 1) % kappa.size();
    // Braking from i to j no harder than friction plus drag allow (brakes alone could do more).
    const double decel = (v * v - p.speed[j] * p.speed[j]) / (2 * step[i]);
    EXPECT_LE(decel, mu * g + limits.resistance(v) / limits.mass + 1e-6) << "point " << i;
    EXPECT_LE(p.acceleration[i], limits.driveForce(v) / limits.mass + 1e-6);
  }
  EXPECT_GT(at_limit, 50) << "the car uses the grip it has in the corners";
}

TEST(SpeedProfile, DownforceRaisesTheCorneringSpeed) {
  const auto limits = sedanLimits();
  auto no_aero = limits;
  no_aero.downforce_coefficient = 0.0;
  const double kappa = 1.0 / 300.0;
  const double v = limits.corneringSpeed(kappa);
  EXPECT_GT(v, no_aero.corneringSpeed(kappa));
  EXPECT_NEAR(limits.mass * v * v * kappa, limits.gripForce(v), 1e-6 * limits.gripForce(v)) << "exactly at the limit";
}

// Over a crest the car weighs less: a corner on it is taken slower, and on a straight crest the car keeps
// kMinCrestLoad of its weight on the tyres, where a 3 g car would otherwise leave the ground.
TEST(SpeedProfile, ACrestSlowsTheCornerOnItAndTheCarKeepsItsWheelsDown) {
  auto limits = sedanLimits();
  limits.downforce_coefficient = 0.0;
  const double kappa = 1.0 / 200.0, crest = -1.0 / 1200.0;
  const double level = limits.corneringSpeed(kappa), over = limits.corneringSpeed(kappa, crest);
  EXPECT_LT(over, level);
  // At that speed the tyres carry the corner with the weight the crest leaves: m v^2 k = mu m (g + v^2 kv).
  EXPECT_NEAR(over * over * kappa, limits.friction * (limits.gravity + over * over * crest), 1e-9);
  const double straight = limits.corneringSpeed(0.0, crest);
  EXPECT_NEAR(straight * straight * -crest, (1.0 - planning::VehicleLimits::kMinCrestLoad) * limits.gravity, 1e-9);
  EXPECT_GT(limits.corneringSpeed(kappa, 1.0 / 1200.0), level) << "a dip presses the car down";

  // A straight 1 km with a crest in its middle: the profile keeps the car on the road over it.
  std::vector<double> step(500, 2.0), curvature(500, 0.0), vertical(500, 0.0);
  for (int i = 240; i < 260; ++i) vertical[i] = crest;
  planning::SpeedProfileOptions options;
  options.vertical_curvature = vertical;
  const auto profile = planning::computeSpeedProfile(step, curvature, limits, false, options);
  for (int i = 240; i < 260; ++i) EXPECT_LE(profile.speed[i], straight + 1e-9) << "point " << i;
  EXPECT_GT(profile.speed[300], straight) << "and goes on beyond it";
  options.vertical_curvature.pop_back();
  EXPECT_THROW(planning::computeSpeedProfile(step, curvature, limits, false, options), std::invalid_argument);
}

TEST(SpeedProfile, ClosedLoopIsTheSameWhereverItStarts) {
  std::vector<double> step, kappa;
  wavyLoop(&step, &kappa);
  const auto limits = sedanLimits();
  const auto a = planning::computeSpeedProfile(step, kappa, limits, true);
  std::rotate(kappa.begin(), kappa.begin() + 400, kappa.end());
  const auto b = planning::computeSpeedProfile(step, kappa, limits, true);
  for (std::size_t i = 0; i < kappa.size(); ++i) ASSERT_NEAR(b.speed[i], a.speed[(i + 400) % kappa.size()], 1e-9);
  EXPECT_NEAR(a.total_time, b.total_time, 1e-9);
}

TEST(SpeedProfile, BrakesForAHairpinAtTheEndOfAStraight) {
  // 600 m straight into a 15 m hairpin; no drag, so braking is exactly mu g.
  std::vector<double> step(301, 2.0), kappa(301, 0.0);
  for (std::size_t i = 290; i < kappa.size(); ++i) kappa[i] = 1.0 / 15.0;
  auto limits = sedanLimits();
  limits.drag_coefficient = limits.downforce_coefficient = limits.rolling_resistance = 0.0;
  planning::SpeedProfileOptions options;
  options.start_speed = 0.0;
  const auto p = planning::computeSpeedProfile(step, kappa, limits, false, options);
  const double corner = std::sqrt(limits.friction * limits.gravity * 15.0);
  EXPECT_NEAR(p.speed[290], corner, 1e-6);
  EXPECT_EQ(p.speed[0], 0.0);
  // 100 m before the corner the car can be no faster than braking at mu g allows.
  EXPECT_LE(p.speed[240], std::sqrt(corner * corner + 2 * limits.friction * limits.gravity * 100.0) + 1e-6);
  EXPECT_GT(p.speed[240], corner + 10.0);
}

TEST(SpeedProfile, ATowRaisesTheSpeedsTheEngineSetsAndNoOther) {
  // Out of a 20 m corner onto a 700 m straight into a 15 m hairpin.
  std::vector<double> step(451, 2.0), kappa(451, 0.0);
  for (std::size_t i = 0; i < 20; ++i) kappa[i] = 1.0 / 20.0;
  for (std::size_t i = 420; i < kappa.size(); ++i) kappa[i] = 1.0 / 15.0;
  const auto limits = sedanLimits();
  const auto free_air = planning::computeSpeedProfile(step, kappa, limits, false);
  const auto same = planning::towedSpeeds(step, kappa, free_air.speed, limits, 1.0);
  EXPECT_EQ(same, free_air.speed) << "no tow, no change";
  const auto towed = planning::towedSpeeds(step, kappa, free_air.speed, limits, 0.7);
  for (std::size_t k = 0; k < towed.size(); ++k) EXPECT_GE(towed[k], free_air.speed[k]) << "point " << k;
  EXPECT_EQ(towed[10], free_air.speed[10]) << "the corner's speed is the grip's";
  EXPECT_EQ(towed.back(), free_air.speed.back()) << "so is the hairpin's";
  // Half way down the straight the engine, pulling against less drag, has made more speed.
  EXPECT_GT(towed[200], free_air.speed[200] + 0.5);
}

// The planner's model of the car and the simulated car agree: full throttle from rest on a straight.
TEST(SpeedProfile, MatchesTheSimulatedCarAcceleratingOnAStraight) {
  const auto car = test::sedan();
  const auto limits = planning::vehicleLimits(car, 1.0, 1.0);
  std::vector<double> step(400, 1.0), kappa(400, 0.0);
  planning::SpeedProfileOptions options;
  options.start_speed = 0.0;
  const auto p = planning::computeSpeedProfile(step, kappa, limits, false, options);

  sim::World world(test::openGround(), {});
  world.spawnVehicle("ego", car, {});
  vehicle::VehicleControl full;
  full.throttle = 1.0;
  double travelled = 0.0;
  Eigen::Vector3d last = world.vehicleState("ego").pose.position;
  while (travelled < 399.0) {
    world.setControl("ego", full);
    world.step();
    const Eigen::Vector3d now = world.vehicleState("ego").pose.position;
    travelled += (now - last).norm();
    last = now;
  }
  const double planned = p.time[399];
  RecordProperty("planned_400m_s", std::to_string(planned));
  RecordProperty("simulated_400m_s", std::to_string(world.time()));
  EXPECT_NEAR(world.time(), planned, 0.04 * planned) << "400 m from rest";
}

TEST(SpeedProfile, BadInputNamesTheEntry) {
  const auto limits = sedanLimits();
  std::vector<double> step(10, 1.0), kappa(10, 0.0);
  kappa[4] = NAN;
  EXPECT_NE(test::errorOf([&] { planning::computeSpeedProfile(step, kappa, limits, true); }).find("curvature 4"),
            std::string::npos);
  kappa[4] = 0.0;
  step[7] = 0.0;
  EXPECT_NE(test::errorOf([&] { planning::computeSpeedProfile(step, kappa, limits, true); }).find("step 7"),
            std::string::npos);
  EXPECT_THROW(planning::computeSpeedProfile({1.0}, {0.0}, limits, true), std::invalid_argument);
}

// Out of a corner the simulated car pulls in the gear the planner assumes: braked from 220 to 150 km/h in
// sixth, floored, the automatic gearbox kicks down and the car accelerates as the profile says.
TEST(SpeedProfile, MatchesTheSimulatedCarAcceleratingOutOfACorner) {
  const auto car = test::sedan();
  const auto limits = planning::vehicleLimits(car, 1.0, 1.0);
  sim::World world(test::openGround(), {});
  world.spawnVehicle("ego", car, {});
  vehicle::VehicleControl control;
  control.throttle = 1.0;
  while (world.vehicleState("ego").forward_speed < 61.0) {
    world.setControl("ego", control);
    world.step();
  }
  EXPECT_EQ(world.vehicleState("ego").gear, 6);
  control.throttle = 0.0;
  control.brake = 0.6;
  while (world.vehicleState("ego").forward_speed > 42.0) {
    world.setControl("ego", control);
    world.step();
  }
  const double v0 = world.vehicleState("ego").forward_speed;
  EXPECT_EQ(world.vehicleState("ego").gear, 6);
  control.throttle = 1.0;
  control.brake = 0.0;
  const double t0 = world.time();
  const Eigen::Vector3d start = world.vehicleState("ego").pose.position;
  for (int tick = 1; world.time() < t0 + 4.0; ++tick) {
    world.setControl("ego", control);
    world.step();
    if (tick == 1) {
      const double v = world.vehicleState("ego").forward_speed;
      EXPECT_EQ(world.vehicleState("ego").gear, limits.gearAt(v)) << "at " << v << " m/s";
    }
  }
  const double travelled = (world.vehicleState("ego").pose.position - start).norm();
  std::vector<double> step(static_cast<std::size_t>(travelled), 1.0), kappa(step.size(), 0.0);
  planning::SpeedProfileOptions options;
  options.start_speed = v0;
  const auto p = planning::computeSpeedProfile(step, kappa, limits, false, options);
  EXPECT_NEAR(world.vehicleState("ego").forward_speed, p.speed.back(), 0.02 * p.speed.back());
  EXPECT_NEAR(4.0, p.time.back(), 0.04 * 4.0) << "the profile's time over the distance the car covered";
}
