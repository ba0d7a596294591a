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
  EXPECT_NE(parseError("{name: cam, type: camera_rgb, image_width: 0}").find("set.yaml: sensor 'cam': field 'image_width'"),
            std::string::npos);
  EXPECT_NE(parseError("{name: cam, type: camera_rgb, image_height: -4}").find("sensor 'cam': field 'image_height'"),
            std::string::npos);
  EXPECT_NE(parseError("{name: cam, type: camera_depth, fov: 180}").find("sensor 'cam': field 'fov' must be in (0, 180)"),
            std::string::npos);
  EXPECT_NE(parseError("{name: cam, type: camera_depth, fov: 0}").find("field 'fov'"), std::string::npos);
  EXPECT_NE(parseError("{name: l, type: lidar, num_lasers: 1000}").find("sensor 'l': field 'num_lasers'"), std::string::npos);
  EXPECT_NE(parseError("{name: l, type: lidar, upper_fov: -40}").find("field 'upper_fov'"), std::string::npos);
  EXPECT_NE(parseError("{name: r, type: radar}").find("sensor 'r': unknown type 'radar'"), std::string::npos);
  EXPECT_NE(parseError("{name: i, type: imu, rate: 0}").find("sensor 'i': field 'rate'"), std::string::npos);
  EXPECT_NE(parseError("{name: i, type: imu, x: abc}").find("field 'x' is not a number"), std::string::npos);
  EXPECT_NE(parseError("{type: imu}").find("needs a 'name'"), std::string::npos);
  const auto twice = errorOf([] {
    sensors::parseSensorSetYaml("sensors: [{name: a, type: imu}, {name: a, type: gnss}]", "set.yaml");
  });
  EXPECT_NE(twice.find("'a' is used twice"), std::string::npos) << twice;
  EXPECT_NE(errorOf([] { sensors::readSensorSet("/no/such/set.yaml"); }).find("/no/such/set.yaml"), std::string::npos);
}
