#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "roar/sim/vehicle_config.h"
#include "test_support.h"

using namespace roar;
using test::errorOf;


TEST(VehicleConfig, SedanLoadsFromUrdfAndYaml) {
  const auto p = test::sedan();
  EXPECT_DOUBLE_EQ(p.chassis.mass, 1850.0);
  EXPECT_NEAR(p.wheelbase(), 2.875, 1e-9);
  EXPECT_NEAR(p.track_width(), 1.58, 1e-9);
  EXPECT_NEAR(p.wheels[0].position.z(), 0.34, 1e-9) << "front wheel centre through the steering link";
  EXPECT_NEAR(p.wheels[3].position.y(), -0.79, 1e-9);
  EXPECT_DOUBLE_EQ(p.wheels[0].radius, 0.34);
  EXPECT_TRUE(p.wheels[0].front && p.wheels[0].left);
  EXPECT_FALSE(p.wheels[3].front || p.wheels[3].left);
  EXPECT_EQ(p.gearbox.ratios.size(), 6u);
  EXPECT_DOUBLE_EQ(p.engine.redline_rpm, 6800);
  EXPECT_TRUE(p.brakes.abs);
}

TEST(VehicleConfig, UnknownModelListsTheKnownOnes) {
  const auto msg = errorOf([] {
    sim::loadVehicleModel("bus", test::sourceDir() + "/urdf", test::sourceDir() + "/config/vehicles");
  });
  EXPECT_NE(msg.find("unknown vehicle model 'bus'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sedan"), std::string::npos) << msg;
}

TEST(VehicleConfig, BrokenUrdfIsAClearError) {
  sim::VehicleParams p;
  auto msg = errorOf([&] { sim::readVehicleUrdfString("<robot name='x'><link", "car.urdf", &p); });
  EXPECT_NE(msg.find("car.urdf: not a valid URDF"), std::string::npos) << msg;
  msg = errorOf([&] {
    sim::readVehicleUrdfString("<robot name='x'><link name='base_link'/></robot>", "car.urdf", &p);
  });
  EXPECT_NE(msg.find("car.urdf: base_link has no <inertial>"), std::string::npos) << msg;
}

TEST(VehicleConfig, MissingYamlFieldIsNamed) {
  const auto dir = std::filesystem::temp_directory_path() / ("roar_vc_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ifstream in(test::sourceDir() + "/config/vehicles/sedan.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto pos = text.find("  final_drive: 3.60\n");
  ASSERT_NE(pos, std::string::npos);
  text.erase(pos, std::string("  final_drive: 3.60\n").size());
  const auto path = (dir / "car.yaml").string();
  std::ofstream(path) << text;
  sim::VehicleParams p;
  const auto msg = errorOf([&] { sim::readVehicleYaml(path, &p); });
  EXPECT_NE(msg.find(path + ": missing field 'gearbox.final_drive'"), std::string::npos) << msg;
  std::ofstream(path) << "engine: {idle_rpm: fast}\n";
  const auto msg2 = errorOf([&] { sim::readVehicleYaml(path, &p); });
  EXPECT_NE(msg2.find("missing field 'drivetrain.front_drive_share'"), std::string::npos) << msg2;
  std::filesystem::remove_all(dir);
}

TEST(VehicleConfig, ValidateRejectsImplausibleValues) {
  auto p = test::sedan();
  p.gearbox.ratios = {2.0, 3.0};
  EXPECT_NE(errorOf([&] { sim::validate(p, "x"); }).find("must fall"), std::string::npos);
  p = test::sedan();
  p.chassis.mass = -1;
  EXPECT_NE(errorOf([&] { sim::validate(p, "x"); }).find("mass"), std::string::npos);
}
