// rostest: roar_sim (step mode) with the default sensor set. After one simulated second every sensor has
// published its rate's worth of messages with the right frame, encoding and content; sensors attach and
// detach at run time.
#include <geometry_msgs/TwistStamped.h>
#include <gtest/gtest.h>
#include <roar_ros/AttachSensor.h>
#include <roar_ros/DetachSensor.h>
#include <roar_ros/Step.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <map>

#include "ros_test_support.h"

namespace {

struct Seen {
  bool heard = false;
  int count = 0;  // messages stamped after the counts were restarted
  std::string frame, encoding;
};

class Recorder {
 public:
  template <class M>
  void watch(const std::string& topic, std::function<void(const M&)> extra = {}) {
    subs_.push_back(nh_.subscribe<M>(topic, 1000, [this, topic, extra](const boost::shared_ptr<const M>& m) {
      Seen& s = seen[topic];
      s.heard = true;
      if (count_after_.isZero() || m->header.stamp > count_after_) ++s.count;
      s.frame = m->header.frame_id;
      if (extra) extra(*m);
    }));
  }
  bool connected() const {
    for (const auto& s : subs_) {
      if (s.getNumPublishers() == 0) return false;
    }
    return true;
  }
  // A subscriber can count its publisher before the publisher counts it: until then messages are dropped.
  bool everyTopicHeard() {
    for (const auto& s : subs_) {
      if (!seen[s.getTopic()].heard) return false;
    }
    return true;
  }
  // Counts afresh the messages stamped after `after`: by stamp, not by arrival, so that a message of an
  // earlier tick still queued on a loaded machine is not counted.
  void restartCounts(const ros::Time& after) {
    count_after_ = after;
    for (auto& [topic, s] : seen) s.count = 0;
  }
  std::map<std::string, Seen> seen;

 private:
  ros::NodeHandle nh_;
  std::vector<ros::Subscriber> subs_;
  ros::Time count_after_;  // zero: every message counts
};

using roar::test::waitFor;

roar_ros::Step::Response step(uint32_t ticks) {
  roar_ros::Step srv;
  srv.request.ticks = ticks;
  EXPECT_TRUE(ros::service::call("/roar_sim/step", srv));
  EXPECT_TRUE(srv.response.success) << srv.response.message;
  return srv.response;
}

// Steps one tick at a time until every connection carries messages (slow on a loaded machine), then restarts
// the counts from the simulated time reached, so that what is counted next is what the steps to come publish.
bool startCountingWhenEveryTopicIsHeard(Recorder& r) {
  if (!waitFor([&] { return r.connected(); })) return false;
  ros::Time reached;
  for (int tick = 0; tick < 100 && !r.everyTopicHeard(); ++tick) {
    reached = step(1).stamp;
    waitFor([&] { return r.everyTopicHeard(); }, 0.5);
  }
  if (!r.everyTopicHeard()) return false;
  r.restartCounts(reached);
  return true;
}

}  // namespace

TEST(Sensors, EverySensorPublishesAtItsRateWithItsFrameAndEncoding) {
  ASSERT_TRUE(ros::service::waitForService("/roar_sim/step", ros::Duration(30)));
  Recorder r;
  std::map<std::string, std::string> encodings;
  sensor_msgs::CameraInfo info;
  sensor_msgs::Imu imu;
  sensor_msgs::NavSatFix fix;
  sensor_msgs::PointCloud2 cloud;
  for (const char* cam : {"front_rgb", "front_depth", "front_semantic"}) {
    const std::string topic = std::string("/ego/camera/") + cam + "/image";
    r.watch<sensor_msgs::Image>(topic, [&, topic](const sensor_msgs::Image& m) { encodings[topic] = m.encoding; });
    r.watch<sensor_msgs::CameraInfo>(std::string("/ego/camera/") + cam + "/camera_info",
                                     [&](const sensor_msgs::CameraInfo& m) { info = m; });
  }
  r.watch<sensor_msgs::PointCloud2>("/ego/lidar/top_lidar/points",
                                    [&](const sensor_msgs::PointCloud2& m) { cloud = m; });
  r.watch<sensor_msgs::Imu>("/ego/imu", [&](const sensor_msgs::Imu& m) { imu = m; });
  r.watch<sensor_msgs::NavSatFix>("/ego/gnss", [&](const sensor_msgs::NavSatFix& m) { fix = m; });
  r.watch<geometry_msgs::TwistStamped>("/ego/velocimeter/twist");
  r.watch<geometry_msgs::TwistStamped>("/ego/velocimeter/twist_map");
  ASSERT_TRUE(startCountingWhenEveryTopicIsHeard(r));

  step(20);  // one simulated second
  // Every topic's second's worth arrived (a loaded machine delivers late), then a moment for any extra.
  const std::map<std::string, int> per_second = {{"/ego/imu", 100},
                                                 {"/ego/gnss", 100},
                                                 {"/ego/lidar/top_lidar/points", 20},
                                                 {"/ego/velocimeter/twist", 20},
                                                 {"/ego/camera/front_rgb/image", 20},
                                                 {"/ego/camera/front_depth/image", 20},
                                                 {"/ego/camera/front_semantic/image", 20},
                                                 {"/ego/camera/front_semantic/camera_info", 20}};
  waitFor([&] {
    for (const auto& [topic, count] : per_second)
      if (r.seen[topic].count < count) return false;
    return true;
  });
  ros::WallDuration(0.3).sleep();
  ros::spinOnce();

  for (const char* cam : {"front_rgb", "front_depth", "front_semantic"}) {
    const std::string topic = std::string("/ego/camera/") + cam + "/image";
    EXPECT_EQ(r.seen[topic].count, 20) << topic;
    EXPECT_EQ(r.seen[topic].frame, std::string("ego/") + cam + "_optical");
    EXPECT_EQ(r.seen[std::string("/ego/camera/") + cam + "/camera_info"].count, 20);
  }
  EXPECT_EQ(encodings["/ego/camera/front_rgb/image"], "rgb8");
  EXPECT_EQ(encodings["/ego/camera/front_depth/image"], "32FC1");
  EXPECT_EQ(encodings["/ego/camera/front_semantic/image"], "mono8");
  EXPECT_EQ(info.width, 84u);
  EXPECT_NEAR(info.K[0], 42.0, 1e-9) << "fx for 90 degrees over 84 pixels";
  EXPECT_NEAR(info.K[2], 42.0, 1e-9);

  EXPECT_EQ(r.seen["/ego/lidar/top_lidar/points"].count, 20);
  EXPECT_EQ(r.seen["/ego/lidar/top_lidar/points"].frame, "ego/top_lidar");
  ASSERT_EQ(cloud.fields.size(), 4u);
  EXPECT_EQ(cloud.fields[3].name, "intensity");
  EXPECT_GT(cloud.width, 1000u) << "2800 beams a sweep, most hit the ground or the barriers";

  EXPECT_EQ(r.seen["/ego/imu"].count, 100);
  EXPECT_EQ(r.seen["/ego/imu"].frame, "ego/imu");
  EXPECT_NEAR(imu.linear_acceleration.z, 9.81, 0.05) << "parked";
  EXPECT_EQ(r.seen["/ego/gnss"].count, 100);
  EXPECT_EQ(r.seen["/ego/gnss"].frame, "ego/gnss");
  EXPECT_NEAR(fix.latitude, 37.9137, 0.01) << "Roar Ring's origin";
  EXPECT_EQ(r.seen["/ego/velocimeter/twist"].count, 20);
  EXPECT_EQ(r.seen["/ego/velocimeter/twist_map"].frame, "map");

  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  EXPECT_TRUE(waitFor([&] { return buffer.canTransform("ego/base_link", "ego/front_rgb_optical", ros::Time(0)); }));
  EXPECT_TRUE(buffer.canTransform("ego/base_link", "ego/top_lidar", ros::Time(0)));
}

TEST(Sensors, AttachAndDetachAtRunTime) {
  Recorder r;
  r.watch<sensor_msgs::Image>("/ego/camera/rear_grey/image");
  roar_ros::AttachSensor bad;
  bad.request.vehicle = "ego";
  bad.request.sensor_yaml = "{name: rear_grey, type: camera_grey, fov: 200}";
  ASSERT_TRUE(ros::service::call("/roar_sim/attach_sensor", bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_NE(bad.response.message.find("sensor 'rear_grey': fov: 200"), std::string::npos) << bad.response.message;

  roar_ros::AttachSensor attach;
  attach.request.vehicle = "ego";
  attach.request.sensor_yaml =
      "{name: rear_grey, type: camera_grey, x: -2.4, z: 1.4, yaw: 180, rate: 10, image_width: 64, image_height: 48}";
  ASSERT_TRUE(ros::service::call("/roar_sim/attach_sensor", attach));
  ASSERT_TRUE(attach.response.success) << attach.response.message;
  ASSERT_TRUE(startCountingWhenEveryTopicIsHeard(r));
  step(20);
  EXPECT_TRUE(waitFor([&] { return r.seen["/ego/camera/rear_grey/image"].count >= 10; }));
  EXPECT_EQ(r.seen["/ego/camera/rear_grey/image"].count, 10) << "10 Hz for one second";

  roar_ros::DetachSensor detach;
  detach.request.vehicle = "ego";
  detach.request.sensor = "rear_grey";
  ASSERT_TRUE(ros::service::call("/roar_sim/detach_sensor", detach));
  EXPECT_TRUE(detach.response.success);
  ASSERT_TRUE(ros::service::call("/roar_sim/detach_sensor", detach));
  EXPECT_FALSE(detach.response.success);
}

TEST(Sensors, HostileAttachRequestsAreRefusedByNameAndTheSimulatorLivesOn) {
  // Anyone who reaches the master can call attach_sensor: mounts at 1e38 once aborted roar_sim in Embree.
  const std::vector<std::pair<std::string, std::string>> hostile = {
      {"{name: far, type: camera_rgb, x: 1e38}", "x: 1e+38 is outside"},
      {"{name: far, type: lidar, z: 1e300}", "z: 1e+300 is outside"},
      {"{name: huge, type: camera_rgb, image_width: 8192, image_height: 8192}", "image_width"},
      {"{name: blind, type: camera_rgb, fov: .nan}", "fov"},
      {"{name: fast, type: lidar, rate: 1e9}", "rate"},
      {"{name: odd, type: sonar}", "type"},
      {"{name: broken, type: camera_rgb, x: [", "sensor_yaml"},
      {"", "sensor_yaml"},
      {"{name: '" + std::string(100000, 'a') + "', type: gnss}", "sensor_yaml is longer than"},
  };
  for (const auto& [yaml, expected] : hostile) {
    roar_ros::AttachSensor attach;
    attach.request.vehicle = "ego";
    attach.request.sensor_yaml = yaml;
    ASSERT_TRUE(ros::service::call("/roar_sim/attach_sensor", attach)) << "roar_sim answered " << yaml.substr(0, 80);
    EXPECT_FALSE(attach.response.success) << yaml.substr(0, 80);
    EXPECT_NE(attach.response.message.find(expected), std::string::npos)
        << yaml.substr(0, 80) << ": " << attach.response.message.substr(0, 300);
  }
  step(2);  // still stepping
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "sensor_tester");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
