#include <gtest/gtest.h>

#include "roar/vehicle/powertrain.h"
#include "test_support.h"

using namespace roar::vehicle;

namespace {
double omegaForRpm(const VehicleParams& p, int gear, double rpm) {
  return rpm / (p.gearbox.ratios[gear - 1] * p.gearbox.final_drive) * 2 * M_PI / 60;
}
}  // namespace

TEST(Powertrain, TorqueCurveInterpolates) {
  const auto p = roar::test::sedan();
  Powertrain pt(p);
  EXPECT_DOUBLE_EQ(pt.engineTorqueAt(3000), 560);
  EXPECT_DOUBLE_EQ(pt.engineTorqueAt(5500), 530);
  EXPECT_DOUBLE_EQ(pt.engineTorqueAt(500), 420);
}

TEST(Powertrain, FullThrottleFromRestPullsForwardInFirst) {
  const auto p = roar::test::sedan();
  Powertrain pt(p);
  const double torque = pt.update({1.0, false, false, 0}, 0.0, 0.005);
  EXPECT_EQ(pt.gear(), 1);
  EXPECT_NEAR(torque, 420 * 4.10 * 3.60 * 0.9, 1.0) << "clutch slips at idle: idle torque through first gear";
}

TEST(Powertrain, ShiftsUpAboveAndDownBelowTheThresholds) {
  const auto p = roar::test::sedan();
  Powertrain pt(p);
  pt.update({1.0, false, false, 0}, omegaForRpm(p, 1, 6600), 0.005);
  EXPECT_EQ(pt.gear(), 2);
  EXPECT_EQ(pt.update({1.0, false, false, 0}, omegaForRpm(p, 2, 5000), 0.005), 0.0) << "no drive while shifting";
  for (int i = 0; i < 40; ++i) pt.update({1.0, false, false, 0}, omegaForRpm(p, 2, 5000), 0.005);
  EXPECT_EQ(pt.gear(), 2);
  EXPECT_GT(pt.update({1.0, false, false, 0}, omegaForRpm(p, 2, 5000), 0.005), 0.0);
  pt.update({0.0, false, false, 0}, omegaForRpm(p, 2, 2500), 0.005);
  EXPECT_EQ(pt.gear(), 1);
}

TEST(Powertrain, ReverseManualAndNeutral) {
  const auto p = roar::test::sedan();
  Powertrain pt(p);
  pt.update({1.0, true, false, 0}, 0.0, 0.005);
  EXPECT_EQ(pt.gear(), -1);
  for (int i = 0; i < 40; ++i) pt.update({1.0, true, false, 0}, 0.0, 0.005);
  EXPECT_LT(pt.update({1.0, true, false, 0}, 0.0, 0.005), 0.0) << "reverse drives backwards";
  pt.update({1.0, false, true, 0}, 0.0, 0.005);
  EXPECT_EQ(pt.gear(), 0);
  EXPECT_EQ(pt.update({1.0, false, true, 0}, 10.0, 0.005), 0.0) << "neutral drives nothing";
  EXPECT_GT(pt.engineRpm(), p.engine.idle_rpm) << "free revving";
  pt.update({0.5, false, true, 4}, 0.0, 0.005);
  EXPECT_EQ(pt.gear(), 4);
}

TEST(Powertrain, EngineBrakingOpposesRotation) {
  const auto p = roar::test::sedan();
  Powertrain pt(p);
  for (int i = 0; i < 40; ++i) pt.update({0.0, false, true, 3}, omegaForRpm(p, 3, 5000), 0.005);
  EXPECT_LT(pt.update({0.0, false, true, 3}, omegaForRpm(p, 3, 5000), 0.005), 0.0);
  EXPECT_NEAR(pt.engineRpm(), 5000, 1e-6);
}

TEST(Powertrain, KickdownDropsToTheStrongestGearAtFullThrottle) {
  const auto p = roar::test::sedan();
  // 4000 rpm in sixth: above shift-down, so only kickdown leaves sixth; fourth turns 6430 rpm there, too
  // close to the 6500 shift-up, so the strongest gear with room to pull is fifth.
  const double omega = omegaForRpm(p, 6, 4000);
  auto inSixth = [&](const VehicleParams& params) {
    Powertrain pt(params);
    pt.update({0.0, false, true, 6}, omega, 0.005);
    for (int i = 0; i < 40; ++i) pt.update({0.5, false, false, 0}, omega, 0.005);
    return pt;
  };
  {
    Powertrain pt = inSixth(p);
    EXPECT_EQ(pt.gear(), 6) << "a part-throttle cruise keeps its gear";
    pt.update({1.0, false, false, 0}, omega, 0.005);
    EXPECT_EQ(pt.gear(), 5);
    EXPECT_EQ(pt.gear(), pt.strongestGear(omega * 60 / (2 * M_PI), 300.0));
    for (int i = 0; i < 40; ++i) pt.update({1.0, false, false, 0}, omega, 0.005);
    EXPECT_EQ(pt.gear(), 5) << "no hunting back up";
    EXPECT_GT(pt.update({1.0, false, false, 0}, omega, 0.005), pt.fullThrottleWheelTorque(6, omega * 60 / (2 * M_PI)));
  }
  {
    Powertrain pt = inSixth(p);
    pt.update({0.0, false, false, 0}, omega, 0.005);
    EXPECT_EQ(pt.gear(), 6) << "lifting keeps the gear until shift-down rpm";
  }
  {
    auto no_kickdown = p;
    no_kickdown.gearbox.kickdown = false;
    Powertrain pt = inSixth(no_kickdown);
    pt.update({1.0, false, false, 0}, omega, 0.005);
    EXPECT_EQ(pt.gear(), 6);
  }
  // The planner's strongest gear: the most wheel torque among the gears below their ceiling.
  Powertrain pt(p);
  const double wheel_rpm = 4000.0 / (p.gearbox.ratios[5] * p.gearbox.final_drive);
  EXPECT_EQ(pt.strongestGear(wheel_rpm), 4) << "6430 rpm in fourth is still below 6500";
  EXPECT_EQ(pt.strongestGear(1e5), 0) << "faster than the top gear's redline";
}

// Climbing at full throttle, a car shifts up at first gear's limit and loses a little speed in the torque
// gap: kickdown must not take it straight back to first (which would shift up again at once, and so on:
// the hatchback hunted between first and second for 15 s up Roar Hillclimb), but may once the second gear
// has had its chance, or at once when the driver lifted or the car lost more speed (braking behind another).
TEST(Powertrain, NoKickdownStraightBackAfterAShiftUpAtFullThrottle) {
  const auto p = roar::test::sedan();
  const double up_rpm = p.gearbox.shift_up_rpm;
  auto shiftedUp = [&] {
    Powertrain pt(p);
    pt.update({1.0, false, false, 0}, omegaForRpm(p, 1, up_rpm + 50), 0.005);
    return pt;
  };
  // A little slower: first would turn 500 rpm below its shift-up, room enough for kickdown to pick it.
  const double slower = omegaForRpm(p, 1, up_rpm - 500);
  ASSERT_EQ(shiftedUp().gear(), 2);
  ASSERT_EQ(shiftedUp().strongestGear(slower * 60 / (2 * M_PI), 300.0), 1);
  {
    Powertrain pt = shiftedUp();
    for (int i = 0; i < 190; ++i) {
      pt.update({1.0, false, false, 0}, slower, 0.005);
      ASSERT_EQ(pt.gear(), 2) << "after " << (i + 1) * 0.005 << " s";
    }
    for (int i = 0; i < 20; ++i) pt.update({1.0, false, false, 0}, slower, 0.005);
    EXPECT_EQ(pt.gear(), 1) << "a second after the shift up, kickdown again";
  }
  {
    Powertrain pt = shiftedUp();
    for (int i = 0; i < 40; ++i) pt.update({1.0, false, false, 0}, slower, 0.005);  // past the shift's gap
    pt.update({0.5, false, false, 0}, slower, 0.005);
    pt.update({1.0, false, false, 0}, slower, 0.005);
    EXPECT_EQ(pt.gear(), 1) << "lifted, then floored again: kickdown at once";
  }
  {
    Powertrain pt = shiftedUp();
    for (int i = 0; i < 40; ++i) pt.update({1.0, false, false, 0}, slower, 0.005);
    pt.update({1.0, false, false, 0}, omegaForRpm(p, 1, 0.85 * up_rpm), 0.005);
    EXPECT_EQ(pt.gear(), 1) << "15% slower than at the shift up: kickdown at once";
  }
}

// EngineParams::response_time: the torque follows the pedal as a first-order lag, both ways.
TEST(Powertrain, TorqueFollowsThePedalWithTheEnginesResponseTime) {
  auto p = roar::test::vehicle("carla_model3");
  p.engine.response_time = 0.2;
  p.gearbox.engage_time = 0.0;
  Powertrain pt(p);
  const double omega = 30.0;  // rad/s at the wheels, clutch closed
  const double full = pt.fullThrottleWheelTorque(1, omega * 60 / (2 * M_PI));
  double torque = 0.0;
  for (int i = 0; i < 40; ++i) torque = pt.update({1.0, false, false, 0}, omega, 0.005);  // 0.2 s: one lag
  EXPECT_NEAR(torque / full, 1.0 - std::exp(-1.0), 0.02);
  for (int i = 0; i < 400; ++i) torque = pt.update({1.0, false, false, 0}, omega, 0.005);
  EXPECT_NEAR(torque / full, 1.0, 1e-3);
  pt.update({0.0, false, false, 0}, omega, 0.005);
  EXPECT_GT(pt.update({0.0, false, false, 0}, omega, 0.005), 0.9 * full) << "lifting takes the lag too";
  pt.settle(0.0);
  EXPECT_LT(pt.update({0.0, false, false, 0}, omega, 0.005), 0.0) << "settled: closed at once, engine braking";
}

// GearboxParams::engage_time: put down, the car stands in neutral until engage_time after its first
// throttle, its engine revving free; then the clutch takes the engine up and passes more than the engine's
// own torque until engine and wheels turn together (CARLA's cars: 1.5 s still, then a surge).
TEST(Powertrain, APutDownCarStandsInNeutralThenSurgesAsTheClutchTakesUpTheEngine) {
  auto p = roar::test::vehicle("carla_model3");
  p.gearbox.engage_time = 1.5;
  p.engine.response_time = 0.0;
  Powertrain pt(p);
  EXPECT_TRUE(pt.standing());
  EXPECT_EQ(pt.gear(), 0);
  for (int i = 0; i < 200; ++i) EXPECT_EQ(pt.update({0.0, false, false, 0}, 0.0, 0.005), 0.0);
  EXPECT_TRUE(pt.standing()) << "no throttle yet: the wait has not begun";
  double torque = 0.0;
  int drive_from = -1;
  for (int i = 0; i < 400 && drive_from < 0; ++i) {
    torque = pt.update({1.0, false, false, 0}, 0.0, 0.005);
    if (torque > 0) drive_from = i;
  }
  EXPECT_NEAR(drive_from * 0.005, 1.5, 0.01) << "drive 1.5 s after the first throttle";
  EXPECT_EQ(pt.gear(), 1);
  EXPECT_GT(pt.engineRpm(), 0.9 * p.engine.redline_rpm) << "the engine revved free meanwhile";
  const double locked = pt.fullThrottleWheelTorque(1, 0.0);
  EXPECT_GT(torque, 2.0 * locked) << "the spinning engine's surge";
  // The wheels follow the engine down: once they turn together, the engine's own torque again.
  double omega = 0.0;
  for (int i = 0; i < 2000; ++i) {
    torque = pt.update({1.0, false, false, 0}, omega, 0.005);
    omega += 0.5;  // rad/s a substep: the car gathering speed
  }
  EXPECT_NEAR(torque, pt.fullThrottleWheelTorque(1, omega * 60 / (2 * M_PI)), 1.0);
  pt.reset(false);
  EXPECT_FALSE(pt.standing()) << "moved, not spawned: in gear";
  pt.reset(true);
  EXPECT_TRUE(pt.standing()) << "put down again";
  pt.settle(1.0);
  EXPECT_FALSE(pt.standing()) << "a car set moving is in gear";
  EXPECT_GT(pt.update({1.0, false, false, 0}, 30.0, 0.005), 0.0);
}

TEST(DriveShares, OpenDifferentialsSplitEachAxleInHalvesWhateverTheSpeeds) {
  const DifferentialParams open;
  const auto shares = driveShares(open, 0.3, {10.0, 30.0, 5.0, 50.0});
  EXPECT_DOUBLE_EQ(shares[0], 0.15);
  EXPECT_DOUBLE_EQ(shares[1], 0.15);
  EXPECT_DOUBLE_EQ(shares[2], 0.35);
  EXPECT_DOUBLE_EQ(shares[3], 0.35);
}

TEST(DriveShares, LimitedSlipMovesTorqueToTheSlowerWheel) {
  DifferentialParams ls;
  ls.type = DifferentialType::kLimitedSlip;
  // Rear-wheel drive, the wheels within the bias (12 < 1.3 x 10): as open.
  auto shares = driveShares(ls, 0.0, {10.0, 10.0, 10.0, 12.0});
  EXPECT_DOUBLE_EQ(shares[2], 0.5);
  EXPECT_DOUBLE_EQ(shares[3], 0.5);
  // The inner wheel spinning at twice the outer's: 20 - 1.3 x 10 = 7, 35 % of 20, moved to the outer.
  shares = driveShares(ls, 0.0, {10.0, 10.0, 10.0, 20.0});
  EXPECT_NEAR(shares[2], 0.5 * 1.35, 1e-12);
  EXPECT_NEAR(shares[3], 0.5 * 0.65, 1e-12);
  EXPECT_DOUBLE_EQ(shares[0] + shares[1], 0.0) << "nothing to the undriven axle";
  // Four-wheel drive, the rear axle spinning at twice the front's: the centre moves torque forward.
  shares = driveShares(ls, 0.45, {10.0, 10.0, 20.0, 20.0});
  const double front = 0.45 * 1.35, rear = 0.55 * 0.65;
  EXPECT_NEAR(shares[0] + shares[1], front / (front + rear), 1e-12);
  EXPECT_NEAR(shares[0], shares[1], 1e-12);
  EXPECT_NEAR(shares[0] + shares[1] + shares[2] + shares[3], 1.0, 1e-12);
  // Wheels turning different ways (a car rocking at rest): shared as open differentials do.
  shares = driveShares(ls, 0.45, {1.0, -1.0, 2.0, 2.0});
  EXPECT_DOUBLE_EQ(shares[0], 0.225);
  EXPECT_DOUBLE_EQ(shares[3], 0.275);
}
