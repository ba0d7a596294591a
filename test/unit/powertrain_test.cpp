#include <gtest/gtest.h>

#include "roar/sim/powertrain.h"
#include "test_support.h"

using namespace roar::sim;

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
