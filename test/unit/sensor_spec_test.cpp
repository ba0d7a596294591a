#include <gtest/gtest.h>

#include "roar/sensors/sensor_spec.h"
#include "test_support.h"

using namespace roar;
using test::errorOf;

namespace {
std::string parseError(const std::string& sensor_yaml) {
  return errorOf([&] { sensors::parseSensorSetYaml("sensors:\n  - " + sensor_yaml + "\n", "set.yaml"); });
}
}  // namespace

TEST(SensorSpec, TheDefaultSetLoads) {
  const auto specs = sensors::readSensorSet(test::sourceDir() + "/config/sensors/default.yaml");
  ASSERT_EQ(specs.size(), 7u);
  EXPECT_EQ(specs[0].type, sensors::SensorType::kCameraRgb);
  EXPECT_EQ(specs[0].camera.width, 84);
  EXPECT_NEAR(specs[0].mount.pitch, 5 * M_PI / 180, 1e-12);
  EXPECT_EQ(specs[3].type, sensors::SensorType::kLidar);
  EXPECT_EQ(specs[3].lidar.num_lasers, 32);
  EXPECT_EQ(specs[3].lidar.points_per_second, 56000);
  EXPECT_EQ(specs[4].rate, 100);
}

TEST(SensorSpec, BadFieldsAreNamedWithTheSensor) {
  EXPECT_NE(parseError("{name: cam, type: camera_rgb, image_width: 0}")
                .find("set.yaml: sensor 'cam': image_width: 0 is outside [1, 4096] pixels"),
            std::string::npos);
  EXPECT_NE(
      parseError("{name: cam, type: camera_rgb, image_height: -4}").find("sensor 'cam': image_height: -4 is outside"),
      std::string::npos);
  EXPECT_NE(parseError("{name: cam, type: camera_depth, fov: 180}")
                .find("sensor 'cam': fov: 180 must be in (0, 180) degrees"),
            std::string::npos);
  EXPECT_NE(parseError("{name: cam, type: camera_depth, fov: 0}").find("fov: 0 must be"), std::string::npos);
  EXPECT_NE(
      parseError("{name: l, type: lidar, num_lasers: 1000}").find("sensor 'l': num_lasers: 1000 is outside [1, 256]"),
      std::string::npos);
  EXPECT_NE(parseError("{name: l, type: lidar, upper_fov: -40}").find("upper_fov: must be above lower_fov"),
            std::string::npos);
  EXPECT_NE(parseError("{name: r, type: sonar}").find("sensor 'r': type: unknown type 'sonar'"), std::string::npos);
  EXPECT_NE(parseError("{name: i, type: imu, rate: 0}").find("sensor 'i': rate: 0 is outside [0.01, 10000] Hz"),
            std::string::npos);
  EXPECT_NE(parseError("{name: i, type: imu, x: abc}").find("sensor 'i': x: is not a number"), std::string::npos);
  EXPECT_NE(parseError("{type: imu}").find("needs a 'name'"), std::string::npos);
  const auto twice = errorOf(
      [] { sensors::parseSensorSetYaml("sensors: [{name: a, type: imu}, {name: a, type: gnss}]", "set.yaml"); });
  EXPECT_NE(twice.find("'a' is used twice"), std::string::npos) << twice;
  EXPECT_NE(errorOf([] { sensors::readSensorSet("/no/such/set.yaml"); }).find("/no/such/set.yaml"), std::string::npos);
}

TEST(SensorSpec, MisspeltAndForeignKeysAreRefusedWithTheNearestKey) {
  const std::string misspelt = parseError("{name: cam, type: camera_rgb, imag_width: 84}");
  EXPECT_NE(misspelt.find("set.yaml: sensor 'cam': imag_width: is not a known key (did you mean 'image_width'?)"),
            std::string::npos)
      << misspelt;
  // A key of another type is as wrong as a misspelt one: an IMU has no image.
  EXPECT_NE(parseError("{name: i, type: imu, image_width: 84}").find("sensor 'i': image_width: is not a known key"),
            std::string::npos);
  EXPECT_NE(errorOf([] {
              sensors::parseSensorSetYaml("sensor: []", "set.yaml");
            }).find("set.yaml: sensor: is not a known key (did you mean 'sensors'?)"),
            std::string::npos);
}

TEST(SensorSpec, ValuesOutsidePhysicalRangesAreRefusedWithTheValue) {
  EXPECT_NE(parseError("{name: c, type: camera_rgb, x: 1e38}")
                .find("sensor 'c': x: 1e+38 is outside [-20, 20] m of base_link"),
            std::string::npos);
  EXPECT_NE(parseError("{name: l, type: lidar, z: 1e300}").find("z: 1e+300 is outside"), std::string::npos);
  EXPECT_NE(parseError("{name: c, type: camera_rgb, yaw: 1e9}").find("yaw: 1e+09 is outside [-360, 360] degrees"),
            std::string::npos);
  EXPECT_NE(parseError("{name: c, type: camera_rgb, image_width: 8192, image_height: 8192}")
                .find("image_width: 8192 is outside"),
            std::string::npos);
  EXPECT_NE(
      parseError("{name: c, type: camera_rgb, image_width: 4096, image_height: 4096}").find("more than 8388608 pixels"),
      std::string::npos);
  EXPECT_NE(parseError("{name: i, type: imu, accel_bias: [.nan, 0, 0]}")
                .find("accel_bias: holds a number that is not finite"),
            std::string::npos);
  EXPECT_NE(parseError("{name: i, type: imu, gyro_bias: [.inf, 0, 0]}").find("gyro_bias:"), std::string::npos);
  EXPECT_NE(parseError("{name: i, type: imu, accel_bias: [0, 0]}").find("accel_bias: must be [x, y, z]"),
            std::string::npos);
  EXPECT_NE(
      parseError("{name: l, type: lidar, points_per_second: 1e9}").find("points_per_second: 1e+09 must be at least"),
      std::string::npos);
  EXPECT_NE(parseError("{name: a, type: accelerometer, noise_std: -1}").find("noise_std: -1 is outside [0, 100] m/s^2"),
            std::string::npos);
  EXPECT_NE(
      parseError("{name: a, type: accelerometer, frame: body}").find("frame: must be 'sensor' or 'map', not 'body'"),
      std::string::npos);
  EXPECT_NE(parseError("{name: r, type: roll_pitch_yaw, frame: map}").find("frame: is not a known key"),
            std::string::npos);
  EXPECT_NE(parseError("{name: o, type: occupancy_map, width_m: 0}").find("width_m: 0 is outside (0, 1000] m"),
            std::string::npos);
  EXPECT_NE(
      parseError("{name: o, type: occupancy_map, image_height: 5000}").find("image_height: 5000 is outside [1, 2048]"),
      std::string::npos);
}

TEST(SensorSpec, ROARPYsOtherSensorsParse) {
  const auto specs = sensors::parseSensorSetYaml(R"(sensors:
  - {name: a, type: accelerometer, rate: 100, noise_std: 0.1, bias: [0.1, 0, 0], frame: map, gravity: false}
  - {name: g, type: gyroscope, rate: 100, noise_std: 0.01}
  - {name: r, type: roll_pitch_yaw, rate: 20, noise_std: 0.001}
  - {name: l, type: location, rate: 20, z: 1.5, noise_std: 0.2}
  - {name: o, type: occupancy_map, rate: 10, image_width: 100, image_height: 60, width_m: 50, height_m: 30})",
                                                 "set.yaml");
  ASSERT_EQ(specs.size(), 5u);
  EXPECT_EQ(specs[0].type, sensors::SensorType::kAccelerometer);
  EXPECT_TRUE(specs[0].vector.map_frame);
  EXPECT_FALSE(specs[0].vector.gravity);
  EXPECT_EQ(specs[0].vector.bias.x(), 0.1);
  EXPECT_EQ(specs[1].type, sensors::SensorType::kGyroscope);
  EXPECT_FALSE(specs[1].vector.map_frame);
  EXPECT_EQ(specs[2].type, sensors::SensorType::kRollPitchYaw);
  EXPECT_EQ(specs[3].vector.noise_std, 0.2);
  EXPECT_EQ(specs[4].occupancy.width, 100);
  EXPECT_EQ(specs[4].occupancy.height_m, 30);
  EXPECT_TRUE(sensors::castsRays(specs[4].type));
  EXPECT_FALSE(sensors::castsRays(specs[3].type));
}

// A sensor on no car is mounted in the map frame: anywhere on the map, where one on a car stays within
// 20 m of its base_link; only the kinds that see can stand on their own.
TEST(SensorSpec, ASensorOnNoCarIsMountedAnywhereOnTheMap) {
  const std::string yaml = "sensors: [{name: post, type: camera_rgb, x: 850, y: -420.5, z: 12, pitch: 20}]";
  const auto specs = sensors::parseSensorSetYaml(yaml, "world.yaml", sensors::kInTheWorld);
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].mount.position.x(), 850.0);
  try {
    sensors::parseSensorSetYaml(yaml, "car.yaml");
    FAIL() << "850 m from base_link accepted on a car";
  } catch (const sensors::SensorSpecError& e) {
    EXPECT_NE(std::string(e.what()).find("x: 850 is outside [-20, 20] m of base_link"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sensors::parseSensorSetYaml("sensors: [{name: far, type: lidar, x: 2e5}]", "w", sensors::kInTheWorld),
               sensors::SensorSpecError);
  for (const auto type : {sensors::SensorType::kCameraRgb, sensors::SensorType::kCameraDepth,
                          sensors::SensorType::kLidar, sensors::SensorType::kRadar})
    EXPECT_TRUE(sensors::seesFromAnywhere(type)) << sensors::typeName(type);
  for (const auto type : {sensors::SensorType::kImu, sensors::SensorType::kGnss, sensors::SensorType::kOccupancyMap,
                          sensors::SensorType::kLocation})
    EXPECT_FALSE(sensors::seesFromAnywhere(type)) << sensors::typeName(type);
}

TEST(SensorSpec, ANameMustBeARosNameAndASetMustHoldASensor) {
  EXPECT_NE(parseError("{name: ~, type: imu}").find("a sensor's 'name' must be a plain name"), std::string::npos);
  EXPECT_NE(parseError("{name: [a], type: imu}").find("a sensor's 'name' must be a plain name"), std::string::npos);
  EXPECT_NE(parseError("{name: 2cam, type: imu}").find("sensor name '2cam' must start with a letter"),
            std::string::npos);
  EXPECT_NE(parseError("{name: a~b, type: imu}").find("sensor name 'a~b'"), std::string::npos);
  EXPECT_EQ(errorOf([] { sensors::parseSensorSetYaml("[]", "set.yaml"); }),
            "set.yaml: the list of sensors is empty (name no set for no sensors)");
  EXPECT_EQ(errorOf([] { sensors::parseSensorSetYaml("sensors: []", "set.yaml"); }),
            "set.yaml: the list of sensors is empty (name no set for no sensors)");
}

TEST(SensorSpec, AServiceCallerNamesASetAndNeverAFile) {
  const std::string dir = test::sourceDir() + "/config/sensors";
  EXPECT_EQ(sensors::sensorSetByName("default", dir), dir + "/default.yaml");
  // A path, an existing file elsewhere and a missing one get the same answer, naming no file's contents.
  for (const std::string asked : {"/etc/shadow", "/etc/passwd", "/no/such", "../sensors/default", "default.yaml"}) {
    const std::string error = errorOf([&] { sensors::sensorSetByName(asked, dir); });
    EXPECT_EQ(error.find("sensor_set: no sensor set '" + asked + "' in " + dir), 0u) << error;
    EXPECT_EQ(error.find("root"), std::string::npos) << error;
  }
  EXPECT_NE(errorOf([&] { sensors::sensorSetByName("defualt", dir); }).find("(did you mean 'default'?)"),
            std::string::npos);
  // A name given at launch (~sensor_set:=defualt, a scenario's sensors:) is looked up the same way.
  EXPECT_NE(errorOf([&] {
              sensors::resolveSensorSet("defualt", dir);
            }).find("no sensor set 'defualt' in " + dir + " (did you mean 'default'?) (sets: default; or a YAML"),
            std::string::npos);
}
