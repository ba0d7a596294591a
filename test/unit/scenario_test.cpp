#include "roar/scenario/scenario.h"

#include <yaml-cpp/yaml.h>

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "roar/planning/trajectory.h"
#include "test_support.h"

using namespace roar;
namespace fs = std::filesystem;

namespace {

scenario::ScenarioContext shipped() {
  const std::string src = test::sourceDir();
  return {src + "/maps", src + "/config/sensors", src + "/urdf", src + "/config/vehicles", src + "/config/rl"};
}

// Writes `text` as a scenario file and returns the error loading it gives ("" when it loads).
std::string errorLoading(const std::string& text) {
  const fs::path path = fs::temp_directory_path() / ("roar_scenario_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << text;
  const std::string error = test::errorOf([&] { scenario::loadScenario(path.string(), shipped()); });
  fs::remove(path);
  return error;
}

}  // namespace

TEST(Scenario, EveryShippedScenarioLoads) {
  const std::string dir = test::sourceDir() + "/config/scenarios";
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    SCOPED_TRACE(entry.path().string());
    const auto scenario = scenario::loadScenario(entry.path().string(), shipped());
    EXPECT_FALSE(scenario.cars.empty());
    EXPECT_FALSE(scenario.description.empty());
    ++count;
  }
  EXPECT_GE(count, 3);
  const auto race = scenario::loadScenario(scenario::resolveScenario("multi_car", dir), shipped());
  EXPECT_GE(race.cars.size(), 3u);
  EXPECT_GT(race.cars[0].max_speed, 0.0) << "a slower car in front";
  const auto rl = scenario::loadScenario(scenario::resolveScenario("rl_headless", dir), shipped());
  EXPECT_FALSE(rl.cars[0].driven);
  EXPECT_EQ(rl.cars[0].sensors, "default");
  EXPECT_NE(test::errorOf([&] { scenario::resolveScenario("nascar", dir); }).find("time_trial"), std::string::npos)
      << "an unknown scenario lists the known ones";
}

TEST(Scenario, BadScenariosNameTheFieldAndTheProblem) {
  const std::string car = "cars:\n  - {name: ego, spawn_point: 0}\n";
  EXPECT_EQ(errorLoading("map: roar_ring\n" + car), "");
  EXPECT_NE(errorLoading("map: monaco\n" + car).find("map: "), std::string::npos);
  EXPECT_NE(errorLoading("map: monaco\n" + car).find("monaco"), std::string::npos);
  EXPECT_NE(errorLoading(car).find("map: is missing"), std::string::npos);
  const std::string two_on_one =
      errorLoading("map: roar_ring\ncars:\n  - {name: a, spawn_point: 2}\n  - {name: b, spawn_point: 2}\n");
  EXPECT_NE(two_on_one.find("cars[1].spawn_point: 2 is taken by another car"), std::string::npos) << two_on_one;
  EXPECT_NE(errorLoading("map: roar_ring\ncars:\n  - {name: a}\n  - {name: a}\n").find("cars[1].name"),
            std::string::npos);
  const std::string sensors = errorLoading("map: roar_ring\ncars:\n  - {name: a, sensors: radar}\n");
  EXPECT_NE(sensors.find("cars[0].sensors: no sensor set 'radar'"), std::string::npos) << sensors;
  EXPECT_NE(errorLoading("map: roar_ring\ncars:\n  - {name: a, model: bus}\n").find("cars[0].model"),
            std::string::npos);
  EXPECT_NE(errorLoading("map: roar_ring\ncars:\n  - {name: a, colour: [1, 2]}\n").find("cars[0].colour"),
            std::string::npos);
  EXPECT_NE(errorLoading("map: roar_ring\ncars:\n  - {name: a, spawn_point: 40}\n").find("not a grid slot"),
            std::string::npos);
  EXPECT_NE(errorLoading("map: roar_ring\ncars: []\n").find("cars: must be a list"), std::string::npos);
  EXPECT_NE(errorLoading("map: [roar_ring\n").find(".yaml"), std::string::npos) << "broken YAML names the file";
  EXPECT_EQ(errorLoading("map: roar_ring\ncars:\n  - {name: a, driven: false, agent: state}\n"), "");
  const std::string agent = errorLoading("map: roar_ring\ncars:\n  - {name: a, driven: false, agent: telepathy}\n");
  EXPECT_NE(agent.find("cars[0].agent: no RL environment 'telepathy'"), std::string::npos) << agent;
  EXPECT_NE(errorLoading("map: roar_ring\ncars:\n  - {name: a, agent: state}\n")
                .find("cars[0].agent: an agent's car must have driven: false"),
            std::string::npos);
  // Misspelt keys are refused, naming the nearest known one (they used to fall back to the default silently).
  const std::string color = errorLoading("map: roar_ring\ncars:\n  - {name: a, color: [1, 0, 0]}\n");
  EXPECT_NE(color.find("cars[0].color: is not a known key (did you mean 'colour'?)"), std::string::npos) << color;
  const std::string lap = errorLoading("map: roar_ring\nlap: 3\n" + car);
  EXPECT_NE(lap.find("lap: is not a known key (did you mean 'laps'?)"), std::string::npos) << lap;
  EXPECT_NE(errorLoading("map: roar_ring\nlaps: many\n" + car).find("laps: is not a"), std::string::npos);
  // Speeds and paces: a NaN cap used to let the pace car race uncapped.
  EXPECT_EQ(errorLoading("map: roar_ring\ncars:\n  - {name: a, pace: 0.9, max_speed: 20}\n"), "");
  for (const char* bad : {".nan", "-1", "1e30", ".inf"}) {
    const std::string e = errorLoading(std::string("map: roar_ring\ncars:\n  - {name: a, max_speed: ") + bad + "}\n");
    EXPECT_NE(e.find("cars[0].max_speed:"), std::string::npos) << bad << ": " << e;
  }
  for (const char* bad : {".nan", "0", "1.5", "-0.9"}) {
    const std::string e = errorLoading(std::string("map: roar_ring\ncars:\n  - {name: a, pace: ") + bad + "}\n");
    EXPECT_NE(e.find("cars[0].pace:"), std::string::npos) << bad << ": " << e;
  }
}

TEST(FollowBehind, SlowsToTheLeadersSpeedBeforeTheGapAndBrakesInTime) {
  planning::Trajectory window;
  window.closed = false;
  for (int i = 0; i <= 200; ++i) {
    planning::TrajectoryPoint p;
    p.position = {1.0 * i, 0.0};
    p.s = i;
    p.speed = 40.0;
    window.points.push_back(p);
  }
  const auto limits = planning::vehicleLimits(test::sedan(), 1.0, 0.85);
  auto following = window;
  planning::followBehind(&following, 0.0, 150.0, 10.0, 12.0, limits);
  EXPECT_NEAR(following.points[138].speed, 10.0, 1e-9) << "at the gap: the leader's speed";
  EXPECT_NEAR(following.points[200].speed, 10.0, 1e-9);
  for (int i = 0; i < 200; ++i) {
    const double decel = (following.points[i].speed * following.points[i].speed -
                          following.points[i + 1].speed * following.points[i + 1].speed) /
                         2.0;
    EXPECT_LE(decel, planning::decelerationAt(limits, following.points[i + 1].speed, 0.0) + 1e-6) << i;
    EXPECT_NEAR(following.points[i].acceleration, -decel, 1e-6) << i;
  }
  EXPECT_NEAR(following.points[0].speed, 40.0, 1e-9) << "far enough back to go on at full speed";
  // Closer than the gap: slower than the leader.
  auto close = window;
  planning::followBehind(&close, 0.0, 5.0, 10.0, 12.0, limits);
  EXPECT_LT(close.points[0].speed, 10.0);
}

// Behind a car that sets the speed just ahead, a car still below that speed keeps the window's own
// acceleration (the tracker feeds it forward) until, gaining at it, it would reach the speed held; the
// speeds themselves are held as ever, and a car already at the held speed reads the braking ramp.
TEST(FollowBehind, ACarBelowTheHeldSpeedKeepsTheWindowsAccelerationUntilItReachesIt) {
  planning::Trajectory window;
  window.closed = false;
  const double a = 4.0;  // m/s^2: the window accelerates from 30 m/s
  for (int i = 0; i <= 200; ++i) {
    planning::TrajectoryPoint p;
    p.position = {1.0 * i, 0.0};
    p.s = i;
    p.speed = std::sqrt(30.0 * 30.0 + 2.0 * a * i);
    p.acceleration = a;
    window.points.push_back(p);
  }
  const auto limits = planning::vehicleLimits(test::sedan(), 1.0, 0.85);
  auto held = window, below = window, at_speed = window;
  planning::followBehind(&held, 0.0, 40.0, 31.0, 12.0, limits);
  planning::followBehind(&below, 0.0, 40.0, 31.0, 12.0, limits, 25.0);
  planning::followBehind(&at_speed, 0.0, 40.0, 31.0, 12.0, limits, 31.0);
  double least_held = a, least_at_speed = a;
  for (std::size_t k = 0; k < window.points.size(); ++k) {
    EXPECT_DOUBLE_EQ(below.points[k].speed, held.points[k].speed) << k;
    EXPECT_DOUBLE_EQ(at_speed.points[k].speed, held.points[k].speed) << k;
    if (window.points[k].s > 28.0) continue;  // up to the gap behind the car ahead
    least_held = std::min(least_held, held.points[k].acceleration);
    least_at_speed = std::min(least_at_speed, at_speed.points[k].acceleration);
    // From 25 m/s at 4 m/s^2 the car is at 29.1 m/s 28 m on: below the 31 held all the way.
    EXPECT_NEAR(below.points[k].acceleration, a, 1e-9) << "at s = " << window.points[k].s;
  }
  EXPECT_LT(least_held, -1.0) << "no braking ramp down to the car ahead's speed";
  EXPECT_LT(least_at_speed, -1.0) << "a car at the held speed not braking for it";
}

TEST(Scenario, EveryNumberAtEveryExtremeIsRefusedByNameOrLoadsInRange) {
  // Property test (issue 17): each number of a two-car scenario set to 0, -1, 1e-30, 1e30, 1e300, NaN and inf
  // in turn: refused naming the field, or a scenario whose numbers are finite and physical.
  const std::vector<std::pair<std::string, std::string>> fields = {
      {"laps", "laps: 2"},   {"spawn_point", "spawn_point: 1"},     {"max_speed", "max_speed: 15.0"},
      {"pace", "pace: 0.9"}, {"colour", "colour: [0.5, 0.5, 0.5]"},
  };
  const std::string base =
      "name: t\nmap: roar_sprint\nlaps: 2\ncars:\n"
      "  - {name: a, spawn_point: 0}\n"
      "  - {name: b, spawn_point: 1, max_speed: 15.0, pace: 0.9, colour: [0.5, 0.5, 0.5]}\n";
  int refused = 0, loaded = 0;
  for (const auto& [key, original] : fields) {
    for (const char* extreme : {"0", "-1", "1e-30", "1e30", "1e300", ".nan", ".inf"}) {
      std::string text = base;
      const std::string value = key == "colour" ? std::string("[") + extreme + ", 0.5, 0.5]" : extreme;
      const std::size_t at = key == "laps" ? text.find(original) : text.rfind(original);
      text.replace(at, original.size(), key + ": " + value);
      const fs::path path = fs::temp_directory_path() / ("roar_scenario_x_" + std::to_string(::getpid()) + ".yaml");
      std::ofstream(path) << text;
      try {
        const auto s = scenario::loadScenario(path.string(), shipped());
        EXPECT_GE(s.laps, 1) << key << " = " << extreme;
        for (const auto& car : s.cars) {
          EXPECT_TRUE(std::isfinite(car.max_speed) && car.max_speed >= 0 && car.max_speed <= 150)
              << key << " = " << extreme;
          EXPECT_TRUE(car.pace > 0 && car.pace <= 1) << key << " = " << extreme;
          EXPECT_TRUE(car.colour.allFinite() && car.colour.maxCoeff() <= 1) << key << " = " << extreme;
          EXPECT_TRUE(car.spawn_point >= 0) << key << " = " << extreme;
        }
        ++loaded;
      } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << key << " = " << extreme << ": " << e.what();
        ++refused;
      }
      fs::remove(path);
    }
  }
  std::printf("scenario property test: %zu fields x 7 extremes: %d refused by name, %d loaded in range\n",
              fields.size(), refused, loaded);
}

// The one reader of a race's cars, whether from a scenario or a node's ~vehicles: names alone or cars with
// a scenario car's keys, checked the same way, errors naming the source, the car and the key.
TEST(RaceCars, NamesOrCarsReadAndCheckedAsAScenariosAre) {
  const auto names =
      scenario::readCars(YAML::Load("[ego, rival]"), "vehicles", "parameter /planner/vehicles", shipped(), "hatchback");
  ASSERT_EQ(names.size(), 2u);
  EXPECT_EQ(names[0].name, "ego");
  EXPECT_EQ(names[1].name, "rival");
  EXPECT_EQ(names[1].model, "hatchback") << "the default model for a car that names none";
  EXPECT_EQ(names[1].spawn_point, 1) << "its place in the list";
  EXPECT_EQ(names[1].pace, 1.0);
  const auto cars = scenario::readCars(YAML::Load("[{name: ego, pace: 0.9, spawn_point: 3}, {name: slow, model: sedan, "
                                                  "max_speed: 15, driven: false}]"),
                                       "vehicles", "parameter /planner/vehicles", shipped(), "hatchback");
  ASSERT_EQ(cars.size(), 2u);
  EXPECT_EQ(cars[0].pace, 0.9);
  EXPECT_EQ(cars[0].spawn_point, 3);
  EXPECT_EQ(cars[0].model, "hatchback");
  EXPECT_EQ(cars[1].model, "sedan");
  EXPECT_EQ(cars[1].max_speed, 15.0);
  EXPECT_FALSE(cars[1].driven);
  EXPECT_TRUE(scenario::readCars(YAML::Load("[]"), "vehicles", "p", shipped()).empty()) << "roar_sim with no car";
  auto error = [](const std::string& yaml) {
    return test::errorOf(
        [&] { scenario::readCars(YAML::Load(yaml), "vehicles", "parameter /planner/vehicles", shipped()); });
  };
  EXPECT_EQ(error("[{name: ego, modle: sedan}]")
                .rfind("parameter /planner/vehicles: vehicles[0].modle: is not a known key (did you mean 'model'?)", 0),
            0u);
  EXPECT_NE(error("[ego, ego]").find("vehicles[1].name: 'ego' is used by another car"), std::string::npos);
  EXPECT_NE(error("[{name: ego, model: tractor}]").find("parameter /planner/vehicles: vehicles[0].model"),
            std::string::npos);
  EXPECT_NE(error("[{name: ego, pace: 2}]").find("vehicles[0].pace"), std::string::npos);
  EXPECT_NE(error("{name: ego}").find("vehicles: must be a list of cars"), std::string::npos);
  EXPECT_NE(error("[{name: bot, agent: state}]").find("driven: false"), std::string::npos);
}
