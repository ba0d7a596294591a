// The shared readers every file goes through: only regular files within a cap, and YAML keys given once.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>

#include "roar/config/text_file.h"
#include "roar/config/yaml_section.h"
#include "roar/rl/env_options.h"
#include "roar/scenario/scenario.h"
#include "roar/sensors/sensor_spec.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"
#include "test_support.h"

using namespace roar;
using test::errorOf;

namespace {

std::string problemReading(const std::string& path, std::size_t cap = config::kMaxYamlBytes) {
  std::string text, problem;
  EXPECT_FALSE(config::tryReadTextFile(path, cap, &text, &problem)) << path;
  EXPECT_TRUE(text.empty()) << path;
  return problem;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(TextFile, ARegularFileIsReadWhole) {
  test::TempDir dir;
  const std::string path = dir.write("a.yaml", "a: 1\nb: [2, 3]\n");
  std::string text, problem;
  ASSERT_TRUE(config::tryReadTextFile(path, 64, &text, &problem)) << problem;
  EXPECT_EQ(text, "a: 1\nb: [2, 3]\n");
}

TEST(TextFile, DevicesFifosFoldersAndMissingFilesAreRefusedByName) {
  test::TempDir dir;
  EXPECT_EQ(problemReading("/dev/zero"), "/dev/zero: is not a regular file (a device, FIFO or socket is not read)");
  const std::string fifo = dir.str() + "/fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A FIFO without a writer would block an ordinary open for ever.
  EXPECT_TRUE(contains(problemReading(fifo), "is not a regular file"));
  EXPECT_EQ(problemReading(dir.str()), dir.str() + ": is a folder, not a file");
  EXPECT_EQ(problemReading(dir.str() + "/none.yaml"), dir.str() + "/none.yaml: no such file");
}

TEST(TextFile, AFileAboveTheCapIsRefusedBeforeItIsRead) {
  test::TempDir dir;
  const std::string path = dir.write("big.csv", std::string(2000, 'x'));
  EXPECT_EQ(problemReading(path, 1000), path + ": is larger than 1000 bytes (2000 bytes)");
  std::string problem;
  EXPECT_FALSE(config::checkRegularFile(path, 1000, &problem));
  EXPECT_TRUE(config::checkRegularFile(path, 2000, &problem)) << problem;
}

TEST(TextFile, EveryReaderRefusesAnEndlessStream) {
  // Each would otherwise read /dev/zero until memory runs out.
  const std::string zero = "/dev/zero";
  const std::string refused = "is not a regular file";
  EXPECT_TRUE(contains(errorOf([&] { track::readCentreLineCsv(zero); }), refused));
  EXPECT_TRUE(contains(errorOf([&] { track::readTrackYaml(zero, nullptr); }), refused));
  EXPECT_TRUE(contains(errorOf([&] { track::readPointList(zero, 10.0); }), refused));
  EXPECT_TRUE(contains(errorOf([&] { sensors::readSensorSet(zero); }), refused));
  EXPECT_TRUE(contains(errorOf([&] { rl::readEnvOptions(zero); }), refused));
  vehicle::VehicleParams params;
  EXPECT_TRUE(contains(errorOf([&] { vehicle::readVehicleYaml(zero, &params); }), refused));
  EXPECT_TRUE(contains(errorOf([&] { vehicle::readVehicleUrdf(zero, &params); }), refused));
  EXPECT_TRUE(contains(errorOf([&] { scenario::loadScenario(zero, scenario::ScenarioContext{}); }), refused));
}

TEST(YamlKeys, AKeyGivenTwiceIsRefusedWhereverItIs) {
  using Section = config::YamlSection<std::runtime_error>;
  EXPECT_EQ(errorOf([] { Section(YAML::Load("friction: 1.0\nfriction: 500\n"), "", "car.yaml"); }),
            "car.yaml: friction: is given twice");
  EXPECT_EQ(errorOf([] { Section(YAML::Load("{a: 1, b: 2}"), "", "f"); }), "");
  EXPECT_EQ(errorOf([] { Section(YAML::Load("[1]: 2"), "tyres", "f"); }),
            "f: tyres: has a key that is not a plain name");
  // Nested: the section a reader asks for is checked as the top is.
  EXPECT_EQ(errorOf([] { Section(YAML::Load("tyres: {mu: 1, mu: 2}"), "", "f").child("tyres"); }),
            "f: tyres.mu: is given twice");
  test::TempDir dir;
  const std::string set = dir.write("s.yaml", "sensors:\n  - {name: imu, type: imu, rate: 10, rate: 1000}\n");
  EXPECT_TRUE(contains(errorOf([&] { sensors::readSensorSet(set); }), "rate: is given twice"));
  const std::string car = dir.write("car.yaml", "blueprint: a\nblueprint: b\n");
  vehicle::VehicleParams params;
  EXPECT_TRUE(contains(errorOf([&] { vehicle::readVehicleYaml(car, &params); }), "blueprint: is given twice"));
}
