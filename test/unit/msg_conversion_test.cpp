#include <gtest/gtest.h>

#include "roar/ros/msg_conversion.h"

using namespace roar;

TEST(MsgConversion, ControlRoundTrip) {
  sim::VehicleControl c;
  c.throttle = 0.25;
  c.steer = -0.5;
  c.brake = 0.75;
  c.hand_brake = true;
  c.reverse = true;
  c.manual_gear_shift = true;
  c.gear = 3;
  const auto back = ros_bridge::fromMessage(ros_bridge::toMessage(c));
  EXPECT_EQ(back.throttle, c.throttle);
  EXPECT_EQ(back.steer, c.steer);
  EXPECT_EQ(back.brake, c.brake);
  EXPECT_EQ(back.hand_brake, c.hand_brake);
  EXPECT_EQ(back.reverse, c.reverse);
  EXPECT_EQ(back.manual_gear_shift, c.manual_gear_shift);
  EXPECT_EQ(back.gear, c.gear);
}

TEST(MsgConversion, PoseRoundTripAndZeroQuaternion) {
  sim::Pose p;
  p.position = {1.5, -2.5, 0.25};
  p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  const auto back = ros_bridge::fromMessage(ros_bridge::toMessage(p));
  EXPECT_EQ(back.position, p.position);
  EXPECT_NEAR(back.orientation.angularDistance(p.orientation), 0.0, 1e-12);
  EXPECT_NEAR(ros_bridge::yawOf(ros_bridge::toMessage(p).orientation), 0.7, 1e-12);
  geometry_msgs::Pose zero;  // all-zero quaternion
  EXPECT_TRUE(ros_bridge::fromMessage(zero).orientation.isApprox(Eigen::Quaterniond::Identity()));
}

TEST(MsgConversion, OdometryUsesBodyTwistAndFrames) {
  sim::VehicleState s;
  s.pose.position = {10, 20, 0};
  s.body_linear_velocity = {5, 0.5, 0};
  s.body_angular_velocity = {0, 0, 0.2};
  const auto odom = ros_bridge::toOdometry(s, ros_bridge::toRosTime(12.35), "map", "ego/base_link");
  EXPECT_EQ(odom.header.frame_id, "map");
  EXPECT_EQ(odom.child_frame_id, "ego/base_link");
  EXPECT_EQ(odom.pose.pose.position.y, 20);
  EXPECT_EQ(odom.twist.twist.linear.x, 5);
  EXPECT_EQ(odom.twist.twist.angular.z, 0.2);
  EXPECT_NEAR(odom.header.stamp.toSec(), 12.35, 1e-9);
}

TEST(MsgConversion, TimeIsExactForControlTicks) {
  // 0.05 s ticks: tick 7 and 7 * 0.05 agree to the nanosecond.
  EXPECT_EQ(ros_bridge::toRosTime(7 * 0.05).toNSec(), 350000000u);
  EXPECT_EQ(ros_bridge::toRosTime(123456 * 0.05).toNSec(), 6172800000000u);
}
