#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>

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
  void camera(const sensors::SensorSpec& s, double, const sensors::CameraFrame& f,
              const sensors::CameraIntrinsics&) override {
    ++count[s.name];
    frame[s.name] = &f;
  }
  void lidar(const sensors::SensorSpec& s, double, const std::vector<sensors::LidarPoint>&) override {
    ++count[s.name];
  }
  void imu(const sensors::SensorSpec& s, double t, const sensors::ImuSample&) override {
    ++count[s.name];
    imu_stamps.push_back(t);
  }
  void gnss(const sensors::SensorSpec& s, double, const sensors::GnssFix&) override { ++count[s.name]; }
  void velocity(const sensors::SensorSpec& s, double, const sensors::Velocity&) override { ++count[s.name]; }
  void vector(const sensors::SensorSpec& s, double, const Eigen::Vector3d& v) override {
    ++count[s.name];
    vectors[s.name] = v;
  }
  void occupancy(const sensors::SensorSpec& s, double, const sensors::OccupancyFrame& f) override {
    ++count[s.name];
    occupancy_frame = f;
  }
  std::map<std::string, Eigen::Vector3d> vectors;
  sensors::OccupancyFrame occupancy_frame;
};

}  // namespace

TEST(SensorRig, EverySensorReportsAtItsRateAndCamerasShareACast) {
  const auto track = test::stadiumTrack();
  sim::World world(track, {});
  world.spawnVehicle("ego", test::sedan(), track::poseOnTrack(track.poseAt(100)));
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

// castsRaysAt says whether sampleRays would cast a ray at a tick, so that a tick whose sensors cast none need
// not pose the scene: an on-demand camera nobody wants casts none, a LiDAR between its samples none.
TEST(SensorRig, OnlySensorsThatAreDueAndWantedCastRays) {
  struct Wanting : Counter {
    bool want = false;
    bool wanted(const sensors::SensorSpec&) override { return want; }
  };
  const auto track = test::stadiumTrack();
  sensors::RayScene scene(track);
  const int id = scene.addVehicle(test::sedanLooks(), {1, 0, 0});
  const auto all = sensors::readSensorSet(test::sourceDir() + "/config/sensors/default.yaml");
  std::vector<sensors::SensorSpec> specs;
  for (auto spec : all) {
    if (spec.name == "front_rgb") {
      spec.camera.on_demand = true;
      specs.push_back(spec);
    }
    if (spec.name == "top_lidar") {
      spec.rate = 10;  // every other tick
      specs.push_back(spec);
    }
  }
  ASSERT_EQ(specs.size(), 2u);
  sensors::SensorRig rig(specs, {}, track.info().origin);
  Wanting sink;
  const Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (int tick = 1; tick <= 8; ++tick) {
    const double t = 0.05 * tick;
    sink.want = tick == 3;
    const bool lidar_due = tick % 2 == 0;
    EXPECT_EQ(rig.castsRaysAt(t, sink), lidar_due || sink.want) << "tick " << tick;
    rig.sampleRays(t, scene, pose, id, sink);
    EXPECT_EQ(sink.count["front_rgb"], tick >= 3 ? 1 : 0) << "rendered only when wanted, at tick 3";
    EXPECT_EQ(sink.count["top_lidar"], tick / 2);
  }
}

TEST(SensorRig, RatesAKindCannotKeepAreRefused) {
  sensors::SensorSpec cam;
  cam.name = "fast_cam";
  cam.type = sensors::SensorType::kCameraRgb;
  cam.rate = 40;  // control rate is 20 Hz
  auto msg = errorOf([&] { sensors::SensorRig({cam}, {}, {}); });
  EXPECT_NE(msg.find("sensor 'fast_cam': rate: 40"), std::string::npos) << msg;
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

TEST(SensorRig, TimingChangesAreRefusedWhenASensorCannotKeepItsRate) {
  sensors::SensorSpec cam;
  cam.name = "cam";
  cam.type = sensors::SensorType::kCameraRgb;
  cam.rate = 20;
  sensors::SensorSpec gyro;
  gyro.name = "gyro";
  gyro.type = sensors::SensorType::kGyroscope;
  gyro.rate = 100;
  sensors::SensorRig rig({cam, gyro}, {}, {});
  const std::string msg = errorOf([&] { rig.setTiming(0.1, 0.005); });
  EXPECT_NE(msg.find("sensor 'cam': rate: 20"), std::string::npos) << msg;
  EXPECT_NE(errorOf([&] { rig.setTiming(0.05, 0.025); }).find("sensor 'gyro'"), std::string::npos);
  rig.setTiming(0.025, 0.005);  // faster steps keep every rate
  EXPECT_NE(errorOf([&] { rig.add(cam, 0.0); }).find("already"), std::string::npos);
}

TEST(SensorRig, OneVectorSensorsAndTheOccupancyMapReport) {
  const auto track = test::stadiumTrack();
  sim::World world(track, {});
  world.spawnVehicle("ego", test::sedan(), track::poseOnTrack(track.poseAt(100)));
  world.spawnVehicle("rival", test::sedan(), track::poseOnTrack(track.poseAt(110)));
  sensors::RayScene scene(track);
  const int ego = scene.addVehicle(test::sedanLooks(), {1, 0, 0});
  const int rival = scene.addVehicle(test::sedanLooks(), {0, 0, 1});
  const auto specs = sensors::parseSensorSetYaml(R"(sensors:
  - {name: accel, type: accelerometer, rate: 50}
  - {name: gyro, type: gyroscope, rate: 50, frame: map}
  - {name: rpy, type: roll_pitch_yaw, rate: 20}
  - {name: where, type: location, rate: 20, z: 1.0}
  - {name: occupancy, type: occupancy_map, rate: 10, image_width: 80, image_height: 80, width_m: 40, height_m: 40})",
                                                 "set.yaml");
  sensors::SensorRig rig(specs, {}, track.info().origin);
  Counter sink;
  for (int tick = 0; tick < 20; ++tick) {
    world.step([&](double t) { rig.sampleMotion(t, sensors::motionOf(world.vehicleState("ego")), sink); });
    scene.setVehiclePose(ego, sensors::poseOf(world.vehicleState("ego")));
    scene.setVehiclePose(rival, sensors::poseOf(world.vehicleState("rival")));
    scene.commit();
    rig.sampleRays(world.time(), scene, sensors::poseOf(world.vehicleState("ego")), ego, sink);
  }
  EXPECT_EQ(sink.count["accel"], 50);
  EXPECT_EQ(sink.count["gyro"], 50);
  EXPECT_EQ(sink.count["rpy"], 20);
  EXPECT_EQ(sink.count["where"], 20);
  EXPECT_EQ(sink.count["occupancy"], 10);
  EXPECT_NEAR(sink.vectors["accel"].z(), 9.81, 0.05) << "parked: gravity up";
  EXPECT_LT(sink.vectors["gyro"].norm(), 1e-3);
  EXPECT_NEAR(sink.vectors["rpy"].z(), 0.0, 1e-3) << "heading east";
  EXPECT_NEAR(sink.vectors["where"].x(), 100.0, 0.01);
  EXPECT_NEAR(sink.vectors["where"].z(), 1.0, 0.05);

  const auto& map = sink.occupancy_frame;
  ASSERT_EQ(map.width, 80);
  ASSERT_EQ(map.height, 80);
  auto pixel = [&](double forward, double left) {
    const int row = static_cast<int>(std::floor(40 - forward / 0.5)),
              col = static_cast<int>(std::floor(40 - left / 0.5));
    return map.pixels[static_cast<std::size_t>(row) * 80 + static_cast<std::size_t>(col)];
  };
  EXPECT_EQ(pixel(0.2, 0.2), sensors::kOccupancyRoad) << "the car's own body is left out";
  EXPECT_EQ(pixel(10.2, 0.2), sensors::kOccupancyVehicle) << "the rival 10 m ahead";
  EXPECT_EQ(pixel(-10.2, 0.2), sensors::kOccupancyRoad);
  EXPECT_EQ(pixel(0.2, 5.2), sensors::kOccupancyRoad) << "the road is 12 m wide";
  EXPECT_EQ(pixel(0.2, 8.2), sensors::kOccupancyElsewhere) << "grass beyond the left edge";
  EXPECT_EQ(pixel(0.2, -8.2), sensors::kOccupancyElsewhere) << "and the right one";
}

namespace {

// Every reading checked for NaN and infinities (a depth camera's +inf, "nothing hit", allowed).
struct FiniteSink : sensors::SensorSink {
  int readings = 0, bad = 0;
  void check(bool finite) {
    ++readings;
    bad += !finite;
  }
  void camera(const sensors::SensorSpec&, double, const sensors::CameraFrame& f,
              const sensors::CameraIntrinsics&) override {
    bool ok = true;
    for (float d : f.depth) ok = ok && !std::isnan(d) && d >= 0.0f;
    check(ok);
  }
  void lidar(const sensors::SensorSpec&, double, const std::vector<sensors::LidarPoint>& points) override {
    bool ok = true;
    for (const auto& p : points)
      ok = ok && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.intensity);
    check(ok);
  }
  void imu(const sensors::SensorSpec&, double, const sensors::ImuSample& s) override {
    check(s.orientation.coeffs().allFinite() && s.angular_velocity.allFinite() && s.linear_acceleration.allFinite());
  }
  void gnss(const sensors::SensorSpec&, double, const sensors::GnssFix& f) override {
    check(std::isfinite(f.latitude) && std::isfinite(f.longitude) && std::isfinite(f.altitude));
  }
  void velocity(const sensors::SensorSpec&, double, const sensors::Velocity& v) override {
    check(v.linear_body.allFinite() && v.angular_body.allFinite() && v.linear_world.allFinite() &&
          v.angular_world.allFinite());
  }
  void vector(const sensors::SensorSpec&, double, const Eigen::Vector3d& v) override { check(v.allFinite()); }
  void occupancy(const sensors::SensorSpec&, double, const sensors::OccupancyFrame& f) override {
    check(f.width > 0 && f.height > 0 && f.pixels.size() == static_cast<std::size_t>(f.width) * f.height);
  }
};

}  // namespace

TEST(SensorRig, EveryNumberOfEverySensorAtEveryExtremeIsRefusedByNameOrReadsFinite) {
  // Property test (issue 17): each number of a sensor of every kind set to 0, -1, 1e-30, 1e30, 1e300, NaN
  // and inf in turn: refused naming the field, or a sensor whose every reading over a second on a moving
  // car is finite.
  const std::vector<std::string> sensors = {
      "{name: s, type: camera_rgb, x: 0.6, y: 0.1, z: 1.55, roll: 1, pitch: 5, yaw: 2, rate: 20, fov: 90, image_width: "
      "32, "
      "image_height: 24, seed: 3}",
      "{name: s, type: camera_depth, x: 0.6, z: 1.55, rate: 10, fov: 60, image_width: 16, image_height: 16}",
      "{name: s, type: lidar, x: 0.1, z: 1.9, rate: 20, num_lasers: 16, max_distance: 50, points_per_second: 20000, "
      "rotation_frequency: 20, upper_fov: 10, lower_fov: -30, horizontal_fov: 360, noise_std: 0.01}",
      "{name: s, type: imu, x: -0.086, z: 0.5, rate: 100, accel_noise_std: 0.1, gyro_noise_std: 0.01, "
      "accel_bias: [0.1, 0.1, 0.1], gyro_bias: [0.01, 0.01, 0.01]}",
      "{name: s, type: gnss, z: 1.5, rate: 10, horizontal_noise_std: 0.5, vertical_noise_std: 0.5}",
      "{name: s, type: velocimeter, x: 1, rate: 20}",
      "{name: s, type: accelerometer, z: 0.5, rate: 50, noise_std: 0.1, bias: [0.1, 0.0, 0.0]}",
      "{name: s, type: location, rate: 20, noise_std: 0.2, bias: [1.0, 0.0, 0.0]}",
      "{name: s, type: occupancy_map, rate: 10, image_width: 32, image_height: 32, width_m: 40, height_m: 40}",
  };
  const auto track = test::stadiumTrack();
  const std::regex number(R"(([a-z_]+): (\[)?(-?[0-9.]+))");
  int refused = 0, loaded = 0, fields = 0;
  for (const auto& sensor : sensors) {
    fields += test::forEachNumberAtExtremes(
        sensor, number, [&](const std::string& key, const std::string& text, const std::string& extreme) {
          const std::string what = text.substr(0, 40) + "... " + key + " = " + extreme;
          std::vector<sensors::SensorSpec> specs;
          try {
            specs = sensors::parseSensorSetYaml("sensors:\n  - " + text + "\n", "set.yaml");
            sensors::SensorRig probe(specs, {}, track.info().origin);  // the rig's own checks (rates it can keep)
          } catch (const std::exception& e) {
            EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << what << ": " << e.what();
            ++refused;
            return;
          }
          ++loaded;
          sim::World world(track, {});
          world.spawnVehicle("ego", test::sedan(), track::poseOnTrack(track.poseAt(100)));
          vehicle::VehicleControl go;
          go.throttle = 1.0;
          go.steer = 0.2;
          sensors::RayScene scene(track);
          const int id = scene.addVehicle(test::sedanLooks(), {1, 0, 0});
          sensors::SensorRig rig(specs, {}, track.info().origin);
          FiniteSink sink;
          for (int tick = 0; tick < 20; ++tick) {
            world.setControl("ego", go);
            world.step([&](double t) { rig.sampleMotion(t, sensors::motionOf(world.vehicleState("ego")), sink); });
            const auto state = world.vehicleState("ego");
            scene.setVehiclePose(id, sensors::poseOf(state));
            scene.commit();
            rig.sampleRays(world.time(), scene, sensors::poseOf(state), id, sink);
          }
          EXPECT_GT(sink.readings, 0) << what;
          EXPECT_EQ(sink.bad, 0) << what << ": " << sink.bad << " of " << sink.readings << " readings not finite";
        });
  }
  std::printf("sensor property test: %d fields x 7 extremes: %d refused by name, %d read finite\n", fields, refused,
              loaded);
}

TEST(SensorRig, SensorsBeyondACarsBudgetAreRefusedByName) {
  sensors::SensorSpec big;
  big.type = sensors::SensorType::kCameraRgb;
  big.camera.width = 4096;
  big.camera.height = 2048;
  big.rate = 10.0;
  sensors::SensorRig rig({}, {}, {});
  for (const char* name : {"a", "b"}) {
    big.name = name;
    rig.add(big, 0.0);  // two of the largest cameras fit a car's budget
  }
  big.name = "c";
  EXPECT_EQ(test::errorOf([&] { rig.add(big, 0.0); }),
            "sensor 'c': a car's sensors would hold 25.2 million pixels or points a frame, more than its budget of "
            "16.8 million; make images smaller or use fewer sensors");
  EXPECT_EQ(rig.specs().size(), 2u) << "a refused sensor leaves the rig as it was";
  // Small frames at a high rate are bounded by the rays they cast.
  sensors::SensorRig fast({}, {}, {});  // 20 Hz control
  sensors::SensorSpec cam = big;
  cam.camera.width = 4096;
  cam.camera.height = 1024;
  cam.rate = 20.0;
  cam.name = "a";
  fast.add(cam, 0.0);
  cam.name = "b";
  fast.add(cam, 0.0);
  cam.name = "c";
  cam.camera.height = 512;
  EXPECT_NE(
      test::errorOf([&] { fast.add(cam, 0.0); }).find("sensor 'c': a car's sensors would cast 209.7 million rays"),
      std::string::npos);
}

TEST(SensorRig, TheSimulatorsBudgetCountsEveryCar) {
  sensors::SensorSpec cam;
  cam.type = sensors::SensorType::kCameraRgb;
  cam.name = "cam";
  cam.camera.width = 4096;
  cam.camera.height = 2048;
  cam.rate = 1.0;
  sensors::SensorLoad in_use;
  for (int car = 0; car < 4; ++car) {
    sensors::checkBudget(in_use, cam, sensors::kSimulatorSensorBudget);
    in_use += sensors::loadOf(cam);
  }
  EXPECT_NE(test::errorOf([&] {
              sensors::checkBudget(in_use, cam, sensors::kSimulatorSensorBudget);
            }).find("sensor 'cam': roar_sim's sensors would hold 41.9 million pixels"),
            std::string::npos);
  sensors::SensorSpec lidar;
  lidar.type = sensors::SensorType::kLidar;
  lidar.lidar.points_per_second = 1e6;
  lidar.rate = 10.0;
  EXPECT_EQ(sensors::loadOf(lidar).rays_per_second, 1e6);
  EXPECT_EQ(sensors::loadOf(lidar).samples, 1e5);
}
