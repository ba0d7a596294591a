#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "roar/vehicle/vehicle_control.h"

using namespace roar::vehicle;

TEST(VehicleControl, NonFiniteFieldsRejectTheControl) {
  for (int field = 0; field < 3; ++field) {
    for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
      VehicleControl c;
      (field == 0 ? c.throttle : field == 1 ? c.steer : c.brake) = bad;
      const auto checked = checkControl(c, 6);
      EXPECT_TRUE(checked.rejected);
      ASSERT_EQ(checked.problems.size(), 1u);
      const char* names[] = {"throttle", "steer", "brake"};
      EXPECT_EQ(checked.problems[0].rfind(names[field], 0), 0u) << checked.problems[0];
    }
  }
}

TEST(VehicleControl, OutOfRangeFieldsAreClamped) {
  VehicleControl c;
  c.throttle = 1.5;
  c.steer = -3;
  c.brake = -0.2;
  const auto checked = checkControl(c, 6);
  EXPECT_FALSE(checked.rejected);
  EXPECT_EQ(checked.problems.size(), 3u);
  EXPECT_EQ(checked.control.throttle, 1.0);
  EXPECT_EQ(checked.control.steer, -1.0);
  EXPECT_EQ(checked.control.brake, 0.0);
}

TEST(VehicleControl, UnknownManualGearIsRejected) {
  VehicleControl c;
  c.manual_gear_shift = true;
  c.gear = 7;
  EXPECT_TRUE(checkControl(c, 6).rejected);
  c.gear = -1;
  EXPECT_FALSE(checkControl(c, 6).rejected);
  c.manual_gear_shift = false;
  c.gear = 99;  // ignored without manual shifting
  EXPECT_FALSE(checkControl(c, 6).rejected);
}

TEST(VehicleControl, ParkedControlHoldsTheCar) {
  const auto c = parkedControl();
  EXPECT_EQ(c.throttle, 0.0);
  EXPECT_EQ(c.brake, 1.0);
  EXPECT_TRUE(c.hand_brake);
}
