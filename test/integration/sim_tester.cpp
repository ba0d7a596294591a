// rostest checks of the roar_sim node in step mode: odometry and /clock, the step service's exact time
// advance, a control message moving the car, bad controls, and the spawn/destroy/reset services.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <roar_ros/DestroyVehicle.h>
#include <roar_ros/ResetVehicle.h>
#include <roar_ros/SpawnVehicle.h>
#include <roar_ros/Step.h>
#include <roar_ros/VehicleControl.h>
#include <roar_ros/VehicleStatus.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <rosgraph_msgs/Log.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "ros_test_support.h"

namespace {

struct Listener {
  Listener() {
    ros::NodeHandle nh;
    odom_sub = nh.subscribe<nav_msgs::Odometry>(
        "ego/odom", 100, [this](const nav_msgs::Odometry::ConstPtr& m) { odom = *m, ++odom_count; });
    clock_sub = nh.subscribe<rosgraph_msgs::Clock>(
        "/clock", 100, [this](const rosgraph_msgs::Clock::ConstPtr& m) { clock = m->clock, ++clock_count; });
    status_sub = nh.subscribe<roar_ros::VehicleStatus>(
        "ego/vehicle_status", 100, [this](const roar_ros::VehicleStatus::ConstPtr& m) { status = *m; });
    control_pub = nh.advertise<roar_ros::VehicleControl>("ego/control", 10);
  }
  bool waitFor(const std::function<bool()>& cond, double seconds = 10.0) { return roar::test::waitFor(cond, seconds); }
  roar_ros::Step::Response step(uint32_t ticks) {
    roar_ros::Step srv;
    srv.request.ticks = ticks;
    EXPECT_TRUE(ros::service::call("/roar_sim/step", srv));
    EXPECT_TRUE(srv.response.success) << srv.response.message;
    const ros::Time stamp = srv.response.stamp;
    // Odometry and status travel on separate connections: wait for both of the last tick.
    EXPECT_TRUE(waitFor([&] { return odom.header.stamp == stamp && status.header.stamp == stamp; }))
        << "odometry and status of the last tick arrive";
    return srv.response;
  }
  // Publishes a control and makes sure the simulator has taken it before the next step.
  void send(const roar_ros::VehicleControl& c) {
    ASSERT_TRUE(waitFor([&] { return control_pub.getNumSubscribers() > 0; }));
    control_pub.publish(c);
    ros::WallDuration(0.3).sleep();
  }

  ros::Subscriber odom_sub, clock_sub, status_sub;
  ros::Publisher control_pub;
  nav_msgs::Odometry odom;
  roar_ros::VehicleStatus status;
  ros::Time clock;
  int odom_count = 0, clock_count = 0;
};

Listener* listener = nullptr;

}  // namespace

TEST(SimNode, PublishesOdometryAndClock) {
  ASSERT_TRUE(ros::service::waitForService("/roar_sim/step", ros::Duration(30)));
  listener->step(1);
  EXPECT_GT(listener->odom_count, 0);
  EXPECT_GT(listener->clock_count, 0);
  EXPECT_EQ(listener->odom.header.frame_id, "map");
  EXPECT_EQ(listener->odom.child_frame_id, "ego/base_link");
  EXPECT_EQ(listener->clock, listener->odom.header.stamp);
}

TEST(SimNode, BetweenStepsTheClockStandsButIsPublished) {
  // Tools on simulated time (rostopic echo, rviz) wait for a /clock: in step mode it comes at 10 Hz of
  // wall time while nobody steps, at the time the world stands at.
  const auto last = listener->step(1);
  const int before = listener->clock_count;
  EXPECT_TRUE(listener->waitFor([&] { return listener->clock_count - before >= 3; }, 3.0)) << "no /clock between steps";
  EXPECT_EQ(listener->clock, last.stamp) << "time stands still between steps";
}

TEST(SimNode, StepAdvancesTimeByExactlyNTicks) {
  const auto before = listener->step(1);
  const auto after = listener->step(7);
  EXPECT_EQ(after.tick, before.tick + 7);
  EXPECT_EQ((after.stamp - before.stamp).toNSec(), 7 * 50000000LL);
  EXPECT_EQ(listener->clock, after.stamp);
  roar_ros::Step look;  // 0 ticks: a snapshot, time stands still
  look.request.ticks = 0;
  look.request.observe = {"ego"};
  ASSERT_TRUE(ros::service::call("/roar_sim/step", look));
  EXPECT_TRUE(look.response.success) << look.response.message;
  EXPECT_EQ(look.response.tick, after.tick);
  ASSERT_EQ(look.response.vehicles.size(), 1u);
  EXPECT_EQ(look.response.vehicles[0].odometry.header.stamp, after.stamp);
  roar_ros::Step bad;
  bad.request.ticks = 1000001;
  ASSERT_TRUE(ros::service::call("/roar_sim/step", bad));
  EXPECT_FALSE(bad.response.success);
  bad.request.ticks = 1;
  bad.request.vehicle_names = {"ghost"};
  bad.request.controls.resize(1);
  ASSERT_TRUE(ros::service::call("/roar_sim/step", bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_NE(bad.response.message.find("ghost"), std::string::npos);
}

TEST(SimNode, ControlMessageMovesTheCar) {
  listener->step(1);
  const auto start = listener->odom.pose.pose.position;
  roar_ros::VehicleControl go;
  go.throttle = 1.0;
  listener->send(go);
  listener->step(40);
  const auto end = listener->odom.pose.pose.position;
  EXPECT_GT(std::hypot(end.x - start.x, end.y - start.y), 10.0);
  EXPECT_GT(listener->odom.twist.twist.linear.x, 10.0);
  EXPECT_EQ(listener->status.applied_control.throttle, 1.0f);
}

TEST(SimNode, NonFiniteControlNeverReachesThePhysics) {
  roar_ros::VehicleControl brake;
  brake.brake = 1.0;
  listener->send(brake);
  listener->step(2);
  roar_ros::VehicleControl bad;
  bad.throttle = std::numeric_limits<float>::quiet_NaN();
  bad.steer = std::numeric_limits<float>::infinity();
  listener->send(bad);
  listener->step(2);
  EXPECT_EQ(listener->status.applied_control.brake, 1.0f) << "the last good control stays";
  EXPECT_TRUE(std::isfinite(listener->status.applied_control.throttle));
  EXPECT_TRUE(std::isfinite(listener->odom.pose.pose.position.x));
  roar_ros::VehicleControl over;
  over.throttle = 5.0;
  over.steer = -2.0;
  listener->send(over);
  listener->step(1);
  EXPECT_EQ(listener->status.applied_control.throttle, 1.0f) << "clamped";
  EXPECT_EQ(listener->status.applied_control.steer, -1.0f);
}

TEST(SimNode, AFloodOfBadControlsLeavesNoNaNAndFewLogLines) {
  // 2,000 bad controls (NaN, inf, huge) as fast as they can be sent, stepping between: the car's state stays
  // finite and roar_sim's warnings about them are throttled in wall time (a few lines, not thousands).
  ros::NodeHandle nh;
  int warnings = 0;
  auto rosout = nh.subscribe<rosgraph_msgs::Log>("/rosout", 1000, [&](const rosgraph_msgs::Log::ConstPtr& m) {
    if (m->name == "/roar_sim" && m->msg.find("rejected") != std::string::npos) ++warnings;
  });
  ASSERT_TRUE(listener->waitFor(
      [&] { return listener->control_pub.getNumSubscribers() > 0 && rosout.getNumPublishers() > 0; }));
  const float kBad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                        -std::numeric_limits<float>::infinity()};
  const auto started = ros::WallTime::now();
  for (int k = 0; k < 2000; ++k) {
    roar_ros::VehicleControl bad;
    bad.throttle = kBad[k % 3];
    bad.steer = kBad[(k + 1) % 3];
    bad.brake = kBad[(k + 2) % 3];
    listener->control_pub.publish(bad);
    if (k % 200 == 199) {
      listener->step(1);
      ros::WallDuration(0.2).sleep();  // over two wall seconds: past the previous test's warning's throttle
    }
  }
  const double seconds = (ros::WallTime::now() - started).toSec();
  listener->step(1);
  ros::WallDuration(0.5).sleep();
  listener->waitFor([] { return false; }, 0.5);  // let the log lines in
  EXPECT_TRUE(std::isfinite(listener->odom.pose.pose.position.x) && std::isfinite(listener->odom.twist.twist.linear.x));
  EXPECT_TRUE(std::isfinite(listener->status.applied_control.throttle));
  EXPECT_GT(warnings, 0) << "the bad controls are reported";
  EXPECT_LE(warnings, 2 + static_cast<int>(seconds)) << "once a wall second at most, over " << seconds << " s";
  std::printf("bad-control flood: 2000 controls over %.1f s of wall time, %d warning lines\n", seconds, warnings);
}

TEST(SimNode, SpawnDestroyAndResetServices) {
  roar_ros::SpawnVehicle spawn;
  spawn.request.name = "rival";
  spawn.request.spawn_point = 3;
  ASSERT_TRUE(ros::service::call("/roar_sim/spawn_vehicle", spawn));
  EXPECT_TRUE(spawn.response.success) << spawn.response.message;

  roar_ros::SpawnVehicle onto;  // onto the rival
  onto.request.name = "third";
  onto.request.spawn_point = 3;
  ASSERT_TRUE(ros::service::call("/roar_sim/spawn_vehicle", onto));
  EXPECT_FALSE(onto.response.success);
  EXPECT_NE(onto.response.message.find("overlap vehicle 'rival'"), std::string::npos) << onto.response.message;

  roar_ros::SpawnVehicle unknown;
  unknown.request.name = "bus";
  unknown.request.model = "bus";
  unknown.request.spawn_point = 5;
  ASSERT_TRUE(ros::service::call("/roar_sim/spawn_vehicle", unknown));
  EXPECT_FALSE(unknown.response.success);
  EXPECT_NE(unknown.response.message.find("unknown vehicle model or blueprint 'bus'"), std::string::npos)
      << unknown.response.message;
  EXPECT_NE(unknown.response.message.find("carla_model3 (vehicle.tesla.model3)"), std::string::npos)
      << unknown.response.message;

  ros::NodeHandle nh;
  nav_msgs::Odometry rival_odom;
  auto sub = nh.subscribe<nav_msgs::Odometry>("rival/odom", 10,
                                              [&](const nav_msgs::Odometry::ConstPtr& m) { rival_odom = *m; });
  listener->waitFor([&] { return sub.getNumPublishers() > 0; });
  const auto stepped = listener->step(2);
  EXPECT_TRUE(listener->waitFor([&] { return rival_odom.header.stamp == stepped.stamp; }));

  roar_ros::DestroyVehicle destroy;
  destroy.request.name = "rival";
  ASSERT_TRUE(ros::service::call("/roar_sim/destroy_vehicle", destroy));
  EXPECT_TRUE(destroy.response.success);
  ASSERT_TRUE(ros::service::call("/roar_sim/destroy_vehicle", destroy));
  EXPECT_FALSE(destroy.response.success) << "already gone";

  roar_ros::ResetVehicle reset;
  reset.request.name = "ego";
  reset.request.spawn_point = -1;
  reset.request.pose.position.x = 100.0;
  reset.request.pose.position.y = 0.0;
  reset.request.pose.orientation.w = 1.0;
  ASSERT_TRUE(ros::service::call("/roar_sim/reset_vehicle", reset));
  EXPECT_TRUE(reset.response.success) << reset.response.message;
  listener->step(1);
  EXPECT_NEAR(listener->odom.pose.pose.position.x, 100.0, 0.05);
  EXPECT_LT(std::abs(listener->odom.twist.twist.linear.x), 0.1);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "sim_tester");
  Listener l;
  listener = &l;
  return RUN_ALL_TESTS();
}
