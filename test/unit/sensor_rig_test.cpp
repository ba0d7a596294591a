#include <gtest/gtest.h>

#include <map>

#include "roar/sensors/sensor_rig.h"
#include "roar/sensors/vehicle_motion.h"
#include "sensor_test_scene.h"

using namespace roar;
using test::errorOf;

namespace {

struct Counter : sensors::SensorSink {
  std::map<std::string, int> count;
  std::map<std::string, const sensors::CameraFrame*> frame;
  std::vector<double> imu_stamps;
  void camera(const sensors::SensorSpec& s, double, const sensors::CameraFrame& f, const sensors::CameraIntrinsics&) override {
    ++count[s.name];
    frame[s.name] = &f;
  }
  void lidar(const sensors::SensorSpec& s, double, const std::vector<sensors::LidarPoint>&) override { ++count[s.name]; }
  void imu(const sensors::SensorSpec& s, double t, const sensors::ImuSample&) override {
    ++count[s.name];
    imu_stamps.push_back(t);
  }
  void gnss(const sensors::SensorSpec& s, double, const sensors::GnssFix&) override { ++count[s.name]; }
  void velocity(const sensors::SensorSpec& s, double, const sensors::Velocity&) override { ++count[s.name]; }
};

}  // namespace

TEST(SensorRig, EverySensorReportsAtItsRateAndCamerasShareACast) {
  const auto track = test::stadiumTrack();
  sim::World world(track, {});
  world.spawnVehicle("ego", test::sedan(), sim::poseOnTrack(track.poseAt(100)));
  sensors::RayScene scene(track);
  const int id = scene.addVehicle(test::sedanLooks(), {1, 0, 0});
  auto specs = sensors::readSensorSet(test::sourceDir() + "/config/sensors/default.yaml");
  sensors::SensorSpec slow = specs[0];
  slow.name = "slow_rgb";
  slow.rate = 5;
  specs.push_back(slow);
  sensors::SensorRig rig(specs, {}, track.info().origin);
  Counter sink;
  for (int tick = 0; tick < 20; ++tick) {  // one simulated second
    world.step([&](double t) { rig.sampleMotion(t, sensors::motionOf(world.vehicleState("ego")), sink); });
    const auto state = world.vehicleState("ego");
    scene.setVehiclePose(id, sensors::poseOf(state));
    scene.commit();
    rig.sampleRays(world.time(), scene, sensors::poseOf(state), id, sink);
  }
  EXPECT_EQ(sink.count["front_rgb"], 20);
  EXPECT_EQ(sink.count["front_depth"], 20);
  EXPECT_EQ(sink.count["front_semantic"], 20);
  EXPECT_EQ(sink.count["slow_rgb"], 5);
  EXPECT_EQ(sink.count["top_lidar"], 20);
  EXPECT_EQ(sink.count["imu"], 100);
  EXPECT_EQ(sink.count["gnss"], 100);
  EXPECT_EQ(sink.count["velocimeter"], 20);
  EXPECT_EQ(sink.frame["front_rgb"], sink.frame["front_depth"]) << "one cast for the three cameras on the mount";
  EXPECT_EQ(sink.frame["front_rgb"], sink.frame["front_semantic"]);
  EXPECT_NE(sink.frame["front_rgb"], sink.frame["slow_rgb"]);
  ASSERT_EQ(sink.imu_stamps.size(), 100u);
  EXPECT_NEAR(sink.imu_stamps[0], 0.01, 1e-9);
  EXPECT_NEAR(sink.imu_stamps[99], 1.0, 1e-9);
}

TEST(SensorRig, RatesAKindCannotKeepAreRefused) {
  sensors::SensorSpec cam;
  cam.name = "fast_cam";
  cam.type = sensors::SensorType::kCameraRgb;
  cam.rate = 40;  // control rate is 20 Hz
  auto msg = errorOf([&] { sensors::SensorRig({cam}, {}, {}); });
  EXPECT_NE(msg.find("sensor 'fast_cam': field 'rate'"), std::string::npos) << msg;
  sensors::SensorSpec imu;
  imu.name = "imu";
  imu.type = sensors::SensorType::kImu;
  imu.rate = 400;  // physics rate is 200 Hz
  msg = errorOf([&] { sensors::SensorRig({imu}, {}, {}); });
  EXPECT_NE(msg.find("physics rate"), std::string::npos) << msg;
}

TEST(SensorRig, SensorsAttachAndDetachAtRunTime) {
  sensors::SensorSpec imu;
  imu.name = "imu";
  imu.type = sensors::SensorType::kImu;
  imu.rate = 10;
  sensors::SensorRig rig({}, {}, {});
  rig.add(imu, 5.0);
  Counter sink;
  rig.sampleMotion(5.05, {}, sink);
  EXPECT_EQ(sink.count["imu"], 0) << "first report one period after attaching";
  rig.sampleMotion(5.1, {}, sink);
  EXPECT_EQ(sink.count["imu"], 1);
  EXPECT_NE(errorOf([&] { rig.add(imu, 5.1); }).find("already has a sensor"), std::string::npos);
  EXPECT_TRUE(rig.remove("imu"));
  EXPECT_FALSE(rig.remove("imu"));
  rig.sampleMotion(6.0, {}, sink);
  EXPECT_EQ(sink.count["imu"], 1);
}
