#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <yaml-cpp/yaml.h>

#include <cstdio>

#include "roar/sim/world.h"
#include "roar/vehicle/vehicle_config.h"
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
  const auto msg = errorOf(
      [] { vehicle::loadVehicleModel("bus", test::sourceDir() + "/urdf", test::sourceDir() + "/config/vehicles"); });
  EXPECT_NE(msg.find("unknown vehicle model or blueprint 'bus'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("carla_a2 (vehicle.audi.a2), carla_model3 (vehicle.tesla.model3), hatchback, racecar "
                     "(vehicle.roar.racecar), sedan"),
            std::string::npos)
      << msg;
}

TEST(VehicleConfig, BlueprintIdsNameTheirModels) {
  const std::string urdf = test::sourceDir() + "/urdf", config = test::sourceDir() + "/config/vehicles";
  // ROAR_PY programs' blueprints are CARLA's cars; the road cars keep their own names.
  EXPECT_EQ(vehicle::resolveVehicleModel("vehicle.tesla.model3", urdf, config), "carla_model3");
  EXPECT_EQ(vehicle::resolveVehicleModel("vehicle.audi.a2", urdf, config), "carla_a2");
  EXPECT_EQ(vehicle::resolveVehicleModel("hatchback", urdf, config), "hatchback");
  EXPECT_EQ(vehicle::resolveVehicleModel("vehicle.roar.racecar", urdf, config), "racecar");
  EXPECT_EQ(vehicle::resolveVehicleModel("sedan", urdf, config), "sedan");
  const auto a2 = vehicle::loadVehicleModel("vehicle.audi.a2", urdf, config);
  EXPECT_EQ(a2.model, "carla_a2");
  EXPECT_EQ(a2.blueprint, "vehicle.audi.a2");
  EXPECT_EQ(a2.front_drive_share, 1.0) << "front-wheel drive";
  const auto racecar = vehicle::loadVehicleModel("racecar", urdf, config);
  EXPECT_EQ(racecar.front_drive_share, 0.0) << "rear-wheel drive";
  EXPECT_GT(racecar.aero.downforce_area, 2.0);
  EXPECT_LT(racecar.chassis.mass, 800.0);
  EXPECT_EQ(vehicle::listVehicleModels(urdf, config).size(), 5u);
}

TEST(VehicleConfig, BrokenUrdfIsAClearError) {
  vehicle::VehicleParams p;
  auto msg = errorOf([&] { vehicle::readVehicleUrdfString("<robot name='x'><link", "car.urdf", &p); });
  EXPECT_NE(msg.find("car.urdf: not a valid URDF"), std::string::npos) << msg;
  msg = errorOf(
      [&] { vehicle::readVehicleUrdfString("<robot name='x'><link name='base_link'/></robot>", "car.urdf", &p); });
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
  vehicle::VehicleParams p;
  const auto msg = errorOf([&] { vehicle::readVehicleYaml(path, &p); });
  EXPECT_NE(msg.find(path + ": gearbox.final_drive: is missing"), std::string::npos) << msg;
  std::ofstream(path) << "engine: {idle_rpm: fast}\n";
  const auto msg2 = errorOf([&] { vehicle::readVehicleYaml(path, &p); });
  EXPECT_NE(msg2.find("drivetrain.front_drive_share: is missing"), std::string::npos) << msg2;
  std::filesystem::remove_all(dir);
}

TEST(VehicleConfig, MisspeltKeysAndValuesOutsidePhysicalRangesAreRefused) {
  const auto dir = std::filesystem::temp_directory_path() / ("roar_vc_range_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ifstream in(test::sourceDir() + "/config/vehicles/sedan.yaml");
  const std::string sedan((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto errorWith = [&](const std::string& from, const std::string& to) {
    std::string text = sedan;
    const auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    text.replace(pos, from.size(), to);
    const auto path = (dir / "car.yaml").string();
    std::ofstream(path) << text;
    vehicle::VehicleParams p;
    return errorOf([&] { vehicle::readVehicleYaml(path, &p); });
  };
  EXPECT_NE(errorWith("stiffness_n_per_m: 45000", "stiffness_n_per_m: 4500000")
                .find("suspension.stiffness_n_per_m: 4.5e+06 is outside [1000, 1e+06] N/m"),
            std::string::npos)
      << "a 100x typo";
  EXPECT_NE(
      errorWith("stiffness_n_per_m: 45000", "stiffness_n_per_m: 1e300").find("stiffness_n_per_m: 1e+300 is outside"),
      std::string::npos);
  EXPECT_NE(errorWith("drag_area_m2: 0.62", "drag_area_m2: 1e30").find("aero.drag_area_m2: 1e+30 is outside [0, 10]"),
            std::string::npos);
  EXPECT_NE(errorWith("downforce_area_m2: 0.25", "downforce_area_m2: 1e30").find("aero.downforce_area_m2"),
            std::string::npos);
  EXPECT_NE(errorWith("drag_area_m2: 0.62", "drag_area_m2: .nan").find("aero.drag_area_m2: is not a finite number"),
            std::string::npos);
  EXPECT_NE(errorWith("  abs: true", "  abss: true").find("brakes.abss: is not a known key (did you mean 'abs'?)"),
            std::string::npos);
  EXPECT_NE(errorWith("aero:", "areo:").find("areo: is not a known key (did you mean 'aero'?)"), std::string::npos);
  EXPECT_NE(errorWith("stiffness_n_per_m: 45000", "stifness_n_per_m: 45000")
                .find("suspension.stiffness_n_per_m: is missing (is 'stifness_n_per_m' a misspelling of it?)"),
            std::string::npos);
  const std::string split = "  front_drive_share: 0.4";
  EXPECT_NE(errorWith(split, split + "\n  differential: locked")
                .find("drivetrain.differential: 'locked' is neither open nor limited_slip"),
            std::string::npos);
  EXPECT_NE(errorWith(split, split + "\n  differential: limited_slip\n  rear_bias: 0.5")
                .find("drivetrain.rear_bias: 0.5 is outside [1, 100]"),
            std::string::npos)
      << "a bias below 1 would move torque with the wheels turning alike";
  EXPECT_NE(errorWith(split, split + "\n  rear_bias: 2").find("drivetrain.rear_bias: is not a known key"),
            std::string::npos)
      << "biases only with a limited-slip differential";
  std::filesystem::remove_all(dir);
}

TEST(VehicleConfig, ALimitedSlipDifferentialReadsItsBiases) {
  const auto dir = std::filesystem::temp_directory_path() / ("roar_vc_diff_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ifstream in(test::sourceDir() + "/config/vehicles/sedan.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string split = "  front_drive_share: 0.4";
  text.replace(text.find(split), split.size(), split + "\n  differential: limited_slip\n  centre_bias: 2.5");
  const auto path = (dir / "car.yaml").string();
  std::ofstream(path) << text;
  vehicle::VehicleParams p;
  vehicle::readVehicleYaml(path, &p);
  EXPECT_EQ(p.differential.type, vehicle::DifferentialType::kLimitedSlip);
  EXPECT_DOUBLE_EQ(p.differential.centre_bias, 2.5);
  EXPECT_DOUBLE_EQ(p.differential.rear_bias, 1.3) << "PhysX's default";
  EXPECT_EQ(test::sedan().differential.type, vehicle::DifferentialType::kOpen);
  std::filesystem::remove_all(dir);
}

TEST(VehicleConfig, ValidateRejectsImplausibleValues) {
  auto p = test::sedan();
  p.gearbox.ratios = {2.0, 3.0};
  EXPECT_NE(errorOf([&] { vehicle::validate(p, "x"); }).find("must fall"), std::string::npos);
  p = test::sedan();
  p.chassis.mass = -1;
  EXPECT_NE(errorOf([&] { vehicle::validate(p, "x"); }).find("base_link mass -1 is outside [50, 50000] kg"),
            std::string::npos);
  p = test::sedan();
  p.wheels[0].radius = 1e300;
  EXPECT_NE(errorOf([&] { vehicle::validate(p, "x"); }).find("wheel 'wheel_front_left' radius 1e+300 is outside"),
            std::string::npos);
}

namespace {

// Every numeric leaf of a YAML document, with its dotted path (sequence items by index).
void numericLeaves(const YAML::Node& node, const std::string& path, std::vector<std::string>* out) {
  if (node.IsMap()) {
    for (const auto& kv : node)
      numericLeaves(kv.second, (path.empty() ? "" : path + ".") + kv.first.as<std::string>(), out);
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) numericLeaves(node[i], path + "[" + std::to_string(i) + "]", out);
  } else if (node.IsScalar()) {
    double v;
    const std::string text = node.Scalar();
    if (text != "true" && text != "false" && YAML::convert<double>::decode(node, v)) out->push_back(path);
  }
}

// The node at a dotted path of numericLeaves.
YAML::Node at(YAML::Node root, const std::string& path) {
  YAML::Node node = root;
  std::size_t from = 0;
  while (from < path.size()) {
    const std::size_t dot = path.find_first_of(".[", from);
    const std::string part = path.substr(from, dot == std::string::npos ? std::string::npos : dot - from);
    if (!part.empty()) node.reset(node[part]);
    if (dot == std::string::npos) break;
    if (path[dot] == '[') {
      const std::size_t close = path.find(']', dot);
      node.reset(node[std::stoul(path.substr(dot + 1, close - dot - 1))]);
      from = close + 1;
      if (from < path.size() && path[from] == '.') ++from;
    } else {
      from = dot + 1;
    }
  }
  return node;
}

}  // namespace

TEST(VehicleConfig, EveryNumericFieldAtEveryExtremeIsRefusedByNameOrDrivesFinite) {
  // Property test (issue 17): each number of sedan.yaml set to 0, -1, 1e-30, 1e30, 1e300, NaN and inf in
  // turn: the file is refused naming the field, or the car it makes drives 10 s (full throttle, steering)
  // with a finite state throughout.
  namespace fs = std::filesystem;
  const auto dir = fs::temp_directory_path() / ("roar_vc_property_" + std::to_string(::getpid()));
  fs::create_directories(dir / "urdf");
  fs::create_directories(dir / "config");
  fs::copy_file(test::sourceDir() + "/urdf/sedan.urdf", dir / "urdf" / "sedan.urdf",
                fs::copy_options::overwrite_existing);
  const YAML::Node original = YAML::LoadFile(test::sourceDir() + "/config/vehicles/sedan.yaml");
  std::vector<std::string> fields;
  numericLeaves(original, "", &fields);
  ASSERT_GT(fields.size(), 40u);
  const auto track = test::openGround();
  int refused = 0, drove = 0;
  for (const auto& field : fields) {
    for (const char* extreme : {"0", "-1", "1e-30", "1e30", "1e300", ".nan", ".inf"}) {
      YAML::Node doc = YAML::Clone(original);
      at(doc, field) = YAML::Load(extreme);
      std::ofstream((dir / "config" / "sedan.yaml").string()) << YAML::Dump(doc) << "\n";
      vehicle::VehicleParams params;
      std::string error;
      try {
        params = vehicle::loadVehicleModel("sedan", (dir / "urdf").string(), (dir / "config").string());
      } catch (const std::exception& e) {
        error = e.what();
      }
      // The leaf's own key (a sequence item is named by its sequence's key).
      std::string key = field.substr(field.find_last_of('.') + 1);
      key = key.substr(0, key.find('['));
      if (!error.empty()) {
        EXPECT_NE(error.find(key), std::string::npos) << field << " = " << extreme << ": " << error;
        ++refused;
        continue;
      }
      sim::World world(track, {});
      track::Pose pose;
      pose.position = {0, 0, 0};
      world.spawnVehicle("ego", params, pose);
      bool finite = true;
      for (int tick = 0; tick < 200 && finite; ++tick) {
        vehicle::VehicleControl control;
        control.throttle = 1.0;
        control.steer = tick > 100 ? 0.3 : 0.0;
        world.setControl("ego", control);
        world.step();
        const auto state = world.vehicleState("ego");
        finite =
            state.pose.position.allFinite() && state.linear_velocity.allFinite() && state.pose.position.norm() < 1e5;
      }
      EXPECT_TRUE(finite) << field << " = " << extreme << " was accepted and the car's state left the finite";
      ++drove;
    }
  }
  RecordProperty("refused", refused);
  RecordProperty("drove", drove);
  std::printf("vehicle file property test: %zu fields x 7 extremes: %d refused by name, %d accepted and drove finite\n",
              fields.size(), refused, drove);
  fs::remove_all(dir);
}

// The response times, the stand in neutral and CarSimEd's tyre read by name, each refused out of range.
TEST(VehicleConfig, LagsStandAndCarSimEdTyreAreReadAndRangeChecked) {
  test::TempDir dir;
  std::ifstream in(test::sourceDir() + "/config/vehicles/sedan.yaml");
  const std::string sedan((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = sedan;
    const auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    text.replace(pos, from.size(), to);
    return dir.write("car.yaml", text);
  };
  vehicle::VehicleParams p;
  vehicle::readVehicleYaml(
      with("brakes:\n", "brakes:\n  pedal_rate_per_s: 6\n  rise_time_s: 0.25\n  release_time_s: 0.5\n"), &p);
  EXPECT_DOUBLE_EQ(p.brakes.pedal_rate, 6.0);
  EXPECT_DOUBLE_EQ(p.brakes.rise_time, 0.25);
  EXPECT_DOUBLE_EQ(p.brakes.release_time, 0.5);
  EXPECT_DOUBLE_EQ(p.pedalResponseTime(), 0.25 + 0.5 / 6.0) << "the lag from the ramp's half-way point";
  vehicle::readVehicleYaml(with("gearbox:\n", "gearbox:\n  engage_time_s: 1.5\n  clutch_strength_nm_s_per_rad: 2\n"),
                           &p);
  EXPECT_DOUBLE_EQ(p.gearbox.engage_time, 1.5);
  EXPECT_DOUBLE_EQ(p.gearbox.clutch_strength, 2.0);
  vehicle::readVehicleYaml(with("engine:\n", "engine:\n  response_time_s: 0.3\n  inertia_kg_m2: 0.2\n"), &p);
  EXPECT_DOUBLE_EQ(p.engine.response_time, 0.3);
  EXPECT_DOUBLE_EQ(p.engine.inertia, 0.2);
  const auto tyre = sedan.find("  longitudinal:");
  const auto end = sedan.find("  nominal_load_n:");
  ASSERT_NE(tyre, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  const std::string magic = sedan.substr(tyre, end - tyre);
  vehicle::readVehicleYaml(
      with(magic,
           "  curve: carsimed\n  carsimed: {lat_stiff_value: 17, lat_stiff_max_load: 2, long_stiff_value: 1000}\n"),
      &p);
  EXPECT_EQ(p.tyre.curve, vehicle::TyreCurve::kCarSimEd);
  EXPECT_DOUBLE_EQ(p.tyre.lateral_stiffness, 17.0);
  EXPECT_DOUBLE_EQ(p.tyre.longitudinal_stiffness, 1000.0);
  auto error = [&](const std::string& from, const std::string& to) {
    return errorOf([&] { vehicle::readVehicleYaml(with(from, to), &p); });
  };
  EXPECT_NE(error("brakes:\n", "brakes:\n  rise_time_s: 5\n").find("brakes.rise_time_s: 5 is outside [0, 2] s"),
            std::string::npos);
  EXPECT_NE(error("brakes:\n", "brakes:\n  pedal_rate_per_s: -1\n").find("brakes.pedal_rate_per_s: -1 is outside"),
            std::string::npos);
  EXPECT_NE(error("gearbox:\n", "gearbox:\n  engage_time_s: -1\n").find("gearbox.engage_time_s: -1 is outside"),
            std::string::npos);
  EXPECT_NE(error(magic, "  curve: pacejka\n").find("tyre.curve: 'pacejka' is neither magic_formula nor carsimed"),
            std::string::npos);
  EXPECT_NE(error(magic, "  curve: carsimed\n  carsimed: {lat_stiff_value: 17, lat_stiff_max_load: 2}\n")
                .find("tyre.carsimed.long_stiff_value: is missing"),
            std::string::npos);
}
